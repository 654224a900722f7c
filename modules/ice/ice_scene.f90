!> The ICE scene (`&run scene = 'ice'`): any number of fluids on the block-structured grid with
!! the implicit pressure equation solved by hypre PCG + PFMG (paper eqs. 29-37, 42-46, 54-65,
!! fluid part). One step (docs/ice.md):
!!  equilibration -> face velocities (eq. 31) -> outer iteration of the pressure equation
!!  (face exchange eq. 34, outer iteration of the pressure equation eq. 35 with the
!!  face-velocity correction, eq. 36) -> face pressures (eq. 37) -> Lagrangian values
!!  (eqs. 42-46, 56-57) -> cell exchange (eqs. 50-51) -> advection (eqs. 58-65).
!! Face conditions from `&boundary` (`ice_bc`): no-slip or free-slip walls, adiabatic or fixed
!! temperature.
module ice_scene
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite, ieee_value, ieee_quiet_nan
  use mpmice_kinds, only: wp, name_len
  use mpmice_errors, only: fatal, int_text, real_short_text
  use mpmice_log, only: log_info, log_warning
  use mpmice_timers, only: timer_set_t, timer_register, timer_start, timer_stop
  use mpmice_faults, only: fault_step
  use config_types, only: config_t
  use parallel_domain, only: domain_t
  use parallel_halo, only: halo_t, halo_init, halo_exchange_cell, halo_free
  use parallel_reduce, only: global_max, global_min, global_sum
  use grid_layout, only: grid_t
  use solver_pressure, only: struct_solver_t, struct_solver_init, struct_solver_set_operator, &
    struct_solver_solve, struct_solver_free, struct_solver_invalidate
  use io_hdf5, only: h5_file_t, h5_write_cell_field, h5_read_cell_field
  use io_xdmf, only: xdmf_particles_t
  use scene_interface, only: scene_t
  use ice_eos, only: eos_t, eos_kind_from_name, eos_sound_speed2
  use ice_state, only: ice_state_t, ice_state_alloc, ice_state_free
  use ice_equilibration, only: ice_equilibrate, report_equilibration_failure
  use ice_face_velocity, only: ice_face_velocities
  use ice_pressure, only: ice_pressure_assemble, ice_pressure_rhs, ice_pressure_correct, &
    ice_face_pressure, report_pressure_failure
  use ice_lagrangian, only: ice_lagrangian_values
  use ice_advection, only: ice_advect
  use ice_interface_compression, only: compress_interface
  use ice_bc, only: ice_bc_t, ice_bc_init, ice_bc_fill, bc_scalar, bc_temperature, bc_pressure, &
    bc_dp
  use ice_exchange, only: ice_exchange_faces, ice_exchange_cells
  use ice_initial, only: ice_initial_state
  use ice_viscous, only: ice_viscous_sources, ice_viscous_dt
  implicit none
  private

  public :: ice_scene_t, exchange_primitives, exchange_lagrangian, ice_pressure_iteration, &
    ice_step_begin, ice_step_reject

  !> Second and later outer passes: the PCG stops once the 2-norm of its linear residual is this
  !! share of outer_tolerance V (docs/performance.md); the first pass always solves to the
  !! solver's relative tolerance.
  real(wp), parameter :: later_pass_share = 0.1_wp

  !> Multi-fluid ICE with implicit pressure.
  type, extends(scene_t) :: ice_scene_t
    type(ice_state_t) :: state                !< fluids and pressure
    type(halo_t) :: halo                      !< halo buffers
    type(struct_solver_t) :: solver           !< hypre PCG + PFMG for eq. 35
    type(ice_bc_t) :: bc                      !< conditions of the domain faces
    real(wp), allocatable :: sources(:, :, :, :, :) !< viscous momentum and heat (i,j,k,4,fluid)
    !> cell pressure at the start of the step [Pa], put back when the step is rejected
    real(wp), allocatable :: p_start(:, :, :)
    real(wp) :: gravity(3) = 0.0_wp           !< [m/s^2]
    real(wp) :: k_exchange = 0.0_wp           !< momentum exchange coefficient [kg/m^3/s]
    real(wp) :: h_exchange = 0.0_wp           !< heat exchange coefficient [W/m^3/K]
    real(wp) :: cfl = 0.5_wp                  !< Courant number
    real(wp) :: sound_speed_factor = 0.0_wp   !< weight of c in the CFL limit (0: advective only)
    real(wp) :: outer_tolerance = 1.0e-7_wp   !< max |rhs|/V of eq. 35
    integer :: max_outer = 20                 !< outer-iteration limit
    real(wp) :: eq_tolerance = 1.0e-10_wp     !< equilibration tolerance
    integer :: eq_max = 100                   !< equilibration iteration limit
    integer :: order = 2                      !< advection order
    real(wp) :: theta = 1.0_wp                !< implicit weight of the pressure change
    real(wp) :: smagorinsky = 0.0_wp          !< Smagorinsky constant C_s (0: no eddy viscosity)
    real(wp) :: compression = 0.0_wp          !< interface compression C (0: off)
    integer :: steps = 0                      !< accepted steps
    !> a NaN met in the pressure equation ended the step (the run then fails, see
    !! ice_pressure_iteration)
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
  contains
    procedure :: init => ice_scene_init
    procedure :: stable_dt => ice_scene_stable_dt
    procedure :: step => ice_scene_step
    procedure :: write_state => ice_scene_write_state
    procedure :: restore => ice_scene_restore
    procedure :: output_layout => ice_scene_output_layout
    procedure :: all_finite => ice_scene_all_finite
    procedure :: summary => ice_scene_summary
    procedure :: free => ice_scene_free
  end type ice_scene_t

  !> Per-fluid datasets of a dump, in order (`cell/<fluid>/<name>`).
  character(len=*), parameter :: fluid_fields(7) = [character(len=16) :: 'density', &
    'velocity_x', 'velocity_y', 'velocity_z', 'temperature', 'volume_fraction', 'specific_volume']

contains

  !> Materials from `&fluid`, initial state from `&fluid` and `&region`, solver and halos.
  subroutine ice_scene_init(self, cfg, dom, grid, timers)
    class(ice_scene_t), intent(inout) :: self    !< scene
    type(config_t), intent(in) :: cfg            !< validated configuration
    type(domain_t), intent(in) :: dom            !< decomposition
    type(grid_t), intent(in) :: grid             !< block geometry
    type(timer_set_t), intent(inout) :: timers   !< stage timers
    integer :: m, its, failed

    self%t_equil = timer_register(timers, 'ICE equilibration')
    self%t_face = timer_register(timers, 'ICE face velocities')
    self%t_pressure = timer_register(timers, 'ICE pressure (hypre)')
    self%t_operator = timer_register(timers, 'ICE  of which operator')
    self%t_pcg = timer_register(timers, 'ICE  of which PCG solve')
    self%t_lagrange = timer_register(timers, 'ICE Lagrangian values')
    self%t_advect = timer_register(timers, 'ICE advection')
    self%t_halo = timer_register(timers, 'ICE halo exchange')
    self%fault_nan_step = fault_step('nan_pressure_step')   ! testing aids (docs/testing.md)
    self%fault_huge_step = fault_step('huge_pressure_step')
    self%gravity = cfg%physics%gravity
    self%k_exchange = cfg%ice%exchange_coefficient
    self%h_exchange = cfg%ice%heat_exchange_coefficient
    self%cfl = cfg%time%cfl
    self%sound_speed_factor = cfg%ice%sound_speed_factor
    self%outer_tolerance = cfg%ice%outer_tolerance
    self%max_outer = cfg%ice%max_outer_iterations
    self%eq_tolerance = cfg%ice%equilibration_tolerance
    self%eq_max = cfg%ice%max_equilibration_iterations
    self%order = cfg%numerics%advection_order
    self%theta = cfg%numerics%time_theta
    if (cfg%ice%smagorinsky) self%smagorinsky = cfg%ice%smagorinsky_constant
    self%compression = cfg%ice%interface_compression
    if (cfg%nfluids < 1) call fatal('ice scene: no &fluid group')

    call ice_state_alloc(self%state, grid, cfg%nfluids)
    do m = 1, cfg%nfluids
      associate (f => self%state%fluid(m), c => cfg%fluids(m))
        f%name = c%name
        f%eos = eos_t(kind=eos_kind_from_name(c%eos), gamma=c%gamma, cv=c%heat_capacity_cv, &
          rho_ref=c%reference_density, p_ref=c%reference_pressure, &
          t_ref=c%reference_temperature, bulk_modulus=c%bulk_modulus, &
          alpha=c%thermal_expansion, p_inf=c%stiffened_pressure)
        f%viscosity = c%viscosity
        f%conductivity = c%conductivity
      end associate
    end do

    call ice_bc_init(self%bc, cfg)
    call ice_initial_state(self%state, cfg, grid)
    self%state%closed = .not. self%bc%open
    self%state%p_boundary = self%bc%p_face
    self%state%inflow_fluid = self%bc%inflow_fluid
    allocate(self%sources(grid%lbc(1):grid%ubc(1), grid%lbc(2):grid%ubc(2), &
      grid%lbc(3):grid%ubc(3), 4, cfg%nfluids), source=0.0_wp)
    allocate(self%p_start, mold=self%state%pressure)

    call halo_init(self%halo, dom, grid, 1)
    call struct_solver_init(self%solver, dom, grid, cfg%solver%tolerance, &
      cfg%solver%max_iterations, cfg%solver%print_level)
    call exchange_primitives(self, dom, grid)
    call ice_equilibrate(self%state, grid, self%eq_tolerance, self%eq_max, its, failed)
    failed = global_sum(dom, failed)
    if (failed > 0) call fatal('ice scene: initial pressure equilibration failed in ' // &
      int_text(failed) // ' cells')
  end subroutine ice_scene_init

  !> CFL limit: cfl * min over cells, directions and fluids of dx / (|u| + f c), f the
  !! sound-speed factor (0: the advective limit of the implicit scheme), and cfl times the
  !! explicit viscosity/conduction limit (`ice_viscous_dt`, with the Smagorinsky eddy viscosity).
  function ice_scene_stable_dt(self, dom, grid) result(dt)
    class(ice_scene_t), intent(inout) :: self  !< scene
    type(domain_t), intent(in) :: dom          !< decomposition
    type(grid_t), intent(in) :: grid           !< block geometry
    real(wp) :: dt
    integer :: m, d, i, j, k
    real(wp) :: c, speed, rate, dt_viscous

    rate = 0.0_wp
    do m = 1, self%state%nfluids
      associate (f => self%state%fluid(m))
        do k = grid%lo(3), grid%hi(3)
          do j = grid%lo(2), grid%hi(2)
            do i = grid%lo(1), grid%hi(1)
              if (f%rho(i, j, k) <= 0.0_wp) cycle
              c = 0.0_wp
              if (self%sound_speed_factor > 0.0_wp) c = sqrt(eos_sound_speed2(f%eos, &
                1.0_wp / f%spvol(i, j, k), f%temp(i, j, k)))
              do d = 1, 3
                if (.not. grid%active(d)) cycle
                speed = abs(f%vel(i, j, k, d)) + self%sound_speed_factor * c
                rate = max(rate, speed / grid%dx(d))
              end do
            end do
          end do
        end do
      end associate
    end do
    rate = global_max(dom, rate)
    if (rate > 0.0_wp) then
      dt = self%cfl / rate
    else
      dt = huge(1.0_wp)
    end if
    ! explicit viscosity and conduction
    call ice_viscous_dt(self%state, grid, dt_viscous, self%smagorinsky)
    dt = min(dt, self%cfl * global_min(dom, dt_viscous))
  end function ice_scene_stable_dt

  !> One ICE step; rejected (state unchanged) when the outer iteration does not converge or a
  !! mass becomes negative. A NaN or Inf in the pressure equation ends the step at once, taken
  !! with the NaN pressure, so that the run fails (exit status 3) with the state dumped.
  subroutine ice_scene_step(self, dom, grid, time, dt, timers, accepted)
    class(ice_scene_t), intent(inout) :: self    !< scene
    type(domain_t), intent(in) :: dom            !< decomposition
    type(grid_t), intent(in) :: grid             !< block geometry
    real(wp), intent(in) :: time                 !< time at the start of the step [s]
    real(wp), intent(in) :: dt                   !< step [s]
    type(timer_set_t), intent(inout) :: timers   !< stage timers
    logical, intent(out) :: accepted             !< the step was taken
    integer :: its, failed, negative, m, bad_cell(3)

    accepted = .false.
    call ice_step_begin(self)
    call timer_start(timers, self%t_equil)
    call ice_equilibrate(self%state, grid, self%eq_tolerance, self%eq_max, its, failed, bad_cell)
    call ice_bc_fill(grid, self%bc, self%state%pressure, bc_pressure)
    call timer_stop(timers, self%t_equil)
    call report_equilibration_failure(self%state, grid, failed, bad_cell)
    if (global_sum(dom, failed) > 0) then
      call log_warning('ICE equilibration failed at t = ' // real_short_text(time) // ' s')
      call ice_step_reject(self)
      return
    end if

    ! face velocities at time n + theta dt (docs/ice.md): theta = 1 the paper's eq. 30-31;
    ! theta < 1 the time-centred prediction, with the advective change
    call timer_start(timers, self%t_face)
    call ice_face_velocities(self%state, grid, self%theta * dt, self%gravity, self%bc, &
      self%theta < 1.0_wp)
    call ice_exchange_faces(self%state, grid, self%theta * dt, self%k_exchange)
    call timer_stop(timers, self%t_face)

    if (.not. ice_pressure_iteration(self, dom, grid, time, dt, timers, self%theta)) then
      ! non-finite: taken as it is, so the run loop's check fails the run and dumps the state
      accepted = self%nonfinite
      if (.not. self%nonfinite) call ice_step_reject(self)
      return
    end if

    ! forces and work with p_eq + theta dp_total (theta = 1: p^{n+1}, backward Euler)
    if (self%theta /= 1.0_wp) self%state%pressure = self%state%p_eq + &
      self%theta * self%state%dp_total
    call timer_start(timers, self%t_halo)
    call halo_exchange_cell(self%halo, dom, grid, self%state%pressure, 1)
    call ice_bc_fill(grid, self%bc, self%state%pressure, bc_pressure)
    call timer_stop(timers, self%t_halo)

    call timer_start(timers, self%t_lagrange)
    call ice_face_pressure(self%state, grid, self%gravity)
    do m = 1, self%state%nfluids
      self%sources(:, :, :, :, m) = 0.0_wp
      call ice_viscous_sources(self%state, grid, m, dt, self%sources(:, :, :, 1:3, m), &
        self%sources(:, :, :, 4, m), self%smagorinsky)
    end do
    call ice_lagrangian_values(self%state, grid, dt, self%gravity, self%sources)
    call ice_exchange_cells(self%state, grid, dt, self%k_exchange, self%h_exchange)
    if (self%theta /= 1.0_wp) self%state%pressure = self%state%p_eq + self%state%dp_total
    call timer_stop(timers, self%t_lagrange)

    call timer_start(timers, self%t_halo)
    call exchange_lagrangian(self, dom, grid)
    call timer_stop(timers, self%t_halo)

    call timer_start(timers, self%t_advect)
    call ice_advect(self%state, grid, dt, self%order, negative, self%gravity)
    call timer_stop(timers, self%t_advect)
    negative = global_sum(dom, negative)
    if (negative > 0) call log_warning('ICE advection: negative mass in ' // &
      int_text(negative) // ' cells at t = ' // real_short_text(time) // ' s')

    call timer_start(timers, self%t_halo)
    call exchange_primitives(self, dom, grid)
    call timer_stop(timers, self%t_halo)
    if (self%compression > 0.0_wp) then
      call timer_start(timers, self%t_advect)
      call compress_interface(self%state, grid, dt, self%compression)
      call timer_stop(timers, self%t_advect)
      call timer_start(timers, self%t_halo)
      call exchange_primitives(self, dom, grid)
      call timer_stop(timers, self%t_halo)
    end if
    self%steps = self%steps + 1
    accepted = .true.
  end subroutine ice_scene_step

  !> Keep what a rejected step must put back: the cell pressure, the equilibration's initial
  !! guess (a failed outer iteration leaves it at any value, up to 1e32 Pa).
  subroutine ice_step_begin(self)
    class(ice_scene_t), intent(inout) :: self  !< scene
    self%p_start = self%state%pressure
  end subroutine ice_step_begin

  !> A rejected step: the cell pressure of the step's start again, so the retry with a shorter
  !! step starts from the accepted state and a failure dump shows it. The other fields a step
  !! writes before it can be rejected (p_eq, specific volumes, face velocities) are recomputed
  !! from the primitive fields by the retry.
  subroutine ice_step_reject(self)
    class(ice_scene_t), intent(inout) :: self  !< scene
    self%state%pressure = self%p_start
  end subroutine ice_step_reject

  !> Outer iteration of eq. 35 (module header): solve for dp (hypre PCG + PFMG, or the direct
  !! tridiagonal solve of a 1D block), correct p, dp_total and the face velocities, until
  !! max |rhs|/V <= outer tolerance; at least one solve. False (with a warning) when it does not
  !! converge: the caller rejects the step. Used by the ICE and the MPMICE scenes.
  logical function ice_pressure_iteration(self, dom, grid, time, dt, timers, face_time) &
    result(ok)
    class(ice_scene_t), intent(inout) :: self    !< scene
    type(domain_t), intent(in) :: dom            !< decomposition
    type(grid_t), intent(in) :: grid             !< block geometry
    real(wp), intent(in) :: time                 !< time at the start of the step [s]
    real(wp), intent(in) :: dt                   !< step [s]
    type(timer_set_t), intent(inout) :: timers   !< stage timers
    !> the face velocities are at time n + face_time dt (their pressure gradient acts for
    !! face_time dt; default 1, the end of the step)
    real(wp), intent(in), optional :: face_time
    integer :: outer, pcg
    real(wp) :: residual, relres, weight
    logical :: converged
    weight = self%theta
    if (present(face_time)) weight = self%theta * face_time
    call timer_start(timers, self%t_pressure)
    self%state%dp_total = 0.0_wp
    residual = global_max(dom, ice_pressure_rhs(self%state, grid, dt))
    outer = 0
    ! at least one solve: skipping it when the constraint residual is small would make the step
    ! explicit in the acoustics (unstable at dt > dx/c) and let round-off grow
    do while ((residual > self%outer_tolerance .or. outer == 0) .and. outer < self%max_outer)
      outer = outer + 1
      call timer_start(timers, self%t_operator)
      call ice_pressure_assemble(self%state, grid, dt, weight)
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
      call ice_pressure_correct(self%state, grid, dt, weight)
      ! a NaN or Inf in the system (the solver's residual is then NaN on every rank): no retry
      ! with a shorter step can help; the pressure keeps the NaN in the cells concerned
      if (.not. ieee_is_finite(relres)) exit
      residual = global_max(dom, ice_pressure_rhs(self%state, grid, dt))
    end do
    call timer_stop(timers, self%t_pressure)
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
      call report_pressure_failure(self%state, grid, residual)
      call log_warning('ICE pressure outer iteration: max |rhs|/V = ' // &
        real_short_text(residual) // ' after ' // int_text(outer) // ' iterations at t = ' // &
        real_short_text(time) // ' s')
      return
    end if
    self%total_outer = self%total_outer + outer
    self%max_outer_seen = max(self%max_outer_seen, outer)
  end function ice_pressure_iteration

  !> Halo exchange and wall ghosts of the primitive fields and the pressure.
  subroutine exchange_primitives(self, dom, grid)
    class(ice_scene_t), intent(inout) :: self  !< scene
    type(domain_t), intent(in) :: dom          !< decomposition
    type(grid_t), intent(in) :: grid           !< block geometry
    integer :: m, d
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
  end subroutine exchange_primitives

  !> Halo exchange and wall ghosts of the Lagrangian mass-specific quantities.
  subroutine exchange_lagrangian(self, dom, grid)
    class(ice_scene_t), intent(inout) :: self  !< scene
    type(domain_t), intent(in) :: dom          !< decomposition
    type(grid_t), intent(in) :: grid           !< block geometry
    integer :: m, n
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
  end subroutine exchange_lagrangian

  !> Writes to a dump `cell/pressure` and `cell/<fluid>/<field>`; checkpoint: the primitive fields and the
  !! pressure under `checkpoint/` (everything the next step reads).
  subroutine ice_scene_write_state(self, file, dom, grid, checkpoint)
    class(ice_scene_t), intent(inout) :: self  !< scene
    type(h5_file_t), intent(in) :: file        !< open file
    type(domain_t), intent(in) :: dom          !< decomposition
    type(grid_t), intent(in) :: grid           !< block geometry
    logical, intent(in) :: checkpoint          !< full restart state
    character(len=:), allocatable :: prefix, g
    integer :: m, d
    prefix = ''
    if (checkpoint) prefix = 'checkpoint/'
    ! a restart starts with a fresh preconditioner: so does the run that goes on
    if (checkpoint) call struct_solver_invalidate(self%solver)
    call h5_write_cell_field(file, prefix // 'cell/pressure', grid, self%state%pressure)
    do m = 1, self%state%nfluids
      associate (f => self%state%fluid(m))
        g = prefix // 'cell/' // trim(f%name) // '/'
        call h5_write_cell_field(file, g // 'density', grid, f%rho)
        do d = 1, 3
          call h5_write_cell_field(file, g // trim(fluid_fields(1 + d)), grid, f%vel(:, :, :, d))
        end do
        call h5_write_cell_field(file, g // 'temperature', grid, f%temp)
        if (.not. checkpoint) then
          f%vfrac = f%rho * f%spvol
          call h5_write_cell_field(file, g // 'volume_fraction', grid, f%vfrac)
        end if
        call h5_write_cell_field(file, g // 'specific_volume', grid, f%spvol)
      end associate
    end do
  end subroutine ice_scene_write_state

  !> Read the primitive fields and the pressure of a checkpoint, then fill the ghosts.
  subroutine ice_scene_restore(self, file, dom, grid)
    class(ice_scene_t), intent(inout) :: self  !< scene
    type(h5_file_t), intent(in) :: file        !< open checkpoint
    type(domain_t), intent(in) :: dom          !< decomposition
    type(grid_t), intent(in) :: grid           !< block geometry
    character(len=:), allocatable :: g
    integer :: m, d
    call h5_read_cell_field(file, 'checkpoint/cell/pressure', grid, self%state%pressure)
    do m = 1, self%state%nfluids
      associate (f => self%state%fluid(m))
        g = 'checkpoint/cell/' // trim(f%name) // '/'
        call h5_read_cell_field(file, g // 'density', grid, f%rho)
        do d = 1, 3
          call h5_read_cell_field(file, g // trim(fluid_fields(1 + d)), grid, f%vel(:, :, :, d))
        end do
        call h5_read_cell_field(file, g // 'temperature', grid, f%temp)
        call h5_read_cell_field(file, g // 'specific_volume', grid, f%spvol)
      end associate
    end do
    call exchange_primitives(self, dom, grid)
  end subroutine ice_scene_restore

  !> Cell datasets of a dump.
  subroutine ice_scene_output_layout(self, cell_paths, particle_sets)
    class(ice_scene_t), intent(in) :: self                              !< scene
    character(len=name_len), allocatable, intent(out) :: cell_paths(:)   !< cell dataset paths
    type(xdmf_particles_t), allocatable, intent(out) :: particle_sets(:) !< particle sets
    integer :: m, n
    allocate(cell_paths(1 + size(fluid_fields) * self%state%nfluids))
    cell_paths(1) = 'cell/pressure'
    do m = 1, self%state%nfluids
      do n = 1, size(fluid_fields)
        cell_paths(1 + (m - 1) * size(fluid_fields) + n) = 'cell/' // &
          trim(self%state%fluid(m)%name) // '/' // trim(fluid_fields(n))
      end do
    end do
    allocate(particle_sets(0))
  end subroutine ice_scene_output_layout

  !> True when the owned pressure and fluid fields are finite.
  function ice_scene_all_finite(self, grid) result(finite)
    class(ice_scene_t), intent(in) :: self  !< scene
    type(grid_t), intent(in) :: grid        !< block geometry
    logical :: finite
    integer :: m
    associate (lo => grid%lo, hi => grid%hi)
      finite = all(ieee_is_finite(self%state%pressure(lo(1):hi(1), lo(2):hi(2), lo(3):hi(3))))
      do m = 1, self%state%nfluids
        associate (f => self%state%fluid(m))
          finite = finite .and. all(ieee_is_finite(f%rho(lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)))) &
            .and. all(ieee_is_finite(f%temp(lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)))) .and. &
            all(ieee_is_finite(f%vel(lo(1):hi(1), lo(2):hi(2), lo(3):hi(3), :)))
        end associate
      end do
    end associate
  end function ice_scene_all_finite

  !> Outer/PCG iteration statistics and the extreme pressures.
  subroutine ice_scene_summary(self, dom, grid)
    class(ice_scene_t), intent(inout) :: self  !< scene
    type(domain_t), intent(in) :: dom          !< decomposition
    type(grid_t), intent(in) :: grid           !< block geometry
    real(wp) :: pmin, pmax
    associate (lo => grid%lo, hi => grid%hi)
      pmin = global_min(dom, minval(self%state%pressure(lo(1):hi(1), lo(2):hi(2), lo(3):hi(3))))
      pmax = global_max(dom, maxval(self%state%pressure(lo(1):hi(1), lo(2):hi(2), lo(3):hi(3))))
    end associate
    if (self%steps > 0) call log_info('ICE: ' // int_text(self%steps) // ' steps, outer ' // &
      'iterations mean ' // real_short_text(real(self%total_outer, wp) / real(self%steps, wp)) &
      // ', max ' // int_text(self%max_outer_seen))
    if (self%solves > 0) call log_info('ICE: ' // int_text(self%solves) // ' pressure solves, ' &
      // 'PCG iterations mean ' // real_short_text(real(self%total_pcg, wp) / &
      real(self%solves, wp)) // ', max ' // int_text(self%max_pcg_seen))
    call log_info('ICE: pressure range ' // real_short_text(pmin) // ' .. ' // &
      real_short_text(pmax) // ' Pa')
  end subroutine ice_scene_summary

  !> Release solver, halo buffers and fields.
  subroutine ice_scene_free(self)
    class(ice_scene_t), intent(inout) :: self  !< scene
    call struct_solver_free(self%solver)
    call halo_free(self%halo)
    call ice_state_free(self%state)
    if (allocated(self%sources)) deallocate(self%sources)
    if (allocated(self%p_start)) deallocate(self%p_start)
  end subroutine ice_scene_free
end module ice_scene
