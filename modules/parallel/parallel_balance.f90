!> Block boundaries along one dimension from a cost per slab (`&grid balance = 'cost'`).
!!
!! A slab is the layer of cells with one index along the dimension; its cost is the work a rank
!! has for it per step, e.g. cells + w x particles. The blocks are contiguous runs of slabs; the
!! k-th boundary is put where the prefix sum of the cost is nearest to k/n of the total (the
!! quantile cut: for two blocks the cut that minimises the larger block's cost), then moved,
!! where needed, so that every block keeps at least `min_cells` slabs. The arithmetic uses only
!! its arguments, so every rank that passes the same costs gets the same blocks.
module parallel_balance
  use mpmice_kinds, only: wp
  implicit none
  private

  public :: balanced_blocks

contains

  !> `cells(1:nblocks)`: the slabs of each block, low block first, for slab costs `cost(1:n)`
  !! (>= 0). Requires n >= nblocks * min_cells. A total cost of zero gives the even quantiles
  !! of the slab count.
  pure subroutine balanced_blocks(cost, nblocks, min_cells, cells)
    real(wp), intent(in) :: cost(:)      !< cost of each slab (>= 0)
    integer, intent(in) :: nblocks       !< number of blocks (>= 1)
    integer, intent(in) :: min_cells     !< fewest slabs a block may hold (>= 1)
    integer, intent(out) :: cells(:)     !< slabs of each block (size >= nblocks)
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
    cells = 0
    do k = 1, nblocks
      cells(k) = cut(k) - cut(k - 1)
    end do
  end subroutine balanced_blocks
end module parallel_balance
