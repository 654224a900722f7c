!> The implicit fluid-solid exchange of a coupled scene (paper eqs. 34 and 50-55, errata E8):
!! the solid phase (`solid_phase_t`) joins the fluids' exchange (`ice_exchange`) as one more
!! material. At the faces its velocity and specific volume are exchanged with the fluids' over
!! face_time dt, with the face drag coefficient of `solid_face_partner`; a prescribed (rigid)
!! face velocity keeps its value (its row zero). In the cells the solid's final velocity is
!! known, so its row is held fixed and only the fluids are dragged toward it; the drag's
!! dissipation heats the fluids. Where the solid takes no part the fluids' own exchange of
!! `ice_exchange` runs (the faces and cells are independent, so the order is free), and its heat
!! exchange takes the solid as the fluids' partner. The option
!! `&coupling drag_scheme = 'explicit'` replaces the implicit solves by forward Euler
!! (`exchange_explicit`), for comparison.
submodule (exchange_solid_phase) exchange_fluid_solid
  use mpmice_kinds, only: wp
  use grid_layout, only: grid_t
  use ice_state, only: ice_state_t
  use ice_face_velocity, only: open_face_sweep, boundary_face
  use ice_exchange, only: max_n, fill_beta, exchange_solve, exchange_faces_two, ice_exchange_cells
  implicit none

  real(wp), parameter :: ratio_max = 1.0e12_wp  !< cap of phi_up / phi_f in the face drag

contains

  !> Face exchange of the fluids and the solid (eq. 34): at each open face of the owned cells the
  !! fluids and, where the face holds solid (`solid_face_partner`), the solid exchange their
  !! face velocities (u_f += du) and specific volumes (v_f := A^-1 v_f, the solid's `vface`,
  !! zero at a face without solid).
  module procedure solid_phase_exchange_faces
    integer :: d, m, i, j, k, o(3), r(2, 3), nf, nm, side
    real(wp) :: beta(max_n, max_n), rhs(max_n, 2), phi(max_n), v(max_n), w(max_n), c(max_n)
    logical :: with_solid, rigid, pair

    nf = state%nfluids
    ! two fluids beside a solid phase: at an inner face where neither cell holds the fluids'
    ! solid partner (`solid_face_partner`: the solid fraction, or with sliding rigid bodies the
    ! partner's fraction xfrac, zero only where the deformable solid's is zero too) the general
    ! path below reduces to the closed-form 2 x 2 solve of exchange_solve, which
    ! `exchange_faces_two` takes directly (the same arithmetic)
    pair = nf == 2 .and. k_exchange > 0.0_wp .and. .not. solid%explicit_drag
    do d = 1, 3
      if (.not. open_face_sweep(state, grid, d, o, r)) cycle
      do k = r(1, 3), r(2, 3)
        do j = r(1, 2), r(2, 2)
          do i = r(1, 1), r(2, 1)
            side = boundary_side(grid, d, [i, j, k])
            if (pair .and. side == 0) then
              ! the fluids' closed-form exchange, `exchange_faces_two` below
              if (partner_free(solid, [i, j, k] - o, [i, j, k])) then
                solid%vface(i, j, k, d) = 0.0_wp
                cycle
              end if
            end if
            ! the fluids' face values; a domain face's control volume is the inner half cell:
            ! the fluids' fractions there (not the mean with the ghost, a reservoir beyond an
            ! open face)
            do m = 1, nf
              associate (fl => state%fluid(m))
                select case (side)
                case (1)
                  phi(m) = fl%vfrac(i, j, k)
                case (2)
                  phi(m) = fl%vfrac(i - o(1), j - o(2), k - o(3))
                case default
                  phi(m) = 0.5_wp * (fl%vfrac(i - o(1), j - o(2), k - o(3)) + fl%vfrac(i, j, k))
                end select
                v(m) = fl%vface(i, j, k, d)
                rhs(m, 1) = fl%uface(i, j, k, d)
              end associate
            end do
            nm = nf
            call solid_face_partner(state, solid, d, o, i, j, k, side, phi(nf + 1), v(nf + 1), &
              c, rigid)
            ! a domain face: the solid of the inner cell (no solid lies beyond)
            with_solid = phi(nf + 1) > 0.0_wp
            if (with_solid) then
              nm = nf + 1
              rhs(nm, 1) = solid%uface(i, j, k, d)
              if (rigid) v(nm) = 0.0_wp
            else if (nf < 2 .or. k_exchange <= 0.0_wp) then
              cycle
            end if
            call fill_beta_solid(nf, nm, dt, v, phi, k_exchange, c, rigid, beta)
            rhs(1:nm, 2) = v(1:nm)
            if (solid%explicit_drag) then
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
            else
              solid%vface(i, j, k, d) = 0.0_wp
            end if
          end do
        end do
      end do
    end do
    ! two fluids beside a solid phase: the inner faces with no solid partner in either cell
    if (pair .and. solid%sliding) then
      call exchange_faces_two(state, grid, dt, k_exchange, solid%xfrac)
    else if (pair) then
      call exchange_faces_two(state, grid, dt, k_exchange, solid%vfrac)
    end if
  end procedure solid_phase_exchange_faces

  !> True when neither cell of a face holds the fluids' solid partner of `solid_face_partner`:
  !! the solid fraction, or with sliding rigid bodies the partner's fraction `xfrac` (the
  !! deformable solid's where it has any, else a wall's, so `frac_def` is zero where it is).
  pure logical function partner_free(solid, lo, hi)
    class(solid_phase_t), intent(in) :: solid  !< solid phase
    integer, intent(in) :: lo(3)               !< cell on the face's low side
    integer, intent(in) :: hi(3)               !< cell on the face's high side
    if (solid%sliding) then
      partner_free = solid%xfrac(lo(1), lo(2), lo(3)) <= 0.0_wp .and. &
        solid%xfrac(hi(1), hi(2), hi(3)) <= 0.0_wp
    else
      partner_free = solid%vfrac(lo(1), lo(2), lo(3)) <= 0.0_wp .and. &
        solid%vfrac(hi(1), hi(2), hi(3)) <= 0.0_wp
    end if
  end function partner_free

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
    type(ice_state_t), intent(in) :: state     !< fluids
    class(solid_phase_t), intent(in) :: solid  !< solid phase
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
      if (sp%plane_drag .and. .not. sp%sliding) then
        ! each half cell with the solid fraction in it (the high half of the low cell, the low
        ! half of the high cell): a half cell resists as the length of solid it holds, so the
        ! empty half of a cell crossed by the solid's free surface adds nothing and the two
        ! halves of a cell together resist as the cell
        pl = sp%half_high(i - o(1), j - o(2), k - o(3), d)
        pr = sp%half_low(i, j, k, d)
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

  !> beta_mn = dt v_m phi_n K_mn with K_mn = `k_fluid` between fluids (`ice_exchange%fill_beta`)
  !! and c_m (the reduced drag coefficient) between fluid m and the solid (material nf + 1 when
  !! nm > nf); the solid's row is zero where its velocity is prescribed (infinite mass).
  pure subroutine fill_beta_solid(nf, nm, dt, v, phi, k_fluid, c, rigid, beta)
    integer, intent(in) :: nf                   !< fluids
    integer, intent(in) :: nm                   !< materials (nf or nf + 1)
    real(wp), intent(in) :: dt                  !< time step [s]
    real(wp), intent(in) :: v(max_n)            !< specific volumes [m^3/kg]
    real(wp), intent(in) :: phi(max_n)          !< volume fractions [-]
    real(wp), intent(in) :: k_fluid             !< fluid-fluid K [kg/m^3/s]
    real(wp), intent(in) :: c(max_n)            !< fluid-solid coefficients [kg/m^3/s]
    logical, intent(in) :: rigid                !< solid velocity prescribed
    real(wp), intent(out) :: beta(max_n, max_n) !< exchange coefficients, zero diagonal
    integer :: m
    call fill_beta(nf, dt, v, phi, k_fluid, beta)
    if (nm == nf) return
    do m = 1, nf
      beta(m, nm) = dt * v(m) * phi(nm) * c(m)
      beta(nm, m) = dt * v(nm) * phi(m) * c(m)
      if (rigid) beta(nm, m) = 0.0_wp
    end do
    beta(nm, nm) = 0.0_wp
  end subroutine fill_beta_solid

  !> Cell exchange with the solid (eqs. 50-55) in the owned cells: where a cell holds solid the
  !! fluids' Lagrangian velocities are dragged toward its final cell velocity (its row held
  !! fixed), the drag's dissipation D |du|^2 dt heating the fluids; elsewhere the fluids'
  !! exchange alone, and the heat exchange with the solid as the fluids' partner in every cell
  !! (`ice_exchange_cells`: `lag(i,j,k,4)` and the solid's `temp`).
  module procedure solid_phase_exchange_cells
    integer :: m, n, i, j, k, nf, nm
    real(wp) :: beta(max_n, max_n), rhs(max_n, 3), phi(max_n), v(max_n), mass(max_n), c(max_n)
    real(wp) :: heat

    nf = state%nfluids
    nm = nf + 1
    do k = grid%lo(3), grid%hi(3)
      do j = grid%lo(2), grid%hi(2)
        do i = grid%lo(1), grid%hi(1)
          if (.not. (solid%vfrac(i, j, k) > 0.0_wp)) cycle
          do m = 1, nf
            phi(m) = state%fluid(m)%vfrac(i, j, k)
            v(m) = state%fluid(m)%spvol(i, j, k)
            mass(m) = state%fluid(m)%rho(i, j, k)
            rhs(m, 1:3) = state%fluid(m)%lag(i, j, k, 1:3)
          end do
          phi(nm) = solid%vfrac(i, j, k)
          ! sliding rigid bodies: the fluids' partner is the deformable solid where the cell
          ! holds any, the rigid body elsewhere (`drag` is per the partner's fraction)
          if (solid%sliding) phi(nm) = solid%xfrac(i, j, k)
          v(nm) = solid%spvol(i, j, k)
          mass(nm) = solid%rho(i, j, k)
          c(1:nf) = solid%drag(i, j, k, 1:nf)
          ! the solid's final cell velocity is known (mpmice_solid_cells), so its row is held
          ! fixed and only the fluids are dragged toward it
          call fill_beta_solid(nf, nm, dt, v, phi, k_exchange, c, .true., beta)
          rhs(nm, 1:3) = solid%vel(i, j, k, 1:3)
          if (solid%explicit_drag) then
            call exchange_explicit(nm, beta, rhs, 3)
          else
            call exchange_solve(nm, beta, rhs, 3)
          end if
          do m = 1, nf
            state%fluid(m)%lag(i, j, k, 1:3) = rhs(m, 1:3)
          end do
          ! the drag's dissipation D |du|^2 dt of every pair at the new velocities
          ! (D = rho_bar_m beta_mn / dt), fluid pairs shared by mass, the fluid-solid part to the
          ! fluid (the solid's velocity comes from the faces, so a kinetic-energy difference
          ! here would not be a dissipation)
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
        end do
      end do
    end do
    ! the cells without solid, and the heat exchange with the solid in every cell
    call ice_exchange_cells(state, grid, dt, k_exchange, h_exchange, solid%vfrac, &
      solid%h_exchange, solid%heat_cap, solid%temp)
  end procedure solid_phase_exchange_cells


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
end submodule exchange_fluid_solid
