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
  use ice_state, only: ice_state_t
  use ice_face_velocity, only: face_range
  implicit none
  private

  public :: ice_advect, limited_slope, potential_gravity

contains

  !> Advect every fluid: new rho, vel, temp and spvol on the owned cells. Returns the number of
  !! owned cells whose mass became negative (0 on success). `gravity`: carried as potential
  !! energy (module header; absent: none).
  subroutine ice_advect(state, grid, dt, order, negative, gravity)
    type(ice_state_t), intent(inout) :: state  !< fluids (rho, lag, uface read; primitives written)
    type(grid_t), intent(in) :: grid           !< block geometry
    real(wp), intent(in) :: dt                 !< time step [s]
    integer, intent(in) :: order               !< 1 first order, 2 limited second order
    integer, intent(out) :: negative           !< owned cells with negative new mass
    real(wp), intent(in), optional :: gravity(3) !< gravitational acceleration [m/s^2]
    integer :: d, m, n, i, j, k, o(3), r(2, 3), up(3)
    real(wp) :: area, u, sweep, dist, rho_f, mflux, q_f, vol, g(3)
    logical :: total

    vol = grid%cell_volume
    negative = 0
    total = .not. state%solid%present
    g = 0.0_wp
    if (present(gravity) .and. total) g = potential_gravity(grid, gravity)
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
          if (.not. grid%active(d)) cycle
          o = 0
          o(d) = 1
          r = face_range(grid, d)
          area = vol / grid%dx(d)
          do k = r(1, 3), r(2, 3)
            do j = r(1, 2), r(2, 2)
              do i = r(1, 1), r(2, 1)
                u = f%uface(i, j, k, d)
                if (u == 0.0_wp) cycle
                sweep = u * dt * area
                ! centroid of the swept volume relative to the upwind cell centre
                if (u > 0.0_wp) then
                  up = [i, j, k] - o
                  dist = 0.5_wp * (grid%dx(d) - u * dt)
                else
                  up = [i, j, k]
                  dist = -0.5_wp * (grid%dx(d) + u * dt)
                end if
                rho_f = f%rho(up(1), up(2), up(3))
                if (order > 1) rho_f = rho_f + dist * limited_slope(f%rho(up(1) - o(1), &
                  up(2) - o(2), up(3) - o(3)), f%rho(up(1), up(2), up(3)), &
                  f%rho(up(1) + o(1), up(2) + o(2), up(3) + o(3)), grid%dx(d))
                mflux = rho_f * sweep
                c(i - o(1), j - o(2), k - o(3), 1) = c(i - o(1), j - o(2), k - o(3), 1) - mflux
                c(i, j, k, 1) = c(i, j, k, 1) + mflux
                do n = 1, 5
                  q_f = f%lag(up(1), up(2), up(3), n)
                  if (order > 1) q_f = q_f + dist * limited_slope(f%lag(up(1) - o(1), &
                    up(2) - o(2), up(3) - o(3), n), q_f, &
                    f%lag(up(1) + o(1), up(2) + o(2), up(3) + o(3), n), grid%dx(d))
                  if (n == 4 .and. total) q_f = q_f + 0.5_wp * ke_face(up, o, dist) + &
                    potential(up(1), up(2), up(3)) - merge(dist, 0.0_wp, order > 1) * g(d)
                  c(i - o(1), j - o(2), k - o(3), 1 + n) = &
                    c(i - o(1), j - o(2), k - o(3), 1 + n) - mflux * q_f
                  c(i, j, k, 1 + n) = c(i, j, k, 1 + n) + mflux * q_f
                end do
              end do
            end do
          end do
        end do
        ! eqs. 62-65: primitives from the conserved quantities
        do k = grid%lo(3), grid%hi(3)
          do j = grid%lo(2), grid%hi(2)
            do i = grid%lo(1), grid%hi(1)
              if (c(i, j, k, 1) < 0.0_wp) negative = negative + 1
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

  contains

    !> Potential -g.x [J/kg] at the centre of cell (ci, cj, ck).
    real(wp) function potential(ci, cj, ck)
      integer, intent(in) :: ci  !< cell index along x
      integer, intent(in) :: cj  !< cell index along y
      integer, intent(in) :: ck  !< cell index along z
      potential = -(g(1) * cell_centre(grid, 1, ci) + g(2) * cell_centre(grid, 2, cj) + &
        g(3) * cell_centre(grid, 3, ck))
    end function potential

    !> |u|^2 carried through a face: the squares of the reconstructed velocity components.
    real(wp) function ke_face(cell, off, distance)
      integer, intent(in) :: cell(3)      !< upwind cell
      integer, intent(in) :: off(3)       !< unit offset along the face normal
      real(wp), intent(in) :: distance    !< centroid offset [m]
      integer :: q
      real(wp) :: w
      ke_face = 0.0_wp
      do q = 1, 3
        w = state%fluid(m)%lag(cell(1), cell(2), cell(3), q)
        if (order > 1) w = w + distance * limited_slope(state%fluid(m)%lag(cell(1) - off(1), &
          cell(2) - off(2), cell(3) - off(3), q), w, state%fluid(m)%lag(cell(1) + off(1), &
          cell(2) + off(2), cell(3) + off(3), q), grid%dx(d))
        ke_face = ke_face + w**2
      end do
    end function ke_face
  end subroutine ice_advect

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
    if (a * b > 0.0_wp) then
      limited_slope = sign(min(2.0_wp * abs(a), 2.0_wp * abs(b), 0.5_wp * abs(a + b)), a) / dx
    else
      limited_slope = 0.0_wp
    end if
  end function limited_slope
end module ice_advection
