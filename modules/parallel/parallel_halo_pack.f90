!> Packing kernels of the halo exchange: copy a box of a cell or node field
!! `(component, i, j, k)` (a scalar field is one component) into a contiguous buffer and back
!! (copy or add).
!!
!! A box is `box(1:2, 1:3)`: first (`box(1, d)`) and last (`box(2, d)`) global index along each
!! dimension d. Buffers are ordered with the leftmost index fastest (component, i, j, k), so the
!! sender and the receiver of a message agree on the order without any metadata.
module parallel_halo_pack
  use mpmice_kinds, only: wp
  implicit none
  private

  public :: box_size, pack_box, unpack_box

contains

  !> Number of points in `box` (0 when empty along any dimension).
  pure function box_size(box) result(n)
    integer, intent(in) :: box(2, 3)  !< first/last index per dimension
    integer :: n
    n = max(0, box(2, 1) - box(1, 1) + 1) * max(0, box(2, 2) - box(1, 2) + 1) &
      * max(0, box(2, 3) - box(1, 3) + 1)
  end function box_size

  !> Copy `field(1:ncomp, box)` into `buf(1:ncomp*box_size(box))`; zero it afterwards when `clear`.
  subroutine pack_box(field, lb, box, buf, clear)
    integer, intent(in) :: lb(3)                                   !< lower bounds of dims 2..4
    real(wp), intent(inout) :: field(:, lb(1):, lb(2):, lb(3):)    !< field (component, i, j, k)
    integer, intent(in) :: box(2, 3)                               !< box to pack
    real(wp), intent(inout) :: buf(:)                              !< contiguous buffer
    logical, intent(in) :: clear                                   !< zero the box after packing
    integer :: c, i, j, k, n, ncomp
    ncomp = size(field, 1)
    n = 0
    do k = box(1, 3), box(2, 3)
      do j = box(1, 2), box(2, 2)
        do i = box(1, 1), box(2, 1)
          do c = 1, ncomp
            n = n + 1
            buf(n) = field(c, i, j, k)
          end do
        end do
      end do
    end do
    if (clear) field(:, box(1, 1):box(2, 1), box(1, 2):box(2, 2), box(1, 3):box(2, 3)) = 0.0_wp
  end subroutine pack_box

  !> Copy `buf` into `field(1:ncomp, box)`, or add it when `add`.
  subroutine unpack_box(field, lb, box, buf, add)
    integer, intent(in) :: lb(3)                                   !< lower bounds of dims 2..4
    real(wp), intent(inout) :: field(:, lb(1):, lb(2):, lb(3):)    !< field (component, i, j, k)
    integer, intent(in) :: box(2, 3)                               !< box to fill
    real(wp), intent(in) :: buf(:)                                 !< received buffer
    logical, intent(in) :: add                                     !< accumulate instead of copy
    integer :: c, i, j, k, n, ncomp
    ncomp = size(field, 1)
    n = 0
    if (add) then
      do k = box(1, 3), box(2, 3)
        do j = box(1, 2), box(2, 2)
          do i = box(1, 1), box(2, 1)
            do c = 1, ncomp
              n = n + 1
              field(c, i, j, k) = field(c, i, j, k) + buf(n)
            end do
          end do
        end do
      end do
    else
      do k = box(1, 3), box(2, 3)
        do j = box(1, 2), box(2, 2)
          do i = box(1, 1), box(2, 1)
            do c = 1, ncomp
              n = n + 1
              field(c, i, j, k) = buf(n)
            end do
          end do
        end do
      end do
    end if
  end subroutine unpack_box
end module parallel_halo_pack
