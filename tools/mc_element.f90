!> Mohr-Coulomb element tests of the MPM constitutive interface (`constitutive_update`, eq. 17
!! with non-associated flow), one material point, small strain (F = I):
!! * drained triaxial compression: axial strain increments, lateral stress held at -p0 by secant
!!   iteration on the lateral strain (p0 = 100 kPa, c' = 10 kPa, phi' = 30 deg, psi' = 10 deg);
!! * plane-strain simple shear: shear increments, vertical stress held at -p0, eps_xx = eps_zz = 0
!!   (phi' = 30, psi' = 0 and phi' = 35, psi' = 10, c' = 0).
!! E = 10 MPa, nu = 0.3. Writes `<dir>/mc_triaxial.csv` (axial strain, axial stress, lateral
!! stress, volumetric strain) and `<dir>/mc_simple_shear.csv` (phi, psi, gamma, tau/sigma_n,
!! eps_yy, d eps_yy / d gamma; every 100th of 60 000 increments of 1e-5).
!! Usage: mc_element DIR (postproc/mpm_mohr_coulomb.py compares both with the analytic values).
program mc_element
  use mpmice_kinds, only: wp
  use mpm_constitutive, only: material_t, material_init, constitutive_update, model_mohr_coulomb
  implicit none
  real(wp), parameter :: p0 = 1.0e5_wp
  real(wp), parameter :: eye(3, 3) = reshape([1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, &
    0.0_wp, 0.0_wp, 1.0_wp], [3, 3])
  character(len=512) :: dir
  type(material_t) :: mat
  real(wp) :: stress(6), su(6), ep, dea, ea, ev, der, dg, g, x
  integer :: n, unit, k
  real(wp), parameter :: phis(2) = [30.0_wp, 35.0_wp], psis(2) = [0.0_wp, 10.0_wp]

  call get_command_argument(1, dir)
  if (len_trim(dir) == 0) dir = '.'

  ! drained triaxial compression
  mat = material_init(model_mohr_coulomb, 2000.0_wp, 1.0e7_wp, 0.3_wp, 1.0e4_wp, 30.0_wp, &
    10.0_wp, .false., 0.0_wp)
  su = [-p0, -p0, -p0, 0.0_wp, 0.0_wp, 0.0_wp]
  ep = 0.0_wp
  dea = -2.0e-5_wp
  ea = 0.0_wp
  ev = 0.0_wp
  open(newunit=unit, file=trim(dir) // '/mc_triaxial.csv', status='replace', action='write')
  write(unit, '(a)') 'axial_strain,axial_stress,lateral_stress,volumetric_strain'
  write(unit, '(es24.16, 3(",", es24.16))') ea, su(3), su(1), ev
  do n = 1, 3000
    der = secant(1, 0.0_wp, -0.5_wp * dea)
    x = residual(1, der)
    su = stress
    ea = ea + dea
    ev = ev + dea + 2.0_wp * der
    write(unit, '(es24.16, 3(",", es24.16))') ea, su(3), su(1), ev
  end do
  close(unit)

  ! plane-strain simple shear
  open(newunit=unit, file=trim(dir) // '/mc_simple_shear.csv', status='replace', action='write')
  write(unit, '(a)') 'phi,psi,gamma,tau_over_sigma_n,eps_yy,deps_yy_dgamma'
  dg = 1.0e-5_wp
  do k = 1, 2
    mat = material_init(model_mohr_coulomb, 2000.0_wp, 1.0e7_wp, 0.3_wp, 0.0_wp, phis(k), &
      psis(k), .false., 0.0_wp)
    su = [-0.5_wp * p0, -p0, -0.5_wp * p0, 0.0_wp, 0.0_wp, 0.0_wp]
    ep = 0.0_wp
    g = 0.0_wp
    ev = 0.0_wp
    do n = 1, 60000
      der = secant(2, 0.0_wp, 1.0e-7_wp)
      x = residual(2, der)
      su = stress
      g = g + dg
      ev = ev + der
      if (mod(n, 100) == 0) write(unit, '(f6.1, ",", f6.1, 4(",", es24.16))') phis(k), psis(k), &
        g, -su(4) / su(2), ev, der / dg
    end do
  end do
  close(unit)

contains

  !> Root of `residual(mode, .)` by the secant method from x0, x1 (to 1e-13 p0).
  real(wp) function secant(mode, x0_in, x1_in) result(x1)
    integer, intent(in) :: mode        !< 1 triaxial, 2 simple shear
    real(wp), intent(in) :: x0_in      !< first guess
    real(wp), intent(in) :: x1_in      !< second guess
    real(wp) :: x0, x2, r0, r1
    integer :: it
    x0 = x0_in
    x1 = x1_in
    r0 = residual(mode, x0)
    r1 = residual(mode, x1)
    do it = 1, 100
      if (abs(r1) <= 1.0e-13_wp * p0 .or. r1 == r0) exit
      x2 = x1 - r1 * (x1 - x0) / (r1 - r0)
      x0 = x1
      r0 = r1
      x1 = x2
      r1 = residual(mode, x1)
    end do
  end function secant

  !> Held stress + p0 after one increment from the state `su`: mode 1, triaxial (axial `dea`,
  !! lateral strain increment x, held sigma_xx); mode 2, simple shear (`dg`, vertical strain
  !! increment x, held sigma_yy). The updated stress is left in `stress`.
  real(wp) function residual(mode, x) result(r)
    integer, intent(in) :: mode        !< 1 triaxial, 2 simple shear
    real(wp), intent(in) :: x          !< strain increment iterated on
    real(wp) :: l(3, 3), s(6), epl
    l = 0.0_wp
    if (mode == 1) then
      l(1, 1) = x
      l(2, 2) = x
      l(3, 3) = dea
    else
      l(1, 2) = dg
      l(2, 2) = x
    end if
    stress = su
    epl = ep
    call constitutive_update(mat, eye, l, 1.0_wp, stress, s, epl)
    if (mode == 1) then
      r = stress(1) + p0
    else
      r = stress(2) + p0
    end if
  end function residual
end program mc_element
