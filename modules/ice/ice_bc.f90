!> Ghost cells of the ICE fields on non-periodic domain boundaries (walls): scalars are mirrored
!! (zero normal gradient), the normal velocity component is mirrored with a sign change (zero
!! normal velocity at the wall; tangential components mirrored: free slip). Called after the halo
!! exchange; the dimensions are filled in order x, y, z over the full extent of the others so that
!! edges and corners beyond a wall are filled too.
module ice_bc
  use mpmice_kinds, only: wp
  use grid_layout, only: grid_t
  implicit none
  private

  public :: ice_bc_fill

contains

  !> Fill the wall ghosts of `field`; `normal_component` = d makes the field odd across the
  !! faces normal to direction d (velocity component d), 0 keeps it even.
  subroutine ice_bc_fill(grid, field, normal_component)
    type(grid_t), intent(in) :: grid          !< block geometry
    real(wp), intent(inout) :: field(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !< cell field
    integer, intent(in) :: normal_component   !< 0 or the velocity component 1..3
    integer :: d, g, lo, hi
    real(wp) :: s

    do d = 1, 3
      if (.not. grid%active(d) .or. grid%periodic(d)) cycle
      s = 1.0_wp
      if (normal_component == d) s = -1.0_wp
      lo = grid%lo(d)
      hi = grid%hi(d)
      do g = 1, grid%ng(d)
        select case (d)
        case (1)
          if (grid%at_lower(1)) field(lo - g, :, :) = s * field(lo + g - 1, :, :)
          if (grid%at_upper(1)) field(hi + g, :, :) = s * field(hi - g + 1, :, :)
        case (2)
          if (grid%at_lower(2)) field(:, lo - g, :) = s * field(:, lo + g - 1, :)
          if (grid%at_upper(2)) field(:, hi + g, :) = s * field(:, hi - g + 1, :)
        case default
          if (grid%at_lower(3)) field(:, :, lo - g) = s * field(:, :, lo + g - 1)
          if (grid%at_upper(3)) field(:, :, hi + g) = s * field(:, :, hi - g + 1)
        end select
      end do
    end do
  end subroutine ice_bc_fill
end module ice_bc
