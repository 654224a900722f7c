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
!! share the ranks among the active dimensions, and `block_particles` counts the particles each
!! block of one layout holds, so that the caller can keep the layout of least F.
module parallel_balance
  use mpmice_kinds, only: wp
  implicit none
  private

  public :: balanced_blocks, modelled_cost, quantile_blocks, block_layouts, block_particles, &
    add_to_slabs

  integer, parameter :: blend_steps = 64  !< blends a tried for more than two blocks

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
  !! `first` first (the layout `MPI_Dims_create` gives), then the others in lexicographic order.
  !! A layout keeps one block along an inactive dimension and `request(d)` along a dimension
  !! where that is positive; along every other dimension it has at most `max_blocks` blocks of at
  !! least `min_cells` cells. `first` is kept as given.
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
    integer :: a, b, dims(3), d, room
    logical :: fits

    room = 1
    do a = 1, nranks
      if (mod(nranks, a) == 0) room = room + nranks / a
    end do
    allocate(layouts(3, room))
    layouts(:, 1) = first
    nlayouts = 1
    do a = 1, nranks
      if (mod(nranks, a) /= 0) cycle
      do b = 1, nranks / a
        if (mod(nranks / a, b) /= 0) cycle
        dims = [a, b, nranks / (a * b)]
        if (all(dims == first)) cycle
        fits = .true.
        do d = 1, 3
          if (.not. active(d)) then
            fits = fits .and. dims(d) == 1
          else if (request(d) > 0) then
            fits = fits .and. dims(d) == request(d)
          else
            fits = fits .and. dims(d) <= max_blocks .and. ncells(d) >= dims(d) * min_cells
          end if
        end do
        if (.not. fits) cycle
        nlayouts = nlayouts + 1
        layouts(:, nlayouts) = dims
      end do
    end do
  end subroutine block_layouts

  !> `counts(b)`: the particles in block b of the layout `dims` (blocks numbered x fastest, then
  !! y, then z), whose blocks along dimension d hold `blocks(1:dims(d), d)` cells, for `hits(p)`
  !! particles in the cell of global indices `cell(:, p)`.
  pure subroutine block_particles(cell, hits, dims, blocks, counts)
    integer, intent(in) :: cell(:, :)          !< (3, n) global cell indices
    integer, intent(in) :: hits(:)             !< particles in each listed cell
    integer, intent(in) :: dims(3)             !< blocks per dimension
    integer, intent(in) :: blocks(:, :)        !< (:, 3) cells of each block per dimension
    real(wp), intent(out) :: counts(:)         !< particles per block (size product(dims))
    integer, allocatable :: owner_x(:), owner_y(:), owner_z(:)
    integer :: p

    call block_owner(blocks(1:dims(1), 1), owner_x)
    call block_owner(blocks(1:dims(2), 2), owner_y)
    call block_owner(blocks(1:dims(3), 3), owner_z)
    counts = 0.0_wp
    do p = 1, size(hits)
      associate (b => 1 + owner_x(cell(1, p)) + dims(1) * (owner_y(cell(2, p)) + &
          dims(2) * owner_z(cell(3, p))))
        counts(b) = counts(b) + real(hits(p), wp)
      end associate
    end do
  end subroutine block_particles

  !> `owner(i)`: the 0-based block holding cell i of a dimension cut into blocks of
  !! `blocks(:)` cells.
  pure subroutine block_owner(blocks, owner)
    integer, intent(in) :: blocks(:)                 !< cells of each block, low block first
    integer, allocatable, intent(out) :: owner(:)    !< block of each cell
    integer :: b, last
    allocate(owner(sum(blocks)))
    last = 0
    do b = 1, size(blocks)
      owner(last + 1:last + blocks(b)) = b - 1
      last = last + blocks(b)
    end do
  end subroutine block_owner

  !> Add `hits(p)` particles in the cells `cell(:, p)` to the slab counts `counts` (x, then y,
  !! then z slabs of a grid of `ncells` cells).
  pure subroutine add_to_slabs(cell, hits, ncells, counts)
    integer, intent(in) :: cell(:, :)          !< (3, n) global cell indices
    integer, intent(in) :: hits(:)             !< particles in each listed cell
    integer, intent(in) :: ncells(3)           !< cells per dimension
    real(wp), intent(inout) :: counts(:)       !< particles per slab, x then y then z
    integer :: p
    do p = 1, size(hits)
      counts(cell(1, p)) = counts(cell(1, p)) + real(hits(p), wp)
      counts(ncells(1) + cell(2, p)) = counts(ncells(1) + cell(2, p)) + real(hits(p), wp)
      counts(ncells(1) + ncells(2) + cell(3, p)) = counts(ncells(1) + ncells(2) + cell(3, p)) &
        + real(hits(p), wp)
    end do
  end subroutine add_to_slabs
end module parallel_balance
