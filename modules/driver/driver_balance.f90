!> Block boundaries of the run: `&grid block_cells_x/y/z` where given, otherwise the even split
!! (`&grid balance = 'cells'`) or the cut from the cost per slab (`balance = 'cost'`).
!!
!! With 'cost' the particles are counted where `particles_seeding%seed_solid` would put them:
!! the centres of the equal sub-cells of every cell that lie inside a solid's shape, the same
!! arithmetic and shape test. The count does not need the decomposition, so the blocks are fixed
!! before anything is allocated: each rank counts every `nranks`-th cell, the per-slab counts are
!! summed over the ranks (integers held exactly in reals: the same sums on every rank), and
!! `parallel_balance%balanced_blocks` cuts each split dimension where the modelled step cost,
!! the most cells of a block + w x the most particles of a block, is least. Rigid solids that
!! `&mpm cache_static_rigid` keeps on the grid cost nothing per step and count 0. A restart
!! counts the particles where its checkpoint holds them instead (each rank reads a chunk of
!! their positions): the blocks follow the particles from one link of a restart chain to the
!! next, and stay those of the run before while the particles have not moved across a cut.
module driver_balance
  use mpmice_kinds, only: wp, i8
  use parallel_comm, only: MPI_Comm, comm_rank, comm_size, sum_in_place
  use parallel_domain, only: choose_dims, blocks_given
  use parallel_balance, only: balanced_blocks
  use config_types, only: config_t, solid_params_t, particles_per_cell_used, max_blocks_per_dim
  use particles_seeding, only: inside_shape, seed_point
  use mpm_rigid, only: rigid_motion_t, rigid_is_static
  use io_hdf5, only: h5_file_t, h5_open, h5_close, h5_read_particles
  implicit none
  private

  public :: run_block_cells, slab_particles, add_to_slabs

contains

  !> Collective over `comm`: the cells of each block along x, y, z for `domain_init` (the
  !! `block_cells` layout: leading positive entries, all zero for an even split). With
  !! `restart_file` (not '') the particles are counted in that checkpoint.
  function run_block_cells(cfg, comm, restart_file) result(block_cells)
    type(config_t), intent(in) :: cfg     !< validated configuration
    type(MPI_Comm), intent(in) :: comm    !< communicator of the run
    character(len=*), intent(in), optional :: restart_file  !< checkpoint continued, '' if none
    integer :: block_cells(max_blocks_per_dim, 3)
    integer :: d, dims(3), request(3), offset, i
    logical :: active(3), split(3)
    real(wp), allocatable :: counts(:), slab_cells(:)
    real(wp) :: cells_per_slab

    block_cells = cfg%grid%block_cells
    if (trim(cfg%grid%balance) /= 'cost') return
    active = cfg%grid%ncells > 1
    request = cfg%grid%dims
    do d = 1, 3
      if (blocks_given(block_cells(:, d)) > 0) request(d) = blocks_given(block_cells(:, d))
    end do
    dims = choose_dims(comm_size(comm), active, request)
    do d = 1, 3
      split(d) = dims(d) > 1 .and. blocks_given(block_cells(:, d)) == 0
    end do
    if (.not. any(split)) return

    if (present(restart_file)) then
      if (len_trim(restart_file) > 0) then
        call checkpoint_slab_particles(cfg, comm, restart_file, counts)
      else
        call slab_particles(cfg, comm, counts)
      end if
    else
      call slab_particles(cfg, comm, counts)
    end if
    offset = 0
    do d = 1, 3
      if (split(d)) then
        cells_per_slab = product(real(cfg%grid%ncells, wp)) / real(cfg%grid%ncells(d), wp)
        slab_cells = [(cells_per_slab, i = 1, cfg%grid%ncells(d))]
        call balanced_blocks(slab_cells, counts(offset + 1:offset + cfg%grid%ncells(d)), &
          cfg%grid%particle_weight, dims(d), max(cfg%grid%ghost_width, 1), block_cells(:, d))
      end if
      offset = offset + cfg%grid%ncells(d)
    end do
  end function run_block_cells

  !> Collective over `comm`: `counts` holds, for x, then y, then z, the particles the solids of
  !! `cfg` seed into each slab (the cells with one index along that dimension), every rank the
  !! same values; rigid solids kept on the grid (`&mpm cache_static_rigid`) are left out, and
  !! scenes without particles give zeros.
  subroutine slab_particles(cfg, comm, counts)
    type(config_t), intent(in) :: cfg                  !< validated configuration
    type(MPI_Comm), intent(in) :: comm                 !< communicator of the run
    real(wp), allocatable, intent(out) :: counts(:)    !< particles per slab, x then y then z
    integer :: s, rank, nranks, i, j, k, n(3), a, b, c, ppc(3), hits
    integer(i8) :: cell
    logical :: active(3)
    real(wp) :: lower(3), dx(3), xp(3)

    n = cfg%grid%ncells
    allocate(counts(sum(n)), source=0.0_wp)
    rank = comm_rank(comm)
    nranks = comm_size(comm)
    active = n > 1
    lower = cfg%grid%lower
    dx = (cfg%grid%upper - cfg%grid%lower) / real(n, wp)
    if (trim(cfg%run%scene) == 'mpm' .or. trim(cfg%run%scene) == 'mpmice') then
      do s = 1, cfg%nsolids
        associate (sp => cfg%solids(s))
          if (kept_on_grid(cfg, sp)) cycle
          ppc = particles_per_cell_used(sp, n)
          cell = 0
          do k = 1, n(3)
            do j = 1, n(2)
              do i = 1, n(1)
                cell = cell + 1
                if (mod(cell, int(nranks, i8)) /= rank) cycle
                hits = 0
                do c = 1, ppc(3)
                  do b = 1, ppc(2)
                    do a = 1, ppc(1)
                      xp = seed_point(lower, dx, [i, j, k], [a, b, c], ppc)
                      if (inside_shape(sp, active, xp)) hits = hits + 1
                    end do
                  end do
                end do
                if (hits == 0) cycle
                counts(i) = counts(i) + real(hits, wp)
                counts(n(1) + j) = counts(n(1) + j) + real(hits, wp)
                counts(n(1) + n(2) + k) = counts(n(1) + n(2) + k) + real(hits, wp)
              end do
            end do
          end do
        end associate
      end do
    end if
    call sum_in_place(comm, counts)
  end subroutine slab_particles

  !> Collective over `comm`: `counts` as `slab_particles` gives them, from the particle
  !! positions stored in the checkpoint `path` (`checkpoint/particles/<solid>/x`), every rank
  !! reading a chunk of them.
  subroutine checkpoint_slab_particles(cfg, comm, path, counts)
    type(config_t), intent(in) :: cfg                  !< configuration of the restart
    type(MPI_Comm), intent(in) :: comm                 !< communicator of the run
    character(len=*), intent(in) :: path               !< checkpoint file
    real(wp), allocatable, intent(out) :: counts(:)    !< particles per slab, x then y then z
    type(h5_file_t) :: file
    real(wp), allocatable :: x(:, :)
    integer :: s

    allocate(counts(sum(cfg%grid%ncells)), source=0.0_wp)
    if (trim(cfg%run%scene) == 'mpm' .or. trim(cfg%run%scene) == 'mpmice') then
      call h5_open(file, path, comm)
      do s = 1, cfg%nsolids
        if (kept_on_grid(cfg, cfg%solids(s))) cycle
        call h5_read_particles(file, 'checkpoint/particles/' // trim(cfg%solids(s)%name) // &
          '/x', x)
        call add_to_slabs(x, cfg%grid%ncells, cfg%grid%lower, cfg%grid%upper, counts)
      end do
      call h5_close(file)
    end if
    call sum_in_place(comm, counts)
  end subroutine checkpoint_slab_particles

  !> Add the particles at `x(:, 1:n)` to the slab counts `counts` (x, then y, then z slabs of a
  !! grid of `ncells` cells from `lower` to `upper`); a particle outside the grid counts in the
  !! nearest slab, an inactive dimension has one slab.
  pure subroutine add_to_slabs(x, ncells, lower, upper, counts)
    real(wp), intent(in) :: x(:, :)            !< particle positions (3, n) [m]
    integer, intent(in) :: ncells(3)           !< cells per dimension
    real(wp), intent(in) :: lower(3)           !< low corner [m]
    real(wp), intent(in) :: upper(3)           !< high corner [m]
    real(wp), intent(inout) :: counts(:)       !< particles per slab, x then y then z
    integer :: p, d, c, offset
    real(wp) :: dx(3)
    dx = (upper - lower) / real(ncells, wp)
    do p = 1, size(x, 2)
      offset = 0
      do d = 1, 3
        c = 1
        if (ncells(d) > 1) c = min(max(floor((x(d, p) - lower(d)) / dx(d)) + 1, 1), ncells(d))
        counts(offset + c) = counts(offset + c) + 1.0_wp
        offset = offset + ncells(d)
      end do
    end do
  end subroutine add_to_slabs

  !> True for a rigid solid that `&mpm cache_static_rigid` keeps on the grid (no prescribed
  !! velocity, no shaking): the same test as `mpm_scene`.
  logical function kept_on_grid(cfg, s)
    type(config_t), intent(in) :: cfg          !< configuration
    type(solid_params_t), intent(in) :: s      !< the solid
    kept_on_grid = cfg%mpm%cache_static_rigid .and. trim(s%model) == 'rigid'
    if (kept_on_grid) kept_on_grid = rigid_is_static(rigid_motion_t(s%prescribed_velocity, &
      s%acceleration_amplitude, s%acceleration_frequency, s%acceleration_duration))
  end function kept_on_grid
end module driver_balance
