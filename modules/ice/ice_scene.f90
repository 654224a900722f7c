!> The ICE scene (`&run scene = 'ice'`): any number of fluids on the block-structured grid with
!! the implicit pressure equation solved by hypre PCG + PFMG (paper eqs. 29-37, 42-46, 54-65,
!! fluid part). One step (docs/ice.md) is the stage sequence of `ice_stages`:
!!  equilibration -> face velocities (eq. 31) -> face exchange (eq. 34) -> outer iteration of
!!  the pressure equation (eq. 35 with the face-velocity correction, eq. 36) -> face pressures
!!  (eq. 37) and Lagrangian values (eqs. 42-46, 56-57) -> cell exchange (eqs. 50-51) ->
!!  advection (eqs. 58-65).
!! Face conditions from `&boundary` (`ice_bc`): no-slip or free-slip walls, adiabatic or fixed
!! temperature.
module ice_scene
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use mpmice_kinds, only: wp, name_len
  use mpmice_errors, only: fatal, int_text, real_short_text
  use mpmice_log, only: log_info
  use mpmice_timers, only: timer_register
  use mpmice_faults, only: fault_step
  use scene_params, only: ice_scene_params_t
  use parallel_halo, only: halo_init, halo_free
  use parallel_reduce, only: global_max, global_min, global_sum
  use grid_layout, only: grid_t
  use scene_interface, only: scene_context_t
  use solver_pressure, only: struct_solver_init, struct_solver_free, struct_solver_set_reuse
  use io_hdf5, only: h5_file_t, h5_write_cell_field, h5_read_cell_field
  use io_xdmf, only: xdmf_particles_t
  use ice_eos, only: eos_t, eos_kind_from_name, eos_sound_speed2
  use ice_state, only: ice_state_alloc, ice_state_free, ice_fluid_t
  use ice_equilibration, only: ice_equilibrate
  use ice_bc, only: ice_bc_init
  use ice_initial, only: ice_initial_state
  use ice_viscous, only: ice_viscous_dt
  use ice_solid_view, only: ice_solid_view_t
  use ice_stages, only: ice_fluids_t, ice_stage_equilibrate, ice_stage_face_velocities, &
    ice_stage_face_exchange, ice_stage_pressure, ice_stage_lagrangian, ice_stage_cell_exchange, &
    ice_stage_advect, ice_step_begin, ice_step_reject, exchange_primitives
  implicit none
  private

  public :: ice_scene_t, ice_scene_setup, ice_fluids_stable_dt, ice_pressure_average_step

  !> Multi-fluid ICE with implicit pressure: the fluids of `ice_fluids_t` and the scene
  !! interface; its step is the sequence of `ice_stages`.
  type, extends(ice_fluids_t) :: ice_scene_t
  contains
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

  !> Materials from `&fluid`, initial state from `&fluid` and `&region`, solver and halos;
  !! keeps `ctx`.
  subroutine ice_scene_setup(self, par, ctx)
    class(ice_scene_t), intent(inout) :: self    !< scene
    type(ice_scene_params_t), intent(in) :: par  !< the scene's groups
    type(scene_context_t), intent(in) :: ctx     !< decomposition, grid and timers of the run
    integer :: m, its, failed

    self%ctx = ctx
    associate (dom => ctx%dom, grid => ctx%grid, timers => ctx%timers)
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
      self%gravity = par%physics%gravity
      self%k_exchange = par%ice%exchange_coefficient
      self%h_exchange = par%ice%heat_exchange_coefficient
      self%sound_speed_factor = par%ice%sound_speed_factor
      self%outer_tolerance = par%ice%outer_tolerance
      self%max_outer = par%ice%max_outer_iterations
      self%eq_tolerance = par%ice%equilibration_tolerance
      self%eq_max = par%ice%max_equilibration_iterations
      self%order = par%numerics%advection_order
      self%theta = par%numerics%time_theta
      self%face_time = self%theta
      if (par%ice%smagorinsky) self%smagorinsky = par%ice%smagorinsky_constant
      self%compression = par%ice%interface_compression
      if (par%nfluids < 1) call fatal('ice scene: no &fluid group')

      call ice_state_alloc(self%state, grid, par%nfluids)
      do m = 1, par%nfluids
        associate (f => self%state%fluid(m), c => par%fluids(m))
          f%name = c%name
          f%eos = eos_t(kind=eos_kind_from_name(c%eos), gamma=c%gamma, cv=c%heat_capacity_cv, &
            rho_ref=c%reference_density, p_ref=c%reference_pressure, &
            t_ref=c%reference_temperature, bulk_modulus=c%bulk_modulus, &
            alpha=c%thermal_expansion, p_inf=c%stiffened_pressure)
          f%viscosity = c%viscosity
          f%conductivity = c%conductivity
        end associate
      end do

      call ice_bc_init(self%bc, par)
      call ice_initial_state(self%state, par, grid)
      self%state%closed = .not. self%bc%open
      self%state%p_boundary = self%bc%p_face
      self%state%inflow_fluid = self%bc%inflow_fluid
      allocate(self%sources(grid%lbc(1):grid%ubc(1), grid%lbc(2):grid%ubc(2), &
        grid%lbc(3):grid%ubc(3), 4, par%nfluids), source=0.0_wp)
      allocate(self%p_start, mold=self%state%pressure)
      self%p_average_time = par%ice%pressure_average_time
      if (self%p_average_time > 0.0_wp) allocate(self%p_average, source=self%state%pressure)

      call halo_init(self%halo, dom, grid, 1)
      call struct_solver_init(self%solver, dom, grid, par%solver%tolerance, &
        par%solver%max_iterations, par%solver%print_level)
      ! one PFMG hierarchy per step (`ice_stage_pressure` invalidates it at the step's start),
      ! kept by the later outer passes
      call struct_solver_set_reuse(self%solver, self%max_outer)
      call exchange_primitives(self)
      call ice_equilibrate(self%state, grid, self%eq_tolerance, self%eq_max, its, failed)
      failed = global_sum(dom, failed)
      if (failed > 0) call fatal('ice scene: initial pressure equilibration failed in ' // &
        int_text(failed) // ' cells')
    end associate
  end subroutine ice_scene_setup

  !> The ICE scene's stable step: `ice_fluids_stable_dt` without a solid phase.
  function ice_scene_stable_dt(self, cfl) result(dt)
    class(ice_scene_t), intent(inout) :: self  !< scene
    real(wp), intent(in) :: cfl                !< Courant number
    real(wp) :: dt
    dt = ice_fluids_stable_dt(self, cfl)
  end function ice_scene_stable_dt

  !> CFL limit: cfl * min over cells, directions and fluids of dx / (|u| + f c), f the
  !! sound-speed factor (0: the advective limit of the implicit scheme), and cfl times the
  !! explicit viscosity/conduction limit (`ice_viscous_dt`, with the Smagorinsky eddy viscosity;
  !! with the solid phase of a coupled scene, the momentum limit of its free fluid only).
  function ice_fluids_stable_dt(self, cfl, solid) result(dt)
    class(ice_fluids_t), intent(inout) :: self !< fluids
    real(wp), intent(in) :: cfl                !< Courant number
    class(ice_solid_view_t), intent(in), optional :: solid !< solid phase of a coupled scene
    real(wp) :: dt
    integer :: m, i, j, k
    real(wp) :: rate, dt_viscous

    rate = 0.0_wp
    associate (dom => self%ctx%dom, grid => self%ctx%grid)
      do m = 1, self%state%nfluids
        do k = grid%lo(3), grid%hi(3)
          do j = grid%lo(2), grid%hi(2)
            do i = grid%lo(1), grid%hi(1)
              rate = max(rate, cell_rate(self%state%fluid(m), grid, [i, j, k], &
                self%sound_speed_factor))
            end do
          end do
        end do
      end do
      rate = global_max(dom, rate)
      if (rate > 0.0_wp) then
        dt = cfl / rate
      else
        dt = huge(1.0_wp)
      end if
      ! explicit viscosity and conduction
      call ice_viscous_dt(self%state, grid, dt_viscous, self%smagorinsky, solid)
      dt = min(dt, cfl * global_min(dom, dt_viscous))
    end associate
  end function ice_fluids_stable_dt

  !> The largest (|u| + f c) / dx of fluid `f` in cell `c` over the active directions (0 where
  !! the fluid is absent), f the sound-speed factor (c not evaluated when f = 0).
  pure real(wp) function cell_rate(f, grid, c, factor) result(rate)
    type(ice_fluid_t), intent(in) :: f   !< fluid
    type(grid_t), intent(in) :: grid     !< block geometry
    integer, intent(in) :: c(3)          !< cell
    real(wp), intent(in) :: factor       !< weight of the sound speed
    real(wp) :: sound, speed
    integer :: d
    rate = 0.0_wp
    if (f%rho(c(1), c(2), c(3)) <= 0.0_wp) return
    sound = 0.0_wp
    if (factor > 0.0_wp) sound = sqrt(eos_sound_speed2(f%eos, 1.0_wp / f%spvol(c(1), c(2), c(3)), &
      f%temp(c(1), c(2), c(3))))
    do d = 1, 3
      if (.not. grid%active(d)) cycle
      speed = abs(f%vel(c(1), c(2), c(3), d)) + factor * sound
      rate = max(rate, speed / grid%dx(d))
    end do
  end function cell_rate

  !> One ICE step, the stages of `ice_stages` in order; rejected (state unchanged) when the
  !! equilibration or the outer iteration does not converge. A NaN or Inf in the pressure
  !! equation ends the step at once, taken with the NaN pressure, so that the run fails (exit
  !! status 3) with the state dumped.
  subroutine ice_scene_step(self, time, dt, accepted)
    class(ice_scene_t), intent(inout) :: self    !< scene
    real(wp), intent(in) :: time                 !< time at the start of the step [s]
    real(wp), intent(in) :: dt                   !< step [s]
    logical, intent(out) :: accepted             !< the step was taken

    accepted = .false.
    call ice_step_begin(self)
    if (.not. ice_stage_equilibrate(self, time)) return
    call ice_stage_face_velocities(self, dt)
    call ice_stage_face_exchange(self, dt)
    if (.not. ice_stage_pressure(self, time, dt)) then
      ! non-finite: taken as it is, so the run loop's check fails the run and dumps the state
      accepted = self%nonfinite
      if (.not. self%nonfinite) call ice_step_reject(self)
      return
    end if
    call ice_stage_lagrangian(self, dt)
    call ice_stage_cell_exchange(self, dt)
    call ice_stage_advect(self, time, dt)
    call ice_pressure_average_step(self, dt)
    self%steps = self%steps + 1
    accepted = .true.
  end subroutine ice_scene_step

  !> The running mean of the cell pressure after an accepted step of length `dt` (`&ice
  !! pressure_average_time` tau > 0): p_avg = w p_avg + (1 - w) p, w = exp(-dt / tau), over
  !! the owned cells; a step's weight depends on its length only, so the mean is that of the
  !! pressure over the last ~tau of time, whatever the steps.
  subroutine ice_pressure_average_step(self, dt)
    class(ice_fluids_t), intent(inout) :: self  !< fluids
    real(wp), intent(in) :: dt                  !< step [s]
    real(wp) :: w
    integer :: i, j, k
    if (.not. allocated(self%p_average)) return
    w = exp(-dt / self%p_average_time)
    associate (lo => self%ctx%grid%lo, hi => self%ctx%grid%hi)
      do k = lo(3), hi(3)
        do j = lo(2), hi(2)
          do i = lo(1), hi(1)
            self%p_average(i, j, k) = w * self%p_average(i, j, k) + (1.0_wp - w) * &
              self%state%pressure(i, j, k)
          end do
        end do
      end do
    end associate
  end subroutine ice_pressure_average_step

  !> Writes to a dump `cell/pressure` and `cell/<fluid>/<field>`; checkpoint: the primitive fields and the
  !! pressure under `checkpoint/` (everything the next step reads). With `&ice
  !! pressure_average_time` > 0 both carry `cell/pressure_average` too.
  subroutine ice_scene_write_state(self, file, checkpoint)
    class(ice_scene_t), intent(inout) :: self  !< scene
    type(h5_file_t), intent(in) :: file        !< open file
    logical, intent(in) :: checkpoint          !< full restart state
    character(len=:), allocatable :: prefix, g
    integer :: m, d
    prefix = ''
    if (checkpoint) prefix = 'checkpoint/'
    associate (grid => self%ctx%grid)
      call h5_write_cell_field(file, prefix // 'cell/pressure', grid, self%state%pressure)
      if (allocated(self%p_average)) call h5_write_cell_field(file, prefix // &
        'cell/pressure_average', grid, self%p_average)
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
    end associate
  end subroutine ice_scene_write_state

  !> Read the primitive fields and the pressure of a checkpoint, then fill the ghosts; the
  !! running pressure mean where the run keeps one (a restart cannot change `&ice
  !! pressure_average_time`, so the checkpoint holds it).
  subroutine ice_scene_restore(self, file)
    class(ice_scene_t), intent(inout) :: self  !< scene
    type(h5_file_t), intent(in) :: file        !< open checkpoint
    character(len=:), allocatable :: g
    integer :: m, d
    associate (grid => self%ctx%grid)
      call h5_read_cell_field(file, 'checkpoint/cell/pressure', grid, self%state%pressure)
      if (allocated(self%p_average)) call h5_read_cell_field(file, &
        'checkpoint/cell/pressure_average', grid, self%p_average)
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
    end associate
    call exchange_primitives(self)
  end subroutine ice_scene_restore

  !> Cell datasets of a dump.
  subroutine ice_scene_output_layout(self, cell_paths, particle_sets)
    class(ice_scene_t), intent(in) :: self                              !< scene
    character(len=name_len), allocatable, intent(out) :: cell_paths(:)   !< cell dataset paths
    type(xdmf_particles_t), allocatable, intent(out) :: particle_sets(:) !< particle sets
    integer :: m, n, first
    first = merge(2, 1, allocated(self%p_average))
    allocate(cell_paths(first + size(fluid_fields) * self%state%nfluids))
    cell_paths(1) = 'cell/pressure'
    if (first == 2) cell_paths(2) = 'cell/pressure_average'
    do m = 1, self%state%nfluids
      do n = 1, size(fluid_fields)
        cell_paths(first + (m - 1) * size(fluid_fields) + n) = 'cell/' // &
          trim(self%state%fluid(m)%name) // '/' // trim(fluid_fields(n))
      end do
    end do
    allocate(particle_sets(0))
  end subroutine ice_scene_output_layout

  !> True when the owned pressure and fluid fields are finite.
  function ice_scene_all_finite(self) result(finite)
    class(ice_scene_t), intent(in) :: self  !< scene
    logical :: finite
    integer :: m
    associate (lo => self%ctx%grid%lo, hi => self%ctx%grid%hi)
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
  subroutine ice_scene_summary(self)
    class(ice_scene_t), intent(inout) :: self  !< scene
    real(wp) :: pmin, pmax
    associate (dom => self%ctx%dom, lo => self%ctx%grid%lo, hi => self%ctx%grid%hi)
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
    if (allocated(self%p_average)) deallocate(self%p_average)
  end subroutine ice_scene_free
end module ice_scene
