!> Pressure equilibration among the fluids of a cell: find p such that the volume fractions
!! phi_m = rho_bar_m / rho_m(p, T_m) sum to one (Newton on sum phi - 1, as Uintah's ICE
!! computeEquilibrationPressure), then the intrinsic specific volumes, sound speeds and
!! compressibilities kappa_m = v_m / c_m^2 used by the implicit pressure equation (eq. 35).
!! With one fluid phi = 1, rho_micro = rho_bar and p = p_eos(rho_bar, T) directly.
module ice_equilibration
  use mpmice_log, only: log_repeated
  use mpmice_kinds, only: wp
  use grid_layout, only: grid_t, cell_centre
  use ice_eos, only: eos_pressure, eos_density, eos_dp_drho, eos_sound_speed2
  use ice_state, only: ice_state_t
  use ice_solid_view, only: ice_solid_view_t
  use mpmice_errors, only: real_short_text
  implicit none
  private

  public :: ice_equilibrate, report_equilibration_failure

  !> Pressure [Pa] at which a trace fluid's volume is judged (trace_fallback) and at which a trace
  !! left out of the volume sum takes its density when the others' pressure is not positive
  real(wp), parameter :: trace_pressure = 1.0_wp

contains

  !> Equilibrate every allocated cell (ghosts included, so no halo exchange is needed after it).
  !! `state%pressure` is the initial guess on entry; `state%p_eq` and `state%pressure` hold the
  !! equilibrium pressure on exit. `max_iterations_used` is the largest Newton count over the
  !! cells and `failed` the number of cells that missed `tolerance` on sum phi - 1.
  subroutine ice_equilibrate(state, grid, tolerance, max_iterations, max_iterations_used, failed, &
      first_failed, solid)
    type(ice_state_t), intent(inout) :: state      !< fluids and pressure
    type(grid_t), intent(in) :: grid               !< block geometry
    real(wp), intent(in) :: tolerance              !< |sum phi - 1| to reach
    integer, intent(in) :: max_iterations          !< Newton iteration limit
    integer, intent(out) :: max_iterations_used    !< largest iteration count
    integer, intent(out) :: failed                 !< cells that did not converge
    integer, intent(out), optional :: first_failed(3) !< the first such cell (0 when none)
    !> the solid phase of a coupled scene: the fluids fill its pores, its compressibility joins
    !! sum_kappa
    class(ice_solid_view_t), intent(in), optional :: solid
    integer :: i, j, k, m, it, n
    real(wp) :: p, p_full, rho_m, porosity
    logical :: converged, full_converged, with_solid

    with_solid = present(solid)
    n = state%nfluids
    max_iterations_used = 0
    failed = 0
    if (present(first_failed)) first_failed = 0
    ! every fluid takes part in the volume sum (the state's work flags: no allocation)
    state%work%active = .true.
    do k = grid%lbc(3), grid%ubc(3)
      do j = grid%lbc(2), grid%ubc(2)
        do i = grid%lbc(1), grid%ubc(1)
          ! the fluids fill the pore space n = 1 - phi_s of a coupled scene (eq. 1)
          porosity = 1.0_wp
          if (with_solid) porosity = 1.0_wp - solid%vfrac(i, j, k)
          if (n == 1) then
            associate (fl => state%fluid(1))
              p = eos_pressure(fl%eos, fl%rho(i, j, k) / porosity, fl%temp(i, j, k))
            end associate
          else
            p = state%pressure(i, j, k)
            call newton_pressure(state, i, j, k, porosity, state%work%active, tolerance, &
              max_iterations, p, it, converged)
            max_iterations_used = max(max_iterations_used, it)
            ! a failed iteration, or a root below 1 Pa (a trace filling the others' deficit):
            ! without the traces (trace_fallback), else the full sum's root stands
            if (.not. converged .or. p < trace_pressure) then
              p_full = p
              full_converged = converged
              call trace_fallback(state, i, j, k, porosity, tolerance, max_iterations, p, &
                converged, state%work%trace_active)
              if (full_converged .and. .not. converged) then
                p = p_full
                converged = .true.
              end if
            end if
            if (.not. converged) then
              failed = failed + 1
              if (present(first_failed) .and. failed == 1) first_failed = [i, j, k]
            end if
          end if
          state%pressure(i, j, k) = p
          state%p_eq(i, j, k) = p
          state%sum_kappa(i, j, k) = 0.0_wp
          do m = 1, n
            associate (fl => state%fluid(m))
              if (n == 1) then
                rho_m = fl%rho(i, j, k) / porosity
              else
                ! a trace left out of the volume sum (trace_fallback) keeps a positive density
                rho_m = eos_density(fl%eos, p, fl%temp(i, j, k))
                if (rho_m <= 0.0_wp) rho_m = eos_density(fl%eos, trace_pressure, fl%temp(i, j, k))
              end if
              fl%spvol(i, j, k) = 1.0_wp / rho_m
              fl%vfrac(i, j, k) = fl%rho(i, j, k) / rho_m
              fl%c2(i, j, k) = eos_sound_speed2(fl%eos, rho_m, fl%temp(i, j, k))
              fl%kappa(i, j, k) = fl%spvol(i, j, k) / fl%c2(i, j, k)
              state%sum_kappa(i, j, k) = state%sum_kappa(i, j, k) + &
                fl%vfrac(i, j, k) * fl%kappa(i, j, k)
            end associate
          end do
          if (with_solid) state%sum_kappa(i, j, k) = state%sum_kappa(i, j, k) + &
            solid%vfrac(i, j, k) * solid%kappa(i, j, k)
        end do
      end do
    end do
  end subroutine ice_equilibrate

  !> Where this rank's equilibration failed (`failed` > 0), one warning line on standard error
  !! about cell `c` (`first_failed` of `ice_equilibrate`): its centre [m], its solid fraction in
  !! a coupled scene, each fluid's bulk density [kg/m^3] and temperature [K], and the pressure
  !! the iteration reached, which the step's rejection otherwise leaves to guess. Every rank
  !! reports its own cell; nothing when `failed` is 0.
  subroutine report_equilibration_failure(state, grid, failed, c, solid)
    type(ice_state_t), intent(in) :: state  !< fluids
    type(grid_t), intent(in) :: grid        !< block geometry
    integer, intent(in) :: failed           !< cells of this rank that failed
    integer, intent(in) :: c(3)             !< the first of them
    class(ice_solid_view_t), intent(in), optional :: solid !< solid phase of a coupled scene
    character(len=:), allocatable :: text
    integer :: d, m
    if (failed <= 0) return
    text = 'mpmice: warning: equilibration failed in the cell at'
    do d = 1, grid%ndim
      text = text // ' ' // real_short_text(cell_centre(grid, d, c(d)))
    end do
    text = text // ' m:'
    if (present(solid)) text = text // ' solid fraction ' // &
      real_short_text(solid%vfrac(c(1), c(2), c(3))) // ','
    do m = 1, state%nfluids
      text = text // ' ' // trim(state%fluid(m)%name) // ' rho_bar ' // &
        real_short_text(state%fluid(m)%rho(c(1), c(2), c(3))) // ' kg/m^3 T ' // &
        real_short_text(state%fluid(m)%temp(c(1), c(2), c(3))) // ' K,'
    end do
    text = text // ' pressure reached ' // &
      real_short_text(state%pressure(c(1), c(2), c(3))) // ' Pa'
    call log_repeated(text)
  end subroutine report_equilibration_failure

  !> Newton iteration on sum phi_m(p) - n = 0 over the fluids marked `active` (eqs. 10-11 with
  !! the pores, as Uintah's computeEquilibrationPressure). `p` is the initial guess on entry and
  !! the pressure [Pa] on exit; `iterations` the count used (max_iterations + 1 when it failed).
  pure subroutine newton_pressure(state, i, j, k, porosity, active, tolerance, max_iterations, &
      p, iterations, converged)
    type(ice_state_t), intent(in) :: state  !< fluids
    integer, intent(in) :: i, j, k          !< cell
    real(wp), intent(in) :: porosity        !< pore fraction n = 1 - phi_s [-]
    logical, intent(in) :: active(:)        !< fluids taking part in the volume sum
    real(wp), intent(in) :: tolerance       !< |sum phi - n| to reach
    integer, intent(in) :: max_iterations   !< iteration limit
    real(wp), intent(inout) :: p            !< pressure [Pa]
    integer, intent(out) :: iterations      !< iterations used
    logical, intent(out) :: converged       !< tolerance reached
    integer :: m, it
    real(wp) :: f, deriv, rho_m, phi, pn, floor

    ! keep the iteration above the pressure floor of the fluids that matter (below it a gas's
    ! volume is negative: a spurious root); a guess below it (a pressure solve that overshot
    ! below zero beside a real amount of gas) starts just above it
    floor = pressure_floor(state, i, j, k, porosity, active, tolerance)
    if (floor > -huge(1.0_wp) .and. .not. p > floor) p = floor + trace_pressure
    do it = 1, max_iterations
      f = -porosity
      deriv = 0.0_wp
      do m = 1, state%nfluids
        if (.not. active(m)) cycle
        associate (fl => state%fluid(m))
          rho_m = eos_density(fl%eos, p, fl%temp(i, j, k))
          phi = fl%rho(i, j, k) / rho_m
          f = f + phi
          deriv = deriv + phi / (rho_m * eos_dp_drho(fl%eos, rho_m, fl%temp(i, j, k)))
        end associate
      end do
      ! d(sum phi)/dp = -deriv: Newton step p <- p + f / deriv, kept above the floor (and
      ! positive from a positive pressure). One more step after reaching the tolerance
      ! (quadratic convergence: error ~ tolerance^2), since |sum phi - 1| = 1e-10 still allows
      ! K 1e-10 = 0.2 Pa of error for water.
      pn = max(p + f / deriv, floor + 0.1_wp * (p - floor))
      if (p > 0.0_wp) pn = max(pn, 0.1_wp * p)
      p = pn
      if (abs(f) <= tolerance) exit
    end do
    iterations = it
    converged = it <= max_iterations
  end subroutine newton_pressure

  !> The lowest pressure [Pa] at which every active fluid that is not a trace (its volume at
  !! `trace_pressure` above the floor at least `tolerance` of the pores) has a positive density:
  !! 0 for an ideal gas, -p_inf for a stiffened gas, p_ref - K (about) for the linear water.
  !! Above it each phi_m(p) = rho_bar_m / rho_m(p) is positive, decreasing and convex, so
  !! sum phi - n has exactly one root there and Newton started below that root approaches it
  !! monotonically. Below it a gas's volume is negative and sum phi - n has a spurious root:
  !! water under tension beside a real amount of air converged there, the air's volume then
  !! came out as rho_bar / rho(1 Pa) (2.7 of the cell for 2.6e-5 kg/m^3) with the
  !! compressibility of air at 1 Pa. Traces do not set the floor (their volume cannot matter
  !! above it; a trace of air in water under tension keeps the water's tension, trace_fallback).
  pure real(wp) function pressure_floor(state, i, j, k, porosity, active, tolerance) &
      result(floor)
    type(ice_state_t), intent(in) :: state  !< fluids
    integer, intent(in) :: i, j, k          !< cell
    real(wp), intent(in) :: porosity        !< pore fraction n = 1 - phi_s [-]
    logical, intent(in) :: active(:)        !< fluids taking part in the volume sum
    real(wp), intent(in) :: tolerance       !< |sum phi - n| to reach
    integer :: m
    real(wp) :: p0
    floor = -huge(1.0_wp)
    do m = 1, state%nfluids
      if (.not. active(m)) cycle
      associate (fl => state%fluid(m))
        p0 = eos_pressure(fl%eos, 0.0_wp, fl%temp(i, j, k))
        if (fl%rho(i, j, k) < tolerance * porosity * eos_density(fl%eos, p0 + trace_pressure, &
          fl%temp(i, j, k))) cycle
        floor = max(floor, p0)
      end associate
    end do
  end function pressure_floor

  !> When the Newton iteration fails, or converges below `trace_pressure` (1 Pa), solve again
  !! without the trace fluids: those whose volume at 1 Pa would still be below `tolerance` of
  !! the pores (e.g. 1e-100 kg/m^3 of air numerically left in water-filled pores). Their volume
  !! cannot matter to the sum within the tolerance at any pressure above 1 Pa, but where the
  !! others' pressure falls toward zero (water under tension in a moving porous body) the full
  !! sum has its root at an absurd pressure: 1e-90 Pa, which the iteration cannot reach, or
  !! 1e-11 Pa (4e-20 kg/m^3 of air), which it reaches, the trace then filling 3e-4 of the cell
  !! with a compressibility of 1e25 /Pa that no pressure solve can balance (the 5 mm debris
  !! flow's failure, docs/mpmice.md departure 10). Left with one fluid, the pressure comes from its
  !! equation of state directly (it may then be negative: tension). Not converged when there
  !! is no trace to leave out (or nothing else).
  pure subroutine trace_fallback(state, i, j, k, porosity, tolerance, max_iterations, p, &
      converged, active)
    type(ice_state_t), intent(in) :: state  !< fluids
    integer, intent(in) :: i, j, k          !< cell
    real(wp), intent(in) :: porosity        !< pore fraction n = 1 - phi_s [-]
    real(wp), intent(in) :: tolerance       !< |sum phi - n| to reach
    integer, intent(in) :: max_iterations   !< iteration limit
    real(wp), intent(inout) :: p            !< pressure [Pa]: the initial guess on entry
    logical, intent(out) :: converged       !< a pressure was found
    !> work: the fluids that are not traces (the state's `work%trace_active`, not referenced
    !! through `state` here)
    logical, intent(out) :: active(state%nfluids)
    integer :: m, it

    do m = 1, state%nfluids
      associate (fl => state%fluid(m))
        active(m) = fl%rho(i, j, k) >= tolerance * porosity * &
          eos_density(fl%eos, trace_pressure, fl%temp(i, j, k))
      end associate
    end do
    converged = .false.
    if (all(active) .or. .not. any(active)) return
    if (count(active) == 1) then
      m = findloc(active, .true., 1)
      associate (fl => state%fluid(m))
        p = eos_pressure(fl%eos, fl%rho(i, j, k) / porosity, fl%temp(i, j, k))
      end associate
      converged = .true.
    else
      p = state%pressure(i, j, k)
      call newton_pressure(state, i, j, k, porosity, active, tolerance, max_iterations, p, it, &
        converged)
    end if
  end subroutine trace_fallback
end module ice_equilibration
