!> Critical-state sand: a pressure-dependent friction law whose friction and dilatancy are set
!! by the packing (solid fraction phi), after Roux & Radjai (1998) and Pailha & Pouliquen
!! (2009), with the viscous-number rheology of Boyer, Guazzelli & Pouliquen (2011) for the
!! critical state; see docs/soil_models.md.
!!
!! Sign convention: stress tension positive; p = -tr(sigma)/3 >= 0 the mean effective stress,
!! tau = sqrt(s:s / 2) the equivalent shear stress (s the deviator), gamma_dot the equivalent
!! plastic shear rate (in simple shear: tau = sigma_xy, gamma_dot = dv_x/dy).
!!   viscous number   J = eta_f gamma_dot / p
!!   critical state   mu_eq(J) = mu_1 + (mu_2 - mu_1) / (1 + J_0 / J) + J + 5/2 phi_m J^(1/2)
!!                    phi_eq(J) = phi_m / (1 + J^(1/2))                (Boyer et al. 2011)
!!   dilatancy        tan(psi) = K (phi - phi_eq)                   (Pailha & Pouliquen 2009)
!!   friction         tau = mu p, mu = max(mu_eq(J) + tan(psi), 0)
!!   flow             d e^p = dgam s / (2 tau),  d eps_vol^p = tan(psi) dgam (dilation > 0)
!! With eta_f = 0 (no pore fluid viscosity given) J = 0: mu_eq = mu_1, phi_eq = phi_m, the
!! quasi-static limit. Every term is evaluated as a product with p (mu_eq p = mu_1 p +
!! (mu_2 - mu_1) p eta gd / (eta gd + J_0 p) + eta gd + 5/2 phi_m sqrt(eta gd p)), finite at
!! p -> 0. Return (elastic predictor with the constant Lame constants, then one scalar equation
!! for the plastic shear increment dgam, solved inside the bracket [0, tau_tr / G] by Illinois
!! regula falsi):
!!   R(dgam) = tau_tr - G dgam - max(mu_eq(J) p + tan(psi) p, 0) = 0,
!!   p = max(p_tr + K_b tan(psi) dgam, 0),  gamma_dot = dgam / dt,
!! (the plastic dilation tan(psi) dgam is taken from the elastic volumetric strain of the
!! step, so a dilating sand gains pressure and a contracting one loses it),
!! phi_eq in tan(psi) taken at J(gamma_dot, p_tr). No tension: a trial p <= 0 returns to zero
!! stress (the apex).
!!
!! Optional memory of the apex (`css_tension_gap`, `tension_gap`): without it the expansion of a
!! particle past p' = 0 is forgotten, so that a particle whose volume oscillates about the
!! contact point gains p' = K d eps_v on every recompression (a zero-mean volume noise is
!! rectified into effective stress). With it the expansion past the apex is kept as a gap
!!   g = max(g_old - p_tr / K, 0)      (p_tr the trial p' before the gap is applied),
!! and the next trial stress is shifted by K g before the return: the grains separated at zero
!! effective stress carry load again only once the skeleton has closed the gap, as a packing
!! below its contact density does.
!!
!! Optional compaction at low effective stress (`css_compaction`, off with lambda_c = 0): a
!! packing looser than the critical one (phi < phi_m) compacts plastically once p' reaches its
!! compaction pressure p_c, along the line
!!   p' + p_a = (p_c + p_a) exp(eps_v^p / lambda_c)      (eps_v^p the plastic compaction),
!! whose modulus (p' + p_a) / lambda_c is small at low p', and reloads and unloads elastically
!! below p_c. p_c follows p' upward (a packing holds the largest p' it has carried), and falls to
!! 0 where the packing has lost all its effective stress (the apex, or a suspension): a
!! liquefied packing has lost its contact network and reconsolidates along the line again, the
!! large post-liquefaction reconsolidation strains of loose sands (Ishihara & Yoshimine 1992).
!! p_a is the effective stress at which a packing without contacts starts to carry load.
!!
!! Optional cyclic densification (`css_densify`, off with C_1 = 0): the irrecoverable volume
!! contraction of a sand under strain cycles inside the yield surface, in the form of Martin,
!! Finn & Seed (1975) as rewritten by Byrne (1991) and implemented in FLAC's Finn model (Itasca,
!! "Finn model", FLAC3D documentation): at each reversal of the engineering shear strain
!! gamma_xy (a half cycle), with gamma the amplitude of that half cycle,
!!   d eps_vd = gamma C_1 exp(-C_2 eps_vd / gamma),   C_2 = 0.4 / C_1 (Byrne 1991),
!! eps_vd >= 0 the accumulated densification (contraction positive). It is a plastic
!! compaction: p' = K (eps_v^e) with eps_v^e = eps_v + eps_vd, so at constant volume p' falls
!! by K d eps_vd (the excess pore pressure of an undrained element), drained the element
!! contracts by d eps_vd. Two optional limits: eps_vd <= `evd_max` (the densest packing the
!! grains can reach, eps_vd_max = 1 - phi_0 / phi_max), and, with `elastic_amp`, the cycled
!! strain is the elastic shear strain gamma_xy^e = tau_xy / G instead of the total one, so that
!! monotonic plastic flow (tau on the yield surface) is no cycle and only the cyclic stress
!! counts (the caller passes its increment). A third filters the count: a reversal is counted
!! only once its half cycle has lasted `t_min` (e.g. a quarter of the shaking period), so the
!! particles' high-frequency strain noise does not count as cycles.
module mpm_critical_state_sand
  use mpmice_kinds, only: wp
  use mpm_illinois, only: illinois_point, illinois_update
  use mpm_tensor, only: mean_pressure
  implicit none
  private

  public :: css_params_t, css_return, css_phi_eq, css_strength, css_densify
  public :: css_n_cyclic, css_evd, css_gamma, css_gamma_rev, css_gamma_ext, css_reversals
  public :: css_t_half, css_compaction, css_tension_gap

  !> Cyclic state of one particle (`css_densify`), indices into `state(css_n_cyclic)`:
  integer, parameter :: css_n_cyclic = 6   !< entries
  integer, parameter :: css_evd = 1        !< accumulated densification eps_vd [-]
  integer, parameter :: css_gamma = 2      !< accumulated engineering shear strain gamma_xy [-]
  integer, parameter :: css_gamma_rev = 3  !< gamma_xy at the last reversal [-]
  integer, parameter :: css_gamma_ext = 4  !< extreme gamma_xy since the last reversal [-]
  integer, parameter :: css_reversals = 5  !< reversals (half cycles) counted [-]
  integer, parameter :: css_t_half = 6     !< time since the last reversal [s]

  !> Parameters of the model (the elastic constants are arguments of `css_return`: a particle's
  !! current ones, `mpm_constitutive` current_moduli).
  type :: css_params_t
    real(wp) :: mu1 = 0.32_wp            !< quasi-static critical friction mu_1 [-]
    real(wp) :: mu2 = 0.7_wp             !< friction at large J, mu_2 [-]
    real(wp) :: j0 = 0.005_wp            !< viscous-number constant J_0 [-]
    real(wp) :: phi_m = 0.585_wp         !< critical (quasi-static) solid fraction phi_m [-]
    real(wp) :: k_dil = 4.09_wp          !< dilatancy constant K [-]
    real(wp) :: eta_f = 0.0_wp           !< pore fluid viscosity eta_f [Pa s] (0: J = 0)
    real(wp) :: lambda_c = 0.0_wp        !< compaction index lambda_c [-] (0: no compaction)
    real(wp) :: p_a = 5.0_wp             !< compaction line's pressure offset p_a [Pa]
    real(wp) :: c1 = 0.0_wp              !< densification constant C_1 [-] (0: off)
    real(wp) :: c2 = 0.0_wp              !< densification constant C_2 [-] (0: 0.4 / C_1)
    real(wp) :: gamma_t = 0.0_wp         !< threshold shear strain amplitude [-]
    real(wp) :: evd_max = 0.0_wp         !< largest eps_vd [-] (0: no bound)
    logical :: elastic_amp = .false.     !< cycle the elastic shear strain tau_xy / G
    real(wp) :: t_min = 0.0_wp           !< shortest half cycle counted [s]
    real(wp) :: t_start = 0.0_wp         !< densification counted from this time [s] (the
                                         !! caller passes C_1 = 0 before it)
    logical :: tension_gap = .false.     !< keep the expansion past the apex (`css_tension_gap`)
  end type css_params_t

  integer, parameter :: max_iterations = 200  !< cap of the scalar solve
  integer, parameter :: falsi_iterations = 60   !< regula falsi, then bisection

contains

  !> Critical solid fraction phi_eq(J) [-] at shear rate `gd` [1/s] and pressure `p` [Pa].
  pure real(wp) function css_phi_eq(prm, gd, p) result(phi_eq)
    type(css_params_t), intent(in) :: prm  !< parameters
    real(wp), intent(in) :: gd             !< shear rate [1/s]
    real(wp), intent(in) :: p              !< mean effective stress [Pa]
    real(wp) :: a
    a = sqrt(max(prm%eta_f * gd, 0.0_wp))
    if (a <= 0.0_wp) then
      phi_eq = prm%phi_m
    else
      phi_eq = prm%phi_m * sqrt(max(p, 0.0_wp)) / (sqrt(max(p, 0.0_wp)) + a)  ! phi_m/(1+J^1/2)
    end if
  end function css_phi_eq

  !> Critical-state shear strength mu_eq(J) p [Pa] at shear rate `gd` [1/s], pressure `p`.
  pure real(wp) function css_strength(prm, gd, p) result(s)
    type(css_params_t), intent(in) :: prm  !< parameters
    real(wp), intent(in) :: gd             !< shear rate [1/s]
    real(wp), intent(in) :: p              !< mean effective stress [Pa]
    real(wp) :: e, pp
    e = max(prm%eta_f * gd, 0.0_wp)   ! J p
    pp = max(p, 0.0_wp)
    s = prm%mu1 * pp
    if (e > 0.0_wp) s = s + (prm%mu2 - prm%mu1) * pp * e / (e + prm%j0 * pp) + e + &
      2.5_wp * prm%phi_m * sqrt(e * pp)
  end function css_strength

  !> Return the elastic trial stress `sig` [Pa] in place; `phi` is the particle's solid
  !! fraction, `dt` the step [s]; `deps_p` the equivalent plastic strain increment
  !! sqrt(2/3 e^p:e^p) = dgam / sqrt(3) [-]; `lam`, `mu` the Lame constants of the trial stress.
  pure subroutine css_return(prm, lam, mu, phi, dt, sig, deps_p)
    type(css_params_t), intent(in) :: prm  !< parameters
    real(wp), intent(in) :: lam            !< first Lame constant [Pa]
    real(wp), intent(in) :: mu             !< shear modulus G [Pa]
    real(wp), intent(in) :: phi            !< solid fraction [-]
    real(wp), intent(in) :: dt             !< step [s]
    real(wp), intent(inout) :: sig(6)      !< trial stress in, returned stress out [Pa]
    real(wp), intent(out) :: deps_p        !< equivalent plastic strain increment [-]
    real(wp) :: p_tr, s(6), tau_tr, kb, lo, hi, r_lo, r_hi, gam, r, p, tau
    integer :: it, side
    deps_p = 0.0_wp
    p_tr = mean_pressure(sig)
    s = sig
    s(1:3) = s(1:3) + p_tr
    tau_tr = sqrt(0.5_wp * (s(1)**2 + s(2)**2 + s(3)**2) + s(4)**2 + s(5)**2 + s(6)**2)
    if (p_tr <= 0.0_wp) then
      ! no tension: the apex, zero effective stress
      deps_p = tau_tr / (mu * sqrt(3.0_wp))
      sig = 0.0_wp
      return
    end if
    kb = lam + 2.0_wp * mu / 3.0_wp
    r_lo = residual(0.0_wp)
    if (r_lo <= 1.0e-14_wp * p_tr) return   ! elastic
    lo = 0.0_wp
    hi = tau_tr / mu
    r_hi = residual(hi)
    gam = hi
    side = 0
    if (r_hi < 0.0_wp) then
      do it = 1, max_iterations
        gam = illinois_point(lo, r_lo, hi, r_hi, it, falsi_iterations)
        r = residual(gam)
        if (abs(r) <= 1.0e-14_wp * max(tau_tr, p_tr) .or. hi - lo <= 1.0e-15_wp * hi) exit
        call illinois_update(gam, r, lo, r_lo, hi, r_hi, side)
      end do
    end if
    call state_at(gam, p, tau)
    sig = s * (tau / tau_tr)
    sig(1:3) = sig(1:3) - p
    deps_p = gam / sqrt(3.0_wp)
  contains
    !> tau - strength at plastic shear increment `dgam` [Pa].
    pure real(wp) function residual(dgam) result(res)
      real(wp), intent(in) :: dgam   !< plastic shear increment [-]
      real(wp) :: pp, tt, gd, tpsi
      call state_at(dgam, pp, tt)
      gd = rate(dgam)
      tpsi = prm%k_dil * (phi - css_phi_eq(prm, gd, p_tr))
      res = tt - max(css_strength(prm, gd, pp) + tpsi * pp, 0.0_wp)
    end function residual

    !> p and tau at plastic shear increment `dgam`.
    pure subroutine state_at(dgam, pp, tt)
      real(wp), intent(in) :: dgam   !< plastic shear increment [-]
      real(wp), intent(out) :: pp    !< p' [Pa]
      real(wp), intent(out) :: tt    !< tau [Pa]
      real(wp) :: tpsi
      tpsi = prm%k_dil * (phi - css_phi_eq(prm, rate(dgam), p_tr))
      pp = max(p_tr + kb * tpsi * dgam, 0.0_wp)
      tt = max(tau_tr - mu * dgam, 0.0_wp)
    end subroutine state_at

    !> Plastic shear rate [1/s] of increment `dgam` (0 without a step).
    pure real(wp) function rate(dgam)
      real(wp), intent(in) :: dgam   !< plastic shear increment [-]
      rate = 0.0_wp
      if (dt > 0.0_wp) rate = dgam / dt
    end function rate
  end subroutine css_return

  !> Compaction at low effective stress (module header) of the trial stress `sig` [Pa] (tension
  !! positive) of a particle at solid fraction `phi`, with `kb` the bulk modulus of its trial
  !! stress [Pa] and `pc` its compaction pressure p_c [Pa] (updated): nothing for a packing at or
  !! above phi_m or a trial p' at or below p_c; otherwise the isotropic plastic compaction
  !! d eps_v^p > 0 that puts p' = p_tr - K d eps_v^p on the compaction line,
  !!   ln(p_tr - K d eps_v^p + p_a) = ln(p_c + p_a) + d eps_v^p / lambda_c,
  !! solved by Newton's method from d eps_v^p = (p_tr - p_c) / K (the root lies below it; the
  !! function is concave and decreasing, so the iterates fall monotonically onto the root), and
  !! p_c becomes that p'. Exact for any step size.
  pure subroutine css_compaction(prm, kb, phi, sig, pc)
    type(css_params_t), intent(in) :: prm  !< parameters
    real(wp), intent(in) :: kb             !< bulk modulus K of the trial stress [Pa]
    real(wp), intent(in) :: phi            !< solid fraction [-]
    real(wp), intent(inout) :: sig(6)      !< trial stress in, compacted stress out [Pa]
    real(wp), intent(inout) :: pc          !< compaction pressure p_c [Pa]
    real(wp) :: p_tr, x, h, dh, step, base
    integer :: it
    if (prm%lambda_c <= 0.0_wp .or. phi >= prm%phi_m) return
    p_tr = mean_pressure(sig)
    if (p_tr <= pc) return
    base = log(pc + prm%p_a)
    x = (p_tr - pc) / kb
    do it = 1, max_iterations
      h = log(p_tr - kb * x + prm%p_a) - base - x / prm%lambda_c
      dh = -kb / (p_tr - kb * x + prm%p_a) - 1.0_wp / prm%lambda_c
      step = h / dh
      x = max(x - step, 0.0_wp)
      if (abs(step) <= 1.0e-14_wp * x) exit
    end do
    sig(1:3) = sig(1:3) + kb * x
    pc = p_tr - kb * x
  end subroutine css_compaction

  !> The apex's memory (module header): shift the trial stress `sig` [Pa] (tension positive) of
  !! a particle whose skeleton has bulk modulus `kb` [Pa] by its volumetric gap `gap` [-], so
  !! that p' = p_tr - K g, and keep as the new gap the expansion that this leaves past p' = 0,
  !! g = max(-p' / K, 0) (`css_return` then returns such a trial stress to the apex, zero).
  pure subroutine css_tension_gap(kb, sig, gap)
    real(wp), intent(in) :: kb         !< bulk modulus K of the trial stress [Pa]
    real(wp), intent(inout) :: sig(6)  !< trial stress in, shifted out [Pa]
    real(wp), intent(inout) :: gap     !< volumetric gap g [-]
    sig(1:3) = sig(1:3) + kb * gap
    gap = max(-mean_pressure(sig) / kb, 0.0_wp)
  end subroutine css_tension_gap

  !> Cyclic densification (Byrne 1991 form of Martin et al. 1975, as FLAC's Finn model applies
  !! it per half cycle): advance the particle's cyclic `state` by the engineering shear strain
  !! increment `dgamma` = 2 d eps_xy and return the densification increment `devd` [-] (>= 0,
  !! contraction). A reversal is counted when gamma_xy has come back from its extreme by more
  !! than the threshold `gamma_t` and the half cycle (since the last reversal) has lasted
  !! `t_min` [s]; the half cycle's amplitude is half the strain between the
  !! last two reversals (the whole excursion for the first one, a quarter cycle from rest).
  !! Amplitudes <= `gamma_t` do not densify:
  !!   devd = gamma C_1 exp(-C_2 eps_vd / gamma),  C_2 = 0.4 / C_1 unless given,
  !! eps_vd + devd <= `evd_max` when that is > 0.
  pure subroutine css_densify(prm, dgamma, dt, state, devd)
    type(css_params_t), intent(in) :: prm          !< parameters
    real(wp), intent(in) :: dgamma                 !< engineering shear strain increment [-]
    real(wp), intent(in) :: dt                     !< step [s]
    real(wp), intent(inout) :: state(css_n_cyclic) !< cyclic state
    real(wp), intent(out) :: devd                  !< densification increment [-]
    real(wp) :: g, dir, amp, c2
    devd = 0.0_wp
    g = state(css_gamma) + dgamma
    state(css_gamma) = g
    state(css_t_half) = state(css_t_half) + dt
    dir = sign(1.0_wp, state(css_gamma_ext) - state(css_gamma_rev))
    if (state(css_gamma_ext) == state(css_gamma_rev) .or. &
      (g - state(css_gamma_ext)) * dir >= 0.0_wp) then
      state(css_gamma_ext) = g   ! moving on in the same direction (or from rest)
      return
    end if
    if (abs(g - state(css_gamma_ext)) <= prm%gamma_t .or. state(css_t_half) < prm%t_min) return
    ! a reversal at the extreme gamma_ext
    amp = abs(state(css_gamma_ext) - state(css_gamma_rev))
    if (state(css_reversals) > 0.0_wp) amp = 0.5_wp * amp
    if (amp > prm%gamma_t .and. amp > 0.0_wp .and. prm%c1 > 0.0_wp) then
      c2 = prm%c2
      if (c2 <= 0.0_wp) c2 = 0.4_wp / prm%c1
      devd = amp * prm%c1 * exp(-c2 * state(css_evd) / amp)
      if (prm%evd_max > 0.0_wp) devd = max(min(devd, prm%evd_max - state(css_evd)), 0.0_wp)
      state(css_evd) = state(css_evd) + devd
    end if
    state(css_reversals) = state(css_reversals) + 1.0_wp
    state(css_t_half) = 0.0_wp
    state(css_gamma_rev) = state(css_gamma_ext)
    state(css_gamma_ext) = g
  end subroutine css_densify
end module mpm_critical_state_sand
