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
  !! viscosity (absent or <= 0: none). Each face's stress is computed once per row of faces
  !! (`row_stress`, loops over the row that vectorise): along x a cell's low and high faces are
  !! neighbours in the same row, along y the high faces of one row are the low faces of the
  !! next (kept), along z both rows of faces are computed. The rows are the state's work
  !! storage (`ice_work_t`): nothing is allocated here.
  subroutine ice_viscous_sources(state, grid, m, dt, mom, heat, smagorinsky)
    type(ice_state_t), intent(inout) :: state  !< fluids (`eddy_viscosity`, `work`: work)
    type(grid_t), intent(in) :: grid           !< block geometry
    integer, intent(in) :: m                   !< fluid
    real(wp), intent(in) :: dt                 !< time step [s]
    real(wp), intent(inout) :: mom(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):, :) !< momentum [kg m/s]
    real(wp), intent(inout) :: heat(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):)   !< energy [J]
    real(wp), intent(in), optional :: smagorinsky  !< Smagorinsky constant C_s [-]
    real(wp) :: cs
    cs = 0.0_wp
    if (present(smagorinsky)) cs = smagorinsky
    call viscous_rows(state, grid, m, dt, mom, heat, cs, state%work%tau_lo, state%work%tau_hi, &
      state%work%stress)
  end subroutine ice_viscous_sources

  !> `ice_viscous_sources` with its rows as explicit-shape arguments (from the work storage,
  !! which is at least this large; not referenced through `state` here).
  subroutine viscous_rows(state, grid, m, dt, mom, heat, cs, tau_lo, tau_hi, work)
    type(ice_state_t), intent(inout) :: state  !< fluids (`eddy_viscosity`: work)
    type(grid_t), intent(in) :: grid           !< block geometry
    integer, intent(in) :: m                   !< fluid
    real(wp), intent(in) :: dt                 !< time step [s]
    real(wp), intent(inout) :: mom(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):, :) !< momentum [kg m/s]
    real(wp), intent(inout) :: heat(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):)   !< energy [J]
    real(wp), intent(in) :: cs                 !< Smagorinsky constant C_s [-] (<= 0: none)
    ! the stresses of a row of faces (face i between cells i - o and i): the low and the high
    ! faces of the row of cells, and the work of `row_stress`
    real(wp), intent(inout) :: tau_lo(grid%lo(1):grid%hi(1) + 1, 3) !< low faces [Pa]
    real(wp), intent(inout) :: tau_hi(grid%lo(1):grid%hi(1) + 1, 3) !< high faces [Pa]
    real(wp), intent(inout) :: work(grid%lo(1):grid%hi(1) + 1, 8)   !< `row_stress` work
    integer :: d, i, j, k, o(3), c, i1, i2
    real(wp) :: area, k_lo, k_hi, phi_lo, phi_hi
    logical :: momentum

    i1 = grid%lo(1)
    i2 = grid%hi(1)
    associate (f => state%fluid(m))
      momentum = f%viscosity > 0.0_wp .or. cs > 0.0_wp
      if (.not. momentum .and. f%conductivity <= 0.0_wp) return
      ! the eddy viscosity (opt-in model) needs the strain rate of every cell first
      if (cs > 0.0_wp) call ice_eddy_viscosity(state, grid, m, cs, state%eddy_viscosity)
      do d = 1, 3
        if (.not. sweep_direction(grid, d, o, area)) cycle
        if (momentum) then
          do k = grid%lo(3), grid%hi(3)
            do j = grid%lo(2), grid%hi(2)
              select case (d)
              case (1)
                call row_stress(state, grid, m, cs, d, j, k, i1, i2 + 1, tau_lo, work)
                do c = 1, 3
                  do i = i1, i2
                    mom(i, j, k, c) = mom(i, j, k, c) + dt * area * (tau_lo(i + 1, c) - &
                      tau_lo(i, c))
                  end do
                end do
              case (2)
                if (j == grid%lo(2)) then
                  call row_stress(state, grid, m, cs, d, j, k, i1, i2, tau_lo, work)
                else
                  tau_lo(i1:i2, :) = tau_hi(i1:i2, :)
                end if
                call row_stress(state, grid, m, cs, d, j + 1, k, i1, i2, tau_hi, work)
              case default
                call row_stress(state, grid, m, cs, d, j, k, i1, i2, tau_lo, work)
                call row_stress(state, grid, m, cs, d, j, k + 1, i1, i2, tau_hi, work)
              end select
              if (d == 1) cycle
              do c = 1, 3
                do i = i1, i2
                  mom(i, j, k, c) = mom(i, j, k, c) + dt * area * (tau_hi(i, c) - tau_lo(i, c))
                end do
              end do
            end do
          end do
        end if
        if (f%conductivity <= 0.0_wp) cycle
        do k = grid%lo(3), grid%hi(3)
          do j = grid%lo(2), grid%hi(2)
            do i = grid%lo(1), grid%hi(1)
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
  end subroutine viscous_rows

  !> tau_c,dn (c = 1..3) [Pa] of fluid m on the faces of normal `dn` between the cells
  !! (i, j, k) - o and (i, j, k), i = i1..i2 (o the unit offset along dn), into tau(i, c)
  !! (module header): the face coefficient is the harmonic mean of the two cells' phi mu_e, the
  !! normal derivatives come from the compact difference, those along another active axis e
  !! from the mean of the two cells' central differences; 0 where the coefficient is 0. Each
  !! pass runs over the whole row (contiguous along x, so the loops vectorise).
  pure subroutine row_stress(state, grid, m, cs, dn, j, k, i1, i2, tau, work)
    type(ice_state_t), intent(in) :: state  !< fluids (`eddy_viscosity` with cs > 0)
    type(grid_t), intent(in) :: grid        !< block geometry
    integer, intent(in) :: m                !< fluid
    real(wp), intent(in) :: cs              !< Smagorinsky constant C_s [-] (<= 0: none)
    integer, intent(in) :: dn               !< face normal
    integer, intent(in) :: j, k             !< the row's high cells (i, j, k)
    integer, intent(in) :: i1, i2           !< faces of the row
    real(wp), intent(inout) :: tau(grid%lo(1):, :)  !< stresses tau(i, c) [Pa] (i1..i2 written)
    !> work: (face coefficient, normal derivatives (3), transverse (3), divergence) per face
    real(wp), intent(inout) :: work(grid%lo(1):, :)
    integer :: i, c, e, o(3), oe(3)
    real(wp) :: a, b, cen_dn, cen_e
    integer, parameter :: w_mu = 1, w_normal = 2, w_trans = 5, w_div = 8
    o = 0
    o(dn) = 1
    associate (vel => state%fluid(m)%vel, phi => state%fluid(m)%vfrac, &
      mu => state%fluid(m)%viscosity, sv => state%fluid(m)%spvol, nu_t => state%eddy_viscosity)
      do i = i1, i2
        a = phi(i - o(1), j - o(2), k - o(3)) * mu
        b = phi(i, j, k) * mu
        if (cs > 0.0_wp) then
          if (sv(i - o(1), j - o(2), k - o(3)) > 0.0_wp) a = a + phi(i - o(1), j - o(2), &
            k - o(3)) * nu_t(i - o(1), j - o(2), k - o(3)) / sv(i - o(1), j - o(2), k - o(3))
          if (sv(i, j, k) > 0.0_wp) b = b + phi(i, j, k) * nu_t(i, j, k) / sv(i, j, k)
        end if
        work(i, w_mu) = face_mean(a, b)
      end do
      ! normal(c) = d u_c / d x_dn; transverse(e) = d u_dn / d x_e (e /= dn, active)
      do c = 1, 3
        do i = i1, i2
          work(i, w_normal + c - 1) = (vel(i, j, k, c) - vel(i - o(1), j - o(2), k - o(3), c)) / &
            grid%dx(dn)
          work(i, w_trans + c - 1) = 0.0_wp
        end do
      end do
      work(i1:i2, w_div) = work(i1:i2, w_normal + dn - 1)
      do e = 1, 3
        if (e == dn .or. .not. grid%active(e)) cycle
        oe = 0
        oe(e) = 1
        ! d u / d x_e on the face: the mean of the two cells' central differences
        do i = i1, i2
          cen_dn = 0.25_wp * (vel(i + oe(1), j + oe(2), k + oe(3), dn) - &
            vel(i - oe(1), j - oe(2), k - oe(3), dn) + &
            vel(i - o(1) + oe(1), j - o(2) + oe(2), k - o(3) + oe(3), dn) - &
            vel(i - o(1) - oe(1), j - o(2) - oe(2), k - o(3) - oe(3), dn)) / grid%dx(e)
          cen_e = 0.25_wp * (vel(i + oe(1), j + oe(2), k + oe(3), e) - &
            vel(i - oe(1), j - oe(2), k - oe(3), e) + &
            vel(i - o(1) + oe(1), j - o(2) + oe(2), k - o(3) + oe(3), e) - &
            vel(i - o(1) - oe(1), j - o(2) - oe(2), k - o(3) - oe(3), e)) / grid%dx(e)
          work(i, w_trans + e - 1) = cen_dn
          work(i, w_div) = work(i, w_div) + cen_e
        end do
      end do
    end associate
    ! tau_c,dn = mu (d u_c/d x_dn + d u_dn/d x_c) - (2/3) mu div u delta_c,dn
    do c = 1, 3
      do i = i1, i2
        tau(i, c) = merge(0.0_wp, work(i, w_mu) * (work(i, w_normal + c - 1) + &
          work(i, w_trans + c - 1)), work(i, w_mu) <= 0.0_wp)
      end do
    end do
    do i = i1, i2
      tau(i, dn) = merge(0.0_wp, work(i, w_mu) * (2.0_wp * work(i, w_normal + dn - 1) - &
        2.0_wp / 3.0_wp * work(i, w_div)), work(i, w_mu) <= 0.0_wp)
    end do
  end subroutine row_stress

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
