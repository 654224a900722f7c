!> Conservative advection of mass, momentum, internal energy and specific volume (paper
!! eqs. 58-65) with the final face velocities of the pressure solve.
!!
!! For every face of the owned cells the swept volume u_f dt A leaves the upwind cell; the bulk
!! density and the mass-specific quantities (u, v, w, cv T, v) carried with it are reconstructed
!! at the centroid of the swept volume from the upwind cell's monotonised-central (MC) limited
!! slope (second order, `order = 2`; MC gave a 2 % lower Sod error than van Leer) or taken as
!! the cell value (`order = 1`). The mass flux is
!! rho_f u_f dt A and every other flux is the mass flux times the reconstructed specific value
!! ("compatible" fluxes: a uniform specific quantity stays uniform). The update is unsplit (all
!! directions from the same Lagrangian state). Needs rho and `lag` valid in two ghost layers.
!! Energy without a solid phase (departure from eq. 60, docs/ice.md): the specific total energy
!! cv T + |u|^2/2 + Phi is advected, Phi = -g.x the potential of the gravity components along
!! non-periodic active axes (`potential_gravity`; its face value the potential at the centroid
!! of the swept volume, its cell value at the cell centre), and the new temperature is
!! (E/m - |u|^2/2 - Phi)/cv: the kinetic energy that momentum advection removes reappears as
!! heat, and the potential energy that the moved mass releases too, so total energy (internal,
!! kinetic and potential) is conserved to round-off together with the Lagrangian step (which
!! leaves the work of those gravity components out of cv T + |u|^2/2, `ice_lagrangian`).
!! Advecting cv T alone left the Sod post-shock pressure 0.3 % low and the two-fluid sloshing
!! box drifting 5e-10 per step. With a solid phase (MPMICE) cv T is advected (eq. 60).
module ice_advection
  use mpmice_kinds, only: wp
  use grid_layout, only: grid_t, cell_centre
  use grid_sweep, only: sweep_direction
  use ice_state, only: ice_state_t
  use ice_solid_view, only: ice_solid_view_t
  use ice_face_velocity, only: face_range
  implicit none
  private

  public :: ice_advect, limited_slope, potential_gravity

contains

  !> Advect every fluid: new rho, vel, temp and spvol on the owned cells. `negative`: the number
  !! of owned cells whose mass became negative (0 on success; a caller that judges the masses
  !! itself leaves it out). `gravity`: carried as potential energy (module header; absent: none).
  !! The rows of the sweeps are the state's work storage (`ice_work_t`): nothing is allocated.
  subroutine ice_advect(state, grid, dt, order, negative, gravity, solid)
    type(ice_state_t), intent(inout) :: state  !< fluids (rho, lag, uface read; primitives written)
    type(grid_t), intent(in) :: grid           !< block geometry
    real(wp), intent(in) :: dt                 !< time step [s]
    integer, intent(in) :: order               !< 1 first order, 2 limited second order
    integer, intent(out), optional :: negative !< owned cells with negative new mass
    real(wp), intent(in), optional :: gravity(3) !< gravitational acceleration [m/s^2]
    !> the solid phase of a coupled scene: cv T advected, porous stencils upwind, the open faces'
    !! inflow through the pores
    class(ice_solid_view_t), intent(in), optional :: solid
    associate (w => state%work)
      call advect_rows(state, grid, dt, order, w%pos, w%urow, w%dist, w%mflux, w%qf, w%vf, &
        w%xc, w%yc, w%zc, negative, gravity, solid)
    end associate
  end subroutine ice_advect

  !> `ice_advect` with its rows as explicit-shape arguments (from the work storage, which is at
  !! least this large; not referenced through `state` here).
  subroutine advect_rows(state, grid, dt, order, pos, urow, dist, mflux, qf, vf, xc, yc, zc, &
    negative, gravity, solid)
    type(ice_state_t), intent(inout) :: state  !< fluids (rho, lag, uface read; primitives written)
    type(grid_t), intent(in) :: grid           !< block geometry
    real(wp), intent(in) :: dt                 !< time step [s]
    integer, intent(in) :: order               !< 1 first order, 2 limited second order
    ! one row of faces along x: upwind side, centroid offset of the swept volume, mass flux,
    ! reconstructed face value and velocities
    logical, intent(inout) :: pos(grid%lbc(1):grid%ubc(1))     !< upwind cell is the low one
    real(wp), intent(inout) :: urow(grid%lbc(1):grid%ubc(1))   !< face velocities [m/s]
    real(wp), intent(inout) :: dist(grid%lbc(1):grid%ubc(1))   !< centroid offset [m]
    real(wp), intent(inout) :: mflux(grid%lbc(1):grid%ubc(1))  !< mass flux [kg]
    real(wp), intent(inout) :: qf(grid%lbc(1):grid%ubc(1))     !< reconstructed face value
    real(wp), intent(inout) :: vf(grid%lbc(1):grid%ubc(1), 3)  !< face velocities [m/s]
    ! cell-centre coordinates per axis (the potential -g.x of a cell) [m]
    real(wp), intent(inout) :: xc(grid%lbc(1):grid%ubc(1))     !< along x [m]
    real(wp), intent(inout) :: yc(grid%lbc(2):grid%ubc(2))     !< along y [m]
    real(wp), intent(inout) :: zc(grid%lbc(3):grid%ubc(3))     !< along z [m]
    integer, intent(out), optional :: negative !< owned cells with negative new mass
    real(wp), intent(in), optional :: gravity(3) !< gravitational acceleration [m/s^2]
    !> the solid phase of a coupled scene
    class(ice_solid_view_t), intent(in), optional :: solid
    integer :: d, m, n, i, j, k, o(3), r(2, 3), i1, i2, negative_cells
    real(wp) :: area, u, vol, g(3), pot_lo, pot_hi
    logical :: total

    vol = grid%cell_volume
    negative_cells = 0
    total = .not. present(solid)
    g = 0.0_wp
    if (present(gravity) .and. total) g = potential_gravity(grid, gravity)
    do i = grid%lbc(1), grid%ubc(1)
      xc(i) = cell_centre(grid, 1, i)
    end do
    do j = grid%lbc(2), grid%ubc(2)
      yc(j) = cell_centre(grid, 2, j)
    end do
    do k = grid%lbc(3), grid%ubc(3)
      zc(k) = cell_centre(grid, 3, k)
    end do
    do m = 1, state%nfluids
      associate (f => state%fluid(m), c => state%cons)
        do k = grid%lo(3), grid%hi(3)
          do j = grid%lo(2), grid%hi(2)
            do i = grid%lo(1), grid%hi(1)
              c(i, j, k, 1) = f%rho(i, j, k) * vol
              do n = 1, 5
                c(i, j, k, 1 + n) = c(i, j, k, 1) * f%lag(i, j, k, n)
              end do
              if (total) c(i, j, k, 5) = c(i, j, k, 5) + c(i, j, k, 1) * &
                (0.5_wp * sum(f%lag(i, j, k, 1:3)**2) + potential(i, j, k))
            end do
          end do
        end do
        do d = 1, 3
          if (.not. sweep_direction(grid, d, o)) cycle
          r = face_range(grid, d)
          i1 = r(1, 1)
          i2 = r(2, 1)
          area = vol / grid%dx(d)
          do k = r(1, 3), r(2, 3)
            do j = r(1, 2), r(2, 2)
              ! the swept volume u dt A leaves the upwind cell (face - o for u > 0); its
              ! centroid lies dist from that cell's centre
              do i = i1, i2
                u = f%uface(i, j, k, d)
                urow(i) = u
                pos(i) = u > 0.0_wp
                dist(i) = merge(0.5_wp * (grid%dx(d) - u * dt), -0.5_wp * (grid%dx(d) + u * dt), &
                  pos(i))
              end do
              call row_face_values(f%rho, grid%lbc, i1, i2, j, k, o, order, urow, dist, &
                grid%dx(d), qf)
              ! a solid phase: where the upwind cell's stencil holds solid the mass leaves with
              ! the upwind cell's bulk density, i.e. the pressure equation's volume flux (upwind
              ! phi_f u_f) times the intrinsic density; a reconstructed bulk density carries the
              ! porosity's slope (the soil's surface, and the varying porosity inside a moving
              ! soil), so the pore water's volume differed from it and the stiff water kept the
              ! difference as pressure (docs/mpmice.md, departure 16)
              if (.not. total .and. order > 1) call row_porous_upwind(solid%vfrac, f%rho, &
                grid, i1, i2, j, k, o, d, urow, qf)
              do i = i1, i2
                u = f%uface(i, j, k, d)
                mflux(i) = merge(qf(i) * (u * dt * area), 0.0_wp, u /= 0.0_wp)
              end do
              call open_face_inflow(state, grid, m, d, o, i1, i2, j, k, dt, area, .not. total, &
                mflux)
              call row_update(c(:, :, :, 1), grid%lbc, i1, i2, j, k, o, mflux)
              do n = 1, 5
                call row_face_values(f%lag(:, :, :, n), grid%lbc, i1, i2, j, k, o, order, urow, &
                  dist, grid%dx(d), qf)
                if (n <= 3) vf(i1:i2, n) = qf(i1:i2)
                if (n == 4 .and. total) then
                  ! specific total energy: + |u_f|^2/2 (the reconstructed velocities) and the
                  ! potential at the swept volume's centroid
                  do i = i1, i2
                    pot_lo = -(g(1) * xc(i - o(1)) + g(2) * yc(j - o(2)) + g(3) * zc(k - o(3)))
                    pot_hi = -(g(1) * xc(i) + g(2) * yc(j) + g(3) * zc(k))
                    qf(i) = qf(i) + 0.5_wp * (vf(i, 1)**2 + vf(i, 2)**2 + vf(i, 3)**2) + &
                      merge(pot_lo, pot_hi, pos(i)) - merge(dist(i), 0.0_wp, order > 1) * g(d)
                  end do
                end if
                qf(i1:i2) = mflux(i1:i2) * qf(i1:i2)
                call row_update(c(:, :, :, 1 + n), grid%lbc, i1, i2, j, k, o, qf)
              end do
            end do
          end do
        end do
        ! eqs. 62-65: primitives from the conserved quantities
        do k = grid%lo(3), grid%hi(3)
          do j = grid%lo(2), grid%hi(2)
            do i = grid%lo(1), grid%hi(1)
              if (c(i, j, k, 1) < 0.0_wp) negative_cells = negative_cells + 1
              f%rho(i, j, k) = c(i, j, k, 1) / vol
              if (c(i, j, k, 1) > 0.0_wp) then
                f%vel(i, j, k, 1:3) = c(i, j, k, 2:4) / c(i, j, k, 1)
                if (total) then
                  f%temp(i, j, k) = (c(i, j, k, 5) / c(i, j, k, 1) - 0.5_wp * &
                    sum(f%vel(i, j, k, 1:3)**2) - potential(i, j, k)) / f%eos%cv
                else
                  f%temp(i, j, k) = c(i, j, k, 5) / (c(i, j, k, 1) * f%eos%cv)
                end if
                f%spvol(i, j, k) = c(i, j, k, 6) / c(i, j, k, 1)
              else
                f%vel(i, j, k, 1:3) = 0.0_wp
                f%temp(i, j, k) = f%lag(i, j, k, 4) / f%eos%cv
                f%spvol(i, j, k) = f%lag(i, j, k, 5)
              end if
            end do
          end do
        end do
      end associate
    end do
    if (present(negative)) negative = negative_cells

  contains

    !> Potential -g.x [J/kg] at the centre of cell (ci, cj, ck).
    real(wp) function potential(ci, cj, ck)
      integer, intent(in) :: ci  !< cell index along x
      integer, intent(in) :: cj  !< cell index along y
      integer, intent(in) :: ck  !< cell index along z
      potential = -(g(1) * xc(ci) + g(2) * yc(cj) + g(3) * zc(ck))
    end function potential
  end subroutine advect_rows

  !> The faces (i1..i2, j, k) of direction o (unit offset, d its dimension) whose upwind cell c
  !! (face - o where u > 0, else the face's own cell) has solid in one of the cells c - o, c,
  !! c + o inside the domain (the free-fluid ghosts beyond an open face of a soil that reaches
  !! it do not count) take that cell's bulk density `rho` as face value. Branch-free over the
  !! row (the four cells face - 2o .. face + o per face), so that the loop vectorises.
  pure subroutine row_porous_upwind(phi_s, rho, grid, i1, i2, j, k, o, d, u, qf)
    type(grid_t), intent(in) :: grid        !< block geometry
    real(wp), intent(in) :: phi_s(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !< solid fraction [-]
    real(wp), intent(in) :: rho(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):)   !< bulk density
    integer, intent(in) :: i1, i2, j, k     !< faces of the row
    integer, intent(in) :: o(3)             !< unit offset along the face normal
    integer, intent(in) :: d                !< the normal's dimension (o(d) = 1)
    real(wp), intent(in) :: u(grid%lbc(1):) !< face velocities [m/s]
    real(wp), intent(inout) :: qf(grid%lbc(1):) !< face values (replaced where porous)
    integer :: i, n
    logical :: pos, s0, s1, s2, s3, porous
    do i = i1, i2
      pos = u(i) > 0.0_wp
      ! index along d of the cell face - 2o
      n = i * o(1) + j * o(2) + k * o(3) - 2
      s0 = phi_s(i - 2 * o(1), j - 2 * o(2), k - 2 * o(3)) > 0.0_wp .and. inside(n)
      s1 = phi_s(i - o(1), j - o(2), k - o(3)) > 0.0_wp .and. inside(n + 1)
      s2 = phi_s(i, j, k) > 0.0_wp .and. inside(n + 2)
      s3 = phi_s(i + o(1), j + o(2), k + o(3)) > 0.0_wp .and. inside(n + 3)
      porous = merge(s0 .or. s1 .or. s2, s1 .or. s2 .or. s3, pos)
      qf(i) = merge(merge(rho(i - o(1), j - o(2), k - o(3)), rho(i, j, k), pos), qf(i), porous)
    end do

  contains

    !> Cell index `c` along d lies inside the domain (always along a periodic axis).
    pure logical function inside(c)
      integer, intent(in) :: c  !< global cell index along d
      inside = grid%periodic(d) .or. (c >= 1 .and. c <= grid%ncells(d))
    end function inside
  end subroutine row_porous_upwind

  !> Upwind face values of `q` on the faces (i1..i2, j, k) of direction o (unit offset): the
  !! upwind cell's value (face - o where u > 0, else the face's own cell) plus `dist` times its
  !! MC-limited slope (`order` > 1). The four cells face - 2o .. face + o of the row's faces are
  !! handed on as four contiguous rows (`limited_face_row`), so that the loop loads them with unit
  !! stride (indexed through o inside the loop, the upwind choice became a gather).
  pure subroutine row_face_values(q, lbc, i1, i2, j, k, o, order, u, dist, dx, qf)
    integer, intent(in) :: lbc(3)                       !< lower bounds of q
    real(wp), intent(in), contiguous :: q(lbc(1):, lbc(2):, lbc(3):) !< cell field
    integer, intent(in) :: i1, i2, j, k                 !< faces of the row
    integer, intent(in) :: o(3)                         !< unit offset along the face normal
    integer, intent(in) :: order                        !< 1 first order, 2 limited second order
    real(wp), intent(in), contiguous :: u(lbc(1):)      !< face velocities [m/s]
    real(wp), intent(in), contiguous :: dist(lbc(1):)   !< centroid offset [m]
    real(wp), intent(in) :: dx                         !< cell size along the normal [m]
    real(wp), intent(inout), contiguous :: qf(lbc(1):)  !< face values (i1..i2 written)
    integer :: i
    if (i2 < i1) return
    if (order > 1) then
      call limited_face_row(i2 - i1 + 1, &
        q(i1 - 2 * o(1):i2 - 2 * o(1), j - 2 * o(2), k - 2 * o(3)), &
        q(i1 - o(1):i2 - o(1), j - o(2), k - o(3)), q(i1:i2, j, k), &
        q(i1 + o(1):i2 + o(1), j + o(2), k + o(3)), u(i1:i2), dist(i1:i2), dx, qf(i1:i2))
    else
      do i = i1, i2
        qf(i) = merge(q(i - o(1), j - o(2), k - o(3)), q(i, j, k), u(i) > 0.0_wp)
      end do
    end if
  end subroutine row_face_values

  !> `row_face_values` of order 2 on n faces whose cells face - 2o, face - o, face, face + o are
  !! the rows q2, q1, q0, qp.
  pure subroutine limited_face_row(n, q2, q1, q0, qp, u, dist, dx, qf)
    integer, intent(in) :: n          !< faces
    real(wp), intent(in) :: q2(n)     !< cells face - 2o
    real(wp), intent(in) :: q1(n)     !< cells face - o
    real(wp), intent(in) :: q0(n)     !< the faces' own cells
    real(wp), intent(in) :: qp(n)     !< cells face + o
    real(wp), intent(in) :: u(n)      !< face velocities [m/s]
    real(wp), intent(in) :: dist(n)   !< centroid offset [m]
    real(wp), intent(in) :: dx        !< cell size along the normal [m]
    real(wp), intent(out) :: qf(n)    !< face values
    integer :: i
    real(wp) :: lo, mid, hi
    logical :: pos
    do i = 1, n
      pos = u(i) > 0.0_wp
      lo = merge(q2(i), q1(i), pos)
      mid = merge(q1(i), q0(i), pos)
      hi = merge(q0(i), qp(i), pos)
      qf(i) = mid + dist(i) * limited_slope(lo, mid, hi, dx)
    end do
  end subroutine limited_face_row

  !> Conservative update of one row of faces: the flux leaves the low cell (face - o) and enters
  !! the high cell (the face's own), face by face in order.
  pure subroutine row_update(c, lbc, i1, i2, j, k, o, flux)
    integer, intent(in) :: lbc(3)                          !< lower bounds of c
    real(wp), intent(inout), contiguous :: c(lbc(1):, lbc(2):, lbc(3):) !< conserved quantity
    integer, intent(in) :: i1, i2, j, k                    !< faces of the row
    integer, intent(in) :: o(3)                            !< unit offset along the face normal
    real(wp), intent(in), contiguous :: flux(lbc(1):)      !< flux of each face
    integer :: i
    if (o(1) == 1 .and. i2 >= i1) then
      ! along x, cell i is the high cell of face i and the low cell of face i + 1: the same two
      ! operations in the same order (+ flux(i), then - flux(i + 1)) without the face-by-face
      ! loop's dependence from one face to the next, so that the loop vectorises
      c(i1 - 1, j, k) = c(i1 - 1, j, k) - flux(i1)
      do i = i1, i2 - 1
        c(i, j, k) = c(i, j, k) + flux(i) - flux(i + 1)
      end do
      c(i2, j, k) = c(i2, j, k) + flux(i2)
      return
    end if
    do i = i1, i2
      c(i - o(1), j - o(2), k - o(3)) = c(i - o(1), j - o(2), k - o(3)) - flux(i)
      c(i, j, k) = c(i, j, k) + flux(i)
    end do
  end subroutine row_update

  !> The gravity components carried as potential energy by the advection (module header): those
  !! along active, non-periodic axes (a potential is not single-valued along a periodic one);
  !! the others stay kinetic work of the Lagrangian step.
  pure function potential_gravity(grid, gravity) result(g)
    type(grid_t), intent(in) :: grid       !< block geometry
    real(wp), intent(in) :: gravity(3)     !< gravitational acceleration [m/s^2]
    real(wp) :: g(3)
    g = merge(gravity, 0.0_wp, grid%active .and. .not. grid%periodic)
  end function potential_gravity

  !> Monotonised-central limited slope [unit/m] of a cell from its neighbours:
  !! minmod(2a, 2b, (a+b)/2) of the one-sided differences a, b (0 at an extremum).
  elemental real(wp) function limited_slope(qm, q0, qp, dx)
    real(wp), intent(in) :: qm  !< value in the low neighbour
    real(wp), intent(in) :: q0  !< value in the cell
    real(wp), intent(in) :: qp  !< value in the high neighbour
    real(wp), intent(in) :: dx  !< cell size [m]
    real(wp) :: a, b
    a = q0 - qm
    b = qp - q0
    ! branch-free, the division after the choice (0 / dx = 0): the row loops vectorise
    limited_slope = merge(sign(min(2.0_wp * abs(a), 2.0_wp * abs(b), 0.5_wp * abs(a + b)), a), &
      0.0_wp, a * b > 0.0_wp) / dx
  end function limited_slope

  !> Mass flux of fluid `m` [kg] through the domain faces of one row where fluid flows in.
  !! - A face with an `inflow_fluid` r (`&boundary`, ice_bc): the volume the fluids carry in,
  !!   sum over the inflowing fluids n of phi_n u_n dt A with the inner cell's fractions phi_n
  !!   (the volume the pressure equation admits there, `ice_pressure` open_face_shift), is
  !!   filled with r at its density in the inner cell, 1/v_r; the other fluids bring nothing in
  !!   (their outflow is unchanged). Without it a water mist next to an open top, carried in
  !!   with the air, added water at every inflow (docs/mpmice.md, departure 11).
  !! - Otherwise, on an open ('pressure') face of a scene with a solid phase: fluid flowing in
  !!   from the ghost reservoir (mpmice `open_face_reservoirs`) carries the inner cell's bulk
  !!   density, i.e. it enters through the inner cell's pores, consistent with the inner-cell
  !!   face fraction of the pressure equation there (departure 11).
  !! - Elsewhere the reconstructed flux stands.
  subroutine open_face_inflow(state, grid, m, d, o, i1, i2, j, k, dt, area, porous, mflux)
    type(ice_state_t), intent(in) :: state     !< fluids (closed faces, inflow fluids)
    type(grid_t), intent(in) :: grid           !< block geometry
    integer, intent(in) :: m                   !< the fluid advected
    integer, intent(in) :: d                   !< face direction
    integer, intent(in) :: o(3)                !< unit offset along d
    integer, intent(in) :: i1, i2, j, k        !< the row of faces
    real(wp), intent(in) :: dt                 !< time step [s]
    real(wp), intent(in) :: area               !< face area [m^2]
    logical, intent(in) :: porous              !< a solid phase is present (coupled scene)
    real(wp), intent(inout) :: mflux(grid%lbc(1):) !< mass flux along +d per face of the row [kg]
    integer :: i, n, r, face, idx(3), c(3)
    real(wp) :: inward, volume_in, u
    if (grid%periodic(d)) return
    ! only domain faces change: along x the row's first and last face, along y / z the whole row
    ! or none
    if (d == 2 .and. j /= 1 .and. j /= grid%ncells(2) + 1) return
    if (d == 3 .and. k /= 1 .and. k /= grid%ncells(3) + 1) return
    do i = i1, i2, merge(max(i2 - i1, 1), 1, d == 1)
      idx = [i, j, k]
      if (idx(d) == 1) then
        face = 2 * d - 1
        c = idx
        inward = 1.0_wp
      else if (idx(d) == grid%ncells(d) + 1) then
        face = 2 * d
        c = idx - o
        inward = -1.0_wp
      else
        cycle
      end if
      r = state%inflow_fluid(face)
      u = inward * state%fluid(m)%uface(i, j, k, d)
      if (r == 0) then
        if (porous .and. .not. state%closed(face) .and. u > 0.0_wp) then
          mflux(i) = state%fluid(m)%rho(c(1), c(2), c(3)) * (inward * u * dt * area)
        end if
        cycle
      end if
      if (u > 0.0_wp) mflux(i) = 0.0_wp
      if (m /= r) cycle
      volume_in = 0.0_wp
      do n = 1, state%nfluids
        u = inward * state%fluid(n)%uface(i, j, k, d)
        if (u > 0.0_wp) volume_in = volume_in + state%fluid(n)%vfrac(c(1), c(2), c(3)) * u
      end do
      mflux(i) = mflux(i) + inward * volume_in * dt * area / state%fluid(r)%spvol(c(1), c(2), c(3))
    end do
  end subroutine open_face_inflow
end module ice_advection
