!> The solid phase's state on the fluid grid between steps of a coupled scene: the free-fluid
!! reservoirs in the ghosts beyond open faces, and the datasets a dump or checkpoint holds of it
!! (the tracked solid fraction, the porosity, the solid cell velocity, the fluids' final face
!! velocities).
module mpmice_solid_state
  use mpmice_kinds, only: wp
  use parallel_domain, only: domain_t
  use parallel_halo, only: halo_t, halo_exchange_cell, halo_exchange_node
  use grid_layout, only: grid_t
  use io_hdf5, only: h5_file_t, h5_write_cell_field, h5_read_cell_field, h5_write_node_field, &
    h5_read_node_field, h5_exists
  use ice_state, only: ice_state_t
  use exchange_solid_phase, only: solid_phase_t
  use ice_bc, only: ice_bc_fill, bc_scalar
  use ice_stages, only: ice_fluids_t
  implicit none
  private

  public :: open_face_reservoirs, solid_state_write, solid_state_restore

  character(len=*), parameter :: comp(3) = ['x', 'y', 'z']  !< component suffixes

contains

  !> Ghost cells beyond an open ('pressure') face hold a free-fluid reservoir: no solid, and the
  !! fluids' bulk densities of the mirrored inner cell divided by its porosity (so their
  !! intrinsic densities are the inner cell's). Beyond a wall the ghosts mirror the inner cell,
  !! solid included, so the equilibration there sees the same mixture.
  pure subroutine open_face_reservoirs(state, solid, grid)
    type(ice_state_t), intent(inout) :: state  !< fluids and solid phase (ghosts updated)
    type(solid_phase_t), intent(inout) :: solid !< solid phase
    type(grid_t), intent(in) :: grid           !< block geometry
    integer :: i, j, k, d, m, face, c(3)
    real(wp) :: porosity
    do k = grid%lbc(3), grid%ubc(3)
      do j = grid%lbc(2), grid%ubc(2)
        do i = grid%lbc(1), grid%ubc(1)
          c = [i, j, k]
          do d = 1, 3
            if (.not. grid%active(d) .or. grid%periodic(d)) cycle
            face = 0
            if (c(d) < 1) face = 2 * d - 1
            if (c(d) > grid%ncells(d)) face = 2 * d
            if (face == 0) cycle
            if (state%closed(face)) cycle
            porosity = 1.0_wp - solid%vfrac(i, j, k)
            if (porosity <= 0.0_wp) cycle
            do m = 1, state%nfluids
              state%fluid(m)%rho(i, j, k) = state%fluid(m)%rho(i, j, k) / porosity
            end do
            solid%vfrac(i, j, k) = 0.0_wp
          end do
        end do
      end do
    end do
  end subroutine open_face_reservoirs

  !> A dump: `cell/solid_volume_fraction` (the tracked phi_s) and `cell/porosity`; a
  !! checkpoint: the tracked fraction, the solid cell velocity and the fluids' final face
  !! velocities (what the next step reads), and with sliding rigid contact the deformable
  !! solids' fraction and specific volume of the step (the next step's contact reads them
  !! before it deposits the particles again).
  subroutine solid_state_write(file, grid, state, solid, nbuf, work, checkpoint)
    type(h5_file_t), intent(in) :: file           !< open file
    type(grid_t), intent(in) :: grid              !< block geometry
    type(ice_state_t), intent(in) :: state        !< fluids and solid phase
    type(solid_phase_t), intent(in) :: solid !< solid phase
    real(wp), intent(inout) :: nbuf(grid%lbn(1):, grid%lbn(2):, grid%lbn(3):) !< node scratch
    real(wp), intent(inout) :: work(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !< cell scratch
    logical, intent(in) :: checkpoint             !< full restart state
    integer :: d, m
    associate (sp => solid)
      if (checkpoint) then
        call h5_write_cell_field(file, 'checkpoint/cell/solid_volume_fraction', grid, sp%vfrac)
        do d = 1, 3
          call h5_write_cell_field(file, 'checkpoint/cell/solid_velocity_' // comp(d), grid, &
            sp%vel(:, :, :, d))
        end do
        ! the fluids' final face velocities, read by the next predictor (stored like node
        ! fields: face i of direction d sits at node index i along d)
        do m = 1, state%nfluids
          do d = 1, 3
            nbuf = state%fluid(m)%uface(grid%lbn(1):grid%ubn(1), &
              grid%lbn(2):grid%ubn(2), grid%lbn(3):grid%ubn(3), d)
            call h5_write_node_field(file, 'checkpoint/face/' // &
              trim(state%fluid(m)%name) // '/velocity_' // comp(d), grid, nbuf)
          end do
        end do
        if (sp%sliding) then
          call h5_write_cell_field(file, 'checkpoint/cell/solid_deformable_fraction', grid, &
            sp%frac_def)
          call h5_write_cell_field(file, 'checkpoint/cell/solid_specific_volume', grid, &
            sp%spvol)
        end if
      else
        call h5_write_cell_field(file, 'cell/solid_volume_fraction', grid, sp%vfrac)
        work = 1.0_wp - sp%vfrac
        call h5_write_cell_field(file, 'cell/porosity', grid, work)
      end if
    end associate
  end subroutine solid_state_write

  !> Read what `solid_state_write` wrote to a checkpoint; ghosts filled (the face velocities
  !! through the node halo of `halo`).
  subroutine solid_state_restore(file, dom, grid, fl, solid, halo, nbuf)
    type(h5_file_t), intent(in) :: file           !< open checkpoint
    type(domain_t), intent(in) :: dom             !< decomposition
    type(grid_t), intent(in) :: grid              !< block geometry
    class(ice_fluids_t), intent(inout) :: fl      !< the fluids (halo, face conditions, state)
    type(solid_phase_t), intent(inout) :: solid !< solid phase
    type(halo_t), intent(inout) :: halo           !< node halo buffers
    real(wp), intent(inout) :: nbuf(grid%lbn(1):, grid%lbn(2):, grid%lbn(3):) !< node scratch
    integer :: d, m
    associate (sp => solid)
      call read_filled('checkpoint/cell/solid_volume_fraction', sp%vfrac)
      call open_face_reservoirs(fl%state, solid, grid)
      do d = 1, 3
        call h5_read_cell_field(file, 'checkpoint/cell/solid_velocity_' // comp(d), grid, &
          sp%vel(:, :, :, d))
        call halo_exchange_cell(fl%halo, dom, grid, sp%vel(:, :, :, d))
      end do
      ! the sliding contact's fields of the step before (checkpoints written before they were
      ! stored: those of the set-up, as such a restart always had)
      if (sp%sliding) then
        if (h5_exists(file, 'checkpoint/cell/solid_deformable_fraction')) then
          call read_filled('checkpoint/cell/solid_deformable_fraction', sp%frac_def)
          call read_filled('checkpoint/cell/solid_specific_volume', sp%spvol)
        end if
      end if
      do m = 1, fl%state%nfluids
        do d = 1, 3
          call h5_read_node_field(file, 'checkpoint/face/' // &
            trim(fl%state%fluid(m)%name) // '/velocity_' // comp(d), grid, nbuf)
          call halo_exchange_node(halo, dom, grid, nbuf)
          fl%state%fluid(m)%uface(grid%lbn(1):grid%ubn(1), grid%lbn(2):grid%ubn(2), &
            grid%lbn(3):grid%ubn(3), d) = nbuf
        end do
      end do
    end associate

  contains

    !> The owned cells of the cell field `field` from the checkpoint's dataset `path`, the
    !! ghosts from the neighbours and the face conditions (a scalar).
    subroutine read_filled(path, field)
      character(len=*), intent(in) :: path                 !< dataset in the checkpoint
      real(wp), intent(inout) :: field(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !< cell field
      call h5_read_cell_field(file, path, grid, field)
      call halo_exchange_cell(fl%halo, dom, grid, field)
      call ice_bc_fill(grid, fl%bc, field, bc_scalar)
    end subroutine read_filled
  end subroutine solid_state_restore
end module mpmice_solid_state
