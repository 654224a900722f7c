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
  use parallel_balance, only: balanced_blocks, block_layouts, particle_tally_t, tally_init, &
    tally_add
  use config_types, only: config_t, solid_params_t, particles_per_cell_used, max_blocks_per_dim
  use particles_seeding, only: inside_shape, seed_point
  use mpm_rigid, only: rigid_motion_t, rigid_is_static
  use io_hdf5, only: h5_file_t, h5_open, h5_close, h5_read_particles
  use mpmice_errors, only: int_text
  implicit none
  private

  public :: run_block_cells, point_cell

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
    integer :: d, request(3), first(3), nlayouts, k
    integer, allocatable :: layouts(:, :), blocks(:, :, :)
    logical :: active(3), given(3)
    real(wp) :: cost, best, first_cost, most_cells
    character(len=:), allocatable :: checkpoint
    type(particle_tally_t) :: per_slab, per_block

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
    if (nlayouts == 0) return   ! input validation refuses such a run
    if (nlayouts == 1 .and. all(layouts(:, 1) == 1 .or. given)) return

    checkpoint = ''
    if (present(restart_file)) checkpoint = trim(restart_file)
    ! the cuts of every layout from the particles per slab, then the particles of its blocks
    call tally_init(per_slab, cfg%grid%ncells)
    call count_particles(cfg, comm, checkpoint, per_slab)
    call sum_in_place(comm, per_slab%slabs)
    allocate(blocks(max_blocks_per_dim, 3, nlayouts))
    do k = 1, nlayouts
      call cut_layout(cfg, layouts(:, k), per_slab%slabs, blocks(:, :, k))
    end do
    call tally_init(per_block, cfg%grid%ncells, layouts(:, 1:nlayouts), blocks)
    call count_particles(cfg, comm, checkpoint, per_block)

    best = huge(1.0_wp)
    first_cost = 0.0_wp
    do k = 1, nlayouts
      call sum_in_place(comm, per_block%per_block(:, k))
      most_cells = 1.0_wp
      do d = 1, 3
        most_cells = most_cells * real(maxval(blocks(1:layouts(d, k), d, k)), wp)
      end do
      cost = most_cells + cfg%grid%particle_weight * maxval(per_block%per_block(:, k))
      if (k == 1) first_cost = cost
      if (cost < best) then
        best = cost
        block_cells = blocks(:, :, k)
      end if
    end do
    if (present(report)) then
      report = 'modelled cost ' // int_text(nint(best, i8)) // ' cells per step'
      if (nlayouts > 1) report = trim(report) // ', the least of ' // int_text(nlayouts) // &
        ' layouts (' // int_text(layouts(1, 1)) // ' x ' // int_text(layouts(2, 1)) // ' x ' // &
        int_text(layouts(3, 1)) // ': ' // int_text(nint(first_cost, i8)) // ')'
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

  !> Collective over `comm`: add this rank's share of the particles to `tally`: with
  !! `checkpoint` ('' for none) a chunk of the positions stored there
  !! (`checkpoint/particles/<solid>/x`), one particle in the cell that holds it (`point_cell`);
  !! otherwise the particles the solids of `cfg` seed into every `nranks`-th cell of the grid.
  !! Rigid solids kept on the grid (`&mpm cache_static_rigid`) are left out, and scenes without
  !! particles add none.
  subroutine count_particles(cfg, comm, checkpoint, tally)
    type(config_t), intent(in) :: cfg                  !< validated configuration
    type(MPI_Comm), intent(in) :: comm                 !< communicator of the run
    character(len=*), intent(in) :: checkpoint         !< checkpoint file, '' for the seeding
    type(particle_tally_t), intent(inout) :: tally     !< counts to add to
    type(h5_file_t) :: file
    real(wp), allocatable :: x(:, :)
    integer :: s, p

    if (trim(cfg%run%scene) /= 'mpm' .and. trim(cfg%run%scene) /= 'mpmice') return
    if (len(checkpoint) == 0) then
      do s = 1, cfg%nsolids
        if (.not. kept_on_grid(cfg, cfg%solids(s))) call count_seeded(cfg, comm, &
          cfg%solids(s), tally)
      end do
      return
    end if
    call h5_open(file, checkpoint, comm)
    do s = 1, cfg%nsolids
      if (kept_on_grid(cfg, cfg%solids(s))) cycle
      call h5_read_particles(file, 'checkpoint/particles/' // trim(cfg%solids(s)%name) // &
        '/x', x)
      do p = 1, size(x, 2)
        call tally_add(tally, point_cell(x(:, p), cfg%grid%ncells, cfg%grid%lower, &
          cfg%grid%upper), 1)
      end do
    end do
    call h5_close(file)
  end subroutine count_particles

  !> Add to `tally` the particles the solid `sp` seeds into every `nranks`-th cell of the grid
  !! of `cfg` (this rank's share): the centres of the equal sub-cells that lie inside its shape,
  !! the arithmetic and the shape test of `particles_seeding%seed_solid`.
  subroutine count_seeded(cfg, comm, sp, tally)
    type(config_t), intent(in) :: cfg                  !< validated configuration
    type(MPI_Comm), intent(in) :: comm                 !< communicator of the run
    type(solid_params_t), intent(in) :: sp             !< the solid
    type(particle_tally_t), intent(inout) :: tally     !< counts to add to
    integer :: rank, nranks, i, j, k, n(3), a, b, c, ppc(3), hits
    integer(i8) :: index
    logical :: active(3)
    real(wp) :: lower(3), dx(3), xp(3)

    n = cfg%grid%ncells
    rank = comm_rank(comm)
    nranks = comm_size(comm)
    active = n > 1
    lower = cfg%grid%lower
    dx = (cfg%grid%upper - cfg%grid%lower) / real(n, wp)
    ppc = particles_per_cell_used(sp, n)
    index = 0
    do k = 1, n(3)
      do j = 1, n(2)
        do i = 1, n(1)
          index = index + 1
          if (mod(index, int(nranks, i8)) /= rank) cycle
          hits = 0
          do c = 1, ppc(3)
            do b = 1, ppc(2)
              do a = 1, ppc(1)
                xp = seed_point(lower, dx, [i, j, k], [a, b, c], ppc)
                if (inside_shape(sp, active, xp)) hits = hits + 1
              end do
            end do
          end do
          if (hits > 0) call tally_add(tally, [i, j, k], hits)
        end do
      end do
    end do
  end subroutine count_seeded

  !> The global indices of the cell of a grid of `ncells` cells from `lower` to `upper` that
  !! holds the point `x`; a point on a cell boundary is in the upper cell, one outside the grid
  !! in the nearest cell, an inactive dimension has one cell.
  pure function point_cell(x, ncells, lower, upper) result(cell)
    real(wp), intent(in) :: x(3)                       !< point [m]
    integer, intent(in) :: ncells(3)                   !< cells per dimension
    real(wp), intent(in) :: lower(3)                   !< low corner [m]
    real(wp), intent(in) :: upper(3)                   !< high corner [m]
    integer :: cell(3)
    integer :: d
    real(wp) :: dx
    cell = 1
    do d = 1, 3
      if (ncells(d) < 2) cycle
      dx = (upper(d) - lower(d)) / real(ncells(d), wp)
      cell(d) = min(max(floor((x(d) - lower(d)) / dx) + 1, 1), ncells(d))
    end do
  end function point_cell

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
