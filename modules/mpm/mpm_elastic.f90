!> Isotropic linear elasticity in rate form (hypo-elastic), applied in the polar-decomposition
!! frame (eqs. 13-15): d sigma* = lambda tr(d eps*) I + 2 mu d eps*.
module mpm_elastic
  use mpmice_kinds, only: wp
  implicit none
  private

  public :: elastic_increment, lame_from_young

contains

  !> Lame constants lambda, mu [Pa] from Young's modulus E [Pa] and Poisson's ratio nu.
  pure subroutine lame_from_young(e, nu, lambda, mu)
    real(wp), intent(in) :: e         !< Young's modulus [Pa]
    real(wp), intent(in) :: nu        !< Poisson's ratio [-]
    real(wp), intent(out) :: lambda   !< first Lame constant [Pa]
    real(wp), intent(out) :: mu       !< shear modulus [Pa]
    lambda = e * nu / ((1.0_wp + nu) * (1.0_wp - 2.0_wp * nu))
    mu = e / (2.0_wp * (1.0_wp + nu))
  end subroutine lame_from_young

  !> Stress increment [Pa] of a symmetric strain increment `deps` (xx, yy, zz, xy, yz, xz; tensor
  !! shear components, not engineering).
  pure function elastic_increment(lambda, mu, deps) result(dsig)
    real(wp), intent(in) :: lambda   !< first Lame constant [Pa]
    real(wp), intent(in) :: mu       !< shear modulus [Pa]
    real(wp), intent(in) :: deps(6)  !< strain increment [-]
    real(wp) :: dsig(6)
    real(wp) :: tr
    tr = deps(1) + deps(2) + deps(3)
    dsig = 2.0_wp * mu * deps
    dsig(1:3) = dsig(1:3) + lambda * tr
  end function elastic_increment
end module mpm_elastic
