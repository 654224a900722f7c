!> The owned cells of a block as the flat box buffer hypre's Struct interface reads and writes
!! (i fastest), and the check that a cell array has the grid's cell bounds.
module solver_box
  use, intrinsic :: iso_c_binding, only: c_double
  use mpmice_kinds, only: wp
  use mpmice_errors, only: fatal
  use grid_layout, only: grid_t
  implicit none
  private

  public :: check_bounds, pack_owned, unpack_owned

contains

  !> Abort unless a cell array covers the grid's cell allocation bounds.
  subroutine check_bounds(grid, upper, name)
    type(grid_t), intent(in) :: grid      !< block geometry
    integer, intent(in) :: upper(3)       !< upper bounds of the array
    character(len=*), intent(in) :: name  !< argument name (for the message)
    if (any(upper < grid%ubc)) call fatal('struct solver: array ' // name // &
      ' does not have the cell allocation bounds of the grid')
  end subroutine check_bounds

  !> Copy the owned cells of a cell array into a hypre box buffer (i fastest), one row of
  !! cells at a time (no temporary).
  subroutine pack_owned(grid, field, buffer)
    type(grid_t), intent(in) :: grid                                        !< block geometry
    real(wp), intent(in) :: field(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !< cell array
    real(c_double), intent(out) :: buffer(:)                                !< owned values
    integer :: j, k, m, row
    row = grid%hi(1) - grid%lo(1) + 1
    m = 0
    do k = grid%lo(3), grid%hi(3)
      do j = grid%lo(2), grid%hi(2)
        buffer(m + 1:m + row) = real(field(grid%lo(1):grid%hi(1), j, k), c_double)
        m = m + row
      end do
    end do
  end subroutine pack_owned

  !> Copy a hypre box buffer back into the owned cells of a cell array (`pack_owned`'s order).
  subroutine unpack_owned(grid, buffer, field)
    type(grid_t), intent(in) :: grid                                           !< block geometry
    real(c_double), intent(in) :: buffer(:)                                    !< owned values
    real(wp), intent(inout) :: field(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !< cell array
    integer :: j, k, m, row
    row = grid%hi(1) - grid%lo(1) + 1
    do k = grid%lo(3), grid%hi(3)
      do j = grid%lo(2), grid%hi(2)
        m = (j - grid%lo(2) + (k - grid%lo(3)) * (grid%hi(2) - grid%lo(2) + 1)) * row
        field(grid%lo(1):grid%hi(1), j, k) = real(buffer(m + 1:m + row), wp)
      end do
    end do
  end subroutine unpack_owned
end module solver_box
