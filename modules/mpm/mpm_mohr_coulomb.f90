!> Mohr-Coulomb elastic-perfectly-plastic model with non-associated flow (eq. 17), return mapping
!! in principal stresses (plane, edge and apex returns) and an optional tension cut-off.
!!
!! Sign convention: tension positive, principal stresses s1 >= s2 >= s3. Eq. 17 is printed for
!! compression positive; in tension-positive stresses it reads
!!   f = (s1 - s3) + (s1 + s3) sin(phi) - 2 c cos(phi),
!!   g = (s1 - s3) + (s1 + s3) sin(psi)   (+ const).
!! Return (elastic predictor, isotropic elasticity, so principal directions are fixed):
!! 1. plane: s = s_tr - dgam D b, dgam = f(s_tr) / (a.D b), a = df/ds, b = dg/ds;
!! 2. if the order s1 >= s2 >= s3 breaks: edge s1 = s2 (planes (1,3) and (2,3)) or s2 = s3
!!    (planes (1,3) and (1,2)): two multipliers from a 2x2 system;
!! 3. if an edge multiplier is negative or the edge passes the apex: apex s = c cot(phi) I.
!! Tension cut-off (optional): afterwards every principal stress above the tensile strength is
!! set to it (a simplification, not a consistent multi-surface return; see docs/mpm.md).
module mpm_mohr_coulomb
  use mpmice_kinds, only: wp
  use mpm_tensor, only: sym_eigen, mat_to_sym, mul3
  implicit none
  private

  public :: mc_params_t, mc_params, mc_return, mc_yield

  !> Parameters of the model (the elastic constants are arguments of `mc_return`: a particle's
  !! current ones, `mpm_constitutive` current_moduli); made by `mc_params`, which also sets the
  !! angles' sines and cosine that every return reads.
  type :: mc_params_t
    real(wp) :: cohesion = 0.0_wp         !< c' [Pa]
    real(wp) :: phi = 0.0_wp              !< friction angle phi' [rad]
    real(wp) :: psi = 0.0_wp              !< dilation angle psi' [rad]
    logical :: tension_cutoff = .false.   !< cap principal stresses at `tensile_strength`
    real(wp) :: tensile_strength = 0.0_wp !< tensile strength [Pa]
    real(wp) :: sin_phi = 0.0_wp          !< sin(phi)
    real(wp) :: cos_phi = 1.0_wp          !< cos(phi)
    real(wp) :: sin_psi = 0.0_wp          !< sin(psi)
  end type mc_params_t

  real(wp), parameter :: order_tol = 1.0e-12_wp  !< relative tolerance of the principal order

contains

  !> The parameters c' [Pa], phi', psi' [rad], the tension cut-off and its strength [Pa].
  pure function mc_params(cohesion, phi, psi, tension_cutoff, tensile_strength) result(p)
    real(wp), intent(in) :: cohesion           !< c' [Pa]
    real(wp), intent(in) :: phi                !< friction angle [rad]
    real(wp), intent(in) :: psi                !< dilation angle [rad]
    logical, intent(in) :: tension_cutoff      !< tension cut-off on
    real(wp), intent(in) :: tensile_strength   !< tensile strength [Pa]
    type(mc_params_t) :: p
    p%cohesion = cohesion
    p%phi = phi
    p%psi = psi
    p%tension_cutoff = tension_cutoff
    p%tensile_strength = tensile_strength
    p%sin_phi = sin(phi)
    p%cos_phi = cos(phi)
    p%sin_psi = sin(psi)
  end function mc_params

  !> Yield function f [Pa] of eq. 17 (tension positive) at principal stresses s(1) >= s(2) >= s(3).
  pure real(wp) function mc_yield(p, s) result(f)
    type(mc_params_t), intent(in) :: p  !< parameters
    real(wp), intent(in) :: s(3)        !< principal stresses [Pa]
    f = (s(1) - s(3)) + (s(1) + s(3)) * p%sin_phi - 2.0_wp * p%cohesion * p%cos_phi
  end function mc_yield

  !> Return the trial stress `sig` (xx, yy, zz, xy, yz, xz) [Pa] to the yield surface in place;
  !! `deps_p` is the increment of equivalent plastic strain sqrt(2/3 e_p:e_p), e_p the deviatoric
  !! part of the plastic strain increment [-]. `lam`, `mu`: the Lame constants of the trial
  !! stress; `psi`: the dilation angle in effect (`p%psi`, or 0 where the caller stops dilation).
  pure subroutine mc_return(p, lam, mu, psi, sig, deps_p)
    type(mc_params_t), intent(in) :: p     !< parameters
    real(wp), intent(in) :: lam            !< first Lame constant [Pa]
    real(wp), intent(in) :: mu             !< shear modulus [Pa]
    real(wp), intent(in) :: psi            !< dilation angle psi' in effect [rad]
    real(wp), intent(inout) :: sig(6)      !< trial stress in, returned stress out [Pa]
    real(wp), intent(out) :: deps_p        !< equivalent plastic strain increment [-]
    real(wp) :: s_tr(3), s(3), q(3, 3), qt(3, 3), a(3), b(3), a2(3), b2(3), db(3), db2(3)
    real(wp) :: k, f, f2
    real(wp) :: m11, m12, m21, m22, det, g1, g2, scale, sphi, spsi, de(3), e_mod, nu, tr
    logical :: plastic
    integer :: i

    deps_p = 0.0_wp
    if (clearly_elastic(p, sig)) return
    call sym_eigen(sig, s_tr, q)
    s = s_tr
    sphi = p%sin_phi
    spsi = p%sin_psi
    if (psi /= p%psi) spsi = sin(psi)
    k = 2.0_wp * p%cohesion * p%cos_phi
    scale = max(abs(s_tr(1)), abs(s_tr(3)), k, tiny(1.0_wp))
    f = mc_yield(p, s_tr)
    plastic = f > 1.0e-14_wp * scale
    if (plastic) then
      a = [1.0_wp + sphi, 0.0_wp, -(1.0_wp - sphi)]
      b = [1.0_wp + spsi, 0.0_wp, -(1.0_wp - spsi)]
      db = elastic_principal(lam, mu, b)
      g1 = f / dot_product(a, db)
      s = s_tr - g1 * db
      if (.not. ordered(s, scale)) then
        ! edge: second plane with s2 as the largest (s1 = s2) or as the smallest (s2 = s3)
        if (s(2) > s(1)) then
          a2 = [0.0_wp, 1.0_wp + sphi, -(1.0_wp - sphi)]
          b2 = [0.0_wp, 1.0_wp + spsi, -(1.0_wp - spsi)]
        else
          a2 = [1.0_wp + sphi, -(1.0_wp - sphi), 0.0_wp]
          b2 = [1.0_wp + spsi, -(1.0_wp - spsi), 0.0_wp]
        end if
        db2 = elastic_principal(lam, mu, b2)
        f2 = dot_product(a2, s_tr) - k
        m11 = dot_product(a, db)
        m12 = dot_product(a, db2)
        m21 = dot_product(a2, db)
        m22 = dot_product(a2, db2)
        det = m11 * m22 - m12 * m21
        g1 = (f * m22 - m12 * f2) / det
        g2 = (m11 * f2 - m21 * f) / det
        s = s_tr - g1 * db - g2 * db2
        if (g1 < 0.0_wp .or. g2 < 0.0_wp .or. .not. ordered(s, scale)) then
          ! apex (phi > 0 required; with phi = 0 the surface has no apex)
          if (sphi > 0.0_wp) then
            s = p%cohesion * p%cos_phi / sphi
          end if
        end if
      end if
    end if
    if (p%tension_cutoff) then
      do i = 1, 3
        if (s(i) > p%tensile_strength) then
          s(i) = p%tensile_strength
          plastic = .true.
        end if
      end do
    end if
    if (.not. plastic) return
    ! plastic strain = elastic compliance applied to the stress returned
    e_mod = mu * (3.0_wp * lam + 2.0_wp * mu) / (lam + mu)
    nu = lam / (2.0_wp * (lam + mu))
    tr = sum(s_tr - s)
    de = ((1.0_wp + nu) * (s_tr - s) - nu * tr) / e_mod
    tr = sum(de) / 3.0_wp
    deps_p = sqrt(2.0_wp / 3.0_wp * sum((de - tr)**2))
    ! the transpose in a local (an expression argument is packed into a heap temporary)
    qt = transpose(q)
    sig = mat_to_sym(mul3(q, mul3(diag3(s), qt)))
  end subroutine mc_return

  !> True when the stress `sig` (xx, yy, zz, xy, yz, xz) lies inside the yield surface (and below
  !! the tensile strength, with the cut-off) by more than 1e-10 of its scale, decided without the
  !! eigen-decomposition: for a stress with yz = xz = 0 (every plane-strain and axisymmetric
  !! state) the principal values are zz and the closed-form pair (xx + yy)/2 +- sqrt(((xx - yy)/2)^2
  !! + xy^2), within a few ulp of `sym_eigen`'s, far inside the margin; `mc_return` then leaves
  !! the stress unchanged exactly as after the decomposition. Other stresses: false.
  pure logical function clearly_elastic(p, sig)
    type(mc_params_t), intent(in) :: p   !< parameters
    real(wp), intent(in) :: sig(6)       !< trial stress [Pa]
    real(wp), parameter :: margin = 1.0e-10_wp
    real(wp) :: mean, radius, s1, s3, k, scale
    clearly_elastic = .false.
    if (sig(5) /= 0.0_wp .or. sig(6) /= 0.0_wp) return
    mean = 0.5_wp * (sig(1) + sig(2))
    radius = sqrt((0.5_wp * (sig(1) - sig(2)))**2 + sig(4)**2)
    s1 = max(mean + radius, sig(3))
    s3 = min(mean - radius, sig(3))
    k = 2.0_wp * p%cohesion * p%cos_phi
    scale = max(abs(sig(1)), abs(sig(2)), abs(sig(3)), abs(sig(4)), k, tiny(1.0_wp))
    if (p%tension_cutoff) then
      if (s1 > p%tensile_strength - margin * scale) return
    end if
    clearly_elastic = (s1 - s3) + (s1 + s3) * p%sin_phi - k < -margin * scale
  end function clearly_elastic

  !> Principal-space elastic stiffness applied to `b`: lambda (sum b) 1 + 2 mu b.
  pure function elastic_principal(lam, mu, b) result(db)
    real(wp), intent(in) :: lam         !< first Lame constant [Pa]
    real(wp), intent(in) :: mu          !< shear modulus [Pa]
    real(wp), intent(in) :: b(3)        !< principal strain-like vector
    real(wp) :: db(3)
    db = lam * (b(1) + b(2) + b(3)) + 2.0_wp * mu * b
  end function elastic_principal

  !> True when s(1) >= s(2) >= s(3) within the relative tolerance.
  pure logical function ordered(s, scale)
    real(wp), intent(in) :: s(3)    !< principal stresses [Pa]
    real(wp), intent(in) :: scale   !< stress scale [Pa]
    ordered = s(1) - s(2) >= -order_tol * scale .and. s(2) - s(3) >= -order_tol * scale
  end function ordered

  !> Diagonal matrix.
  pure function diag3(s) result(a)
    real(wp), intent(in) :: s(3)  !< diagonal
    real(wp) :: a(3, 3)
    a = 0.0_wp
    a(1, 1) = s(1)
    a(2, 2) = s(2)
    a(3, 3) = s(3)
  end function diag3
end module mpm_mohr_coulomb
