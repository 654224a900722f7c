!> Heat of the solid phase of a coupled scene (paper eqs. 38-39, 52-55, 68, 73; errata E9:
!! q = -k grad T with the conductivity k).
!!
!! The solid's heat lives where the fluid's does, on the ICE cells:
!! * the particles deposit their heat capacity m_p c_s, energy m_p c_s T_p and grain conductance
!!   (m_p / rho_s) k_s with the same overlap weights w_pc as their grain volume
!!   (`mpmice_deposit%solid_deposit`); the cell temperature is the capacity-weighted mean;
!! * conduction (eqs. 38-39) is explicit on the cells with face conductances the harmonic mean of
!!   phi_s k_s of the two cells (zero where either has no solid), the same stencil and ghost
!!   conditions as the fluid's conduction (`ice_viscous`), so that at local thermal equilibrium
!!   the mixture conducts with k_m = sum_f phi_f k_f + phi_s k_s;
!! * the fluid-solid exchange (eqs. 52-55) is implicit, in `exchange_fluid_solid`;
!! * the particles receive the cell increments with the deposit's weights,
!!   T_p += sum_c w_pc dT_c (eqs. 68, 73), so sum_p m_p c_s dT_p = sum_c C_c dT_c exactly.
!! Departure from the paper (docs/mpmice.md): the solid's conduction is done on the cells, not on
!! the MPM nodes (eq. 38) followed by a cell-to-node interpolation of the exchange.
module mpmice_solid_heat
  use mpmice_kinds, only: wp
  use grid_layout, only: grid_t
  use grid_sweep, only: sweep_direction
  use ice_state, only: ice_state_t
  use exchange_solid_phase, only: solid_phase_t
  use particles_store, only: particles_t
  use mpmice_deposit, only: overlap_weights, deformed_half_widths
  use ice_viscous, only: face_mean, face_conduction
  implicit none
  private

  public :: solid_conduction, solid_conduction_dt, solid_heat_to_particles

contains

  !> Explicit conduction of the solid over dt: `solid%temp` of the owned cells with solid
  !! (heat capacity > 0) gets dt / (C V) sum_faces A k_face (T_nb - T) / dx. Needs `temp` and
  !! `conductance` valid in one ghost layer (domain faces: the fluid's thermal conditions).
  subroutine solid_conduction(solid, grid, dt, scratch)
    type(solid_phase_t), intent(inout) :: solid !< solid phase
    type(grid_t), intent(in) :: grid            !< block geometry
    real(wp), intent(in) :: dt                  !< time step [s]
    real(wp), intent(inout) :: scratch(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !< heat [J]
    integer :: d, i, j, k, o(3)
    real(wp) :: area, k_lo, k_hi
    associate (sp => solid)
      if (.not. any(sp%conductance > 0.0_wp)) return
      scratch = 0.0_wp
      do d = 1, 3
        if (.not. sweep_direction(grid, d, o, area)) cycle
        do k = grid%lo(3), grid%hi(3)
          do j = grid%lo(2), grid%hi(2)
            do i = grid%lo(1), grid%hi(1)
              if (sp%heat_cap(i, j, k) <= 0.0_wp) cycle
              call face_conductances(grid, sp%conductance, [i, j, k], o, k_lo, k_hi)
              scratch(i, j, k) = scratch(i, j, k) + face_conduction(dt * area / grid%dx(d), k_lo, &
                k_hi, sp%temp(i - o(1), j - o(2), k - o(3)), sp%temp(i, j, k), &
                sp%temp(i + o(1), j + o(2), k + o(3)))
            end do
          end do
        end do
      end do
      associate (lo => grid%lo, hi => grid%hi)
        where (sp%heat_cap(lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)) > 0.0_wp) &
          sp%temp(lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)) = &
          sp%temp(lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)) + &
          scratch(lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)) / &
          (sp%heat_cap(lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)) * grid%cell_volume)
      end associate
    end associate
  end subroutine solid_conduction

  !> Stability limit [s] of `solid_conduction` on this rank: 1 / max_c sum_faces k_face /
  !! (C_c dx^2) (the forward-Euler update stays a convex combination); huge without conduction.
  !! Needs the same ghost values as `solid_conduction`.
  function solid_conduction_dt(solid, grid) result(dt)
    type(solid_phase_t), intent(in) :: solid !< solid phase
    type(grid_t), intent(in) :: grid        !< block geometry
    real(wp) :: dt
    real(wp) :: rate, rate_max, k_lo, k_hi
    integer :: d, i, j, k, o(3)
    rate_max = 0.0_wp
    associate (sp => solid)
      if (.not. any(sp%conductance > 0.0_wp)) then
        dt = huge(1.0_wp)
        return
      end if
      do k = grid%lo(3), grid%hi(3)
        do j = grid%lo(2), grid%hi(2)
          do i = grid%lo(1), grid%hi(1)
            if (sp%heat_cap(i, j, k) <= 0.0_wp) cycle
            rate = 0.0_wp
            do d = 1, 3
              if (.not. grid%active(d)) cycle
              o = 0
              o(d) = 1
              call face_conductances(grid, sp%conductance, [i, j, k], o, k_lo, k_hi)
              rate = rate + (k_lo + k_hi) / grid%dx(d)**2
            end do
            rate_max = max(rate_max, rate / sp%heat_cap(i, j, k))
          end do
        end do
      end do
    end associate
    dt = huge(1.0_wp)
    if (rate_max > 0.0_wp) dt = 1.0_wp / rate_max
  end function solid_conduction_dt

  !> Conductances [W/m/K] of the low and high faces of cell `c` along the unit offset `o`: the
  !! harmonic means of phi_s k_s of the two cells (zero where either holds no solid).
  pure subroutine face_conductances(grid, conductance, c, o, k_lo, k_hi)
    type(grid_t), intent(in) :: grid              !< block geometry
    real(wp), intent(in) :: conductance(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !< phi_s k_s
    integer, intent(in) :: c(3)                   !< cell
    integer, intent(in) :: o(3)                   !< unit offset of the face direction
    real(wp), intent(out) :: k_lo                 !< low face [W/m/K]
    real(wp), intent(out) :: k_hi                 !< high face [W/m/K]
    k_lo = face_mean(conductance(c(1) - o(1), c(2) - o(2), c(3) - o(3)), &
      conductance(c(1), c(2), c(3)))
    k_hi = face_mean(conductance(c(1), c(2), c(3)), &
      conductance(c(1) + o(1), c(2) + o(2), c(3) + o(3)))
  end subroutine face_conductances

  !> Add the cell temperature increments `dtemp` [K] to the particles with the weights of their
  !! deposit (positions and F as at the deposit: call before G2P). `dtemp` valid in the ghost
  !! cells the particles' domains reach.
  subroutine solid_heat_to_particles(p, grid, dtemp)
    type(particles_t), intent(inout) :: p      !< particles (temperature updated)
    type(grid_t), intent(in) :: grid           !< block geometry
    real(wp), intent(in) :: dtemp(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !< increment [K]
    integer :: ip, d, a, b, c, first(3), nc(3)
    real(wp) :: w(2, 3), l(3), inc
    do ip = 1, p%np
      l = deformed_half_widths(p, ip, grid)
      do d = 1, 3
        call overlap_weights(grid, d, p%x(d, ip), l(d), first(d), nc(d), w(:, d))
      end do
      inc = 0.0_wp
      do c = 1, nc(3)
        do b = 1, nc(2)
          do a = 1, nc(1)
            inc = inc + w(a, 1) * w(b, 2) * w(c, 3) * &
              dtemp(first(1) + a - 1, first(2) + b - 1, first(3) + c - 1)
          end do
        end do
      end do
      p%temperature(ip) = p%temperature(ip) + inc
    end do
  end subroutine solid_heat_to_particles
end module mpmice_solid_heat
