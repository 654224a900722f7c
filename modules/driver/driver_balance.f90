!> Block boundaries of the run: `&grid block_cells_x/y/z` where given, otherwise the even split
!! (`&grid balance = 'cells'`) or the blocks of least modelled cost (`balance = 'cost'`).
!!
!! With 'cost' the particles are counted where `particles_seeding%seed_solid` would put them:
!! the centres of the equal sub-cells of every cell that lie inside a solid's shape, the same
!! arithmetic and shape test. The count does not need the decomposition, so the blocks are fixed
!! before anything is allocated: each rank counts every `nranks`-th cell, the per-slab counts are
!! summed over the ranks (integers held exactly in reals: the same sums on every rank), and
!! `parallel_balance%balanced_blocks` cuts each split dimension where the modelled step cost,
!! the most cells of a block + w x the most particles of a block, is least. Where `&grid dims`
!! leaves the blocks per dimension free, every layout of the ranks over the active dimensions
!! (`parallel_balance%block_layouts`: 2 x 1 and 1 x 2 on 2 ranks of a 2-D grid) is cut so, the
!! particles of each of its blocks counted, and the layout of least modelled cost kept (ties:
!! the one `MPI_Dims_create` gives). Rigid solids that `&mpm cache_static_rigid` keeps on the
!! grid cost nothing per step and count 0. A restart counts the particles where its checkpoint
!! holds them instead (each rank reads a chunk of their positions): the blocks follow the
!! particles from one link of a restart chain to the next, and stay those of the run before
!! while the particles have not moved across a cut.
module driver_balance
  use mpmice_kinds, only: wp, i8
  use parallel_comm, only: MPI_Comm, comm_rank, comm_size, sum_in_place
  use parallel_domain, only: choose_dims, blocks_given
  use parallel_balance, only: balanced_blocks, block_layouts, block_particles, add_to_slabs
  use config_types, only: config_t, solid_params_t, particles_per_cell_used, max_blocks_per_dim
  use particles_seeding, only: inside_shape, seed_point
  use mpm_rigid, only: rigid_motion_t, rigid_is_static
  use io_hdf5, only: h5_file_t, h5_open, h5_close, h5_read_particles
  use mpmice_errors, only: int_text
  implicit none
  private

  public :: run_block_cells, point_cells

contains

  !> Collective over `comm`: the cells of each block along x, y, z for `domain_init` (the
  !! `block_cells` layout: leading positive entries, all zero for an even split). With
  !! `restart_file` (not '') the particles are counted in that checkpoint. `report`: for
  !! `balance = 'cost'`, the modelled cost of the blocks and, where several layouts were
  !! compared, of the one `MPI_Dims_create` gives ('' otherwise).
  function run_block_cells(cfg, comm, restart_file, report) result(block_cells)
    type(config_t), intent(in) :: cfg     !< validated configuration
    type(MPI_Comm), intent(in) :: comm    !< communicator of the run
    character(len=*), intent(in), optional :: restart_file  !< checkpoint continued, '' if none
    character(len=*), intent(out), optional :: report  !< what was compared
    integer :: block_cells(max_blocks_per_dim, 3)
    integer :: d, request(3), first(3), nlayouts, k, trial(max_blocks_per_dim, 3)
    integer, allocatable :: layouts(:, :), cell(:, :), hits(:)
    logical :: active(3), given(3)
    real(wp), allocatable :: slabs(:)
    real(wp) :: cost, best, first_cost
    character(len=:), allocatable :: checkpoint

    block_cells = cfg%grid%block_cells
    if (present(report)) report = ''
    if (trim(cfg%grid%balance) /= 'cost') return
    active = cfg%grid%ncells > 1
    request = cfg%grid%dims
    do d = 1, 3
      given(d) = blocks_given(block_cells(:, d)) > 0
      if (given(d)) request(d) = blocks_given(block_cells(:, d))
    end do
    first = choose_dims(comm_size(comm), active, request)
    call block_layouts(comm_size(comm), active, request, cfg%grid%ncells, &
      max(cfg%grid%ghost_width, 1), max_blocks_per_dim, first, layouts, nlayouts)
    if (nlayouts == 1 .and. all(first == 1 .or. given)) return

    checkpoint = ''
    if (present(restart_file)) checkpoint = trim(restart_file)
    if (len(checkpoint) > 0) then
      call checkpoint_particles(cfg, comm, checkpoint, cell, hits)
    else
      call seeded_particles(cfg, comm, cell, hits)
    end if
    allocate(slabs(sum(cfg%grid%ncells)), source=0.0_wp)
    call add_to_slabs(cell, hits, cfg%grid%ncells, slabs)
    call sum_in_place(comm, slabs)

    best = huge(1.0_wp)
    first_cost = 0.0_wp
    do k = 1, nlayouts
      call cut_layout(cfg, layouts(:, k), slabs, trial)
      cost = layout_cost(cfg, comm, layouts(:, k), trial, cell, hits)
      if (k == 1) first_cost = cost
      if (cost < best) then
        best = cost
        block_cells = trial
      end if
    end do
    if (present(report)) then
      report = 'modelled cost ' // int_text(nint(best, i8)) // ' cells per step'
      if (nlayouts > 1) report = trim(report) // ', the least of ' // int_text(nlayouts) // &
        ' layouts (' // int_text(first(1)) // ' x ' // int_text(first(2)) // ' x ' // &
        int_text(first(3)) // ': ' // int_text(nint(first_cost, i8)) // ')'
    end if
  end function run_block_cells

  !> `blocks`: the cells of each block of the layout `dims`: the given `&grid block_cells`
  !! kept, one block of all cells where `dims(d)` = 1, otherwise `balanced_blocks` from the
  !! particles per slab `slabs` (x, then y, then z).
  subroutine cut_layout(cfg, dims, slabs, blocks)
    type(config_t), intent(in) :: cfg          !< validated configuration
    integer, intent(in) :: dims(3)             !< blocks per dimension
    real(wp), intent(in) :: slabs(:)           !< particles per slab, x then y then z
    integer, intent(out) :: blocks(:, :)       !< (max_blocks_per_dim, 3) cells of each block
    real(wp), allocatable :: slab_cells(:)
    integer :: d, offset, n
    blocks = 0
    offset = 0
    do d = 1, 3
      n = cfg%grid%ncells(d)
      if (blocks_given(cfg%grid%block_cells(:, d)) > 0) then
        blocks(:, d) = cfg%grid%block_cells(:, d)
      else if (dims(d) == 1) then
        blocks(1, d) = n
      else
        slab_cells = spread(product(real(cfg%grid%ncells, wp)) / real(n, wp), 1, n)
        call balanced_blocks(slab_cells, slabs(offset + 1:offset + n), &
          cfg%grid%particle_weight, dims(d), max(cfg%grid%ghost_width, 1), blocks(:, d))
      end if
      offset = offset + n
    end do
  end subroutine cut_layout

  !> Collective over `comm`: the modelled step cost of the blocks `blocks` of the layout `dims`,
  !! the most cells of a block + `particle_weight` x the most particles of a block, for this
  !! rank's share `hits(p)` of the particles in the cells `cell(:, p)`.
  function layout_cost(cfg, comm, dims, blocks, cell, hits) result(cost)
    type(config_t), intent(in) :: cfg          !< validated configuration
    type(MPI_Comm), intent(in) :: comm         !< communicator of the run
    integer, intent(in) :: dims(3)             !< blocks per dimension
    integer, intent(in) :: blocks(:, :)        !< (:, 3) cells of each block per dimension
    integer, intent(in) :: cell(:, :)          !< (3, n) global cell indices
    integer, intent(in) :: hits(:)             !< particles in each listed cell
    real(wp) :: cost
    real(wp) :: counts(product(dims)), most_cells
    integer :: d
    call block_particles(cell, hits, dims, blocks, counts)
    call sum_in_place(comm, counts)
    most_cells = 1.0_wp
    do d = 1, 3
      most_cells = most_cells * real(maxval(blocks(1:dims(d), d)), wp)
    end do
    cost = most_cells + cfg%grid%particle_weight * maxval(counts)
  end function layout_cost

  !> This rank's share of the particles the solids of `cfg` seed: `hits(p)` particles in the
  !! cell of global indices `cell(:, p)`, for every `nranks`-th cell of the grid; rigid solids
  !! kept on the grid (`&mpm cache_static_rigid`) are left out, and scenes without particles give
  !! none.
  subroutine seeded_particles(cfg, comm, cell, hits)
    type(config_t), intent(in) :: cfg                  !< validated configuration
    type(MPI_Comm), intent(in) :: comm                 !< communicator of the run
    integer, allocatable, intent(out) :: cell(:, :)    !< (3, n) global cell indices
    integer, allocatable, intent(out) :: hits(:)       !< particles in each listed cell
    integer :: s, rank, nranks, i, j, k, n(3), a, b, c, ppc(3), count, listed
    integer(i8) :: index
    logical :: active(3)
    real(wp) :: lower(3), dx(3), xp(3)

    n = cfg%grid%ncells
    allocate(cell(3, 64), hits(64))
    listed = 0
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
          index = 0
          do k = 1, n(3)
            do j = 1, n(2)
              do i = 1, n(1)
                index = index + 1
                if (mod(index, int(nranks, i8)) /= rank) cycle
                count = 0
                do c = 1, ppc(3)
                  do b = 1, ppc(2)
                    do a = 1, ppc(1)
                      xp = seed_point(lower, dx, [i, j, k], [a, b, c], ppc)
                      if (inside_shape(sp, active, xp)) count = count + 1
                    end do
                  end do
                end do
                if (count > 0) call append(cell, hits, listed, [i, j, k], count)
              end do
            end do
          end do
        end associate
      end do
    end if
    cell = cell(:, 1:listed)
    hits = hits(1:listed)
  end subroutine seeded_particles

  !> Append `hits_here` particles in cell `ijk` to the first `listed` entries of `cell` and
  !! `hits`, doubling their room when full.
  pure subroutine append(cell, hits, listed, ijk, hits_here)
    integer, allocatable, intent(inout) :: cell(:, :)  !< (3, room) global cell indices
    integer, allocatable, intent(inout) :: hits(:)     !< particles in each listed cell
    integer, intent(inout) :: listed                   !< entries in use
    integer, intent(in) :: ijk(3)                      !< the cell
    integer, intent(in) :: hits_here                   !< its particles
    integer, allocatable :: more_cell(:, :), more_hits(:)
    if (listed == size(hits)) then
      allocate(more_cell(3, 2 * listed), more_hits(2 * listed))
      more_cell(:, 1:listed) = cell(:, 1:listed)
      more_hits(1:listed) = hits(1:listed)
      call move_alloc(more_cell, cell)
      call move_alloc(more_hits, hits)
    end if
    listed = listed + 1
    cell(:, listed) = ijk
    hits(listed) = hits_here
  end subroutine append

  !> Collective over `comm`: this rank's chunk of the particles stored in the checkpoint `path`
  !! (`checkpoint/particles/<solid>/x`), one entry per particle (`hits` = 1) in the cell that
  !! holds it (`point_cells`).
  subroutine checkpoint_particles(cfg, comm, path, cell, hits)
    type(config_t), intent(in) :: cfg                  !< configuration of the restart
    type(MPI_Comm), intent(in) :: comm                 !< communicator of the run
    character(len=*), intent(in) :: path               !< checkpoint file
    integer, allocatable, intent(out) :: cell(:, :)    !< (3, n) global cell indices
    integer, allocatable, intent(out) :: hits(:)       !< 1 for each particle
    type(h5_file_t) :: file
    real(wp), allocatable :: x(:, :)
    integer, allocatable :: more(:, :)
    integer :: s

    allocate(cell(3, 0))
    if (trim(cfg%run%scene) == 'mpm' .or. trim(cfg%run%scene) == 'mpmice') then
      call h5_open(file, path, comm)
      do s = 1, cfg%nsolids
        if (kept_on_grid(cfg, cfg%solids(s))) cycle
        call h5_read_particles(file, 'checkpoint/particles/' // trim(cfg%solids(s)%name) // &
          '/x', x)
        call point_cells(x, cfg%grid%ncells, cfg%grid%lower, cfg%grid%upper, more)
        cell = reshape([cell, more], [3, size(cell, 2) + size(more, 2)])
      end do
      call h5_close(file)
    end if
    allocate(hits(size(cell, 2)), source=1)
  end subroutine checkpoint_particles

  !> `cell(:, p)`: the global indices of the cell of a grid of `ncells` cells from `lower` to
  !! `upper` that holds the point `x(:, p)`; a point on a cell boundary is in the upper cell, one
  !! outside the grid in the nearest cell, an inactive dimension has one cell.
  pure subroutine point_cells(x, ncells, lower, upper, cell)
    real(wp), intent(in) :: x(:, :)                    !< points (3, n) [m]
    integer, intent(in) :: ncells(3)                   !< cells per dimension
    real(wp), intent(in) :: lower(3)                   !< low corner [m]
    real(wp), intent(in) :: upper(3)                   !< high corner [m]
    integer, allocatable, intent(out) :: cell(:, :)    !< (3, n) global cell indices
    integer :: p, d
    real(wp) :: dx(3)
    dx = (upper - lower) / real(ncells, wp)
    allocate(cell(3, size(x, 2)), source=1)
    do p = 1, size(x, 2)
      do d = 1, 3
        if (ncells(d) > 1) cell(d, p) = min(max(floor((x(d, p) - lower(d)) / dx(d)) + 1, 1), &
          ncells(d))
      end do
    end do
  end subroutine point_cells

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
