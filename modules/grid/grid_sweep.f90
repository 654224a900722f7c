!> Sweeps of the grid one direction at a time: the unit offset of a direction and the area of its
!! faces, so that a loop over the active directions reads
!!
!!     do d = 1, 3
!!       if (.not. sweep_direction(grid, d, o, area)) cycle
!!       ... cell (i,j,k), its low face (i,j,k) and its neighbours (i,j,k) -/+ o ...
!!
!! (face `i` in direction d is the low face of cell `i`, `grid_layout`).
module grid_sweep
  use mpmice_kinds, only: wp
  use grid_layout, only: grid_t
  implicit none
  private

  public :: sweep_direction, unit_offset

contains

  !> Unit offset of direction `d`: cell (i,j,k) + o is the high neighbour along d.
  pure function unit_offset(d) result(o)
    integer, intent(in) :: d  !< direction 1..3
    integer :: o(3)
    o = 0
    o(d) = 1
  end function unit_offset

  !> True when direction `d` is active (a sweep has work); sets its unit offset `o` and, if asked,
  !! the face area A_d = V / dx_d of its faces. Not pure (it sets `o` and `area`): pure callers
  !! use `unit_offset`.
  logical function sweep_direction(grid, d, o, area) result(active)
    type(grid_t), intent(in) :: grid           !< block geometry
    integer, intent(in) :: d                   !< direction 1..3
    integer, intent(out) :: o(3)               !< unit offset of d
    real(wp), intent(out), optional :: area    !< face area [m^2]
    active = grid%active(d)
    o = unit_offset(d)
    if (present(area)) area = grid%cell_volume / grid%dx(d)
  end function sweep_direction
end module grid_sweep
