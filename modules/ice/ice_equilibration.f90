!> Pressure equilibration among the fluids of a cell: find p such that the volume fractions
!! phi_m = rho_bar_m / rho_m(p, T_m) sum to one (Newton on sum phi - 1, as Uintah's ICE
!! computeEquilibrationPressure), then the intrinsic specific volumes, sound speeds and
!! compressibilities kappa_m = v_m / c_m^2 used by the implicit pressure equation (eq. 35).
!! With one fluid phi = 1, rho_micro = rho_bar and p = p_eos(rho_bar, T) directly.
module ice_equilibration
  use mpmice_kinds, only: wp
  use grid_layout, only: grid_t
  use ice_eos, only: eos_pressure, eos_density, eos_dp_drho, eos_sound_speed2
  use ice_state, only: ice_state_t
  implicit none
  private

  public :: ice_equilibrate

contains

  !> Equilibrate every allocated cell (ghosts included, so no halo exchange is needed after it).
  !! `state%pressure` is the initial guess on entry; `state%p_eq` and `state%pressure` hold the
  !! equilibrium pressure on exit. `max_iterations_used` is the largest Newton count over the
  !! cells and `failed` the number of cells that missed `tolerance` on sum phi - 1.
  subroutine ice_equilibrate(state, grid, tolerance, max_iterations, max_iterations_used, failed)
    type(ice_state_t), intent(inout) :: state      !< fluids and pressure
    type(grid_t), intent(in) :: grid               !< block geometry
    real(wp), intent(in) :: tolerance              !< |sum phi - 1| to reach
    integer, intent(in) :: max_iterations          !< Newton iteration limit
    integer, intent(out) :: max_iterations_used    !< largest iteration count
    integer, intent(out) :: failed                 !< cells that did not converge
    integer :: i, j, k, m, it, n
    real(wp) :: p, pn, f, deriv, rho_m, phi, porosity

    n = state%nfluids
    max_iterations_used = 0
    failed = 0
    do k = grid%lbc(3), grid%ubc(3)
      do j = grid%lbc(2), grid%ubc(2)
        do i = grid%lbc(1), grid%ubc(1)
          ! the fluids fill the pore space n = 1 - phi_s of a coupled scene (eq. 1)
          porosity = 1.0_wp
          if (state%solid%present) porosity = 1.0_wp - state%solid%vfrac(i, j, k)
          if (n == 1) then
            associate (fl => state%fluid(1))
              p = eos_pressure(fl%eos, fl%rho(i, j, k) / porosity, fl%temp(i, j, k))
            end associate
          else
            p = state%pressure(i, j, k)
            do it = 1, max_iterations
              f = -porosity
              deriv = 0.0_wp
              do m = 1, n
                associate (fl => state%fluid(m))
                  rho_m = eos_density(fl%eos, p, fl%temp(i, j, k))
                  phi = fl%rho(i, j, k) / rho_m
                  f = f + phi
                  deriv = deriv + phi / (rho_m * eos_dp_drho(fl%eos, rho_m, fl%temp(i, j, k)))
                end associate
              end do
              ! d(sum phi)/dp = -deriv: Newton step p <- p + f / deriv, kept positive. One more
              ! step after reaching the tolerance (quadratic convergence: error ~ tolerance^2),
              ! since |sum phi - 1| = 1e-10 still allows K 1e-10 = 0.2 Pa of error for water.
              pn = p + f / deriv
              if (p > 0.0_wp) pn = max(pn, 0.1_wp * p)
              p = pn
              if (abs(f) <= tolerance) exit
            end do
            max_iterations_used = max(max_iterations_used, it)
            if (it > max_iterations) failed = failed + 1
          end if
          state%pressure(i, j, k) = p
          state%p_eq(i, j, k) = p
          state%sum_kappa(i, j, k) = 0.0_wp
          do m = 1, n
            associate (fl => state%fluid(m))
              if (n == 1) then
                rho_m = fl%rho(i, j, k) / porosity
              else
                rho_m = eos_density(fl%eos, p, fl%temp(i, j, k))
              end if
              fl%spvol(i, j, k) = 1.0_wp / rho_m
              fl%vfrac(i, j, k) = fl%rho(i, j, k) / rho_m
              fl%c2(i, j, k) = eos_sound_speed2(fl%eos, rho_m, fl%temp(i, j, k))
              fl%kappa(i, j, k) = fl%spvol(i, j, k) / fl%c2(i, j, k)
              state%sum_kappa(i, j, k) = state%sum_kappa(i, j, k) + &
                fl%vfrac(i, j, k) * fl%kappa(i, j, k)
            end associate
          end do
          if (state%solid%present) state%sum_kappa(i, j, k) = state%sum_kappa(i, j, k) + &
            state%solid%vfrac(i, j, k) * state%solid%kappa(i, j, k)
        end do
      end do
    end do
  end subroutine ice_equilibrate
end module ice_equilibration
