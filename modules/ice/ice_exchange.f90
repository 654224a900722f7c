!> Implicit momentum and heat exchange between the fluids of a cell or face with constant
!! coefficients (paper eqs. 34 and 50-53 written for N fluids, errata E8: beta = dt K v phi).
!!
!! For fluids m, n: beta_mn = dt v_m phi_n K (dimensionless; v_m the intrinsic specific volume,
!! phi_n the volume fraction, K [kg/m^3/s]), so the drag per unit volume is phi_m phi_n K du
!! (Uintah's convention, implementation notes §3). The increments solve
!!   (1 + sum_n beta_mn) du_m - sum_n beta_mn du_n = sum_n beta_mn (u_n - u_m),
!! in closed form for two materials, by elimination without pivoting for three (the matrix is
!! strictly diagonally dominant) and by elimination with pivoting for more (both in
!! `solver_dense`). At faces the same matrix applied to the face specific volumes gives the
!! exchange-modified v_f used by the pressure equation (Uintah's sp_vol_FC). In cells the
!! velocities and, with H > 0, the temperatures (beta = dt H v_m phi_n / cv_m) are exchanged; the
!! kinetic energy the drag removes is added to the internal energies in proportion to mass, so
!! total energy is conserved.
!!
!! The fluids alone: the exchange with a solid phase (one more material, `ice_solid_view_t`) is
!! the exchange layer's (`exchange_solid_phase`), which builds on the pieces made public here
!! (`fill_beta`, `exchange_solve`) and leaves to this module the fluids' own exchange at the faces
!! and cells where the solid takes no part (`exchange_faces_two` and `ice_exchange_cells` with the
!! solid's fraction as their partner's) and the heat exchange with the solid as the fluids'
!! partner.
module ice_exchange
  use mpmice_kinds, only: wp
  use mpmice_errors, only: fatal
  use grid_layout, only: grid_t
  use ice_state, only: ice_state_t, ice_fluid_t
  use ice_face_velocity, only: open_face_sweep
  use solver_dense, only: solve_3, solve_pivoted
  implicit none
  private

  public :: ice_exchange_faces, ice_exchange_cells, exchange_solve, max_n
  public :: fill_beta, exchange_faces_two

  integer, parameter :: max_n = 9  !< most materials: config_materials%max_fluids + the solid

contains

  !> Exchange at the faces of the owned cells: u_f += du and v_f := A^-1 v_f. No-op for one
  !! fluid or K = 0.
  subroutine ice_exchange_faces(state, grid, dt, k_exchange)
    type(ice_state_t), intent(inout) :: state  !< fluids (uface, vface updated)
    type(grid_t), intent(in) :: grid           !< block geometry
    real(wp), intent(in) :: dt                 !< time step [s]
    real(wp), intent(in) :: k_exchange         !< K [kg/m^3/s]
    integer :: d, m, i, j, k, o(3), r(2, 3), nf
    real(wp) :: beta(max_n, max_n), rhs(max_n, 2), phi(max_n), v(max_n), w(max_n)

    nf = state%nfluids
    if (nf < 2 .or. k_exchange <= 0.0_wp) return
    if (nf == 2) then
      call exchange_faces_two(state, grid, dt, k_exchange)
      return
    end if
    do d = 1, 3
      if (.not. open_face_sweep(state, grid, d, o, r)) cycle
      do k = r(1, 3), r(2, 3)
        do j = r(1, 2), r(2, 2)
          do i = r(1, 1), r(2, 1)
            do m = 1, nf
              phi(m) = 0.5_wp * (state%fluid(m)%vfrac(i - o(1), j - o(2), k - o(3)) + &
                state%fluid(m)%vfrac(i, j, k))
              v(m) = state%fluid(m)%vface(i, j, k, d)
              rhs(m, 1) = state%fluid(m)%uface(i, j, k, d)
            end do
            call fill_beta(nf, dt, v, phi, k_exchange, beta)
            rhs(1:nf, 2) = v(1:nf)
            ! one elimination for the velocities (column 1) and the specific volumes (2); the
            ! masses per volume phi / v (a fluid absent at the face: v = 0, none)
            w(1:nf) = merge(phi(1:nf) / max(v(1:nf), tiny(1.0_wp)), 0.0_wp, v(1:nf) > 0.0_wp)
            call exchange_solve(nf, beta, rhs, 2, w, weighted_columns=1)
            do m = 1, nf
              state%fluid(m)%uface(i, j, k, d) = rhs(m, 1)
              state%fluid(m)%vface(i, j, k, d) = rhs(m, 2)
            end do
          end do
        end do
      end do
    end do
  end subroutine ice_exchange_faces

  !> `ice_exchange_faces` for two fluids without a solid phase: the closed-form 2 x 2 solve of
  !! `exchange_solve` (the same arithmetic) as one branch-free sweep per direction over the
  !! open faces (closed domain faces are whole planes, left out of the range).
  !! With `partner_fraction` (the solid fraction of a coupled scene, cell field): only the inner
  !! faces where neither cell holds any; the others are the exchange layer's
  !! (`exchange_fluid_solid`).
  subroutine exchange_faces_two(state, grid, dt, k_exchange, partner_fraction)
    type(ice_state_t), intent(inout) :: state  !< two fluids (uface, vface updated)
    type(grid_t), intent(in) :: grid           !< block geometry
    real(wp), intent(in) :: dt                 !< time step [s]
    real(wp), intent(in) :: k_exchange         !< K [kg/m^3/s]
    !> volume fraction of a partner material sharing the cells [-]
    real(wp), intent(in), optional :: partner_fraction(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):)
    integer :: d, i, j, k, o(3), r(2, 3)

    do d = 1, 3
      if (.not. open_face_sweep(state, grid, d, o, r)) cycle
      if (present(partner_fraction) .and. .not. grid%periodic(d)) then
        r(1, d) = max(r(1, d), 2)
        r(2, d) = min(r(2, d), grid%ncells(d))
      end if
      associate (f1 => state%fluid(1), f2 => state%fluid(2))
        if (present(partner_fraction)) then
          do k = r(1, 3), r(2, 3)
            do j = r(1, 2), r(2, 2)
              do i = r(1, 1), r(2, 1)
                if (.not. (partner_fraction(i - o(1), j - o(2), k - o(3)) <= 0.0_wp .and. &
                  partner_fraction(i, j, k) <= 0.0_wp)) cycle
                call pair_face_exchange(f1, f2, i, j, k, d, o, dt, k_exchange)
              end do
            end do
          end do
        else
          ! branch-free: the sweep vectorises
          do k = r(1, 3), r(2, 3)
            do j = r(1, 2), r(2, 2)
              do i = r(1, 1), r(2, 1)
                call pair_face_exchange(f1, f2, i, j, k, d, o, dt, k_exchange)
              end do
            end do
          end do
        end if
      end associate
    end do
  end subroutine exchange_faces_two

  !> The closed-form 2 x 2 face exchange of `exchange_solve` (A = [1 + b12, -b12; -b21, 1 + b21],
  !! beta_mn = dt v_m,f phi_n,f K with the face mean fractions) applied in place to the face
  !! velocities u and the face specific volumes v of two fluids at the low face of cell (i,j,k)
  !! in direction d.
  pure subroutine pair_face_exchange(f1, f2, i, j, k, d, o, dt, k_exchange)
    type(ice_fluid_t), intent(inout) :: f1, f2 !< the two fluids (uface, vface updated)
    integer, intent(in) :: i, j, k             !< face (low face of cell i,j,k)
    integer, intent(in) :: d                   !< face direction
    integer, intent(in) :: o(3)                !< unit offset along d
    real(wp), intent(in) :: dt                 !< time step [s]
    real(wp), intent(in) :: k_exchange         !< K [kg/m^3/s]
    real(wp) :: phi1, phi2, b12, b21, det, x1, x2
    phi1 = 0.5_wp * (f1%vfrac(i - o(1), j - o(2), k - o(3)) + f1%vfrac(i, j, k))
    phi2 = 0.5_wp * (f2%vfrac(i - o(1), j - o(2), k - o(3)) + f2%vfrac(i, j, k))
    b12 = dt * f1%vface(i, j, k, d) * phi2 * k_exchange
    b21 = dt * f2%vface(i, j, k, d) * phi1 * k_exchange
    det = 1.0_wp + b12 + b21
    associate (u1 => f1%uface(i, j, k, d), u2 => f2%uface(i, j, k, d), &
      v1 => f1%vface(i, j, k, d), v2 => f2%vface(i, j, k, d))
      x1 = u1
      x2 = u2
      u1 = ((1.0_wp + b21) * x1 + b12 * x2) / det
      u2 = (b21 * x1 + (1.0_wp + b12) * x2) / det
      x1 = v1
      x2 = v2
      v1 = ((1.0_wp + b21) * x1 + b12 * x2) / det
      v2 = (b21 * x1 + (1.0_wp + b12) * x2) / det
    end associate
  end subroutine pair_face_exchange

  !> `ice_exchange_cells` for two fluids, no solid and no heat exchange: the closed-form 2 x 2
  !! velocity exchange of `exchange_solve` and the dissipated kinetic energy to the fluids by
  !! mass, with the same arithmetic, in one loop without calls.
  subroutine exchange_cells_two(state, grid, dt, k_exchange)
    type(ice_state_t), intent(inout) :: state  !< two fluids (lag updated)
    type(grid_t), intent(in) :: grid           !< block geometry
    real(wp), intent(in) :: dt                 !< time step [s]
    real(wp), intent(in) :: k_exchange         !< K [kg/m^3/s]
    integer :: i, j, k, c
    real(wp) :: m1, m2, b12, b21, det, x1, x2, u1(3), u2(3), ke_old, ke_new, total_mass

    associate (f1 => state%fluid(1), f2 => state%fluid(2))
      do k = grid%lo(3), grid%hi(3)
        do j = grid%lo(2), grid%hi(2)
          do i = grid%lo(1), grid%hi(1)
            m1 = f1%rho(i, j, k)
            m2 = f2%rho(i, j, k)
            total_mass = m1 + m2
            u1 = f1%lag(i, j, k, 1:3)
            u2 = f2%lag(i, j, k, 1:3)
            ke_old = 0.5_wp * m1 * (u1(1)**2 + u1(2)**2 + u1(3)**2) + &
              0.5_wp * m2 * (u2(1)**2 + u2(2)**2 + u2(3)**2)
            b12 = dt * f1%spvol(i, j, k) * f2%vfrac(i, j, k) * k_exchange
            b21 = dt * f2%spvol(i, j, k) * f1%vfrac(i, j, k) * k_exchange
            det = 1.0_wp + b12 + b21
            do c = 1, 3
              x1 = u1(c)
              x2 = u2(c)
              u1(c) = ((1.0_wp + b21) * x1 + b12 * x2) / det
              u2(c) = (b21 * x1 + (1.0_wp + b12) * x2) / det
            end do
            ke_new = 0.5_wp * m1 * (u1(1)**2 + u1(2)**2 + u1(3)**2) + &
              0.5_wp * m2 * (u2(1)**2 + u2(2)**2 + u2(3)**2)
            f1%lag(i, j, k, 1:3) = u1
            f2%lag(i, j, k, 1:3) = u2
            if (total_mass > 0.0_wp) then
              f1%lag(i, j, k, 4) = f1%lag(i, j, k, 4) + (ke_old - ke_new) / total_mass
              f2%lag(i, j, k, 4) = f2%lag(i, j, k, 4) + (ke_old - ke_new) / total_mass
            end if
          end do
        end do
      end do
    end associate
  end subroutine exchange_cells_two

  !> beta_mn = dt v_m phi_n K among the fluids 1..nf (K = `k_fluid`), zero diagonal; the
  !! exchange with a solid phase adds its row and column (`exchange_solid_phase`).
  pure subroutine fill_beta(nf, dt, v, phi, k_fluid, beta)
    integer, intent(in) :: nf                   !< fluids
    real(wp), intent(in) :: dt                  !< time step [s]
    real(wp), intent(in) :: v(max_n)            !< specific volumes [m^3/kg]
    real(wp), intent(in) :: phi(max_n)          !< volume fractions [-]
    real(wp), intent(in) :: k_fluid             !< fluid-fluid K [kg/m^3/s]
    real(wp), intent(out) :: beta(max_n, max_n) !< exchange coefficients, zero diagonal
    integer :: m, n
    do m = 1, nf
      do n = 1, nf
        beta(m, n) = dt * v(m) * phi(n) * k_fluid
      end do
      beta(m, m) = 0.0_wp
    end do
  end subroutine fill_beta

  !> Exchange of the Lagrangian velocities (and temperatures when h_exchange > 0) in the owned
  !! cells, `lag(:,:,:,1:4)` updated. No-op for one fluid. With a heat partner (the solid of a
  !! coupled scene: its fraction, heat capacity per volume and temperature, and H_fs): the
  !! velocities only where the cell holds none of it (the exchange layer drags the fluids toward
  !! the solid elsewhere, `exchange_fluid_solid`), the heat with it in every cell
  !! (`exchange_heat`).
  subroutine ice_exchange_cells(state, grid, dt, k_exchange, h_exchange, partner_fraction, &
      h_partner, partner_capacity, partner_temperature)
    type(ice_state_t), intent(inout) :: state  !< fluids (lag updated)
    type(grid_t), intent(in) :: grid           !< block geometry
    real(wp), intent(in) :: dt                 !< time step [s]
    real(wp), intent(in) :: k_exchange         !< K [kg/m^3/s]
    real(wp), intent(in) :: h_exchange         !< H [W/m^3/K]
    !> the partner's volume fraction [-]
    real(wp), intent(in), optional :: partner_fraction(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):)
    real(wp), intent(in), optional :: h_partner !< fluid-partner H_fs [W/m^3/K]
    !> the partner's heat capacity per volume [J/m^3/K]
    real(wp), intent(in), optional :: partner_capacity(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):)
    !> the partner's temperature [K] (updated)
    real(wp), intent(inout), optional :: &
      partner_temperature(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):)
    integer :: m, i, j, k, nf
    real(wp) :: phi(max_n), v(max_n), mass(max_n)
    logical :: with_partner

    nf = state%nfluids
    with_partner = present(partner_temperature)
    if (.not. with_partner) then
      if (nf < 2) return
      if (nf == 2 .and. h_exchange <= 0.0_wp) then
        if (k_exchange > 0.0_wp) call exchange_cells_two(state, grid, dt, k_exchange)
        return
      end if
    end if
    do k = grid%lo(3), grid%hi(3)
      do j = grid%lo(2), grid%hi(2)
        do i = grid%lo(1), grid%hi(1)
          do m = 1, nf
            phi(m) = state%fluid(m)%vfrac(i, j, k)
            v(m) = state%fluid(m)%spvol(i, j, k)
            mass(m) = state%fluid(m)%rho(i, j, k)
          end do
          if (with_partner) then
            ! a cell with the partner (and only such: NaN counts as none) is the exchange
            ! layer's
            if (k_exchange > 0.0_wp .and. .not. (partner_fraction(i, j, k) > 0.0_wp)) then
              call exchange_cell_fluids(state, i, j, k, dt, k_exchange, phi, v, mass)
            end if
            call exchange_heat(state, i, j, k, dt, h_exchange, phi, v, h_partner, &
              partner_fraction(i, j, k), partner_capacity(i, j, k), partner_temperature(i, j, k))
          else
            if (k_exchange > 0.0_wp) call exchange_cell_fluids(state, i, j, k, dt, k_exchange, &
              phi, v, mass)
            call exchange_heat(state, i, j, k, dt, h_exchange, phi, v)
          end if
        end do
      end do
    end do
  end subroutine ice_exchange_cells

  !> Implicit velocity exchange among the fluids of cell (i,j,k) (eqs. 50-51), `lag(i,j,k,1:3)`
  !! updated; the kinetic energy it dissipates becomes heat of the fluids by mass
  !! (`lag(i,j,k,4)`).
  subroutine exchange_cell_fluids(state, i, j, k, dt, k_exchange, phi, v, mass)
    type(ice_state_t), intent(inout) :: state  !< fluids (lag updated)
    integer, intent(in) :: i, j, k             !< cell
    real(wp), intent(in) :: dt                 !< time step [s]
    real(wp), intent(in) :: k_exchange         !< K [kg/m^3/s]
    real(wp), intent(in) :: phi(max_n)         !< fluid volume fractions
    real(wp), intent(in) :: v(max_n)           !< fluid specific volumes [m^3/kg]
    real(wp), intent(in) :: mass(max_n)        !< fluid bulk densities [kg/m^3]
    real(wp) :: beta(max_n, max_n), rhs(max_n, 3), ke_old, ke_new, total_mass
    integer :: m, nf
    nf = state%nfluids
    total_mass = sum(mass(1:nf))
    ke_old = 0.0_wp
    do m = 1, nf
      rhs(m, 1:3) = state%fluid(m)%lag(i, j, k, 1:3)
      ke_old = ke_old + 0.5_wp * mass(m) * sum(rhs(m, 1:3)**2)
    end do
    call fill_beta(nf, dt, v, phi, k_exchange, beta)
    call exchange_solve(nf, beta, rhs, 3, mass)
    ke_new = 0.0_wp
    do m = 1, nf
      ke_new = ke_new + 0.5_wp * mass(m) * sum(rhs(m, 1:3)**2)
      state%fluid(m)%lag(i, j, k, 1:3) = rhs(m, 1:3)
    end do
    if (total_mass > 0.0_wp) then
      do m = 1, nf
        state%fluid(m)%lag(i, j, k, 4) = state%fluid(m)%lag(i, j, k, 4) + &
          (ke_old - ke_new) / total_mass
      end do
    end if
  end subroutine exchange_cell_fluids

  !> Implicit heat exchange (eqs. 52-55) in cell (i,j,k): among the fluids with H_ff =
  !! `h_exchange` and, when a partner is given (the solid of a coupled scene) and has a
  !! fraction, a heat capacity and H_fs > 0, between each fluid and it; beta_mn =
  !! dt v_m phi_n H / c_m for a fluid m, dt phi_s phi_n H / C_s for the partner (C_s its heat
  !! capacity per volume, rho_bar_s c_s). The fluids' `lag(i,j,k,4)` and the partner's
  !! temperature are updated; sum C T is conserved.
  subroutine exchange_heat(state, i, j, k, dt, h_exchange, phi, v, h_partner, phi_partner, &
      cap_partner, temp_partner)
    type(ice_state_t), intent(inout) :: state  !< fluids (lag)
    integer, intent(in) :: i, j, k             !< cell
    real(wp), intent(in) :: dt                 !< time step [s]
    real(wp), intent(in) :: h_exchange         !< fluid-fluid H [W/m^3/K]
    real(wp), intent(in) :: phi(max_n)         !< fluid volume fractions
    real(wp), intent(in) :: v(max_n)           !< fluid specific volumes [m^3/kg]
    real(wp), intent(in), optional :: h_partner    !< fluid-partner H_fs [W/m^3/K]
    real(wp), intent(in), optional :: phi_partner  !< the partner's volume fraction [-]
    real(wp), intent(in), optional :: cap_partner  !< its heat capacity per volume [J/m^3/K]
    real(wp), intent(inout), optional :: temp_partner !< its temperature [K]
    real(wp) :: beta(max_n, max_n), x(max_n, 1), w(max_n), phi_s, h_s, cap
    integer :: m, n, nf, nh
    logical :: with_partner
    nf = state%nfluids
    with_partner = .false.
    phi_s = 0.0_wp
    h_s = 0.0_wp
    cap = 0.0_wp
    if (present(temp_partner)) then
      h_s = h_partner
      phi_s = phi_partner
      cap = cap_partner
      with_partner = h_s > 0.0_wp .and. phi_s > 0.0_wp .and. cap > 0.0_wp
    end if
    if (.not. (with_partner .or. (h_exchange > 0.0_wp .and. nf > 1))) return
    nh = nf
    if (with_partner) nh = nf + 1
    beta(1:nh, 1:nh) = 0.0_wp  ! the block exchange_solve reads
    do m = 1, nf
      associate (f => state%fluid(m))
        x(m, 1) = f%lag(i, j, k, 4) / f%eos%cv
        w(m) = f%rho(i, j, k) * f%eos%cv
        do n = 1, nf
          if (n /= m) beta(m, n) = dt * v(m) * phi(n) * h_exchange / f%eos%cv
        end do
        if (with_partner) beta(m, nh) = dt * v(m) * phi_s * h_s / f%eos%cv
      end associate
    end do
    if (with_partner) then
      x(nh, 1) = temp_partner
      w(nh) = cap
      do n = 1, nf
        beta(nh, n) = dt * phi_s * phi(n) * h_s / cap
      end do
    end if
    call exchange_solve(nh, beta, x, 1, w)
    do m = 1, nf
      state%fluid(m)%lag(i, j, k, 4) = x(m, 1) * state%fluid(m)%eos%cv
    end do
    if (with_partner) temp_partner = x(nh, 1)
  end subroutine exchange_heat

  !> Apply the exchange to `nrhs` columns of values x(1:n, :): x := x + dx with
  !! (I + diag(sum_n beta_mn) - beta) dx = sum_n beta_mn (x_n - x_m) for column 1 of a velocity-
  !! like quantity, i.e. x_new = A^-1 x_old for every column (A = I + diag(rowsum beta) - beta).
  !! Nothing to do for n = 1 (A = 1: a cell with one fluid and no solid), closed form for n = 2,
  !! elimination without pivoting for n = 3 (`solve_3`), with pivoting otherwise
  !! (`solve_pivoted`). `beta` has a zero diagonal.
  subroutine exchange_solve(n, beta, x, nrhs, weight, weighted_columns)
    integer, intent(in) :: n                      !< number of fluids
    real(wp), intent(in) :: beta(max_n, max_n)    !< beta_mn, zero diagonal
    real(wp), intent(inout) :: x(max_n, *)        !< values in, exchanged values out
    integer, intent(in) :: nrhs                   !< columns
    real(wp), intent(in), optional :: weight(max_n) !< masses per volume phi/v (n > 2: restore
                                                    !! sum weight x, which LU round-off breaks)
    !> the weight restores columns 1 .. weighted_columns (default: all)
    integer, intent(in), optional :: weighted_columns
    real(wp) :: a(max_n, max_n), det, x1, x2, x_old(max_n, 3), defect
    integer :: m, c, nweighted
    logical :: singular

    if (n == 1) return
    if (n == 2) then
      ! A = [1 + b12, -b12; -b21, 1 + b21]; A^-1 = [1 + b21, b12; b21, 1 + b12] / det
      det = 1.0_wp + beta(1, 2) + beta(2, 1)
      do c = 1, nrhs
        x1 = x(1, c)
        x2 = x(2, c)
        x(1, c) = ((1.0_wp + beta(2, 1)) * x1 + beta(1, 2) * x2) / det
        x(2, c) = (beta(2, 1) * x1 + (1.0_wp + beta(1, 2)) * x2) / det
      end do
      return
    end if
    a(1:n, 1:n) = -beta(1:n, 1:n)
    do m = 1, n
      a(m, m) = 1.0_wp + sum(beta(m, 1:n))
    end do
    x_old(1:n, 1:nrhs) = x(1:n, 1:nrhs)
    if (n == 3) then
      ! three materials (two fluids and the solid, the common coupled case): elimination
      ! without pivoting, exact in exact arithmetic and stable here because A is strictly
      ! diagonally dominant by rows; a general solve per face and cell cost more than the step's
      ! face exchange itself
      call solve_3(max_n, a, x, nrhs)
    else
      call solve_pivoted(n, max_n, a, x, nrhs, singular)
      if (singular) call fatal('ice_exchange: singular exchange matrix')
    end if
    if (present(weight)) then
      ! with weights w_m beta_mn symmetric, A conserves sum w x exactly; the LU's round-off
      ! (condition ~ beta) does not: remove the defect by a uniform shift
      nweighted = nrhs
      if (present(weighted_columns)) nweighted = weighted_columns
      if (sum(weight(1:n)) > 0.0_wp) then
        do c = 1, nweighted
          defect = sum(weight(1:n) * (x(1:n, c) - x_old(1:n, c))) / sum(weight(1:n))
          x(1:n, c) = x(1:n, c) - defect
        end do
      end if
    end if
  end subroutine exchange_solve
end module ice_exchange
