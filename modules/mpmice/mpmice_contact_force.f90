!> Forces on the rigid bodies of a coupled scene with sliding contact (`&mpm rigid_contact =
!! 'friction'`; docs/mpmice.md "Forces on the rigid bodies"): the owner map of the contact nodes,
!! each body's own cell fraction, and the per-step series `<output_dir>/<name>_contact_force.csv`.
module mpmice_contact_force
  use mpmice_kinds, only: wp, path_len
  use parallel_domain, only: domain_t
  use parallel_halo, only: halo_t, halo_exchange_cell
  use parallel_reduce, only: global_sum
  use grid_layout, only: grid_t
  use io_files, only: io_open_series
  use ice_state, only: ice_state_t
  use exchange_solid_phase, only: solid_phase_t
  use mpm_scene, only: mpm_scene_t
  use mpm_constitutive, only: model_rigid
  use mpm_rigid, only: rigid_is_static
  use mpm_p2g, only: p2g_accumulate_rigid
  use mpm_nodes, only: node_rigid_mass
  use mpmice_rigid_contact, only: fluid_pressure_force
  use mpmice_deposit_layout, only: deposit_solid_volume
  implicit none
  private

  public :: contact_force_t, contact_force_init, contact_force_write, contact_force_free

  !> The contact-force series and what it needs between steps.
  type :: contact_force_t
    real(wp), allocatable :: qscr(:, :, :, :)             !< one rigid body's P2G (nodes)
    real(wp), allocatable :: owner_m(:, :, :)             !< mass of a node's main rigid body
    integer, allocatable :: owner(:, :, :)                !< that body (solid index)
    real(wp), allocatable :: body_frac(:, :, :, :)        !< each rigid body's own cell fraction
                                                          !! (cells, solid; 0 for deformable)
    character(len=path_len) :: path = ''                  !< contact-force series file
    logical :: started = .false.                          !< series opened this run
    logical :: owner_fixed = .false.                      !< owner map final (static bodies)
  end type contact_force_t

contains

  !> Work arrays on `grid` for `so`'s solids; the series goes to `path`.
  subroutine contact_force_init(self, so, grid, path)
    type(contact_force_t), intent(inout) :: self  !< series (freed first)
    type(mpm_scene_t), intent(in) :: so           !< the solids (node fields allocated)
    type(grid_t), intent(in) :: grid              !< block geometry
    character(len=*), intent(in) :: path          !< series file
    call contact_force_free(self)
    allocate(self%qscr, mold=so%nodes%q)
    allocate(self%owner_m(grid%lbn(1):grid%ubn(1), grid%lbn(2):grid%ubn(2), &
      grid%lbn(3):grid%ubn(3)), source=0.0_wp)
    allocate(self%owner(grid%lbn(1):grid%ubn(1), grid%lbn(2):grid%ubn(2), &
      grid%lbn(3):grid%ubn(3)), source=0)
    allocate(self%body_frac(grid%lbc(1):grid%ubc(1), grid%lbc(2):grid%ubc(2), &
      grid%lbc(3):grid%ubc(3), so%nsolids), source=0.0_wp)
    self%path = path
  end subroutine contact_force_init

  !> Sliding rigid bodies: append the force the soil exerts on each rigid body through the
  !! contact (sum over its contact nodes of m (v - v_contact) / dt at the end of the step, each
  !! node counted for the rigid body with the most mass there) and the fluids' pressure force on
  !! it (`mpmice_rigid_contact%fluid_pressure_force` with the step's pressure and the body's own
  !! cell fraction from this step's deposit) to `<output_dir>/<name>_contact_force.csv` (rank 0
  !! writes): time, then `<solid>_fx, _fy, _fz` (contact) per rigid solid, then
  !! `<solid>_fluid_fx, _fluid_fy, _fluid_fz` per rigid solid [N] (per the grid's depth in an
  !! inactive dimension). Like the owner map, the bodies' cell fractions are computed once when
  !! none of the bodies moves.
  subroutine contact_force_write(self, so, state, solid, halo, dom, grid, time, dep, contact_f, &
    gravity)
    type(contact_force_t), intent(inout) :: self  !< series and owner map
    type(mpm_scene_t), intent(in) :: so           !< the solids
    type(ice_state_t), intent(in) :: state        !< fluids (pressure) and solid phase
    type(solid_phase_t), intent(in) :: solid !< solid phase
    type(halo_t), intent(inout) :: halo           !< cell halo buffers (one component)
    type(domain_t), intent(in) :: dom             !< decomposition
    type(grid_t), intent(in) :: grid              !< block geometry
    real(wp), intent(in) :: time                  !< time [s]
    real(wp), intent(in) :: dep(:, grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !< this step's
                                                  !! particle deposit (`mpmice_solid_coupling`)
    real(wp), intent(in) :: contact_f(:, grid%lbn(1):, grid%lbn(2):, grid%lbn(3):) !< contact
                                                  !! force per node (3, nodes) [N]
    real(wp), intent(in) :: gravity(3)            !< gravitational acceleration [m/s^2]
    real(wp) :: force(3, so%nsolids), fluid(3, so%nsolids)
    integer :: s, i, j, k, unit
    logical :: fresh
    character(len=:), allocatable :: header
    ! the owner map moves with the bodies: computed once when none of them moves
    if (.not. self%owner_fixed) then
      self%owner = 0
      self%owner_m = 0.0_wp
      do s = 1, so%nsolids
        if (so%mats(s)%model /= model_rigid) cycle
        self%qscr = 0.0_wp
        call p2g_accumulate_rigid(so%parts(s), self%qscr, so%shape_kind, grid)
        where (self%qscr(node_rigid_mass, :, :, :) > self%owner_m)
          self%owner = s
          self%owner_m = self%qscr(node_rigid_mass, :, :, :)
        end where
        ! the body's grain volume deposited at the start of the step (deposit_solids), ghosts
        ! from their owners
        self%body_frac(:, :, :, s) = min(dep(deposit_solid_volume(s), :, :, :) / &
          grid%cell_volume, 1.0_wp)
        call halo_exchange_cell(halo, dom, grid, self%body_frac(:, :, :, s))
      end do
      self%owner_fixed = all(pack(rigid_is_static(so%motions(1:so%nsolids)), &
        so%mats(1:so%nsolids)%model == model_rigid))
    end if
    force = 0.0_wp
    do k = grid%nlo(3), grid%nhi(3)
      do j = grid%nlo(2), grid%nhi(2)
        do i = grid%nlo(1), grid%nhi(1)
          if (self%owner(i, j, k) > 0) force(:, self%owner(i, j, k)) = &
            force(:, self%owner(i, j, k)) + contact_f(:, i, j, k)
        end do
      end do
    end do
    fluid = 0.0_wp
    do s = 1, so%nsolids
      if (so%mats(s)%model /= model_rigid) cycle
      fluid(:, s) = fluid_pressure_force(state, solid, grid, self%body_frac, s, gravity)
    end do
    do s = 1, so%nsolids
      force(:, s) = global_sum(dom, force(:, s))
      fluid(:, s) = global_sum(dom, fluid(:, s))
    end do
    if (dom%rank /= 0) return
    call io_open_series(trim(self%path), so%restored, self%started, unit, fresh)
    if (fresh) then
      header = 'time'
      do s = 1, so%nsolids
        if (so%mats(s)%model /= model_rigid) cycle
        header = header // ',' // trim(so%names(s)) // '_fx,' // trim(so%names(s)) // &
          '_fy,' // trim(so%names(s)) // '_fz'
      end do
      do s = 1, so%nsolids
        if (so%mats(s)%model /= model_rigid) cycle
        header = header // ',' // trim(so%names(s)) // '_fluid_fx,' // &
          trim(so%names(s)) // '_fluid_fy,' // trim(so%names(s)) // '_fluid_fz'
      end do
      write(unit, '(a)') header
    end if
    write(unit, '(es24.16e3)', advance='no') time
    do s = 1, so%nsolids
      if (so%mats(s)%model /= model_rigid) cycle
      write(unit, '(3(",", es24.16e3))', advance='no') force(:, s)
    end do
    do s = 1, so%nsolids
      if (so%mats(s)%model /= model_rigid) cycle
      write(unit, '(3(",", es24.16e3))', advance='no') fluid(:, s)
    end do
    write(unit, '(a)') ''
    close(unit)
  end subroutine contact_force_write

  !> Release the work arrays.
  subroutine contact_force_free(self)
    type(contact_force_t), intent(inout) :: self  !< series
    if (allocated(self%qscr)) deallocate(self%qscr, self%owner_m, self%owner, self%body_frac)
    self%started = .false.
    self%owner_fixed = .false.
  end subroutine contact_force_free
end module mpmice_contact_force
