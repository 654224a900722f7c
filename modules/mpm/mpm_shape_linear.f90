!> Linear (tent) MPM shape function of one dimension: S(r) = 1 - |r|/h for |r| < h.
module mpm_shape_linear
  use mpmice_kinds, only: wp
  implicit none
  private

  public :: linear_1d

contains

  !> Weight and derivative d/dx_p of the tent function of node spacing `h` at offset
  !! `r = x_p - x_i` [m].
  pure elemental subroutine linear_1d(r, h, w, dw)
    real(wp), intent(in) :: r    !< particle minus node position [m]
    real(wp), intent(in) :: h    !< node spacing [m]
    real(wp), intent(out) :: w   !< weight [-]
    real(wp), intent(out) :: dw  !< derivative with respect to the particle position [1/m]
    real(wp) :: a
    a = abs(r)
    if (a < h) then
      w = 1.0_wp - a / h
      dw = -sign(1.0_wp, r) / h
    else
      w = 0.0_wp
      dw = 0.0_wp
    end if
  end subroutine linear_1d
end module mpm_shape_linear
