!> Geometry and index ranges of a rank's block of the uniform Cartesian grid (filled from the
!! decomposition by `parallel_domain%grid_init`).
!!
!! Conventions (all indices are global, 1-based; arrays are always rank 3 `(i,j,k)`):
!! * cell `i` spans `[lower + (i-1) dx, lower + i dx]`; owned cells `lo..hi`; cell fields are
!!   allocated `lbc..ubc` = `lo-ng .. hi+ng` (ng = 0 in inactive dimensions);
!! * node `i` sits at `lower + (i-1) dx`, nodes `1..ncells+1` in active dimensions and node 1 only in
!!   inactive ones. A block owns nodes `nlo..nhi` = `lo..hi`, plus node `ncells+1` on the last block
!!   of a non-periodic dimension (in a periodic one node `ncells+1` is node 1). Node fields are
!!   allocated `lbn..ubn` = `lo-ng .. hi+1+ng`: the node `hi+1` of an inner block is a ghost copy;
!! * face `i` in direction d is the low face of cell `i`, faces `1..ncells+1`; a face is owned like
!!   the node of the same index; face fields use the node bounds in direction d and the cell
!!   bounds in the other two.
module grid_layout
  use mpmice_kinds, only: wp
  implicit none
  private

  public :: grid_t, cell_centre, node_position, clamped_cell

  !> Geometry and index ranges of one block.
  type :: grid_t
    integer :: ndim = 0                 !< number of active dimensions
    logical :: active(3) = .false.      !< active dimensions (more than one cell)
    logical :: periodic(3) = .false.    !< periodic dimensions
    integer :: ncells(3) = 1            !< global cells per dimension
    real(wp) :: lower(3) = 0.0_wp       !< low corner of the domain [m]
    real(wp) :: upper(3) = 1.0_wp       !< high corner of the domain [m]
    real(wp) :: dx(3) = 1.0_wp          !< cell size [m]
    real(wp) :: cell_volume = 1.0_wp    !< dx(1) dx(2) dx(3) [m^3]
    integer :: ng(3) = 0                !< ghost width per dimension
    integer :: lo(3) = 1                !< first owned cell
    integer :: hi(3) = 1                !< last owned cell
    integer :: lbc(3) = 1               !< lower allocation bound of cell fields
    integer :: ubc(3) = 1               !< upper allocation bound of cell fields
    integer :: nlo(3) = 1               !< first owned node
    integer :: nhi(3) = 1               !< last owned node
    integer :: lbn(3) = 1               !< lower allocation bound of node fields
    integer :: ubn(3) = 1               !< upper allocation bound of node fields
    logical :: at_lower(3) = .false.    !< block touches the low boundary of the domain
    logical :: at_upper(3) = .false.    !< block touches the high boundary of the domain
  end type grid_t

contains

  !> Coordinate [m] of the centre of cell `i` along dimension `d`.
  pure elemental function cell_centre(grid, d, i) result(x)
    type(grid_t), intent(in) :: grid  !< block geometry
    integer, intent(in) :: d          !< dimension 1..3
    integer, intent(in) :: i          !< global cell index
    real(wp) :: x
    x = grid%lower(d) + (real(i, wp) - 0.5_wp) * grid%dx(d)
  end function cell_centre

  !> Coordinate [m] of node `i` along dimension `d`.
  pure elemental function node_position(grid, d, i) result(x)
    type(grid_t), intent(in) :: grid  !< block geometry
    integer, intent(in) :: d          !< dimension 1..3
    integer, intent(in) :: i          !< global node index
    real(wp) :: x
    x = grid%lower(d) + real(i - 1, wp) * grid%dx(d)
  end function node_position

  !> Global indices of the cell that holds the point `x` (a point on a cell boundary is in the
  !! upper cell), each clamped to `first(d)..last(d)` (e.g. the owned cells `lo..hi`, or
  !! `lbc..ubc` with the ghosts); 1 along an inactive dimension.
  pure function clamped_cell(grid, x, first, last) result(c)
    type(grid_t), intent(in) :: grid  !< block geometry
    real(wp), intent(in) :: x(3)      !< point [m]
    integer, intent(in) :: first(3)   !< lowest index returned per dimension
    integer, intent(in) :: last(3)    !< highest index returned per dimension
    integer :: c(3)
    integer :: d
    c = 1
    do d = 1, 3
      if (grid%active(d)) c(d) = min(max(floor((x(d) - grid%lower(d)) / grid%dx(d)) + 1, &
        first(d)), last(d))
    end do
  end function clamped_cell
end module grid_layout
