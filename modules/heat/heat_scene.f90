!> The heat-conduction scene for the generic time loop: state in `heat_t`, one implicit hypre
!! solve per step, output `cell/temperature`.
module heat_scene
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use mpmice_kinds, only: wp, name_len
  use mpmice_errors, only: int_text, real_short_text
  use mpmice_log, only: log_info, log_warning
  use mpmice_timers, only: timer_register, timer_start, timer_stop
  use scene_params, only: heat_scene_params_t
  use parallel_halo, only: halo_t, halo_init, halo_exchange_cell, halo_free
  use parallel_reduce, only: global_sum_field
  use solver_pressure, only: struct_solver_t, struct_solver_init, struct_solver_set_operator, &
    struct_solver_solve, struct_solver_free, struct_solver_invalidate
  use io_hdf5, only: h5_file_t, h5_write_cell_field, h5_read_cell_field
  use io_xdmf, only: xdmf_particles_t
  use heat_conduction, only: heat_t, heat_init, heat_assemble, heat_free
  use scene_interface, only: scene_t, scene_context_t
  implicit none
  private

  public :: heat_scene_t, heat_scene_setup

  !> Heat conduction through the implicit solver.
  type, extends(scene_t) :: heat_scene_t
    type(heat_t) :: heat                      !< temperature and assembled system
    type(halo_t) :: halo                      !< halo buffers
    type(struct_solver_t) :: solver           !< hypre PCG + PFMG
    real(wp) :: tolerance = 1.0e-10_wp        !< solver tolerance (for messages)
    real(wp) :: dt_operator = -1.0_wp         !< dt of the operator hypre holds [s]
    integer :: solves = 0                     !< implicit solves done
    integer :: total_iterations = 0           !< PCG iterations summed over solves
    integer :: max_iterations_seen = 0        !< largest PCG iteration count
    integer :: unconverged = 0                !< solves that missed the tolerance
    real(wp) :: max_residual = 0.0_wp         !< largest final relative residual
    integer :: t_assemble = 0                 !< timer id
    integer :: t_halo = 0                     !< timer id
    integer :: t_solve = 0                    !< timer id
  contains
    procedure :: stable_dt => heat_scene_stable_dt
    procedure :: step => heat_scene_step
    procedure :: write_state => heat_scene_write_state
    procedure :: restore => heat_scene_restore
    procedure :: output_layout => heat_scene_output_layout
    procedure :: all_finite => heat_scene_all_finite
    procedure :: summary => heat_scene_summary
    procedure :: free => heat_scene_free
  end type heat_scene_t

  character(len=*), parameter :: temperature_path = 'cell/temperature'  !< dataset of T

contains

  !> Initial field (exact solution at t = 0), halo buffers and solver; keeps `ctx`.
  subroutine heat_scene_setup(self, par, ctx)
    class(heat_scene_t), intent(inout) :: self   !< scene
    type(heat_scene_params_t), intent(in) :: par !< the scene's groups
    type(scene_context_t), intent(in) :: ctx     !< decomposition, grid and timers of the run
    self%ctx = ctx
    associate (dom => ctx%dom, grid => ctx%grid, timers => ctx%timers)
      self%t_assemble = timer_register(timers, 'assemble')
      self%t_halo = timer_register(timers, 'halo exchange')
      self%t_solve = timer_register(timers, 'implicit solve (hypre)')
      call heat_init(self%heat, grid, par%heat%conductivity, par%heat%density, &
        par%heat%heat_capacity, par%heat%base_temperature, par%heat%amplitude, par%heat%modes, &
        par%numerics%time_theta)
      call halo_init(self%halo, dom, grid, 1)
      call struct_solver_init(self%solver, dom, grid, par%solver%tolerance, &
        par%solver%max_iterations, par%solver%print_level)
    end associate
    self%tolerance = par%solver%tolerance
  end subroutine heat_scene_setup

  !> No stability limit: the scheme is implicit.
  function heat_scene_stable_dt(self, cfl) result(dt)
    class(heat_scene_t), intent(inout) :: self  !< scene
    real(wp), intent(in) :: cfl                 !< Courant number (unused)
    real(wp) :: dt
    dt = huge(1.0_wp)
  end function heat_scene_stable_dt

  !> One theta-scheme step: halo, assembly, operator update when dt changed, PCG solve.
  subroutine heat_scene_step(self, time, dt, accepted)
    class(heat_scene_t), intent(inout) :: self   !< scene
    real(wp), intent(in) :: time                 !< time at the start of the step [s]
    real(wp), intent(in) :: dt                   !< step [s]
    logical, intent(out) :: accepted             !< always true (a missed tolerance is logged)
    integer :: iterations
    real(wp) :: residual
    logical :: converged

    associate (dom => self%ctx%dom, grid => self%ctx%grid, timers => self%ctx%timers)
      if (self%heat%theta < 1.0_wp) then
        call timer_start(timers, self%t_halo)
        call halo_exchange_cell(self%halo, dom, grid, self%heat%temperature)
        call timer_stop(timers, self%t_halo)
      end if
      call timer_start(timers, self%t_assemble)
      call heat_assemble(self%heat, grid, dt)
      call timer_stop(timers, self%t_assemble)
      call timer_start(timers, self%t_solve)
      if (dt /= self%dt_operator) then
        call struct_solver_set_operator(self%solver, grid, self%heat%diag, &
          self%heat%coef(:, :, :, 1), self%heat%coef(:, :, :, 2), self%heat%coef(:, :, :, 3))
        self%dt_operator = dt
      end if
      call struct_solver_solve(self%solver, grid, self%heat%rhs, self%heat%temperature, &
        iterations, residual, converged)
      call timer_stop(timers, self%t_solve)
    end associate
    self%solves = self%solves + 1
    self%total_iterations = self%total_iterations + iterations
    self%max_iterations_seen = max(self%max_iterations_seen, iterations)
    self%max_residual = max(self%max_residual, residual)
    if (.not. converged) then
      self%unconverged = self%unconverged + 1
      call log_warning('heat solve at t = ' // real_short_text(time) // ' s missed the tolerance')
    end if
    accepted = .true.
  end subroutine heat_scene_step

  !> `cell/temperature` (dumps) or `checkpoint/cell/temperature` (checkpoints).
  subroutine heat_scene_write_state(self, file, checkpoint)
    class(heat_scene_t), intent(inout) :: self  !< scene
    type(h5_file_t), intent(in) :: file         !< open file
    logical, intent(in) :: checkpoint           !< full restart state
    if (checkpoint) then
      ! a restart starts with a fresh preconditioner: so does the run that goes on
      call struct_solver_invalidate(self%solver)
      call h5_write_cell_field(file, 'checkpoint/' // temperature_path, self%ctx%grid, &
        self%heat%temperature)
    else
      call h5_write_cell_field(file, temperature_path, self%ctx%grid, self%heat%temperature)
    end if
  end subroutine heat_scene_write_state

  !> Read the temperature of a checkpoint.
  subroutine heat_scene_restore(self, file)
    class(heat_scene_t), intent(inout) :: self  !< scene
    type(h5_file_t), intent(in) :: file         !< open checkpoint
    call h5_read_cell_field(file, 'checkpoint/' // temperature_path, self%ctx%grid, &
      self%heat%temperature)
  end subroutine heat_scene_restore

  !> A dump holds `cell/temperature` and no particles.
  subroutine heat_scene_output_layout(self, cell_paths, particle_sets)
    class(heat_scene_t), intent(in) :: self                              !< scene
    character(len=name_len), allocatable, intent(out) :: cell_paths(:)   !< cell dataset paths
    type(xdmf_particles_t), allocatable, intent(out) :: particle_sets(:) !< particle sets
    cell_paths = [character(len=name_len) :: temperature_path]
    allocate(particle_sets(0))
  end subroutine heat_scene_output_layout

  !> True when every owned temperature is finite.
  function heat_scene_all_finite(self) result(finite)
    class(heat_scene_t), intent(in) :: self  !< scene
    logical :: finite
    associate (lo => self%ctx%grid%lo, hi => self%ctx%grid%hi)
      finite = all(ieee_is_finite(self%heat%temperature(lo(1):hi(1), lo(2):hi(2), lo(3):hi(3))))
    end associate
  end function heat_scene_all_finite

  !> Solver statistics and the mean temperature.
  subroutine heat_scene_summary(self)
    class(heat_scene_t), intent(inout) :: self  !< scene
    if (self%solves > 0) then
      call log_info('implicit solves: ' // int_text(self%solves) // ', PCG iterations mean ' // &
        real_short_text(real(self%total_iterations, wp) / real(self%solves, wp)) // ', max ' // &
        int_text(self%max_iterations_seen) // ', largest final relative residual ' // &
        real_short_text(self%max_residual))
    end if
    if (self%unconverged > 0) call log_warning(int_text(self%unconverged) // ' implicit solves ' &
      // 'did not reach &solver tolerance = ' // real_short_text(self%tolerance))
    associate (dom => self%ctx%dom, grid => self%ctx%grid)
      call log_info('mean temperature at the end: ' // real_short_text(global_sum_field(dom, grid, &
        self%heat%temperature) / real(product(grid%ncells), wp)) // ' K')
    end associate
  end subroutine heat_scene_summary

  !> Release solver, halo buffers and arrays.
  subroutine heat_scene_free(self)
    class(heat_scene_t), intent(inout) :: self  !< scene
    self%dt_operator = -1.0_wp  ! the solver holds no operator any more
    call struct_solver_free(self%solver)
    call halo_free(self%halo)
    call heat_free(self%heat)
  end subroutine heat_scene_free
end module heat_scene
