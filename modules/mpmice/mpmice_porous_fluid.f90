!> The fluids' corrections next to a porous solid in a coupled scene (departures from paper eqs.
!! 31 and 42-51, docs/mpmice.md): the face predictor keeps the faces' own momentum next to solid
!! (`fluid_face_predictor_porous`), and the Lagrangian cell velocity there is the flux-consistent
!! mean of the final face velocities (`fluid_face_blend`), so that the pore velocity's jump at
!! the edge of a porous body does not push an odd-even pattern into the free fluid.
module mpmice_porous_fluid
  use mpmice_kinds, only: wp
  use grid_layout, only: grid_t
  use ice_state, only: ice_state_t, ice_fluid_t
  use exchange_solid_phase, only: solid_phase_t
  use ice_face_velocity, only: open_face_sweep, upwind
  use grid_sweep, only: sweep_direction
  implicit none
  private

  public :: fluid_face_blend, fluid_face_predictor_porous

contains

  !> Advective part of the fluid face predictor (eq. 31) at faces next to solid: the face's own
  !! final velocity of the previous step instead of the mass-weighted mean of the two cell
  !! velocities (a staggered momentum there; departure from eq. 31). A fluid's cell velocity in
  !! a porous cell is its pore velocity, which jumps with the porosity while the flux is
  !! continuous, and ICE's cell momentum sees only the two-cell-wide pressure difference of the
  !! face pressures (eq. 37): the cell mean is wrong at the edge of a porous body (a 20-cell
  !! Darcy column had a 7 % too fast pore velocity and an odd-even velocity pattern in the free
  !! water) and lags in a consolidating column. The drag makes the face inertia negligible
  !! there, so the face momentum is not advected. The pressure and gravity terms stay.
  subroutine fluid_face_predictor_porous(state, solid, grid, previous)
    type(ice_state_t), intent(inout) :: state   !< fluids (uface updated)
    type(solid_phase_t), intent(in) :: solid !< solid phase
    type(grid_t), intent(in) :: grid            !< block geometry
    real(wp), intent(in) :: previous(:, grid%lbc(1):, grid%lbc(2):, grid%lbc(3):, :) !< last
                                                !! step's final face velocities (3, cells, fluid)
    integer :: m, i, j, k, d, o(3), r(2, 3)
    real(wp) :: rl, rr, mean
    do d = 1, 3
      if (.not. open_face_sweep(state, grid, d, o, r)) cycle
      do k = r(1, 3), r(2, 3)
        do j = r(1, 2), r(2, 2)
          do i = r(1, 1), r(2, 1)
            if (solid%vfrac(i - o(1), j - o(2), k - o(3)) <= 0.0_wp .and. &
              solid%vfrac(i, j, k) <= 0.0_wp) cycle
            do m = 1, state%nfluids
              rl = state%fluid(m)%rho(i - o(1), j - o(2), k - o(3))
              rr = state%fluid(m)%rho(i, j, k)
              if (rl + rr <= 0.0_wp) cycle
              mean = (rl * state%fluid(m)%vel(i - o(1), j - o(2), k - o(3), d) + &
                rr * state%fluid(m)%vel(i, j, k, d)) / (rl + rr)
              state%fluid(m)%uface(i, j, k, d) = state%fluid(m)%uface(i, j, k, d) - mean + &
                previous(d, i, j, k, m)
            end do
          end do
        end do
      end do
    end do
  end subroutine fluid_face_predictor_porous

  !> Near solid (a cell holding solid or next to one), the Lagrangian cell velocity of every
  !! fluid becomes the flux-consistent mean of its two final face velocities, component by
  !! component: u_c = (n_up,lo u_lo + n_up,hi u_hi) / (2 n_c) with the pore fractions
  !! n = 1 - phi_s (upwind at the faces). Departure from eqs. 42-51 for the normal components
  !! there: the faces carry the fluid's momentum next to solid (`fluid_face_predictor_porous`),
  !! and fluid leaving a porous body at the pore velocity would otherwise push an odd-even
  !! velocity pattern into the free fluid, a null mode of ICE's cell momentum that nothing
  !! restores. The pore fractions, not the fluid's own: with one fluid they are the same, but
  !! at a free surface next to the bed the fluid's fraction jumps from a full cell to a partly
  !! filled one, and n_up u / (2 phi_c) with phi_c < n_up / 2 amplified the face velocity (the
  !! 40 mm debris flow's water over the shelf edge: ten-fold per millisecond, then failure).
  subroutine fluid_face_blend(state, solid, grid)
    type(ice_state_t), intent(inout) :: state   !< fluids (lag(:,:,:,1:3) updated, owned cells)
    type(solid_phase_t), intent(in) :: solid !< solid phase
    type(grid_t), intent(in) :: grid            !< block geometry
    integer :: m
    do m = 1, state%nfluids
      call blend_fluid(state%fluid(m), solid, grid)
    end do
  end subroutine fluid_face_blend

  !> `fluid_face_blend` of one fluid `f`.
  subroutine blend_fluid(f, solid, grid)
    type(ice_fluid_t), intent(inout) :: f       !< the fluid (lag(:,:,:,1:3) updated)
    type(solid_phase_t), intent(in) :: solid    !< solid phase
    type(grid_t), intent(in) :: grid            !< block geometry
    integer :: i, j, k, d, o(3)
    real(wp) :: flo, fhi, ulo, uhi
    associate (phi_s => solid%vfrac)
      do d = 1, 3
        if (.not. sweep_direction(grid, d, o)) cycle
        do k = grid%lo(3), grid%hi(3)
          do j = grid%lo(2), grid%hi(2)
            do i = grid%lo(1), grid%hi(1)
              if (f%rho(i, j, k) <= 0.0_wp .or. f%vfrac(i, j, k) <= 0.0_wp) cycle
              if (.not. near_solid(solid, grid, [i, j, k])) cycle
              ulo = f%uface(i, j, k, d)
              uhi = f%uface(i + o(1), j + o(2), k + o(3), d)
              flo = 1.0_wp - upwind(ulo, phi_s(i - o(1), j - o(2), k - o(3)), phi_s(i, j, k))
              fhi = 1.0_wp - upwind(uhi, phi_s(i, j, k), phi_s(i + o(1), j + o(2), k + o(3)))
              f%lag(i, j, k, d) = 0.5_wp * (flo * ulo + fhi * uhi) / (1.0_wp - phi_s(i, j, k))
            end do
          end do
        end do
      end do
    end associate
  end subroutine blend_fluid

  !> True when cell c or one of its face neighbours holds solid.
  pure logical function near_solid(solid, grid, c) result(near)
    type(solid_phase_t), intent(in) :: solid !< solid phase
    type(grid_t), intent(in) :: grid        !< block geometry
    integer, intent(in) :: c(3)             !< cell
    integer :: d, o(3)
    near = solid%vfrac(c(1), c(2), c(3)) > 0.0_wp
    do d = 1, 3
      if (near) return
      if (.not. grid%active(d)) cycle
      o = 0
      o(d) = 1
      near = solid%vfrac(c(1) - o(1), c(2) - o(2), c(3) - o(3)) > 0.0_wp .or. &
        solid%vfrac(c(1) + o(1), c(2) + o(2), c(3) + o(3)) > 0.0_wp
    end do
  end function near_solid
end module mpmice_porous_fluid
