!> Block boundaries along one dimension from the work per slab (`&grid balance = 'cost'`).
!!
!! A slab is the layer of cells with one index along the dimension. A step's stages end in halo
!! exchanges or collectives, and the fluid stages (work per cell) and the particle stages (work
!! per particle) are separate stages, so each waits for its own busiest rank. The modelled cost of
!! a step on blocks b is therefore
!!
!!     F = max_b C_b + w max_b P_b,
!!
!! C_b the cells and P_b the particles of block b, w the cost of a particle in cells' worth of
!! fluid work (docs/performance.md "Balancing the particles"). Two blocks: every cut is tried and
!! the one of least F kept. More blocks: the cuts where the prefix sum of (1 - a) C / C_total +
!! a P / P_total is nearest to k/p of the total, for a = 0, 1/64, ..., 1 (a = 0: the cells split
!! evenly, a = 1: the particles), the set of least F kept. Every block keeps at least
!! `min_cells` slabs. Ties keep the first candidate (the lower cut, the smaller a). The arithmetic
!! uses only the arguments, so every rank that passes the same counts gets the same blocks.
!!
!! Where the blocks per dimension are not fixed by the input, `block_layouts` lists every way to
!! share the ranks among the active dimensions, and a `particle_tally_t` counts the particles
!! each block of every layout holds, so that the caller can keep the layout of least F; the
!! tally holds counts per slab and per block only, not the particles, so it fits any scene.
module parallel_balance
  use mpmice_kinds, only: wp
  implicit none
  private

  public :: balanced_blocks, modelled_cost, quantile_blocks, block_layouts
  public :: particle_tally_t, tally_init, tally_add

  integer, parameter :: blend_steps = 64  !< blends a tried for more than two blocks

  !> Particles counted per slab (the cells with one index along a dimension: x slabs, then y,
  !! then z) and, where layouts are given, per block of each layout.
  type :: particle_tally_t
    integer :: ncells(3) = 1                   !< cells per dimension
    real(wp), allocatable :: slabs(:)          !< particles per slab, x then y then z
    integer, allocatable :: dims(:, :)         !< (3, nlayouts) blocks per dimension
    !> (slab, layout): the 0-based block coordinate of each slab along its dimension
    integer, allocatable :: owner(:, :)
    !> (block, layout): particles per block, blocks numbered x fastest, then y, then z
    real(wp), allocatable :: per_block(:, :)
  end type particle_tally_t

contains

  !> `blocks(1:nblocks)`: the slabs of each block, low block first, that minimise the modelled
  !! cost F for slabs of `cells(i)` cells and `particles(i)` particles (both >= 0). Requires
  !! size(cells) >= nblocks * min_cells.
  pure subroutine balanced_blocks(cells, particles, weight, nblocks, min_cells, blocks)
    real(wp), intent(in) :: cells(:)      !< cells of each slab
    real(wp), intent(in) :: particles(:)  !< particles of each slab
    real(wp), intent(in) :: weight        !< w: a particle's cost in cells (>= 0)
    integer, intent(in) :: nblocks        !< number of blocks (>= 1)
    integer, intent(in) :: min_cells      !< fewest slabs a block may hold (>= 1)
    integer, intent(out) :: blocks(:)     !< slabs of each block (size >= nblocks)
    real(wp) :: share(size(cells)), best, f, a, cell_total, particle_total
    integer :: n, c, step, trial(nblocks)

    n = size(cells)
    blocks = 0
    if (nblocks == 1) then
      blocks(1) = n
      return
    end if
    best = huge(1.0_wp)
    if (nblocks == 2) then
      do c = min_cells, n - min_cells
        f = modelled_cost(cells, particles, weight, [c, n - c])
        if (f < best) then
          best = f
          blocks(1:2) = [c, n - c]
        end if
      end do
      return
    end if
    cell_total = max(sum(cells), tiny(1.0_wp))
    particle_total = sum(particles)
    do step = 0, blend_steps
      if (step > 0 .and. .not. particle_total > 0.0_wp) exit
      a = real(step, wp) / real(blend_steps, wp)
      share = (1.0_wp - a) * cells / cell_total
      if (step > 0) share = share + a * particles / particle_total
      call quantile_blocks(share, nblocks, min_cells, trial)
      f = modelled_cost(cells, particles, weight, trial)
      if (f < best) then
        best = f
        blocks(1:nblocks) = trial
      end if
    end do
  end subroutine balanced_blocks

  !> F = max_b C_b + w max_b P_b of the blocks `blocks` (slabs of each, tiling the slabs).
  pure real(wp) function modelled_cost(cells, particles, weight, blocks) result(f)
    real(wp), intent(in) :: cells(:)      !< cells of each slab
    real(wp), intent(in) :: particles(:)  !< particles of each slab
    real(wp), intent(in) :: weight        !< w: a particle's cost in cells
    integer, intent(in) :: blocks(:)      !< slabs of each block, low block first
    real(wp) :: most_cells, most_particles
    integer :: b, first, last
    most_cells = 0.0_wp
    most_particles = 0.0_wp
    last = 0
    do b = 1, size(blocks)
      first = last + 1
      last = last + blocks(b)
      most_cells = max(most_cells, sum(cells(first:last)))
      most_particles = max(most_particles, sum(particles(first:last)))
    end do
    f = most_cells + weight * most_particles
  end function modelled_cost

  !> `blocks(1:nblocks)`: the k-th boundary where the prefix sum of `cost` is nearest to k /
  !! nblocks of its total (ties: the upper boundary), moved where needed so that every block keeps
  !! `min_cells` slabs. A total of zero gives the even quantiles of the slab count.
  pure subroutine quantile_blocks(cost, nblocks, min_cells, blocks)
    real(wp), intent(in) :: cost(:)      !< cost of each slab (>= 0)
    integer, intent(in) :: nblocks       !< number of blocks (>= 1)
    integer, intent(in) :: min_cells     !< fewest slabs a block may hold (>= 1)
    integer, intent(out) :: blocks(:)    !< slabs of each block (size >= nblocks)
    real(wp) :: prefix(0:size(cost)), target
    integer :: n, i, k, cut(0:nblocks)

    n = size(cost)
    prefix(0) = 0.0_wp
    do i = 1, n
      prefix(i) = prefix(i - 1) + cost(i)
    end do
    if (.not. prefix(n) > 0.0_wp) then
      do i = 1, n
        prefix(i) = real(i, wp)
      end do
    end if

    cut(0) = 0
    cut(nblocks) = n
    do k = 1, nblocks - 1
      target = prefix(n) * real(k, wp) / real(nblocks, wp)
      ! first slab boundary at or above the target, or the one below when that is nearer
      i = 1
      do while (i < n .and. prefix(i) < target)
        i = i + 1
      end do
      if (target - prefix(i - 1) < prefix(i) - target) i = i - 1
      ! keep min_cells slabs for this block and for each block after it
      cut(k) = min(max(i, cut(k - 1) + min_cells), n - (nblocks - k) * min_cells)
    end do
    blocks = 0
    do k = 1, nblocks
      blocks(k) = cut(k) - cut(k - 1)
    end do
  end subroutine quantile_blocks

  !> `layouts(:, 1:nlayouts)`: the blocks per dimension (x, y, z) whose product is `nranks`,
  !! `first` first (the layout `MPI_Dims_create` gives) where it fits, then the others in
  !! lexicographic order. A layout fits when it keeps one block along an inactive dimension and
  !! `request(d)` along a dimension where that is positive, and along every other dimension at
  !! most `max_blocks` blocks of at least `min_cells` cells. None fits: `nlayouts` = 0.
  pure subroutine block_layouts(nranks, active, request, ncells, min_cells, max_blocks, first, &
      layouts, nlayouts)
    integer, intent(in) :: nranks                  !< number of ranks (>= 1)
    logical, intent(in) :: active(3)               !< dimensions with more than one cell
    integer, intent(in) :: request(3)              !< blocks fixed per dimension (0: free)
    integer, intent(in) :: ncells(3)               !< cells per dimension
    integer, intent(in) :: min_cells               !< fewest cells of a block (>= 1)
    integer, intent(in) :: max_blocks              !< most blocks along one dimension
    integer, intent(in) :: first(3)                !< the layout listed first
    integer, allocatable, intent(out) :: layouts(:, :)  !< (3, nlayouts) blocks per dimension
    integer, intent(out) :: nlayouts               !< layouts listed
    integer :: a, b, dims(3), room

    room = 1
    do a = 1, nranks
      if (mod(nranks, a) == 0) room = room + nranks / a
    end do
    allocate(layouts(3, room))
    nlayouts = 0
    if (fits(first)) then
      nlayouts = 1
      layouts(:, 1) = first
    end if
    do a = 1, nranks
      if (mod(nranks, a) /= 0) cycle
      do b = 1, nranks / a
        if (mod(nranks / a, b) /= 0) cycle
        dims = [a, b, nranks / (a * b)]
        if (all(dims == first) .or. .not. fits(dims)) cycle
        nlayouts = nlayouts + 1
        layouts(:, nlayouts) = dims
      end do
    end do

  contains

    pure logical function fits(blocks)
      integer, intent(in) :: blocks(3)   !< blocks per dimension
      integer :: d
      fits = product(blocks) == nranks
      do d = 1, 3
        if (.not. active(d)) then
          fits = fits .and. blocks(d) == 1
        else if (request(d) > 0) then
          fits = fits .and. blocks(d) == request(d)
        else
          fits = fits .and. blocks(d) <= max_blocks .and. ncells(d) >= blocks(d) * min_cells
        end if
      end do
    end function fits
  end subroutine block_layouts

  !> A tally ready for `tally_add`: per slab of a grid of `ncells` cells (`slabs`), and, with
  !! `dims` and `blocks`, per block of each layout k, whose blocks along dimension d hold
  !! `blocks(1:dims(d, k), d, k)` cells (`per_block`, blocks numbered x fastest, then y, then z).
  pure subroutine tally_init(tally, ncells, dims, blocks)
    type(particle_tally_t), intent(out) :: tally     !< tally to set up, all counts 0
    integer, intent(in) :: ncells(3)                 !< cells per dimension
    integer, intent(in), optional :: dims(:, :)      !< (3, nlayouts) blocks per dimension
    integer, intent(in), optional :: blocks(:, :, :) !< (:, 3, nlayouts) cells of each block
    integer :: k, d, b, first
    tally%ncells = ncells
    allocate(tally%slabs(sum(ncells)), source=0.0_wp)
    if (.not. present(dims)) return
    tally%dims = dims
    allocate(tally%owner(sum(ncells), size(dims, 2)))
    do k = 1, size(dims, 2)
      first = 0
      do d = 1, 3
        do b = 1, dims(d, k)
          tally%owner(first + 1:first + blocks(b, d, k), k) = b - 1
          first = first + blocks(b, d, k)
        end do
      end do
    end do
    allocate(tally%per_block(maxval(product(dims, dim=1)), size(dims, 2)), source=0.0_wp)
  end subroutine tally_init

  !> Add `hits` particles in the cell of global indices `cell` to `tally`.
  pure subroutine tally_add(tally, cell, hits)
    type(particle_tally_t), intent(inout) :: tally  !< tally (`tally_init`)
    integer, intent(in) :: cell(3)                  !< global cell indices
    integer, intent(in) :: hits                     !< particles in the cell
    integer :: k, slab(3), b
    slab = [cell(1), tally%ncells(1) + cell(2), tally%ncells(1) + tally%ncells(2) + cell(3)]
    tally%slabs(slab) = tally%slabs(slab) + real(hits, wp)
    if (.not. allocated(tally%dims)) return
    do k = 1, size(tally%dims, 2)
      b = 1 + tally%owner(slab(1), k) + tally%dims(1, k) * (tally%owner(slab(2), k) + &
        tally%dims(2, k) * tally%owner(slab(3), k))
      tally%per_block(b, k) = tally%per_block(b, k) + real(hits, wp)
    end do
  end subroutine tally_add
end module parallel_balance
