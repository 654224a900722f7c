!> Generalized interpolation material point (uGIMP, Bardenhagen & Kober 2004) shape function of
!! one dimension: the tent function of spacing h convolved with the particle characteristic
!! function of half-width l_p (l_p <= h/2), divided by 2 l_p. With r = x_p - x_i:
!! * |r| < l_p:            S = 1 - (r^2 + l_p^2) / (2 h l_p)
!! * l_p <= |r| < h - l_p: S = 1 - |r| / h
!! * h - l_p <= |r| < h + l_p: S = (h + l_p - |r|)^2 / (4 h l_p)
module mpm_shape_gimp
  use mpmice_kinds, only: wp
  implicit none
  private

  public :: gimp_1d

contains

  !> Weight and derivative d/dx_p of the uGIMP function at offset `r = x_p - x_i` [m].
  pure elemental subroutine gimp_1d(r, h, lp, w, dw)
    real(wp), intent(in) :: r    !< particle minus node position [m]
    real(wp), intent(in) :: h    !< node spacing [m]
    real(wp), intent(in) :: lp   !< particle half-width [m], 0 < lp <= h/2
    real(wp), intent(out) :: w   !< weight [-]
    real(wp), intent(out) :: dw  !< derivative with respect to the particle position [1/m]
    real(wp) :: a, s
    a = abs(r)
    s = sign(1.0_wp, r)
    if (a < lp) then
      w = 1.0_wp - (r * r + lp * lp) / (2.0_wp * h * lp)
      dw = -r / (h * lp)
    else if (a < h - lp) then
      w = 1.0_wp - a / h
      dw = -s / h
    else if (a < h + lp) then
      w = (h + lp - a)**2 / (4.0_wp * h * lp)
      dw = -s * (h + lp - a) / (2.0_wp * h * lp)
    else
      w = 0.0_wp
      dw = 0.0_wp
    end if
  end subroutine gimp_1d
end module mpm_shape_gimp
