!> One interface to the solid constitutive models: linear elastic, Neo-Hookean (eq. 16, E2),
!! Mohr-Coulomb (eq. 17), Modified Cam-Clay, critical-state sand (docs/soil_models.md) and
!! rigid. Rate-form models (elastic, Mohr-Coulomb) work in the
!! polar-decomposition frame (eqs. 12-15): with F^{n+1} = V R (eq. 12) the strain increment
!! d eps = sym(L) dt is rotated, d eps* = R^T d eps R (eq. 14); the state `stress_unrot` is the
!! stress already in that frame (eq. 13), so after the update sigma = R sigma* R^T (eq. 15).
!! Modified Cam-Clay and the critical-state sand are rate models of the same frame.
module mpm_constitutive
  use mpmice_kinds, only: wp
  use mpm_tensor, only: polar_rotation, rotate_to, rotate_from, mat_to_sym, det3, mean_pressure
  use mpm_elastic, only: elastic_increment, lame_from_young
  use mpm_neo_hookean, only: neo_hookean_stress
  use mpm_mohr_coulomb, only: mc_params_t, mc_params, mc_return
  use mpm_cam_clay, only: mcc_params_t, mcc_update, mcc_moduli, mcc_invariants
  use mpm_critical_state_sand, only: css_params_t, css_return, css_densify, css_n_cyclic, &
    css_gamma, css_gamma_ext, css_compaction, css_tension_gap
  implicit none
  private

  public :: material_t, material_init, constitutive_update, wave_speed
  public :: model_linear_elastic, model_neo_hookean, model_mohr_coulomb, model_rigid
  public :: model_from_name, model_cam_clay, model_critical_state_sand, model_state
  public :: material_at, current_moduli

  integer, parameter :: model_linear_elastic = 1  !< linear (hypo-)elastic
  integer, parameter :: model_neo_hookean = 2     !< compressible Neo-Hookean
  integer, parameter :: model_mohr_coulomb = 3    !< Mohr-Coulomb, non-associated
  integer, parameter :: model_rigid = 4           !< prescribed motion, no stress
  integer, parameter :: model_cam_clay = 5        !< Modified Cam-Clay
  integer, parameter :: model_critical_state_sand = 6  !< packing-dependent sand
  !> floor of the pressure-dependent modulus's p', as a fraction of p_ref (`current_moduli`)
  real(wp), parameter :: modulus_floor = 0.01_wp
  !> the `&solid model` names of the models, in their order ('modified_cam_clay': cam_clay)
  character(len=*), parameter :: model_names(6) = [character(len=19) :: 'linear_elastic', &
    'neo_hookean', 'mohr_coulomb', 'rigid', 'cam_clay', 'critical_state_sand']

  !> Constitutive parameters of one solid material.
  type :: material_t
    integer :: model = model_linear_elastic  !< model id
    real(wp) :: density = 1.0_wp             !< density [kg/m^3]
    real(wp) :: lambda = 0.0_wp              !< first Lame constant [Pa]
    real(wp) :: mu = 0.0_wp                  !< shear modulus [Pa]
    type(mc_params_t) :: mc                  !< Mohr-Coulomb parameters
    type(mcc_params_t) :: mcc                !< Modified Cam-Clay parameters
    type(css_params_t) :: css                !< critical-state sand parameters
    !> solid fraction 1 - n0 at J = 1 (`&solid porosity`); the packing is phi = phi0 / J
    real(wp) :: solid_fraction0 = 1.0_wp
    !> For Mohr-Coulomb, the J = det F beyond which the grains lose contact (the porosity
    !! 1 - (1 - n0) / J passes `&solid max_porosity`): no effective stress, no stiffness
    real(wp) :: j_loose = huge(1.0_wp)
    !> J at which a contractant Mohr-Coulomb particle (psi < 0) reaches its densest packing
    !! (porosity `&solid min_porosity`): from there it flows at psi = 0 (no further compaction)
    real(wp) :: j_dense = 0.0_wp
    !> `&solid plastic_start` [s]: before it the plastic models update their stress elastically
    !! (`material_at` sets `elastic_only` for the steps that start earlier)
    real(wp) :: plastic_start = 0.0_wp
    !> elastic law only: no return to the yield surface but to its apex (`apex_limit`), no
    !! tension cut-off, no densification
    logical :: elastic_only = .false.
    !> `&solid modulus_exponent` m: the Lame constants scale as (max(p', p_min) / p_ref)^m
    !! (`current_moduli`); 0: constant lambda, mu
    real(wp) :: modulus_exponent = 0.0_wp
    !> `&solid modulus_reference_pressure` p_ref [Pa]: the p' at which lambda, mu apply
    real(wp) :: modulus_p_ref = 1.0e5_wp
  end type material_t

contains

  !> Model id of a `&solid model` value (unknown names give the elastic model).
  pure integer function model_from_name(name) result(model)
    character(len=*), intent(in) :: name  !< namelist value
    model = findloc(model_names, name, dim=1)
    if (name == 'modified_cam_clay') model = model_cam_clay
    if (model == 0) model = model_linear_elastic
  end function model_from_name

  !> The per-particle state a solid carries beyond the common fields: the Cam-Clay
  !! preconsolidation pressure or the critical-state sand's compaction pressure (`hardening`,
  !! model `cam_clay`, or `critical_state_sand` with `&solid compaction_index > 0`), the
  !! critical-state sand's cyclic densification state (`cyclic`, model `critical_state_sand`
  !! with `&solid densification_c1 > 0`; `constitutive_update` reads and writes nothing else),
  !! its volumetric gap (`gap`, model `critical_state_sand` with `&solid tension_gap`), and the
  !! APIC affine velocity of a deformable solid (`affine`, `&mpm velocity_transfer =
  !! 'apic'`; `mpm_p2g`, `mpm_g2p`).
  pure subroutine model_state(model, densification_c1, compaction_index, tension_gap, &
    velocity_transfer, hardening, cyclic, gap, affine)
    integer, intent(in) :: model                       !< model id (`model_from_name`)
    real(wp), intent(in) :: densification_c1           !< `&solid densification_c1` [-]
    real(wp), intent(in) :: compaction_index           !< `&solid compaction_index` [-]
    logical, intent(in) :: tension_gap                 !< `&solid tension_gap`
    character(len=*), intent(in) :: velocity_transfer  !< `&mpm velocity_transfer`
    logical, intent(out) :: hardening                  !< carries p_c
    logical, intent(out) :: cyclic                     !< carries the cyclic state
    logical, intent(out) :: gap                        !< carries the volumetric gap
    logical, intent(out) :: affine                     !< carries C_p
    hardening = model == model_cam_clay .or. &
      (model == model_critical_state_sand .and. compaction_index > 0.0_wp)
    cyclic = model == model_critical_state_sand .and. densification_c1 > 0.0_wp
    gap = model == model_critical_state_sand .and. tension_gap
    affine = trim(velocity_transfer) == 'apic' .and. model /= model_rigid
  end subroutine model_state

  !> The material in effect over a step that starts at `time` [s]: `mat` itself, except
  !! * before `mat%plastic_start` (`&solid plastic_start`, elastic gravity loading): the
  !!   elastic law only (`elastic_only`: the plastic models' elastic trial stress is the
  !!   stress, limited only to the yield surface's apex (`apex_limit`), with no tension
  !!   cut-off and no densification; the stress-free suspension above `j_loose` stays, since
  !!   grains out of contact carry no stress);
  !! * before `mat%css%t_start` (`&solid densification_start`): no cyclic densification
  !!   (C_1 = 0, the particle's cyclic state is left untouched).
  !! Both times are absolute, so a restart (which keeps `&solid`) resumes the same phase.
  pure function material_at(mat, time) result(now)
    type(material_t), intent(in) :: mat  !< material of the namelist
    real(wp), intent(in) :: time         !< time at the start of the step [s]
    type(material_t) :: now
    now = mat
    now%elastic_only = time < mat%plastic_start
    if (now%elastic_only .or. time < mat%css%t_start) now%css%c1 = 0.0_wp
  end function material_at

  !> The Lame constants [Pa] of a particle whose stress is `sig` [Pa] (tension positive),
  !! for the Hardin-type pressure-dependent elasticity of Mohr-Coulomb and the critical-state
  !! sand (Hardin & Richart 1963, Hardin & Black 1966; the power form G = G_ref (p'/p_ref)^m of
  !! Wroth & Houlsby 1985 with constant Poisson's ratio, docs/soil_models.md):
  !!   G = mu (max(p', p_min) / p_ref)^m,  K = G 2 (1 + nu) / (3 (1 - 2 nu)),
  !! i.e. both `mat%lambda` and `mat%mu` times the same factor; p' = -tr(sig) / 3, p_ref =
  !! `modulus_p_ref`, p_min = p_ref / 100 (`modulus_floor`: the stiffness of a stress-free
  !! particle, (1/100)^m of the reference one, is > 0). With m = 0 they are `mat%lambda`,
  !! `mat%mu` exactly. Hypoelastic: the caller takes them at the start of a step.
  pure subroutine current_moduli(mat, sig, lam, mu)
    type(material_t), intent(in) :: mat  !< material
    real(wp), intent(in) :: sig(6)       !< stress [Pa]
    real(wp), intent(out) :: lam         !< first Lame constant [Pa]
    real(wp), intent(out) :: mu          !< shear modulus [Pa]
    real(wp) :: p, fac
    lam = mat%lambda
    mu = mat%mu
    if (mat%modulus_exponent == 0.0_wp) return
    p = mean_pressure(sig)
    fac = (max(p, modulus_floor * mat%modulus_p_ref) / mat%modulus_p_ref)**mat%modulus_exponent
    lam = lam * fac
    mu = mu * fac
  end subroutine current_moduli

  !> Material from the namelist parameters (angles in degrees).
  pure function material_init(model, density, youngs, poisson, cohesion, phi_deg, psi_deg, &
    tension_cutoff, tensile_strength) result(mat)
    integer, intent(in) :: model               !< model id
    real(wp), intent(in) :: density            !< density [kg/m^3]
    real(wp), intent(in) :: youngs             !< Young's modulus [Pa]
    real(wp), intent(in) :: poisson            !< Poisson's ratio [-]
    real(wp), intent(in) :: cohesion           !< c' [Pa]
    real(wp), intent(in) :: phi_deg            !< friction angle [deg]
    real(wp), intent(in) :: psi_deg            !< dilation angle [deg]
    logical, intent(in) :: tension_cutoff      !< tension cut-off on
    real(wp), intent(in) :: tensile_strength   !< tensile strength [Pa]
    type(material_t) :: mat
    real(wp), parameter :: deg = acos(-1.0_wp) / 180.0_wp
    mat%model = model
    mat%density = density
    call lame_from_young(youngs, poisson, mat%lambda, mat%mu)
    mat%mc = mc_params(cohesion, phi_deg * deg, psi_deg * deg, tension_cutoff, tensile_strength)
  end function material_init

  !> Dilatational (P) wave speed [m/s] of a particle with deformation gradient `f` (0 for a
  !! rigid material), for the explicit step limit: the stiffness that resists a compression wave
  !! against the current density rho0 / J (J = det F).
  !! * rate models (linear elastic, Mohr-Coulomb): the stress rate is lambda tr(D) I + 2 mu D
  !!   whatever J, so c^2 = (lambda + 2 mu) J / rho0: a dilated particle (J > 1) keeps its
  !!   stiffness with less mass per volume and is faster (floored at J = 1, the initial speed);
  !! * Neo-Hookean (eq. 16, E2): the spatial tangent plus the initial-stress term along a unit
  !!   direction n gives c^2 = (lambda (1 - ln J) + mu (1 + n.b.n)) / rho0, b = F F^T; n.b.n is
  !!   bounded by the largest row sum of |b| (equal to it at F = I, where c^2 = (lambda + 2 mu)
  !!   / rho0), the lambda term floored at 0;
  !! * Modified Cam-Clay: the current moduli, K = v max(p', p'_min) / kappa (v = v0 J) and G,
  !!   c^2 = (K + 4/3 G) max(J, 1) / rho0, p' from `stress` (without it, p' = p'_min);
  !! * a loose Mohr-Coulomb or critical-state sand particle (J > `j_loose`, grains out of
  !!   contact) has no stiffness: 0;
  !! * with a pressure-dependent modulus (`modulus_exponent` > 0) the rate models' lambda, mu
  !!   are those of the particle's current p' (`current_moduli` of `stress`; without it, of
  !!   p' = p_ref).
  pure real(wp) function wave_speed(mat, f, stress) result(c)
    type(material_t), intent(in) :: mat           !< material
    real(wp), intent(in) :: f(3, 3)               !< deformation gradient F [-]
    real(wp), intent(in), optional :: stress(6)   !< effective stress [Pa]
    real(wp) :: jac, b(3, 3), p, q, s(6), k, g, lam, mu
    jac = det3(f)
    select case (mat%model)
    case (model_rigid)
      c = 0.0_wp
    case (model_neo_hookean)
      b = matmul(f, transpose(f))
      c = sqrt((mat%lambda * max(1.0_wp - log(max(jac, tiny(1.0_wp))), 0.0_wp) + &
        mat%mu * (1.0_wp + maxval(sum(abs(b), dim=2)))) / mat%density)
    case (model_cam_clay)
      p = 0.0_wp
      if (present(stress)) call mcc_invariants(stress, p, q, s)
      call mcc_moduli(mat%mcc, p, mat%mcc%v0 * jac, k, g)
      c = sqrt((k + 4.0_wp / 3.0_wp * g) * max(jac, 1.0_wp) / mat%density)
    case default
      if (jac > mat%j_loose) then
        c = 0.0_wp  ! grains out of contact: no stiffness
      else
        lam = mat%lambda
        mu = mat%mu
        if (present(stress)) call current_moduli(mat, stress, lam, mu)
        c = sqrt((lam + 2.0_wp * mu) * max(jac, 1.0_wp) / mat%density)
      end if
    end select
  end function wave_speed

  !> Stress update of one particle over a step: `f` is F^{n+1}, `l` the velocity gradient L
  !! (l(i,j) = dv_i/dx_j) [1/s], `dt` [s]. Updates `stress_unrot` (rotated frame), `stress`
  !! (current frame) [Pa], `plastic_strain` [-] and, for Modified Cam-Clay, `hardening` = p_c
  !! [Pa] (0 before the first update: set then from the stress and `&solid ocr`,
  !! `preconsolidation_pressure`; a caller without it gets p_c set afresh at every call). A
  !! rate-model particle dilated past `mat%j_loose` (`&solid max_porosity`) carries no stress.
  !! For the critical-state sand with `mat%css%c1 > 0`, `cyclic` is the particle's cyclic
  !! densification state (`css_densify`; without it, no densification): the increment d eps_vd
  !! of a reversal is taken from the elastic volumetric strain, sigma_ii += K d eps_vd. With
  !! `mat%css%elastic_amp` the cycled strain is tau_xy / G of the trial stress (the state
  !! starts at the initial stress's value), otherwise the total gamma_xy = 2 eps_xy.
  !! For the critical-state sand with `mat%css%lambda_c > 0`, `hardening` is the compaction
  !! pressure p_c (`css_compaction`, applied to the trial stress before the return): raised to
  !! the p' of the step's start before it and to the returned p' after it, 0 once the particle
  !! has lost all its effective stress or is suspended; without it, no compaction.
  !! For the critical-state sand with `mat%css%tension_gap`, `gap` is the particle's volumetric
  !! gap (`css_tension_gap`), applied to the trial stress after the densification and before
  !! the compaction and the return; 0 in a suspension (the packing's own porosity rules there);
  !! not applied before `plastic_start`.
  !! With `mat%elastic_only` (`material_at` before `&solid plastic_start`) the stress is the
  !! model's elastic trial stress: linear (lambda, mu) for Mohr-Coulomb and the sand, the
  !! pressure-dependent law of Cam-Clay (p_c set but not hardened), limited to the yield
  !! surface's apex (`apex_limit`); no plastic strain.
  !! Mohr-Coulomb and the sand use the Lame constants of the stress at the start of the step
  !! (`current_moduli`, `&solid modulus_exponent`) for the trial stress, the densification's
  !! K d eps_vd, tau_xy / G and the return.
  pure subroutine constitutive_update(mat, f, l, dt, stress_unrot, stress, plastic_strain, &
    hardening, cyclic, gap)
    type(material_t), intent(in) :: mat              !< material
    real(wp), intent(in) :: f(3, 3)                  !< deformation gradient F^{n+1}
    real(wp), intent(in) :: l(3, 3)                  !< velocity gradient [1/s]
    real(wp), intent(in) :: dt                       !< step [s]
    real(wp), intent(inout) :: stress_unrot(6)       !< stress in the rotated frame [Pa]
    real(wp), intent(inout) :: stress(6)             !< Cauchy stress [Pa]
    real(wp), intent(inout) :: plastic_strain        !< equivalent plastic strain [-]
    !> Cam-Clay's preconsolidation or the sand's compaction pressure p_c [Pa]
    real(wp), intent(inout), optional :: hardening
    real(wp), intent(inout), optional :: cyclic(css_n_cyclic)  !< sand's cyclic state
    real(wp), intent(inout), optional :: gap         !< sand's volumetric gap [-]
    real(wp) :: r(3, 3), deps(6), dep, pc, devd, dgamma, lam, mu, psi, p_start, p_end, phi, kb
    select case (mat%model)
    case (model_neo_hookean)
      stress = neo_hookean_stress(mat%lambda, mat%mu, f)
      r = polar_rotation(f)
      stress_unrot = rotate_to(r, stress)
    case (model_linear_elastic, model_mohr_coulomb, model_critical_state_sand, model_cam_clay)
      if (det3(f) > mat%j_loose) then
        ! loose: the grains are out of contact (a suspension), no effective stress; the
        ! stress grows again from zero once the particle compacts below j_loose (the sand's
        ! compaction along its line from p_c = 0)
        stress_unrot = 0.0_wp
        stress = 0.0_wp
        if (mat%model == model_critical_state_sand .and. present(hardening)) hardening = 0.0_wp
        if (present(gap)) gap = 0.0_wp
        return
      end if
      r = polar_rotation(f)                                  ! eq. 12
      deps = rotate_to(r, mat_to_sym(l) * dt)                ! eq. 14
      if (mat%model == model_cam_clay) then
        pc = 0.0_wp
        if (present(hardening)) pc = hardening
        call mcc_update(mat%mcc, deps, mat%mcc%v0 * det3(f), stress_unrot, pc, dep, &
          mat%elastic_only)
        if (present(hardening)) hardening = pc
        plastic_strain = plastic_strain + dep
        stress = rotate_from(r, stress_unrot)                ! eq. 15
        return
      end if
      call current_moduli(mat, stress_unrot, lam, mu)       ! at the start of the step
      p_start = mean_pressure(stress_unrot)
      dgamma = 2.0_wp * deps(4)                                           ! gamma_xy
      if (mat%model == model_critical_state_sand .and. mat%css%elastic_amp .and. &
        mat%css%c1 > 0.0_wp .and. present(cyclic)) then
        ! cycled strain: the elastic gamma_xy^e = tau_xy / G of the trial stress, from the
        ! initial stress's value (a fresh state starts there, not at zero)
        if (all(cyclic == 0.0_wp)) cyclic(css_gamma:css_gamma_ext) = stress_unrot(4) / mu
        dgamma = stress_unrot(4) / mu + dgamma - cyclic(css_gamma)
      end if
      stress_unrot = stress_unrot + elastic_increment(lam, mu, deps)
      ! with `elastic_only` (elastic gravity loading, `&solid plastic_start`) the trial stress
      ! stands, within the yield surface's apex: no densification, no return
      if (mat%elastic_only) call apex_limit(mat, stress_unrot)
      if (mat%model == model_critical_state_sand .and. .not. mat%elastic_only) then
        kb = lam + 2.0_wp * mu / 3.0_wp                     ! the skeleton's bulk modulus
        if (mat%css%c1 > 0.0_wp .and. present(cyclic)) then
          call css_densify(mat%css, dgamma, dt, cyclic, devd)
          stress_unrot(1:3) = stress_unrot(1:3) + kb * devd
        end if
        if (mat%css%tension_gap .and. present(gap)) call css_tension_gap(kb, stress_unrot, gap)
        phi = mat%solid_fraction0 / det3(f)
        if (mat%css%lambda_c > 0.0_wp .and. present(hardening)) then
          ! p_c at least the p' of the step's start, then the compaction of the trial stress
          hardening = max(hardening, p_start)
          call css_compaction(mat%css, kb, phi, stress_unrot, hardening)
        end if
        call css_return(mat%css, lam, mu, phi, dt, stress_unrot, dep)
        plastic_strain = plastic_strain + dep
        if (mat%css%lambda_c > 0.0_wp .and. present(hardening)) then
          ! p_c follows p' up; a packing that flows in shear keeps no memory of its past
          ! consolidation (p_c = p'), nor one that lost all its effective stress (0)
          p_end = max(mean_pressure(stress_unrot), 0.0_wp)
          hardening = merge(p_end, max(hardening, p_end), dep > 0.0_wp)
          if (p_end <= 0.0_wp) hardening = 0.0_wp
        end if
      else if (mat%model == model_mohr_coulomb .and. .not. mat%elastic_only) then
        ! contractant sand at its densest packing: plastic flow without volume change
        psi = mat%mc%psi
        if (psi < 0.0_wp .and. det3(f) <= mat%j_dense) psi = 0.0_wp
        call mc_return(mat%mc, lam, mu, psi, stress_unrot, dep)  ! eq. 17
        plastic_strain = plastic_strain + dep
      end if
      stress = rotate_from(r, stress_unrot)                  ! eq. 15
    case default
      ! rigid: no stress
    end select
  end subroutine constitutive_update

  !> The one plastic rule of the elastic phase (`elastic_only`): no mean stress beyond the apex
  !! of the yield surface, where the model has no shear strength either. A trial stress `sig`
  !! [Pa] (tension positive) whose mean stress passes the apex becomes the apex stress: zero
  !! for the critical-state sand (p' <= 0, the no-tension rule of `css_return`), the isotropic
  !! tension c cot(phi) for Mohr-Coulomb with phi > 0 (its apex in `mc_return`). Modified
  !! Cam-Clay's elastic law has no tension (p' >= 0, `mcc_update`); the elastic model has no
  !! apex. Without it, a cohesionless skeleton would carry tension at the free surface.
  pure subroutine apex_limit(mat, sig)
    type(material_t), intent(in) :: mat  !< material
    real(wp), intent(inout) :: sig(6)    !< trial stress in, limited stress out [Pa]
    real(wp) :: apex
    select case (mat%model)
    case (model_critical_state_sand)
      apex = 0.0_wp
    case (model_mohr_coulomb)
      if (mat%mc%sin_phi <= 0.0_wp) return
      apex = mat%mc%cohesion * mat%mc%cos_phi / mat%mc%sin_phi
    case default
      return
    end select
    if (-mean_pressure(sig) < apex) return   ! the mean stress, tension positive
    sig(1:3) = apex
    sig(4:6) = 0.0_wp
  end subroutine apex_limit
end module mpm_constitutive
