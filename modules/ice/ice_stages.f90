!> The ICE step as named stages (paper eqs. 29-37, 42-46, 50-51, 54-65; docs/architecture.md
!! "Step pipeline"), shared by the ICE scene and the coupled scene:
!!
!!  `ice_stage_equilibrate` (eqs. 10-11) -> `ice_stage_face_velocities` (eqs. 30-31, at time
!!  n + face_time dt) -> `ice_stage_face_exchange` (eq. 34) -> `ice_stage_pressure` (eqs. 35-36,
!!  outer iteration) -> `ice_stage_lagrangian` (face pressure eq. 37, viscous and Smagorinsky
!!  sources eqs. 23-25, Lagrangian values eqs. 42-46) -> `ice_stage_cell_exchange`
!!  (eqs. 50-51) -> `ice_stage_advect` (eqs. 58-65, interface compression).
!!
!! Each stage works in the scene's context (`scene_t%ctx`: decomposition, grid, timers) and runs
!! its own stage timer. The solid phase of a coupled scene is an optional
!! argument of the stages it changes, handed on to the kernels; the coupled scene adds the
!! solid's own stages between
!! these (`mpmice_scene`). `ice_fluids_t` holds what the stages need: the fluids, halos, the
!! pressure solver, the face conditions and the numerical parameters.
module ice_stages
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite, ieee_value, ieee_quiet_nan
  use mpmice_kinds, only: wp
  use mpmice_errors, only: int_text, real_short_text
  use mpmice_log, only: log_warning
  use mpmice_timers, only: timer_start, timer_stop
  use parallel_halo, only: halo_t, halo_exchange_cell
  use parallel_reduce, only: global_max, global_sum
  use solver_pressure, only: struct_solver_t, struct_solver_set_operator, struct_solver_solve, &
    struct_solver_invalidate
  use scene_interface, only: scene_t
  use ice_state, only: ice_state_t
  use ice_solid_view, only: ice_solid_view_t
  use ice_equilibration, only: ice_equilibrate, report_equilibration_failure
  use ice_face_velocity, only: ice_face_velocities
  use ice_pressure, only: ice_pressure_assemble, ice_pressure_rhs, ice_pressure_correct, &
    report_pressure_failure, platen_fluid_faces
  use ice_face_pressures, only: ice_face_pressure
  use ice_lagrangian, only: ice_lagrangian_values
  use ice_advection, only: ice_advect
  use ice_trace_fluids, only: tame_trace_fluids
  use ice_interface_compression, only: compress_interface
  use ice_bc, only: ice_bc_t, ice_bc_fill, bc_scalar, bc_temperature, bc_pressure, bc_dp
  use ice_exchange, only: ice_exchange_faces, ice_exchange_cells
  use ice_viscous, only: ice_viscous_sources
  implicit none
  private

  public :: ice_fluids_t, ice_stage_equilibrate, ice_stage_face_velocities, &
    ice_stage_face_exchange, ice_stage_pressure, ice_stage_lagrangian, ice_stage_cell_exchange, &
    ice_stage_advect, ice_step_begin, ice_step_reject, exchange_primitives, exchange_lagrangian

  !> Second and later outer passes: the PCG stops once the 2-norm of its linear residual is this
  !! share of outer_tolerance V (docs/performance.md); the first pass always solves to the
  !! solver's relative tolerance.
  real(wp), parameter :: later_pass_share = 0.1_wp

  !> What the ICE stages work on: the fluids and everything their step needs. The ICE scene
  !! (`ice_scene_t`) extends it with the scene interface.
  type, abstract, extends(scene_t) :: ice_fluids_t
    type(ice_state_t) :: state                !< fluids and pressure
    type(halo_t) :: halo                      !< halo buffers
    type(struct_solver_t) :: solver           !< hypre PCG + PFMG for eq. 35
    type(ice_bc_t) :: bc                      !< conditions of the domain faces
    real(wp), allocatable :: sources(:, :, :, :, :) !< viscous momentum and heat (i,j,k,4,fluid)
    !> cell pressure at the start of the step [Pa], put back when the step is rejected
    real(wp), allocatable :: p_start(:, :, :)
    !> running mean of the cell pressure [Pa] (`&ice pressure_average_time` > 0 only)
    real(wp), allocatable :: p_average(:, :, :)
    real(wp) :: p_average_time = 0.0_wp       !< its time constant tau [s] (0: none)
    character(len=8) :: label = 'ICE'         !< scene name in warnings
    real(wp) :: gravity(3) = 0.0_wp           !< [m/s^2]
    real(wp) :: k_exchange = 0.0_wp           !< momentum exchange coefficient [kg/m^3/s]
    real(wp) :: h_exchange = 0.0_wp           !< heat exchange coefficient [W/m^3/K]
    real(wp) :: sound_speed_factor = 0.0_wp   !< weight of c in the CFL limit (0: advective only)
    real(wp) :: outer_tolerance = 1.0e-7_wp   !< max |rhs|/V of eq. 35
    integer :: max_outer = 20                 !< outer-iteration limit
    real(wp) :: eq_tolerance = 1.0e-10_wp     !< equilibration tolerance
    integer :: eq_max = 100                   !< equilibration iteration limit
    integer :: order = 2                      !< advection order
    real(wp) :: theta = 1.0_wp                !< implicit weight of the pressure change
    !> the face velocities are predicted at time n + face_time dt (ICE: theta; the coupled
    !! scene: 1, the end of the step, like its solid's face velocities)
    real(wp) :: face_time = 1.0_wp
    real(wp) :: smagorinsky = 0.0_wp          !< Smagorinsky constant C_s (0: no eddy viscosity)
    real(wp) :: compression = 0.0_wp          !< interface compression C (0: off)
    integer :: steps = 0                      !< accepted steps
    !> a NaN met in the pressure equation ended the step (the run then fails, see
    !! ice_stage_pressure)
    logical :: nonfinite = .false.
    integer :: fault_nan_step = -1            !< MPMICE_FAULT=nan_pressure_step:N (-1: none)
    integer :: fault_huge_step = -1           !< MPMICE_FAULT=huge_pressure_step:N (-1: none)
    integer :: total_outer = 0                !< outer iterations summed
    integer :: max_outer_seen = 0             !< largest outer-iteration count
    integer :: total_pcg = 0                  !< PCG iterations summed
    integer :: solves = 0                     !< linear solves
    integer :: max_pcg_seen = 0               !< largest PCG count
    integer :: t_equil = 0                    !< timer id
    integer :: t_face = 0                     !< timer id
    integer :: t_pressure = 0                 !< timer id
    integer :: t_operator = 0                 !< timer id
    integer :: t_pcg = 0                      !< timer id
    integer :: t_lagrange = 0                 !< timer id
    integer :: t_advect = 0                   !< timer id
    integer :: t_halo = 0                     !< timer id
  end type ice_fluids_t

contains

  !> Keep what a rejected step must put back: the cell pressure, the equilibration's initial
  !! guess (a failed outer iteration leaves it at any value, up to 1e32 Pa).
  subroutine ice_step_begin(self)
    class(ice_fluids_t), intent(inout) :: self  !< fluids
    self%p_start = self%state%pressure
  end subroutine ice_step_begin

  !> A rejected step: the cell pressure of the step's start again, so the retry with a shorter
  !! step starts from the accepted state and a failure dump shows it. The other fields a step
  !! writes before it can be rejected (p_eq, specific volumes, face velocities) are recomputed
  !! from the primitive fields by the retry.
  subroutine ice_step_reject(self)
    class(ice_fluids_t), intent(inout) :: self  !< fluids
    self%state%pressure = self%p_start
  end subroutine ice_step_reject

  !> Pressure equilibration of every cell (eqs. 10-11; with a solid phase sum phi_f = n).
  !! False (with a warning, the step rejected by `ice_step_reject`) when a cell fails.
  logical function ice_stage_equilibrate(self, time, solid) result(ok)
    class(ice_fluids_t), intent(inout) :: self   !< fluids
    real(wp), intent(in) :: time                 !< time at the start of the step [s]
    class(ice_solid_view_t), intent(in), optional :: solid !< solid phase of a coupled scene
    integer :: its, failed, bad_cell(3)
    associate (dom => self%ctx%dom, grid => self%ctx%grid, timers => self%ctx%timers)
      call timer_start(timers, self%t_equil)
      call ice_equilibrate(self%state, grid, self%eq_tolerance, self%eq_max, its, failed, bad_cell, &
        solid)
      call ice_bc_fill(grid, self%bc, self%state%pressure, bc_pressure)
      call timer_stop(timers, self%t_equil)
      call report_equilibration_failure(self%state, grid, failed, bad_cell, solid)
      ok = global_sum(dom, failed) == 0
    end associate
    if (ok) return
    call log_warning(trim(self%label) // ' equilibration failed at t = ' // &
      real_short_text(time) // ' s')
    call ice_step_reject(self)
  end function ice_stage_equilibrate

  !> Face velocities of the fluids at time n + face_time dt (docs/ice.md): face_time = 1 the
  !! paper's eqs. 30-31; face_time < 1 (ICE with theta < 1) the time-centred prediction, with the
  !! advective change.
  subroutine ice_stage_face_velocities(self, dt)
    class(ice_fluids_t), intent(inout) :: self   !< fluids
    real(wp), intent(in) :: dt                   !< step [s]
    call timer_start(self%ctx%timers, self%t_face)
    call ice_face_velocities(self%state, self%ctx%grid, self%face_time * dt, self%gravity, &
      self%bc, self%face_time < 1.0_wp)
    call timer_stop(self%ctx%timers, self%t_face)
  end subroutine ice_stage_face_velocities

  !> Implicit momentum exchange at the faces over face_time dt (eq. 34; with a solid phase the
  !! exchange layer's, `ice_solid_view_t%exchange_faces`, with its drag) and, with loading
  !! platens, the fluids' face velocities there.
  subroutine ice_stage_face_exchange(self, dt, solid)
    class(ice_fluids_t), intent(inout) :: self   !< fluids
    real(wp), intent(in) :: dt                   !< step [s]
    class(ice_solid_view_t), intent(inout), optional :: solid !< solid phase of a coupled scene
    associate (grid => self%ctx%grid)
      call timer_start(self%ctx%timers, self%t_face)
      if (present(solid)) then
        call solid%exchange_faces(self%state, grid, self%face_time * dt, self%k_exchange)
      else
        call ice_exchange_faces(self%state, grid, self%face_time * dt, self%k_exchange)
      end if
      call platen_fluid_faces(self%state, grid, solid)
      call timer_stop(self%ctx%timers, self%t_face)
    end associate
  end subroutine ice_stage_face_exchange

  !> Outer iteration of eq. 35: solve for dp (hypre PCG + PFMG, or the direct tridiagonal solve
  !! of a 1D block), correct p, dp_total and the face velocities (their pressure gradient acts
  !! for face_time dt with the weight theta of the pressure change: theta face_time), until
  !! max |rhs|/V <= outer tolerance; at least one solve. False (with a warning) when it does not
  !! converge: the caller rejects the step. False with `nonfinite` set when a NaN or Inf met
  !! the system: the caller takes the step as it is, so the run fails with its state dumped.
  logical function ice_stage_pressure(self, time, dt, solid) result(ok)
    class(ice_fluids_t), intent(inout) :: self   !< fluids
    real(wp), intent(in) :: time                 !< time at the start of the step [s]
    real(wp), intent(in) :: dt                   !< step [s]
    class(ice_solid_view_t), intent(inout), optional :: solid !< solid phase of a coupled scene
    integer :: outer, pcg
    real(wp) :: residual, relres, weight
    logical :: converged
    weight = self%theta * self%face_time
    associate (dom => self%ctx%dom, grid => self%ctx%grid, timers => self%ctx%timers)
      call timer_start(timers, self%t_pressure)
      self%state%dp_total = 0.0_wp
      ! one PFMG hierarchy per step: built for the first pass's operator, kept by the later
      ! passes (their operators differ only where a face's upwind choice flipped; the reuse
      ! count is set at `ice_scene_setup`); a step, and so a restart, starts with a fresh one
      call struct_solver_invalidate(self%solver)
      residual = global_max(dom, ice_pressure_rhs(self%state, grid, dt, solid))
      outer = 0
      ! at least one solve: skipping it when the constraint residual is small would make the step
      ! explicit in the acoustics (unstable at dt > dx/c) and let round-off grow
      do while ((residual > self%outer_tolerance .or. outer == 0) .and. outer < self%max_outer)
        outer = outer + 1
        call timer_start(timers, self%t_operator)
        call ice_pressure_assemble(self%state, grid, dt, weight, solid)
        call struct_solver_set_operator(self%solver, grid, self%state%diag, &
          self%state%coef(:, :, :, 1), self%state%coef(:, :, :, 2), self%state%coef(:, :, :, 3))
        call timer_stop(timers, self%t_operator)
        self%state%dp = 0.0_wp
        if (outer == 1 .and. dom%rank == 0) then
          associate (r => self%state%rhs(grid%lo(1), grid%lo(2), grid%lo(3)))
            if (self%steps + 1 == self%fault_nan_step) r = ieee_value(1.0_wp, ieee_quiet_nan)
            ! finite, but PCG's products overflow: hypre stops with an error
            if (self%steps + 1 == self%fault_huge_step) r = 1.0e153_wp
          end associate
        end if
        call timer_start(timers, self%t_pcg)
        if (outer == 1) then
          call struct_solver_solve(self%solver, grid, self%state%rhs, self%state%dp, pcg, relres, &
            converged)
        else
          ! a later pass only has to bring the residual below the outer tolerance: its linear
          ! residual may be a small share of it (2-norm >= max norm, so per cell as well)
          call struct_solver_solve(self%solver, grid, self%state%rhs, self%state%dp, pcg, relres, &
            converged, later_pass_share * self%outer_tolerance * grid%cell_volume)
        end if
        call timer_stop(timers, self%t_pcg)
        self%solves = self%solves + 1
        self%total_pcg = self%total_pcg + pcg
        self%max_pcg_seen = max(self%max_pcg_seen, pcg)
        call halo_exchange_cell(self%halo, dom, grid, self%state%dp, 1)
        call ice_bc_fill(grid, self%bc, self%state%dp, bc_dp)
        call ice_pressure_correct(self%state, grid, dt, weight, solid)
        ! a NaN or Inf in the system (the solver's residual is then NaN on every rank): no retry
        ! with a shorter step can help; the pressure keeps the NaN in the cells concerned
        if (.not. ieee_is_finite(relres)) exit
        residual = global_max(dom, ice_pressure_rhs(self%state, grid, dt, solid))
      end do
      call timer_stop(timers, self%t_pressure)
    end associate
    if (.not. ieee_is_finite(relres)) then
      self%nonfinite = .true.
      ok = .false.
      call log_warning('ICE pressure equation: non-finite values at t = ' // &
        real_short_text(time) // ' s; the step ends here and the run fails with its state ' // &
        'dumped')
      return
    end if
    ok = residual <= self%outer_tolerance
    if (.not. ok) then
      call report_pressure_failure(self%state, self%ctx%grid, residual, solid)
      call log_warning('ICE pressure outer iteration: max |rhs|/V = ' // &
        real_short_text(residual) // ' after ' // int_text(outer) // ' iterations at t = ' // &
        real_short_text(time) // ' s')
      return
    end if
    self%total_outer = self%total_outer + outer
    self%max_outer_seen = max(self%max_outer_seen, outer)
  end function ice_stage_pressure

  !> The forces and work of the step with p_eq + theta dp_total (theta = 1: p^{n+1}, backward
  !! Euler; ghosts filled): face pressures (eq. 37), viscous and Smagorinsky sources
  !! (eqs. 23-25), Lagrangian values (eqs. 42-46). The pressure stays at p_eq + theta dp_total
  !! until `ice_stage_cell_exchange`.
  subroutine ice_stage_lagrangian(self, dt, solid)
    class(ice_fluids_t), intent(inout) :: self   !< fluids
    real(wp), intent(in) :: dt                   !< step [s]
    class(ice_solid_view_t), intent(in), optional :: solid !< solid phase of a coupled scene
    integer :: m
    if (self%theta /= 1.0_wp) self%state%pressure = self%state%p_eq + &
      self%theta * self%state%dp_total
    associate (dom => self%ctx%dom, grid => self%ctx%grid, timers => self%ctx%timers)
      call timer_start(timers, self%t_halo)
      call halo_exchange_cell(self%halo, dom, grid, self%state%pressure, 1)
      call ice_bc_fill(grid, self%bc, self%state%pressure, bc_pressure)
      call timer_stop(timers, self%t_halo)

      call timer_start(timers, self%t_lagrange)
      call ice_face_pressure(self%state, grid, self%gravity, solid)
      do m = 1, self%state%nfluids
        self%sources(:, :, :, :, m) = 0.0_wp
        call ice_viscous_sources(self%state, grid, m, dt, self%sources(:, :, :, 1:3, m), &
          self%sources(:, :, :, 4, m), self%smagorinsky)
      end do
      call ice_lagrangian_values(self%state, grid, dt, self%gravity, self%sources, solid)
      call timer_stop(timers, self%t_lagrange)
    end associate
  end subroutine ice_stage_lagrangian

  !> Implicit momentum and heat exchange in the cells (eqs. 50-51; with a solid phase the
  !! exchange layer's, `ice_solid_view_t%exchange_cells`, with its drag and heat, eqs. 52-55),
  !! then the end-of-step pressure p_eq + dp_total again.
  subroutine ice_stage_cell_exchange(self, dt, solid)
    class(ice_fluids_t), intent(inout) :: self   !< fluids
    real(wp), intent(in) :: dt                   !< step [s]
    class(ice_solid_view_t), intent(inout), optional :: solid !< solid phase of a coupled scene
    call timer_start(self%ctx%timers, self%t_lagrange)
    if (present(solid)) then
      call solid%exchange_cells(self%state, self%ctx%grid, dt, self%k_exchange, self%h_exchange)
    else
      call ice_exchange_cells(self%state, self%ctx%grid, dt, self%k_exchange, self%h_exchange)
    end if
    if (self%theta /= 1.0_wp) self%state%pressure = self%state%p_eq + self%state%dp_total
    call timer_stop(self%ctx%timers, self%t_lagrange)
  end subroutine ice_stage_cell_exchange

  !> Advection of the Lagrangian values (eqs. 58-65) with the ghosts filled before and after;
  !! `traces` (default false): traces of a fluid take the cell's mixture values
  !! (`tame_trace_fluids`, the coupled scene). Then the interface compression. Logs the cells
  !! left with a negative mass.
  subroutine ice_stage_advect(self, time, dt, traces, solid)
    class(ice_fluids_t), intent(inout) :: self   !< fluids
    real(wp), intent(in) :: time                 !< time at the start of the step [s]
    real(wp), intent(in) :: dt                   !< step [s]
    logical, intent(in), optional :: traces      !< tame the fluids' traces
    class(ice_solid_view_t), intent(in), optional :: solid !< solid phase of a coupled scene
    integer :: negative
    logical :: tame
    tame = .false.
    if (present(traces)) tame = traces
    associate (dom => self%ctx%dom, grid => self%ctx%grid, timers => self%ctx%timers)
      call timer_start(timers, self%t_halo)
      call exchange_lagrangian(self)
      call timer_stop(timers, self%t_halo)

      call timer_start(timers, self%t_advect)
      call ice_advect(self%state, grid, dt, self%order, negative, self%gravity, solid)
      call timer_stop(timers, self%t_advect)
      if (tame) call tame_trace_fluids(self%state, grid, negative)
      negative = global_sum(dom, negative)
      if (negative > 0) call log_warning(trim(self%label) // ' advection: negative fluid mass ' // &
        'in ' // int_text(negative) // ' cells at t = ' // real_short_text(time) // ' s')

      call timer_start(timers, self%t_halo)
      call exchange_primitives(self)
      call timer_stop(timers, self%t_halo)
      if (self%compression > 0.0_wp) then
        ! the free surface's compression (free fluid only; ice_interface_compression)
        call timer_start(timers, self%t_advect)
        call compress_interface(self%state, grid, dt, self%compression, solid)
        call timer_stop(timers, self%t_advect)
        call timer_start(timers, self%t_halo)
        call exchange_primitives(self)
        call timer_stop(timers, self%t_halo)
      end if
    end associate
  end subroutine ice_stage_advect

  !> Halo exchange and wall ghosts of the primitive fields and the pressure.
  subroutine exchange_primitives(self)
    class(ice_fluids_t), intent(inout) :: self  !< fluids
    integer :: m, d
    associate (dom => self%ctx%dom, grid => self%ctx%grid)
      do m = 1, self%state%nfluids
        associate (f => self%state%fluid(m))
          call halo_exchange_cell(self%halo, dom, grid, f%rho)
          call ice_bc_fill(grid, self%bc, f%rho, bc_scalar)
          call halo_exchange_cell(self%halo, dom, grid, f%temp)
          call ice_bc_fill(grid, self%bc, f%temp, bc_temperature)
          call halo_exchange_cell(self%halo, dom, grid, f%spvol)
          call ice_bc_fill(grid, self%bc, f%spvol, bc_scalar)
          do d = 1, 3
            call halo_exchange_cell(self%halo, dom, grid, f%vel(:, :, :, d))
            call ice_bc_fill(grid, self%bc, f%vel(:, :, :, d), d)
          end do
        end associate
      end do
      call halo_exchange_cell(self%halo, dom, grid, self%state%pressure)
      call ice_bc_fill(grid, self%bc, self%state%pressure, bc_pressure)
    end associate
  end subroutine exchange_primitives

  !> Halo exchange and wall ghosts of the Lagrangian mass-specific quantities.
  subroutine exchange_lagrangian(self)
    class(ice_fluids_t), intent(inout) :: self  !< fluids
    integer :: m, n
    associate (dom => self%ctx%dom, grid => self%ctx%grid)
      do m = 1, self%state%nfluids
        do n = 1, 5
          call halo_exchange_cell(self%halo, dom, grid, self%state%fluid(m)%lag(:, :, :, n))
          if (n <= 3) then
            call ice_bc_fill(grid, self%bc, self%state%fluid(m)%lag(:, :, :, n), n)
          else if (n == 4) then
            call ice_bc_fill(grid, self%bc, self%state%fluid(m)%lag(:, :, :, n), bc_temperature, &
              self%state%fluid(m)%eos%cv)
          else
            call ice_bc_fill(grid, self%bc, self%state%fluid(m)%lag(:, :, :, n), bc_scalar)
          end if
        end do
      end do
    end associate
  end subroutine exchange_lagrangian
end module ice_stages
