!> Modified Cam-Clay (Roscoe & Burland 1968; as in Wood 1990, ch. 4-6, and Borja & Lee 1990)
!! for the effective stress of a clay skeleton, integrated by an implicit (backward-Euler,
!! closest-point) return mapping in p'-q with substepping (docs/soil_models.md).
!!
!! Sign convention: the stress argument is tension positive (xx, yy, zz, xy, yz, xz), like the
!! other models; inside, p = -tr(sigma)/3 is the mean effective stress, compression positive,
!! q = sqrt(3/2 s:s) the deviator stress (s = sigma + p I), eps_v = -tr(eps) the volumetric
!! strain, compression positive.
!!   yield surface:  f = q^2 / M^2 + p (p - p_c) = 0                          (ellipse)
!!   elasticity:     dp = K d eps_v^e, K = v max(p, p_min) / kappa; G constant or
!!                   G = 3 K (1 - 2 nu) / (2 (1 + nu))
!!   flow (assoc.):  d eps_v^p = dgam df/dp = dgam (2 p - p_c),
!!                   d e^p = dgam 3 s / M^2  (d eps_q^p = dgam 2 q / M^2)
!!   hardening:      dp_c / p_c = v d eps_v^p / (lambda - kappa)
!! v = 1 + e is the specific volume, v = v0 J (J = det F). Over a (sub)step v is frozen at
!! its mid value and the two exponential laws are integrated exactly:
!!   p = p_n exp(v (deps_v - x) / kappa),  p_c = p_cn exp(v x / (lambda - kappa)),
!! x = d eps_v^p. The return solves, for the multiplier dgam >= 0,
!!   F(dgam) = q(dgam)^2 / M^2 + p(x) (p(x) - p_c(x)) = 0,  q = q_tr / (1 + 6 G dgam / M^2),
!! where x(dgam) is the root of the monotone g(x) = x - dgam (2 p(x) - p_c(x)); both scalar
!! equations are solved inside a bracket (Illinois regula falsi, bisection after 60 iterations;
!! exponents capped at 200 so that no bracket end overflows), so the return converges from
!! any trial state, also on the softening (dry) side and at large steps. A step whose strain
!! increment exceeds `max_substep_strain` is split into equal substeps.
module mpm_cam_clay
  use mpmice_kinds, only: wp
  use mpm_illinois, only: illinois_point, illinois_update
  use mpm_tensor, only: mean_pressure
  implicit none
  private

  public :: mcc_params_t, mcc_update, mcc_initial_pc, mcc_moduli, mcc_invariants

  !> Parameters of the model.
  type :: mcc_params_t
    real(wp) :: m = 1.0_wp               !< critical-state stress ratio M = q/p' [-]
    real(wp) :: lambda = 0.2_wp          !< slope of the normal compression line in v-ln p' [-]
    real(wp) :: kappa = 0.04_wp          !< slope of the swelling line in v-ln p' [-]
    real(wp) :: v0 = 2.0_wp              !< specific volume at J = 1 (1 / (1 - porosity)) [-]
    real(wp) :: pc0 = 0.0_wp             !< initial preconsolidation pressure p_c0 [Pa]
    real(wp) :: ocr = 1.0_wp             !< overconsolidation ratio on the initial stress [-]
    real(wp) :: shear_modulus = 0.0_wp   !< constant G [Pa] (0: G from `poisson`)
    real(wp) :: poisson = 0.3_wp         !< Poisson's ratio of the pressure-dependent G [-]
    real(wp) :: min_pressure = 1.0e3_wp  !< p'_min of the bulk modulus [Pa]
  end type mcc_params_t

  !> Largest strain-increment norm of one substep [-].
  real(wp), parameter :: max_substep_strain = 1.0e-3_wp
  integer, parameter :: max_iterations = 200  !< cap of each scalar solve
  !> iterations of Illinois regula falsi before the solves fall back to bisection (a bracket
  !! end far from the root can stall regula falsi)
  integer, parameter :: falsi_iterations = 60
  real(wp), parameter :: max_exponent = 200.0_wp  !< cap of the exponential laws' arguments

contains

  !> p = -tr(sig)/3 [Pa], q = sqrt(3/2 s:s) [Pa] and the deviator s [Pa] of `sig`.
  pure subroutine mcc_invariants(sig, p, q, s)
    real(wp), intent(in) :: sig(6)   !< stress, tension positive [Pa]
    real(wp), intent(out) :: p       !< mean effective stress, compression positive [Pa]
    real(wp), intent(out) :: q       !< deviator stress [Pa]
    real(wp), intent(out) :: s(6)    !< deviatoric stress [Pa]
    p = mean_pressure(sig)
    s = sig
    s(1:3) = s(1:3) + p
    q = sqrt(1.5_wp * (s(1)**2 + s(2)**2 + s(3)**2 + 2.0_wp * (s(4)**2 + s(5)**2 + s(6)**2)))
  end subroutine mcc_invariants

  !> Preconsolidation pressure of a particle at its first update [Pa]: the largest of `pc0`,
  !! OCR times the size of the ellipse through the stress (p + q^2 / (M^2 p)), and p'_min, so
  !! that the initial stress lies inside or on the yield surface.
  pure real(wp) function mcc_initial_pc(prm, sig) result(pc)
    type(mcc_params_t), intent(in) :: prm  !< parameters
    real(wp), intent(in) :: sig(6)         !< initial stress [Pa]
    real(wp) :: p, q, s(6), p_eq
    call mcc_invariants(sig, p, q, s)
    p_eq = 0.0_wp
    if (p > 0.0_wp) p_eq = p + q**2 / (prm%m**2 * p)
    pc = max(prm%pc0, prm%ocr * p_eq, prm%min_pressure)
  end function mcc_initial_pc

  !> Elastic moduli [Pa] at mean effective stress `p` and specific volume `v`.
  pure subroutine mcc_moduli(prm, p, v, k, g)
    type(mcc_params_t), intent(in) :: prm  !< parameters
    real(wp), intent(in) :: p              !< mean effective stress [Pa]
    real(wp), intent(in) :: v              !< specific volume [-]
    real(wp), intent(out) :: k             !< bulk modulus [Pa]
    real(wp), intent(out) :: g             !< shear modulus [Pa]
    k = v * max(p, prm%min_pressure) / prm%kappa
    if (prm%shear_modulus > 0.0_wp) then
      g = prm%shear_modulus
    else
      g = 1.5_wp * k * (1.0_wp - 2.0_wp * prm%poisson) / (1.0_wp + prm%poisson)
    end if
  end subroutine mcc_moduli

  !> Stress update over one step: `deps` is the strain increment in the rotated frame
  !! (tension positive, tensor shear components), `v_end` the specific volume at the end of
  !! the step. Updates `sig` [Pa] and `pc` [Pa] (0 on entry: set by `mcc_initial_pc`);
  !! `deps_p` is the equivalent plastic strain increment sqrt(2/3 e^p:e^p) [-]. With
  !! `elastic_only` the elastic predictor is the stress (no return, p_c unchanged; `&solid
  !! plastic_start`).
  pure subroutine mcc_update(prm, deps, v_end, sig, pc, deps_p, elastic_only)
    type(mcc_params_t), intent(in) :: prm  !< parameters
    real(wp), intent(in) :: deps(6)        !< strain increment [-]
    real(wp), intent(in) :: v_end          !< specific volume at the end of the step [-]
    real(wp), intent(inout) :: sig(6)      !< stress [Pa]
    real(wp), intent(inout) :: pc          !< preconsolidation pressure [Pa]
    real(wp), intent(out) :: deps_p        !< equivalent plastic strain increment [-]
    logical, intent(in), optional :: elastic_only  !< elastic predictor only (default: no)
    real(wp) :: size, tr, v_start, v_mid, dep
    integer :: n, k
    logical :: elastic
    elastic = .false.
    if (present(elastic_only)) elastic = elastic_only
    if (pc <= 0.0_wp) pc = mcc_initial_pc(prm, sig)
    size = sqrt(sum(deps(1:3)**2) + 2.0_wp * sum(deps(4:6)**2))
    n = max(1, ceiling(size / max_substep_strain))
    tr = deps(1) + deps(2) + deps(3)
    v_start = v_end * exp(-tr)
    deps_p = 0.0_wp
    do k = 1, n
      v_mid = v_start * exp(tr * (real(k, wp) - 0.5_wp) / real(n, wp))
      call mcc_substep(prm, deps / real(n, wp), v_mid, elastic, sig, pc, dep)
      deps_p = deps_p + dep
    end do
  end subroutine mcc_update

  !> Mean effective stress after an elastic volumetric strain `de` (compression positive)
  !! from `p0`: dp = v max(p, p_min) / kappa de integrated exactly (linear below p_min,
  !! exponential above), never below 0 (no tension).
  pure real(wp) function elastic_pressure(prm, p0, de, v) result(p)
    type(mcc_params_t), intent(in) :: prm  !< parameters
    real(wp), intent(in) :: p0             !< start [Pa]
    real(wp), intent(in) :: de             !< elastic volumetric strain [-]
    real(wp), intent(in) :: v              !< specific volume [-]
    real(wp) :: a, pm, d1
    a = v / prm%kappa
    pm = prm%min_pressure
    if (p0 >= pm) then
      p = p0 * exp(min(a * de, max_exponent))
      if (p < pm) then
        d1 = log(pm / p0) / a          ! strain to reach p_min, then linear
        p = pm + a * pm * (de - d1)
      end if
    else
      p = p0 + a * pm * de
      if (p > pm) then
        d1 = (pm - p0) / (a * pm)      ! strain to reach p_min, then exponential
        p = pm * exp(min(a * (de - d1), max_exponent))
      end if
    end if
    p = max(p, 0.0_wp)
  end function elastic_pressure

  !> One substep: elastic predictor, then the closest-point return if the trial state yields
  !! (never with `elastic`).
  pure subroutine mcc_substep(prm, deps, v, elastic, sig, pc, deps_p)
    type(mcc_params_t), intent(in) :: prm  !< parameters
    real(wp), intent(in) :: deps(6)        !< strain increment [-]
    real(wp), intent(in) :: v              !< specific volume [-]
    logical, intent(in) :: elastic         !< elastic predictor only
    real(wp), intent(inout) :: sig(6)      !< stress [Pa]
    real(wp), intent(inout) :: pc          !< preconsolidation pressure [Pa]
    real(wp), intent(out) :: deps_p        !< equivalent plastic strain increment [-]
    real(wp) :: p_n, q_n, s(6), k, g, dev(6), dv, p_tr, q_tr, s_tr(6), f_tr, m2
    real(wp) :: lo, hi, f_lo, f_hi, gam, f_mid, p, q, pc_new, x
    integer :: it, side
    m2 = prm%m**2
    call mcc_invariants(sig, p_n, q_n, s)
    call mcc_moduli(prm, p_n, v, k, g)
    dv = -(deps(1) + deps(2) + deps(3))
    dev = deps
    dev(1:3) = dev(1:3) + dv / 3.0_wp
    p_tr = elastic_pressure(prm, p_n, dv, v)
    s_tr = s + 2.0_wp * g * dev
    q_tr = sqrt(1.5_wp * (s_tr(1)**2 + s_tr(2)**2 + s_tr(3)**2 + &
      2.0_wp * (s_tr(4)**2 + s_tr(5)**2 + s_tr(6)**2)))
    f_tr = q_tr**2 / m2 + p_tr * (p_tr - pc)
    deps_p = 0.0_wp
    if (elastic .or. f_tr <= 1.0e-14_wp * pc**2) then
      sig = s_tr
      sig(1:3) = sig(1:3) - p_tr
      return
    end if
    ! bracket the multiplier: F(0) = f_tr > 0, F(dgam) < 0 for dgam large enough
    lo = 0.0_wp
    f_lo = f_tr
    hi = 1.0e-6_wp / max(pc, p_tr)
    do it = 1, max_iterations
      f_hi = residual(hi)
      if (f_hi <= 0.0_wp) exit
      lo = hi
      f_lo = f_hi
      hi = 2.0_wp * hi
    end do
    ! Illinois regula falsi on [lo, hi]
    gam = hi
    side = 0
    do it = 1, max_iterations
      gam = illinois_point(lo, f_lo, hi, f_hi, it, falsi_iterations)
      f_mid = residual(gam)
      if (abs(f_mid) <= 1.0e-13_wp * pc**2 .or. hi - lo <= 1.0e-15_wp * hi) exit
      call illinois_update(gam, f_mid, lo, f_lo, hi, f_hi, side)
    end do
    call state_at(gam, p, q, pc_new, x)
    if (q_tr > 0.0_wp) then
      sig = s_tr * (q / q_tr)
    else
      sig = 0.0_wp
    end if
    sig(1:3) = sig(1:3) - p
    pc = pc_new
    deps_p = 2.0_wp * gam * q / m2
  contains
    !> Yield function at the end of the substep for multiplier `dgam` [Pa^2].
    pure real(wp) function residual(dgam) result(res)
      real(wp), intent(in) :: dgam   !< plastic multiplier [1/Pa]
      real(wp) :: pp, qq, ppc, xx
      call state_at(dgam, pp, qq, ppc, xx)
      res = qq**2 / m2 + pp * (pp - ppc)
    end function residual

    !> p, q, p_c and x = d eps_v^p at multiplier `dgam`: x solves g(x) = 0 (g increasing).
    pure subroutine state_at(dgam, pp, qq, ppc, xx)
      real(wp), intent(in) :: dgam   !< plastic multiplier [1/Pa]
      real(wp), intent(out) :: pp    !< p' [Pa]
      real(wp), intent(out) :: qq    !< q [Pa]
      real(wp), intent(out) :: ppc   !< p_c [Pa]
      real(wp), intent(out) :: xx    !< plastic volumetric strain increment [-]
      real(wp) :: a, b, ga, gb, gx
      integer :: j, sd
      qq = q_tr / (1.0_wp + 6.0_wp * g * dgam / m2)
      xx = 0.0_wp
      if (dgam > 0.0_wp) then
        gx = gfun(0.0_wp, dgam)
        if (gx < 0.0_wp) then
          a = 0.0_wp
          ga = gx
          b = 2.0_wp * dgam * p_tr
          gb = gfun(b, dgam)
        else
          b = 0.0_wp
          gb = gx
          a = -dgam * pc
          ga = gfun(a, dgam)
        end if
        xx = a
        sd = 0
        if (ga /= 0.0_wp .and. gb /= 0.0_wp) then
          do j = 1, max_iterations
            xx = illinois_point(a, ga, b, gb, j, falsi_iterations)
            gx = gfun(xx, dgam)
            if (abs(gx) <= 1.0e-15_wp * (abs(xx) + dgam * pc) .or. &
              b - a <= 1.0e-15_wp * max(abs(a), abs(b))) exit
            call illinois_update(xx, gx, a, ga, b, gb, sd)
          end do
        else if (gb == 0.0_wp) then
          xx = b
        end if
      end if
      pp = elastic_pressure(prm, p_n, dv - xx, v)
      ppc = pc * exp(min(v * xx / (prm%lambda - prm%kappa), max_exponent))
    end subroutine state_at

    !> g(x) = x - dgam (2 p(x) - p_c(x)), increasing in x.
    pure real(wp) function gfun(xv, dgam) result(gv)
      real(wp), intent(in) :: xv     !< plastic volumetric strain increment x [-]
      real(wp), intent(in) :: dgam   !< plastic multiplier [1/Pa]
      gv = xv - dgam * (2.0_wp * elastic_pressure(prm, p_n, dv - xv, v) - &
        pc * exp(min(v * xv / (prm%lambda - prm%kappa), max_exponent)))
    end function gfun
  end subroutine mcc_substep
end module mpm_cam_clay
