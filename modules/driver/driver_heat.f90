!> Time loop of the heat-conduction scene: implicit theta-scheme steps through hypre, dumps,
!! checkpoints, progress, failure detection and the stage-timer summary.
module driver_heat
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use mpi_f08, only: MPI_Bcast, MPI_LOGICAL
  use mpmice_kinds, only: wp, path_len
  use mpmice_errors, only: int_text, real_text
  use mpmice_log, only: log_info, log_warning
  use mpmice_timers, only: timer_set_t, timer_register, timer_start, timer_stop, timer_summary
  use mpmice_progress, only: progress_t, progress_init, progress_update, progress_elapsed
  use config_types, only: config_t
  use parallel_domain, only: domain_t
  use parallel_halo, only: halo_t, halo_init, halo_exchange_cell, halo_free
  use parallel_reduce, only: global_any, global_sum_field
  use grid_layout, only: grid_t
  use solver_pressure, only: struct_solver_t, struct_solver_init, struct_solver_set_operator, &
    struct_solver_solve, struct_solver_free
  use heat_conduction, only: heat_t, heat_init, heat_assemble, heat_free
  use driver_clock, only: clock_t, clock_init, clock_propose_dt, clock_advance, clock_finished
  use driver_output, only: cell_field_ref_t, write_dump, write_checkpoint, read_checkpoint
  implicit none
  private

  public :: run_heat, run_status_t

  !> How a run ended.
  type :: run_status_t
    integer :: exit_code = 0                  !< 0 finished or stopped cleanly, 3 failed
    character(len=path_len) :: reason = ''    !< one-line reason
  end type run_status_t

contains

  !> Run (or continue from `restart_file`) the heat-conduction scene.
  subroutine run_heat(cfg, namelist_text, dom, grid, restart_file, status)
    type(config_t), intent(in) :: cfg                !< validated configuration
    character(len=*), intent(in) :: namelist_text    !< resolved input (stored in every file)
    type(domain_t), intent(in) :: dom                !< decomposition
    type(grid_t), intent(in) :: grid                 !< block geometry
    character(len=*), intent(in) :: restart_file     !< checkpoint to continue, '' if none
    type(run_status_t), intent(out) :: status        !< how the run ended
    type(heat_t), target :: heat
    type(halo_t) :: halo
    type(struct_solver_t) :: solver
    type(clock_t) :: clock
    type(timer_set_t) :: timers
    type(progress_t) :: progress
    type(cell_field_ref_t) :: fields(1)
    real(wp) :: dt, dt_operator, residual, max_residual, slowest_step_s, step_start_s
    integer :: iterations, total_iterations, max_iterations_seen, unconverged, solves
    integer :: t_assemble, t_halo, t_solve, t_output
    logical :: converged, stop_for_wall_time, stopped_early

    t_assemble = timer_register(timers, 'assemble')
    t_halo = timer_register(timers, 'halo exchange')
    t_solve = timer_register(timers, 'implicit solve (hypre)')
    t_output = timer_register(timers, 'output and checkpoint')

    call heat_init(heat, grid, cfg%heat%conductivity, cfg%heat%density, cfg%heat%heat_capacity, &
      cfg%heat%base_temperature, cfg%heat%amplitude, cfg%heat%modes, cfg%numerics%time_theta)
    call halo_init(halo, dom, grid, 1)
    call struct_solver_init(solver, dom, grid, cfg%solver%tolerance, cfg%solver%max_iterations, &
      cfg%solver%print_level)
    call clock_init(clock, cfg%run%end_time, cfg%run%output_interval, &
      cfg%run%checkpoint_interval, cfg%run%max_steps, cfg%time%dt_init, cfg%time%dt_max, &
      cfg%time%dt_growth)
    fields(1)%path = 'cell/temperature'
    fields(1)%values => heat%temperature

    call progress_init(progress, cfg%run%progress_interval, clock%time, cfg%run%end_time)
    call timer_start(timers, t_output)
    if (len_trim(restart_file) > 0) then
      call read_checkpoint(dom, grid, restart_file, clock, fields)
      call log_info('restarted from ' // trim(restart_file) // ' at step ' // int_text(clock%step) &
        // ', t = ' // real_text(clock%time) // ' s')
    else
      call write_dump(dom, grid, clock, cfg%run%output_dir, cfg%run%name, namelist_text, fields, &
        cfg%output%xdmf, 'dump')
    end if
    call timer_stop(timers, t_output)
    progress%start_time = clock%time
    dt_operator = -1.0_wp
    total_iterations = 0
    max_iterations_seen = 0
    unconverged = 0
    solves = 0
    max_residual = 0.0_wp
    slowest_step_s = 0.0_wp
    stopped_early = .false.

    do while (.not. clock_finished(clock))
      step_start_s = progress_elapsed(progress)
      dt = clock_propose_dt(clock, huge(1.0_wp))
      if (dt < cfg%time%dt_min) then
        status%exit_code = 3
        status%reason = 'time step ' // real_text(dt) // ' s fell below &time dt_min = ' // &
          real_text(cfg%time%dt_min) // ' s'
        exit
      end if

      if (cfg%numerics%time_theta < 1.0_wp) then
        call timer_start(timers, t_halo)
        call halo_exchange_cell(halo, dom, grid, heat%temperature)
        call timer_stop(timers, t_halo)
      end if
      call timer_start(timers, t_assemble)
      call heat_assemble(heat, grid, dt)
      call timer_stop(timers, t_assemble)
      call timer_start(timers, t_solve)
      if (dt /= dt_operator) then
        call struct_solver_set_operator(solver, grid, heat%diag, heat%coef(:, :, :, 1), &
          heat%coef(:, :, :, 2), heat%coef(:, :, :, 3))
        dt_operator = dt
      end if
      call struct_solver_solve(solver, grid, heat%rhs, heat%temperature, iterations, residual, &
        converged)
      call timer_stop(timers, t_solve)
      solves = solves + 1
      total_iterations = total_iterations + iterations
      max_iterations_seen = max(max_iterations_seen, iterations)
      max_residual = max(max_residual, residual)
      if (.not. converged) unconverged = unconverged + 1

      call clock_advance(clock, dt, huge(1.0_wp))

      if (global_any(dom, .not. all_finite(heat, grid))) then
        call write_dump(dom, grid, clock, cfg%run%output_dir, cfg%run%name, namelist_text, &
          fields, cfg%output%xdmf, 'failed', status%reason)
        status%reason = 'non-finite temperature at step ' // int_text(clock%step) // ', t = ' // &
          real_text(clock%time) // ' s; state dumped to ' // trim(status%reason)
        status%exit_code = 3
        exit
      end if

      call timer_start(timers, t_output)
      if (clock%output_due .or. clock_finished(clock)) then
        call write_dump(dom, grid, clock, cfg%run%output_dir, cfg%run%name, namelist_text, &
          fields, cfg%output%xdmf, 'dump')
      end if
      if (clock%checkpoint_due) then
        call write_checkpoint(dom, grid, clock, cfg%run%output_dir, cfg%run%name, namelist_text, &
          fields)
      end if
      call timer_stop(timers, t_output)

      slowest_step_s = max(slowest_step_s, progress_elapsed(progress) - step_start_s)
      stop_for_wall_time = .false.
      if (cfg%run%wall_time_limit > 0.0_wp) then
        stop_for_wall_time = progress_elapsed(progress) + 2.0_wp * slowest_step_s &
          + 10.0_wp > cfg%run%wall_time_limit
        call MPI_Bcast(stop_for_wall_time, 1, MPI_LOGICAL, 0, dom%comm)
      end if
      if (stop_for_wall_time .and. .not. clock_finished(clock)) then
        status%reason = 'stopped before &run wall_time_limit = ' // &
          real_text(cfg%run%wall_time_limit) // ' s'
        stopped_early = .true.
        exit
      end if
      call progress_update(progress, clock%step, clock%time, clock%dt)
    end do

    if (status%exit_code == 0) then
      if (clock%time < cfg%run%end_time .and. .not. stopped_early) then
        stopped_early = .true.
        status%reason = 'stopped at &run max_steps = ' // int_text(cfg%run%max_steps)
      end if
      if (stopped_early) then
        ! leave a continuable state: checkpoint (and a dump of where the run stopped)
        call write_dump(dom, grid, clock, cfg%run%output_dir, cfg%run%name, namelist_text, &
          fields, cfg%output%xdmf, 'dump')
        call write_checkpoint(dom, grid, clock, cfg%run%output_dir, cfg%run%name, namelist_text, &
          fields)
      else
        status%reason = 'finished: end time reached'
      end if
    end if
    call progress_update(progress, clock%step, clock%time, clock%dt, force=.true.)

    if (solves > 0) then
      call log_info('implicit solves: ' // int_text(solves) // ', PCG iterations mean ' // &
        real_text(real(total_iterations, wp) / real(solves, wp)) // ', max ' // &
        int_text(max_iterations_seen) // ', largest final relative residual ' // &
        real_text(max_residual))
    end if
    if (unconverged > 0) call log_warning(int_text(unconverged) // ' implicit solves did not ' // &
      'reach &solver tolerance = ' // real_text(cfg%solver%tolerance))
    call log_info('mean temperature at the end: ' // real_text(global_sum_field(dom, grid, &
      heat%temperature) / real(product(grid%ncells), wp)) // ' K')
    call timer_summary(timers, dom%comm, progress_elapsed(progress))

    call struct_solver_free(solver)
    call halo_free(halo)
    call heat_free(heat)
  end subroutine run_heat

  !> True when every owned temperature is finite.
  function all_finite(heat, grid) result(finite)
    type(heat_t), intent(in) :: heat  !< scene state
    type(grid_t), intent(in) :: grid  !< block geometry
    logical :: finite
    finite = all(ieee_is_finite(heat%temperature(grid%lo(1):grid%hi(1), grid%lo(2):grid%hi(2), &
      grid%lo(3):grid%hi(3))))
  end function all_finite
end module driver_heat
