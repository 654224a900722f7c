!> Compressible Neo-Hookean solid, eq. 16 as corrected by errata E2:
!! sigma' = (lambda ln J / J) I + (mu / J) (F F^T - I), with the Lame constants lambda, mu.
!! The stress follows from F directly (hyper-elastic, objective without the rotated frame).
module mpm_neo_hookean
  use mpmice_kinds, only: wp
  use mpm_tensor, only: det3, mat_to_sym, mul3
  implicit none
  private

  public :: neo_hookean_stress

contains

  !> Cauchy stress [Pa] (xx, yy, zz, xy, yz, xz) of deformation gradient `f` (det > 0).
  pure function neo_hookean_stress(lambda, mu, f) result(sig)
    real(wp), intent(in) :: lambda   !< first Lame constant [Pa]
    real(wp), intent(in) :: mu       !< shear modulus [Pa]
    real(wp), intent(in) :: f(3, 3)  !< deformation gradient [-]
    real(wp) :: sig(6)
    real(wp) :: j, ft(3, 3)
    j = det3(f)
    ft = transpose(f)  ! a local, not an expression argument packed into a heap temporary
    ! eq. 16, errata E2: (lambda ln J / J) I + (mu / J)(F F^T - I)
    sig = (mu / j) * mat_to_sym(mul3(f, ft))
    sig(1:3) = sig(1:3) + (lambda * log(j) - mu) / j
  end function neo_hookean_stress
end module mpm_neo_hookean
