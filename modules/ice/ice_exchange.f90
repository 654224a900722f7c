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
module ice_exchange
  use mpmice_kinds, only: wp
  use mpmice_errors, only: fatal
  use grid_layout, only: grid_t
  use ice_state, only: ice_state_t
  use exchange_solid_phase, only: solid_phase_t
  use ice_face_velocity, only: closed_face, face_range, boundary_face
  use solver_dense, only: solve_3, solve_pivoted
  implicit none
  private

  public :: ice_exchange_faces, ice_exchange_cells, exchange_solve, max_n

  integer, parameter :: max_n = 9  !< most materials: config_materials%max_fluids + the solid
  real(wp), parameter :: ratio_max = 1.0e12_wp  !< cap of phi_up / phi_f in the face drag


contains

  !> Exchange at the faces of the owned cells: u_f += du and v_f := A^-1 v_f. No-op for one
  !! fluid or K = 0.
  subroutine ice_exchange_faces(state, grid, dt, k_exchange, solid)
    type(ice_state_t), intent(inout) :: state  !< fluids (uface, vface updated)
    type(grid_t), intent(in) :: grid           !< block geometry
    real(wp), intent(in) :: dt                 !< time step [s]
    real(wp), intent(in) :: k_exchange         !< K [kg/m^3/s]
    type(solid_phase_t), intent(inout), optional :: solid !< solid phase of a coupled scene
    integer :: d, m, i, j, k, o(3), r(2, 3), nf, nm, side
    real(wp) :: beta(max_n, max_n), rhs(max_n, 2), phi(max_n), v(max_n), w(max_n), c(max_n)
    logical :: with_solid, rigid, pair, explicit

    nf = state%nfluids
    if ((nf < 2 .or. k_exchange <= 0.0_wp) .and. .not. present(solid)) return
    if (nf == 2 .and. .not. present(solid)) then
      call exchange_faces_two(state, grid, dt, k_exchange)
      return
    end if
    ! two fluids beside a solid phase: at an inner face with no solid in either cell the general
    ! path below reduces to the closed-form 2 x 2 solve of exchange_solve; taken directly (the
    ! same arithmetic) without the solid partner's drag and the general set-up
    pair = .false.
    explicit = .false.
    if (present(solid)) then
      pair = nf == 2 .and. k_exchange > 0.0_wp .and. .not. solid%sliding .and. &
        .not. solid%explicit_drag
      explicit = solid%explicit_drag
    end if
    do d = 1, 3
      if (.not. grid%active(d)) cycle
      o = 0
      o(d) = 1
      r = face_range(grid, d)
      do k = r(1, 3), r(2, 3)
        do j = r(1, 2), r(2, 2)
          do i = r(1, 1), r(2, 1)
            if (closed_face(state, grid, d, [i, j, k])) cycle
            do m = 1, nf
              phi(m) = 0.5_wp * (state%fluid(m)%vfrac(i - o(1), j - o(2), k - o(3)) + &
                state%fluid(m)%vfrac(i, j, k))
              v(m) = state%fluid(m)%vface(i, j, k, d)
              rhs(m, 1) = state%fluid(m)%uface(i, j, k, d)
            end do
            nm = nf
            with_solid = .false.
            rigid = .false.
            if (present(solid)) then
              side = boundary_side(grid, d, [i, j, k])
              if (pair .and. side == 0) then
                if (solid%vfrac(i - o(1), j - o(2), k - o(3)) <= 0.0_wp .and. &
                  solid%vfrac(i, j, k) <= 0.0_wp) then
                  call pair_face_exchange(dt * v(1) * phi(2) * k_exchange, &
                    dt * v(2) * phi(1) * k_exchange, state%fluid(1)%uface(i, j, k, d), &
                    state%fluid(2)%uface(i, j, k, d), state%fluid(1)%vface(i, j, k, d), &
                    state%fluid(2)%vface(i, j, k, d))
                  solid%vface(i, j, k, d) = 0.0_wp
                  cycle
                end if
              end if
              ! a domain face's control volume is the inner half cell: the fluids' fractions
              ! there (not the mean with the ghost, a reservoir beyond an open face)
              select case (side)
              case (1)
                phi(1:nf) = [(state%fluid(m)%vfrac(i, j, k), m = 1, nf)]
              case (2)
                phi(1:nf) = [(state%fluid(m)%vfrac(i - o(1), j - o(2), k - o(3)), m = 1, nf)]
              case default
              end select
              call solid_face_partner(state, solid, d, o, i, j, k, side, phi(nf + 1), &
                v(nf + 1), c, rigid)
              ! a domain face: the solid of the inner cell (no solid lies beyond)
              with_solid = phi(nf + 1) > 0.0_wp
            end if
            if (with_solid) then
              nm = nf + 1
              rhs(nm, 1) = solid%uface(i, j, k, d)
              if (rigid) v(nm) = 0.0_wp
            else if (nf < 2 .or. k_exchange <= 0.0_wp) then
              cycle
            end if
            call fill_beta(nf, nm, dt, v, phi, k_exchange, c, rigid, beta)
            rhs(1:nm, 2) = v(1:nm)
            if (explicit) then
              ! explicit drag (comparison option): forward Euler on the velocities, no
              ! exchange-modified face specific volume
              call exchange_explicit(nm, beta, rhs(:, 1:1), 1)
            else
              ! one elimination for the velocities (column 1) and the specific volumes (2)
              if (rigid) then
                call exchange_solve(nm, beta, rhs, 2)
              else
                ! the masses per volume phi / v (a material absent at the face: v = 0, none)
                w(1:nm) = merge(phi(1:nm) / max(v(1:nm), tiny(1.0_wp)), 0.0_wp, v(1:nm) > 0.0_wp)
                call exchange_solve(nm, beta, rhs, 2, w, weighted_columns=1)
              end if
            end if
            do m = 1, nf
              state%fluid(m)%uface(i, j, k, d) = rhs(m, 1)
              state%fluid(m)%vface(i, j, k, d) = rhs(m, 2)
            end do
            if (with_solid) then
              solid%uface(i, j, k, d) = rhs(nm, 1)
              solid%vface(i, j, k, d) = rhs(nm, 2)
            else if (present(solid)) then
              solid%vface(i, j, k, d) = 0.0_wp
            end if
          end do
        end do
      end do
    end do
  end subroutine ice_exchange_faces

  !> `ice_exchange_faces` for two fluids without a solid phase: the closed-form 2 x 2 solve of
  !! `exchange_solve` (the same arithmetic) as one branch-free sweep per direction over the
  !! open faces (closed domain faces are whole planes, left out of the range).
  subroutine exchange_faces_two(state, grid, dt, k_exchange)
    type(ice_state_t), intent(inout) :: state  !< two fluids (uface, vface updated)
    type(grid_t), intent(in) :: grid           !< block geometry
    real(wp), intent(in) :: dt                 !< time step [s]
    real(wp), intent(in) :: k_exchange         !< K [kg/m^3/s]
    integer :: d, i, j, k, o(3), r(2, 3)
    real(wp) :: phi1, phi2

    do d = 1, 3
      if (.not. grid%active(d)) cycle
      o = 0
      o(d) = 1
      r = face_range(grid, d)
      if (.not. grid%periodic(d)) then
        if (state%closed(2 * d - 1) .and. r(1, d) == 1) r(1, d) = 2
        if (state%closed(2 * d) .and. r(2, d) == grid%ncells(d) + 1) r(2, d) = grid%ncells(d)
      end if
      associate (f1 => state%fluid(1), f2 => state%fluid(2))
        do k = r(1, 3), r(2, 3)
          do j = r(1, 2), r(2, 2)
            do i = r(1, 1), r(2, 1)
              phi1 = 0.5_wp * (f1%vfrac(i - o(1), j - o(2), k - o(3)) + f1%vfrac(i, j, k))
              phi2 = 0.5_wp * (f2%vfrac(i - o(1), j - o(2), k - o(3)) + f2%vfrac(i, j, k))
              call pair_face_exchange(dt * f1%vface(i, j, k, d) * phi2 * k_exchange, &
                dt * f2%vface(i, j, k, d) * phi1 * k_exchange, f1%uface(i, j, k, d), &
                f2%uface(i, j, k, d), f1%vface(i, j, k, d), f2%vface(i, j, k, d))
            end do
          end do
        end do
      end associate
    end do
  end subroutine exchange_faces_two

  !> The closed-form 2 x 2 face exchange of `exchange_solve` (A = [1 + b12, -b12; -b21, 1 + b21])
  !! applied to the face velocities u and the face specific volumes v of two fluids, in place.
  pure subroutine pair_face_exchange(b12, b21, u1, u2, v1, v2)
    real(wp), intent(in) :: b12, b21          !< beta_12, beta_21
    real(wp), intent(inout) :: u1, u2         !< face velocities [m/s]
    real(wp), intent(inout) :: v1, v2         !< face specific volumes [m^3/kg]
    real(wp) :: det, x1, x2
    det = 1.0_wp + b12 + b21
    x1 = u1
    x2 = u2
    u1 = ((1.0_wp + b21) * x1 + b12 * x2) / det
    u2 = (b21 * x1 + (1.0_wp + b12) * x2) / det
    x1 = v1
    x2 = v2
    v1 = ((1.0_wp + b21) * x1 + b12 * x2) / det
    v2 = (b21 * x1 + (1.0_wp + b12) * x2) / det
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

  !> The solid phase at the low face of cell (i,j,k) in direction d: mean volume fraction,
  !! grain specific volume, whether its velocity is prescribed there, and per fluid m the
  !! effective reduced drag coefficient of the face. The face's momentum control volume is half
  !! in each cell, and the two halves resist the fluid's volume flux q_m = phi_m,up u_m (the
  !! upwind fraction of the pressure equation) in series: dp/dx = R q_m with
  !! R = (1/2) sum_halves phi_s c_m / phi_m (a half without solid adds nothing). The coefficient
  !! c_eff = phi_m,up R / phi_s,face makes the exchange's steady state obey exactly that, so a
  !! porous column ending at a face has the resistance of its length (a plain mean of phi_s and
  !! c at the face would lose about half a cell of it at each end).
  pure subroutine solid_face_partner(state, solid, d, o, i, j, k, ghost_side, phi, v, c, rigid)
    type(ice_state_t), intent(in) :: state  !< fluids
    type(solid_phase_t), intent(in) :: solid !< solid phase
    integer, intent(in) :: d                !< face direction
    integer, intent(in) :: o(3)             !< unit offset along d
    integer, intent(in) :: i, j, k          !< face index
    integer, intent(in) :: ghost_side       !< 1 / 2: the low / high cell lies beyond a domain
                                            !! face (no solid there), 0: an inner face
    real(wp), intent(out) :: phi            !< solid volume fraction at the face
    real(wp), intent(out) :: v              !< grain specific volume [m^3/kg]
    real(wp), intent(out) :: c(max_n)       !< reduced drag coefficient per fluid [kg/m^3/s]
    logical, intent(out) :: rigid           !< solid velocity prescribed at the face
    real(wp) :: pl, pr, wl, wr, fl, fr, resistance, up
    integer :: m
    associate (sp => solid)
      rigid = sp%rigid_face(i, j, k, d) > 0.5_wp
      if (sp%sliding) then
        ! the partner's fraction per cell (drag is per it); a face next to a cell with rigid and
        ! no deformable solid moves with the rigid body (rigid), any other the deformable solid
        ! alone
        pl = sp%xfrac(i - o(1), j - o(2), k - o(3))
        pr = sp%xfrac(i, j, k)
        if (rigid) then
          call face_pair_mean(pl, pr, ghost_side, phi, wl, wr)
        else
          call face_pair_mean(sp%frac_def(i - o(1), j - o(2), k - o(3)), sp%frac_def(i, j, k), &
            ghost_side, phi, wl, wr)
        end if
      else
        pl = sp%vfrac(i - o(1), j - o(2), k - o(3))
        pr = sp%vfrac(i, j, k)
        call face_pair_mean(pl, pr, ghost_side, phi, wl, wr)
      end if
      if (ghost_side == 1) pl = 0.0_wp
      if (ghost_side == 2) pr = 0.0_wp
      if (ghost_side /= 0) phi = 2.0_wp * phi
      c = 0.0_wp
      v = 0.0_wp
      if (wl + wr <= 0.0_wp .or. phi <= 0.0_wp) then
        phi = 0.0_wp
        return
      end if
      v = (wl * sp%spvol(i - o(1), j - o(2), k - o(3)) + wr * sp%spvol(i, j, k)) / (wl + wr)
      do m = 1, state%nfluids
        associate (f => state%fluid(m))
          fl = f%vfrac(i - o(1), j - o(2), k - o(3))
          fr = f%vfrac(i, j, k)
          if (f%uface(i, j, k, d) >= 0.0_wp) then
            up = fl
          else
            up = fr
          end if
          ! up * R with R = sum_halves phi_s c / (2 phi_f); the ratios up / phi_f are capped
          ! (ratio_max) so that a trace of a fluid (phi_f ~ 1e-300 next to its bulk) cannot
          ! overflow: its exchange with the solid is then merely very stiff
          resistance = 0.0_wp
          if (fl > 0.0_wp) resistance = resistance + 0.5_wp * pl * &
            sp%drag(i - o(1), j - o(2), k - o(3), m) * min(up / fl, ratio_max)
          if (fr > 0.0_wp) resistance = resistance + 0.5_wp * pr * sp%drag(i, j, k, m) * &
            min(up / fr, ratio_max)
          c(m) = resistance / phi
        end associate
      end do
    end associate
  end subroutine solid_face_partner

  !> Mean of a solid fraction over the two cells of a face, the cell beyond a domain face
  !! (ghost_side 1: the low cell, 2: the high cell) counted as empty, and the 0/1 weights of the
  !! sides that hold solid.
  pure subroutine face_pair_mean(low, high, ghost_side, phi, w_low, w_high)
    real(wp), intent(in) :: low       !< fraction in the low cell
    real(wp), intent(in) :: high      !< fraction in the high cell
    integer, intent(in) :: ghost_side !< 0, or the side beyond a domain face
    real(wp), intent(out) :: phi      !< face mean
    real(wp), intent(out) :: w_low    !< 1 where the low cell holds solid
    real(wp), intent(out) :: w_high   !< 1 where the high cell holds solid
    real(wp) :: a, b

    a = merge(0.0_wp, low, ghost_side == 1)
    b = merge(0.0_wp, high, ghost_side == 2)
    phi = 0.5_wp * (a + b)
    w_low = merge(1.0_wp, 0.0_wp, a > 0.0_wp)
    w_high = merge(1.0_wp, 0.0_wp, b > 0.0_wp)
  end subroutine face_pair_mean

  !> 1 when the low cell of face `idx` (direction d) lies beyond a domain face, 2 for the high
  !! cell, 0 for an inner face.
  pure integer function boundary_side(grid, d, idx) result(side)
    type(grid_t), intent(in) :: grid  !< block geometry
    integer, intent(in) :: d          !< face direction
    integer, intent(in) :: idx(3)     !< face index
    side = 0
    if (.not. boundary_face(grid, d, idx)) return
    side = 2
    if (idx(d) == 1) side = 1
  end function boundary_side

  !> beta_mn = dt v_m phi_n K_mn with K_mn = `k_fluid` between fluids and c_m (the reduced drag
  !! coefficient) between fluid m and the solid (material nf + 1 when nm > nf); the solid's row is
  !! zero where its velocity is prescribed (infinite mass).
  pure subroutine fill_beta(nf, nm, dt, v, phi, k_fluid, c, rigid, beta)
    integer, intent(in) :: nf                   !< fluids
    integer, intent(in) :: nm                   !< materials (nf or nf + 1)
    real(wp), intent(in) :: dt                  !< time step [s]
    real(wp), intent(in) :: v(max_n)            !< specific volumes [m^3/kg]
    real(wp), intent(in) :: phi(max_n)          !< volume fractions [-]
    real(wp), intent(in) :: k_fluid             !< fluid-fluid K [kg/m^3/s]
    real(wp), intent(in) :: c(max_n)            !< fluid-solid coefficients [kg/m^3/s]
    logical, intent(in) :: rigid                !< solid velocity prescribed
    real(wp), intent(out) :: beta(max_n, max_n) !< exchange coefficients, zero diagonal
    integer :: m, n
    do m = 1, nf
      do n = 1, nf
        beta(m, n) = dt * v(m) * phi(n) * k_fluid
      end do
      beta(m, m) = 0.0_wp
    end do
    if (nm == nf) return
    do m = 1, nf
      beta(m, nm) = dt * v(m) * phi(nm) * c(m)
      beta(nm, m) = dt * v(nm) * phi(m) * c(m)
      if (rigid) beta(nm, m) = 0.0_wp
    end do
    beta(nm, nm) = 0.0_wp
  end subroutine fill_beta

  !> Exchange of the Lagrangian velocities (and temperatures when h_exchange > 0) in the owned
  !! cells, `lag(:,:,:,1:4)` updated. No-op for one fluid.
  subroutine ice_exchange_cells(state, grid, dt, k_exchange, h_exchange, solid)
    type(ice_state_t), intent(inout) :: state  !< fluids (lag updated)
    type(grid_t), intent(in) :: grid           !< block geometry
    real(wp), intent(in) :: dt                 !< time step [s]
    real(wp), intent(in) :: k_exchange         !< K [kg/m^3/s]
    real(wp), intent(in) :: h_exchange         !< H [W/m^3/K]
    type(solid_phase_t), intent(inout), optional :: solid !< solid phase of a coupled scene
    integer :: m, n, i, j, k, nf, nm
    real(wp) :: beta(max_n, max_n), rhs(max_n, 3), phi(max_n), v(max_n), mass(max_n), c(max_n)
    real(wp) :: ke_old, ke_new, total_mass, heat

    nf = state%nfluids
    if (nf < 2 .and. .not. present(solid)) return
    if (nf == 2 .and. .not. present(solid) .and. h_exchange <= 0.0_wp) then
      if (k_exchange > 0.0_wp) call exchange_cells_two(state, grid, dt, k_exchange)
      return
    end if
    do k = grid%lo(3), grid%hi(3)
      do j = grid%lo(2), grid%hi(2)
        do i = grid%lo(1), grid%hi(1)
          do m = 1, nf
            phi(m) = state%fluid(m)%vfrac(i, j, k)
            v(m) = state%fluid(m)%spvol(i, j, k)
            mass(m) = state%fluid(m)%rho(i, j, k)
          end do
          total_mass = sum(mass(1:nf))
          nm = nf
          if (present(solid)) then
            if (solid%vfrac(i, j, k) > 0.0_wp) then
              nm = nf + 1
              phi(nm) = solid%vfrac(i, j, k)
              ! sliding rigid bodies: the fluids' partner is the deformable solid where the cell
              ! holds any, the rigid body elsewhere (`drag` is per the partner's fraction)
              if (solid%sliding) phi(nm) = solid%xfrac(i, j, k)
              v(nm) = solid%spvol(i, j, k)
              mass(nm) = solid%rho(i, j, k)
              c(1:nf) = solid%drag(i, j, k, 1:nf)
            end if
          end if
          if (k_exchange > 0.0_wp .or. nm > nf) then
            ke_old = 0.0_wp
            do m = 1, nf
              rhs(m, 1:3) = state%fluid(m)%lag(i, j, k, 1:3)
              ke_old = ke_old + 0.5_wp * mass(m) * sum(rhs(m, 1:3)**2)
            end do
            ! with the solid: its final cell velocity is known (mpmice_solid_cells), so its row
            ! is held fixed and only the fluids are dragged toward it
            call fill_beta(nf, nm, dt, v, phi, k_exchange, c, nm > nf, beta)
            if (nm > nf) then
              rhs(nm, 1:3) = solid%vel(i, j, k, 1:3)
              if (solid%explicit_drag) then
                call exchange_explicit(nm, beta, rhs, 3)
              else
                call exchange_solve(nm, beta, rhs, 3)
              end if
            else
              call exchange_solve(nf, beta, rhs, 3, mass)
            end if
            ke_new = 0.0_wp
            do m = 1, nf
              ke_new = ke_new + 0.5_wp * mass(m) * sum(rhs(m, 1:3)**2)
              state%fluid(m)%lag(i, j, k, 1:3) = rhs(m, 1:3)
            end do
            if (nm > nf) then
              ! with the solid: the drag's dissipation D |du|^2 dt of every pair at the new
              ! velocities (D = rho_bar_m beta_mn / dt), fluid pairs shared by mass, the
              ! fluid-solid part to the fluid (the solid's velocity comes from the faces, so a
              ! kinetic-energy difference here would not be a dissipation)
              do m = 1, nf
                if (mass(m) <= 0.0_wp) cycle
                heat = beta(m, nm) * sum((rhs(nm, 1:3) - rhs(m, 1:3))**2)
                do n = 1, nf
                  if (n == m .or. mass(n) <= 0.0_wp) cycle
                  heat = heat + beta(m, n) * sum((rhs(n, 1:3) - rhs(m, 1:3))**2) * mass(m) / &
                    (mass(m) + mass(n))
                end do
                state%fluid(m)%lag(i, j, k, 4) = state%fluid(m)%lag(i, j, k, 4) + heat
              end do
            else if (total_mass > 0.0_wp) then
              ! the kinetic energy the exchange dissipates becomes heat of the fluids, by mass
              do m = 1, nf
                state%fluid(m)%lag(i, j, k, 4) = state%fluid(m)%lag(i, j, k, 4) + &
                  (ke_old - ke_new) / total_mass
              end do
            end if
          end if
          call exchange_heat(state, i, j, k, dt, h_exchange, phi, v, solid)
        end do
      end do
    end do
  end subroutine ice_exchange_cells

  !> Implicit heat exchange (eqs. 52-55) in cell (i,j,k): among the fluids with H_ff =
  !! `h_exchange` and, where the cell holds solid with a heat capacity, between each fluid and the
  !! solid with H_fs = `solid%h_exchange`; beta_mn = dt v_m phi_n H / c_m for a fluid m,
  !! dt phi_s phi_n H / C_s for the solid (C_s = rho_bar_s c_s). The fluids' `lag(i,j,k,4)` and the
  !! solid's `temp(i,j,k)` are updated; sum C T is conserved.
  subroutine exchange_heat(state, i, j, k, dt, h_exchange, phi, v, solid)
    type(ice_state_t), intent(inout) :: state  !< fluids (lag)
    integer, intent(in) :: i, j, k             !< cell
    real(wp), intent(in) :: dt                 !< time step [s]
    real(wp), intent(in) :: h_exchange         !< fluid-fluid H [W/m^3/K]
    real(wp), intent(in) :: phi(max_n)         !< fluid volume fractions
    real(wp), intent(in) :: v(max_n)           !< fluid specific volumes [m^3/kg]
    type(solid_phase_t), intent(inout), optional :: solid !< solid phase (temp)
    real(wp) :: beta(max_n, max_n), x(max_n, 1), w(max_n), phi_s, h_s, cap
    integer :: m, n, nf, nh
    logical :: with_solid
    nf = state%nfluids
    with_solid = .false.
    phi_s = 0.0_wp
    h_s = 0.0_wp
    cap = 0.0_wp
    if (present(solid)) then
      h_s = solid%h_exchange
      phi_s = solid%vfrac(i, j, k)
      cap = solid%heat_cap(i, j, k)
      with_solid = h_s > 0.0_wp .and. phi_s > 0.0_wp .and. cap > 0.0_wp
    end if
    if (.not. (with_solid .or. (h_exchange > 0.0_wp .and. nf > 1))) return
    nh = nf
    if (with_solid) nh = nf + 1
    beta = 0.0_wp
    do m = 1, nf
      associate (f => state%fluid(m))
        x(m, 1) = f%lag(i, j, k, 4) / f%eos%cv
        w(m) = f%rho(i, j, k) * f%eos%cv
        do n = 1, nf
          if (n /= m) beta(m, n) = dt * v(m) * phi(n) * h_exchange / f%eos%cv
        end do
        if (with_solid) beta(m, nh) = dt * v(m) * phi_s * h_s / f%eos%cv
      end associate
    end do
    if (with_solid) then
      x(nh, 1) = solid%temp(i, j, k)
      w(nh) = cap
      do n = 1, nf
        beta(nh, n) = dt * phi_s * phi(n) * h_s / cap
      end do
    end if
    call exchange_solve(nh, beta, x, 1, w)
    do m = 1, nf
      state%fluid(m)%lag(i, j, k, 4) = x(m, 1) * state%fluid(m)%eos%cv
    end do
    if (with_solid) solid%temp(i, j, k) = x(nh, 1)
  end subroutine exchange_heat

  !> Explicit (forward Euler) exchange: x_m += sum_n beta_mn (x_n - x_m), for the comparison
  !! option `&coupling drag_scheme = 'explicit'` (unstable once beta > 1).
  pure subroutine exchange_explicit(n, beta, x, nrhs)
    integer, intent(in) :: n                      !< materials
    real(wp), intent(in) :: beta(max_n, max_n)    !< beta_mn, zero diagonal
    real(wp), intent(inout) :: x(max_n, *)        !< values in, exchanged values out
    integer, intent(in) :: nrhs                   !< columns
    real(wp) :: x_old(max_n)
    integer :: m, c
    do c = 1, nrhs
      x_old(1:n) = x(1:n, c)
      do m = 1, n
        x(m, c) = x_old(m) + sum(beta(m, 1:n) * (x_old(1:n) - x_old(m)))
      end do
    end do
  end subroutine exchange_explicit

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
