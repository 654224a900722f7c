!> Explicit viscous momentum and heat-conduction sources of the Lagrangian step (paper eqs. 23-25
!! with the optional Smagorinsky eddy viscosity, and the conduction term of eq. 43, errata E9:
!! q = -k grad T).
!!
!! Momentum: the divergence of the Newtonian stress (eqs. 23-25, Stokes' hypothesis)
!!   tau = mu_e (grad u + grad u^T) - (2/3) mu_e (div u) I,   mu_e = mu + mu_t,
!!   mu_t = rho (C_s Delta)^2 |S|,  |S| = sqrt(2 S:S),  S = (grad u + grad u^T)/2,
!!   Delta = (product of the active dx_d)^(1/ndim)    (Smagorinsky, `&ice smagorinsky`),
!! in flux form: per fluid m, owned cell and component c,
!!   d(M u_c) = dt sum_d A_d [tau_cd]_lo^hi,   d(M e) = dt sum_d A_d [k_f (T_R - T_L)/dx_d]_lo^hi,
!! with tau_cd at a face normal to d from the compact difference (u_R - u_L)/dx_d of the two
!! cells for the normal derivatives and, for the derivatives along another axis e, the mean of
!! the two cells' central differences (u(+e) - u(-e))/(2 dx_e); div u at the face likewise.
!! Face coefficients: the harmonic mean of phi (mu + v^-1 nu_t) of the two cells (zero when the
!! fluid is absent on either side; v^-1 nu_t = rho_micro (C_s Delta)^2 |S| is the fluid's eddy
!! viscosity, so phi mu_t = rho_bar (C_s Delta)^2 |S|), and of phi k. For constant mu this is
!! mu lap(u) + (mu/3) grad(div u) to second order; for a variable mu_e the cross terms
!! d_d(mu_e d_c u_d) are kept. The strain rate |S| of a cell uses the central differences of
!! its neighbours' velocities. Walls: the mirrored ghosts (no slip: all components odd) give the
!! wall shear stress; adiabatic walls carry no heat. Needs velocity and temperature valid in one
!! ghost layer (edges and corners included) and, with Smagorinsky, the velocity in two. The
!! stability limit of the explicit update is `ice_viscous_dt`. Viscous heating: the kinetic
!! energy the stress removes reappears as heat through the energy correction of the Lagrangian
!! step (`ice_lagrangian`, ICE scene without a solid phase).
module ice_viscous
  use mpmice_kinds, only: wp
  use mpmice_errors, only: fatal
  use grid_layout, only: grid_t
  use grid_sweep, only: sweep_direction
  use ice_state, only: ice_state_t
  use ice_solid_view, only: ice_solid_view_t
  implicit none
  private

  public :: ice_viscous_sources, ice_viscous_dt, ice_eddy_viscosity, stress_factor, face_mean
  public :: face_conduction

  !> Largest eigenvalue of the discrete stress divergence over that of the Laplacian form mu lap:
  !! the symbol is -(Lambda I + M/3), Lambda the Laplacian's, M = diag(lambda_c - s_c^2) + s s^T
  !! with lambda_c = 4 sin^2(theta_c/2)/dx_c^2 >= s_c^2 = sin^2(theta_c)/dx_c^2, so its
  !! eigenvalues lie in [Lambda, 4 Lambda / 3] (4/3 reached by the longitudinal mode theta = pi).
  real(wp), parameter :: stress_factor = 4.0_wp / 3.0_wp

contains

  !> Add dt times the viscous force [kg m/s] to `mom(:,:,:,1:3)` and dt times the conducted
  !! heat [J] to `heat(:,:,:)` of fluid m (owned cells). `smagorinsky`: C_s of the eddy
  !! viscosity (absent or <= 0: none). Each face's stress is computed once: a cell's low-face
  !! stress is its low neighbour's high-face stress, carried along the row (normal 1) or from
  !! the previous row (normal 2); normal 3 computes both faces of a cell.
  subroutine ice_viscous_sources(state, grid, m, dt, mom, heat, smagorinsky)
    type(ice_state_t), intent(inout) :: state  !< fluids (`eddy_viscosity`: work)
    type(grid_t), intent(in) :: grid           !< block geometry
    integer, intent(in) :: m                   !< fluid
    real(wp), intent(in) :: dt                 !< time step [s]
    real(wp), intent(inout) :: mom(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):, :) !< momentum [kg m/s]
    real(wp), intent(inout) :: heat(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):)   !< energy [J]
    real(wp), intent(in), optional :: smagorinsky  !< Smagorinsky constant C_s [-]
    integer :: d, i, j, k, o(3), c
    real(wp) :: area, k_lo, k_hi, phi_lo, phi_hi, cs, flux_lo(3), flux_hi(3)
    ! the high-face stresses of the previous row (normal 2)
    real(wp) :: row_flux(3, grid%lo(1):grid%hi(1))
    logical :: momentum

    cs = 0.0_wp
    if (present(smagorinsky)) cs = smagorinsky
    associate (f => state%fluid(m))
      momentum = f%viscosity > 0.0_wp .or. cs > 0.0_wp
      if (.not. momentum .and. f%conductivity <= 0.0_wp) return
      ! the eddy viscosity (opt-in model) needs the strain rate of every cell first
      if (cs > 0.0_wp) call ice_eddy_viscosity(state, grid, m, cs, state%eddy_viscosity)
      do d = 1, 3
        if (.not. sweep_direction(grid, d, o, area)) cycle
        do k = grid%lo(3), grid%hi(3)
          do j = grid%lo(2), grid%hi(2)
            do i = grid%lo(1), grid%hi(1)
              if (momentum) then
                if (d == 1 .and. i > grid%lo(1)) then
                  flux_lo = flux_hi
                else if (d == 2 .and. j > grid%lo(2)) then
                  flux_lo = row_flux(:, i)
                else
                  flux_lo = stress_between(d, [i - o(1), j - o(2), k - o(3)], [i, j, k])
                end if
                flux_hi = stress_between(d, [i, j, k], [i + o(1), j + o(2), k + o(3)])
                if (d == 2) row_flux(:, i) = flux_hi
                do c = 1, 3
                  mom(i, j, k, c) = mom(i, j, k, c) + dt * area * (flux_hi(c) - flux_lo(c))
                end do
              end if
              if (f%conductivity <= 0.0_wp) cycle
              phi_lo = face_mean(f%vfrac(i - o(1), j - o(2), k - o(3)), f%vfrac(i, j, k))
              phi_hi = face_mean(f%vfrac(i, j, k), f%vfrac(i + o(1), j + o(2), k + o(3)))
              k_lo = phi_lo * f%conductivity
              k_hi = phi_hi * f%conductivity
              heat(i, j, k) = heat(i, j, k) + face_conduction(dt * area / grid%dx(d), k_lo, k_hi, &
                f%temp(i - o(1), j - o(2), k - o(3)), f%temp(i, j, k), &
                f%temp(i + o(1), j + o(2), k + o(3)))
            end do
          end do
        end do
      end do
    end associate

  contains

    !> tau_c,dn [Pa] on the face of normal `dn` between cells `l` and `h`, with the harmonic
    !! mean of their cell coefficients.
    function stress_between(dn, l, h) result(tau)
      integer, intent(in) :: dn    !< face normal
      integer, intent(in) :: l(3)  !< low cell
      integer, intent(in) :: h(3)  !< high cell
      real(wp) :: tau(3)           !< stress components [Pa]
      tau = face_stress(state%fluid(m)%vel, grid, dn, l, h, &
        face_mean(cell_coefficient(l(1), l(2), l(3)), cell_coefficient(h(1), h(2), h(3))))
    end function stress_between

    !> The cell coefficient phi mu_e = phi mu + phi v^-1 nu_t [Pa s] of cell (ic, jc, kc).
    real(wp) function cell_coefficient(ic, jc, kc)
      integer, intent(in) :: ic, jc, kc  !< cell
      associate (f => state%fluid(m))
        cell_coefficient = f%vfrac(ic, jc, kc) * f%viscosity
        if (cs > 0.0_wp) then
          if (f%spvol(ic, jc, kc) > 0.0_wp) cell_coefficient = cell_coefficient + &
            f%vfrac(ic, jc, kc) * state%eddy_viscosity(ic, jc, kc) / f%spvol(ic, jc, kc)
        end if
      end associate
    end function cell_coefficient
  end subroutine ice_viscous_sources

  !> tau_c,dn (c = 1..3) [Pa] on the face of normal `dn` between cells `l` and `h` with the face
  !! coefficient `mu_f` [Pa s] (module header): the normal derivatives from the compact
  !! difference, those along another active axis e from the mean of the two cells' central
  !! differences.
  pure function face_stress(vel, grid, dn, l, h, mu_f) result(tau)
    type(grid_t), intent(in) :: grid  !< block geometry
    real(wp), intent(in) :: vel(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):, :) !< cell velocity [m/s]
    integer, intent(in) :: dn         !< face normal
    integer, intent(in) :: l(3)       !< the face's low cell
    integer, intent(in) :: h(3)       !< the face's high cell
    real(wp), intent(in) :: mu_f      !< face coefficient [Pa s]
    real(wp) :: tau(3)                !< stress components tau_c,dn [Pa]
    integer :: e, oe(3)
    real(wp) :: normal(3), transverse(3), div, central(3)
    tau = 0.0_wp
    if (mu_f <= 0.0_wp) return
    ! normal(c) = d u_c / d x_dn; transverse(e) = d u_dn / d x_e (e /= dn, active)
    normal = (vel(h(1), h(2), h(3), :) - vel(l(1), l(2), l(3), :)) / grid%dx(dn)
    transverse = 0.0_wp
    div = normal(dn)
    do e = 1, 3
      if (e == dn .or. .not. grid%active(e)) cycle
      oe = 0
      oe(e) = 1
      ! d u / d x_e on the face: the mean of the two cells' central differences
      central = 0.25_wp * (vel(h(1) + oe(1), h(2) + oe(2), h(3) + oe(3), :) - &
        vel(h(1) - oe(1), h(2) - oe(2), h(3) - oe(3), :) + &
        vel(l(1) + oe(1), l(2) + oe(2), l(3) + oe(3), :) - &
        vel(l(1) - oe(1), l(2) - oe(2), l(3) - oe(3), :)) / grid%dx(e)
      transverse(e) = central(dn)
      div = div + central(e)
    end do
    ! tau_c,dn = mu (d u_c/d x_dn + d u_dn/d x_c) - (2/3) mu div u delta_c,dn
    tau = mu_f * (normal + transverse)
    tau(dn) = mu_f * (2.0_wp * normal(dn) - 2.0_wp / 3.0_wp * div)
  end function face_stress

  !> Kinematic Smagorinsky eddy viscosity nu_t = (C_s Delta)^2 |S| [m^2/s] of fluid m on the owned
  !! cells and one ghost layer (0 beyond), from the central differences of the cell velocities
  !! (module header). Needs the velocity valid in two ghost layers.
  subroutine ice_eddy_viscosity(state, grid, m, cs, nu_t)
    type(ice_state_t), intent(in) :: state   !< fluids
    type(grid_t), intent(in) :: grid         !< block geometry
    integer, intent(in) :: m                 !< fluid
    real(wp), intent(in) :: cs               !< Smagorinsky constant C_s [-]
    real(wp), intent(out) :: nu_t(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !< [m^2/s]
    integer :: i, j, k, a, b, lo(3), hi(3), o(3)
    real(wp) :: g(3, 3), s2, delta2
    nu_t = 0.0_wp
    if (any(grid%active .and. grid%ng < 2)) call fatal('ice_eddy_viscosity: the Smagorinsky ' // &
      'model needs two ghost layers')
    delta2 = product(merge(grid%dx, 1.0_wp, grid%active))**(2.0_wp / real(count(grid%active), wp))
    lo = merge(grid%lo - 1, grid%lo, grid%active)
    hi = merge(grid%hi + 1, grid%hi, grid%active)
    associate (v => state%fluid(m)%vel)
      do k = lo(3), hi(3)
        do j = lo(2), hi(2)
          do i = lo(1), hi(1)
            g = 0.0_wp
            do b = 1, 3
              if (.not. grid%active(b)) cycle
              o = 0
              o(b) = 1
              g(:, b) = (v(i + o(1), j + o(2), k + o(3), :) - v(i - o(1), j - o(2), k - o(3), :)) &
                / (2.0_wp * grid%dx(b))
            end do
            ! 2 S:S with S = (g + g^T)/2
            s2 = 0.0_wp
            do b = 1, 3
              do a = 1, 3
                s2 = s2 + 0.5_wp * (g(a, b) + g(b, a))**2
              end do
            end do
            nu_t(i, j, k) = cs**2 * delta2 * sqrt(s2)
          end do
        end do
      end do
    end associate
  end subroutine ice_eddy_viscosity

  !> Stability limit [s] of the explicit diffusion on this rank: 0.5 / (sum_d 1/dx_d^2) divided
  !! by the largest diffusivity, (4/3) (mu v + nu_t) (momentum: `stress_factor`, nu_t the largest
  !! Smagorinsky eddy viscosity of the fluid when `smagorinsky` > 0) or k v / cv (heat), over
  !! fluids and owned cells (momentum: without the cells holding solid of a coupled scene); huge
  !! when there is no diffusion.
  subroutine ice_viscous_dt(state, grid, dt, smagorinsky, solid)
    type(ice_state_t), intent(inout) :: state  !< fluids (`eddy_viscosity`: work)
    type(grid_t), intent(in) :: grid        !< block geometry
    real(wp), intent(out) :: dt             !< the limit [s]
    real(wp), intent(in), optional :: smagorinsky  !< Smagorinsky constant C_s [-] (<= 0: none)
    !> the solid phase of a coupled scene: its cells do not limit the momentum diffusion
    class(ice_solid_view_t), intent(in), optional :: solid
    real(wp) :: diffusivity, s_all, s_free, rho_min, cs, nu_max
    logical :: with_solid
    integer :: m, i, j, k
    with_solid = present(solid)
    cs = 0.0_wp
    if (present(smagorinsky)) cs = smagorinsky
    diffusivity = 0.0_wp
    do m = 1, state%nfluids
      associate (f => state%fluid(m), lo => grid%lo, hi => grid%hi)
        if (f%viscosity <= 0.0_wp .and. f%conductivity <= 0.0_wp .and. cs <= 0.0_wp) cycle
        if (.not. any(f%rho(lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)) > 0.0_wp)) cycle
        ! cells where the fluid is present, not a trace: the specific volume of a trace
        ! (advected m v over a vanishing m) is not a physical one and must not set the step
        rho_min = 1.0e-6_wp * maxval(f%rho(lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)))
        ! s_all: largest specific volume where the fluid is present (heat); s_free: the same
        ! without the cells holding solid of a coupled scene (momentum): there the coupled step
        ! replaces the fluid's cell velocity by the mean of its face velocities
        ! (mpmice_solid_cells%fluid_face_blend), the explicit viscous update cannot grow, only
        ! the free fluid limits the step; nu_max: the largest eddy viscosity of those free cells
        if (cs > 0.0_wp) call ice_eddy_viscosity(state, grid, m, cs, state%eddy_viscosity)
        s_all = 0.0_wp
        s_free = 0.0_wp
        nu_max = 0.0_wp
        do k = lo(3), hi(3)
          do j = lo(2), hi(2)
            do i = lo(1), hi(1)
              if (f%rho(i, j, k) <= rho_min) cycle
              s_all = max(s_all, f%spvol(i, j, k))
              if (with_solid) then
                if (solid%vfrac(i, j, k) > 0.0_wp) cycle
              end if
              s_free = max(s_free, f%spvol(i, j, k))
              if (cs > 0.0_wp) nu_max = max(nu_max, state%eddy_viscosity(i, j, k))
            end do
          end do
        end do
        diffusivity = max(diffusivity, f%conductivity * s_all / f%eos%cv)
        diffusivity = max(diffusivity, stress_factor * (f%viscosity * s_free + nu_max))
      end associate
    end do
    if (diffusivity > 0.0_wp) then
      dt = 0.5_wp / (sum(merge(1.0_wp / grid%dx**2, 0.0_wp, grid%active)) * diffusivity)
    else
      dt = huge(1.0_wp)
    end if
  end subroutine ice_viscous_dt

  !> Harmonic mean of two non-negative face coefficients (0 when either is 0).
  pure real(wp) function face_mean(a, b)
    real(wp), intent(in) :: a  !< low cell
    real(wp), intent(in) :: b  !< high cell
    if (a > 0.0_wp .and. b > 0.0_wp) then
      face_mean = 2.0_wp * a * b / (a + b)
    else
      face_mean = 0.0_wp
    end if
  end function face_mean

  !> Heat [J] a cell gains by conduction through its low and high faces of one direction (eqs.
  !! 38-39, errata E9): `factor` (k_hi (T_hi - T) - k_lo (T - T_lo)), factor = dt A / dx.
  elemental real(wp) function face_conduction(factor, k_lo, k_hi, t_lo, t, t_hi) result(heat)
    real(wp), intent(in) :: factor  !< dt A / dx [s m]
    real(wp), intent(in) :: k_lo    !< conductance of the low face [W/m/K]
    real(wp), intent(in) :: k_hi    !< conductance of the high face [W/m/K]
    real(wp), intent(in) :: t_lo    !< temperature of the low neighbour [K]
    real(wp), intent(in) :: t       !< temperature of the cell [K]
    real(wp), intent(in) :: t_hi    !< temperature of the high neighbour [K]
    heat = factor * (k_hi * (t_hi - t) - k_lo * (t - t_lo))
  end function face_conduction
end module ice_viscous
