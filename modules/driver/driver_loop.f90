!> The generic time loop: clock, retries of rejected steps, dumps, checkpoints, failure detection
!! (NaN/Inf, and the optional stops of `driver_stops`: energy growth, particle loss, step
!! collapse; each reports, dumps the state and stops), the wall-time stop, progress lines and the
!! stage-timer summary. Every scene (`scene_interface`) runs through it. With `&grid rebalance`
!! a run stops at a checkpoint whose particles call for other blocks (`rebalance_due`) and the
!! caller continues it from there on those blocks: the `run_segment_t` carries the invocation's
!! step count, wall clock and stage timers from one segment to the next.
module driver_loop
  use parallel_comm, only: bcast
  use mpmice_kinds, only: wp, path_len
  use mpmice_errors, only: int_text, real_short_text
  use mpmice_log, only: log_info, log_warning, log_warning_summary
  use mpmice_timers, only: timer_set_t, timer_register, timer_start, timer_stop
  use parallel_timers, only: timer_summary
  use mpmice_progress, only: progress_t, progress_init, progress_update, progress_elapsed
  use config_types, only: config_t
  use parallel_domain, only: domain_t
  use parallel_reduce, only: global_any, global_max
  use mpmice_signals, only: signals_install, signal_received, signal_name
  use grid_layout, only: grid_t
  use driver_clock, only: clock_t, clock_from_config, clock_next_dt, clock_reject, clock_refusal, &
    clock_accept, clock_finished, clock_resume
  use driver_output, only: write_state_file, read_checkpoint
  use scene_interface, only: scene_t, scene_context_t
  use scene_params, only: scene_params_t
  use driver_scene_params, only: scene_create
  use driver_stops, only: stops_watch_state, stops_start, stops_check_dt, stops_check_state
  use io_files, only: io_join_path
  use io_write_failure, only: io_close_checked
  use driver_balance, only: run_block_cells
  use config_types, only: max_blocks_per_dim
  implicit none
  private

  public :: run_scene, run_status_t, run_segment_t

  !> How a run ended.
  type :: run_status_t
    integer :: exit_code = 0                  !< 0 finished or stopped cleanly, 3 failed
    !> finished, stopped (continuable) or failed; running while the run goes on
    character(len=16) :: state = 'finished'
    character(len=path_len) :: reason = ''    !< one-line reason
    character(len=path_len) :: checkpoint = '' !< checkpoint to continue from (stopped runs)
  end type run_status_t

  !> What one invocation carries from one segment to the next when `&grid rebalance` moves the
  !! blocks: its first step (for `&run max_steps`), its wall-clock and simulated start (for the
  !! progress lines and `&run wall_time_limit`), its rejected steps and its stage timers;
  !! `rebalance_from` is the checkpoint a segment stopped at to continue on other blocks (''
  !! when it did not).
  type :: run_segment_t
    integer :: first_step = -1                     !< step at the invocation's start (-1: unset)
    real(wp) :: start_s = -1.0_wp                  !< wall clock at its start [s] (-1: unset)
    real(wp) :: start_time = 0.0_wp                !< simulated time at its start [s]
    integer :: rejected = 0                        !< steps rejected in earlier segments
    type(timer_set_t) :: timers                    !< stage timers of the invocation
    character(len=path_len) :: rebalance_from = '' !< checkpoint to continue from on new blocks
    character(len=path_len) :: blocks_report = ''  !< the new blocks' modelled cost
    integer :: block_cells(max_blocks_per_dim, 3) = 0  !< the new blocks (`domain_init` layout)
  end type run_segment_t

contains

  !> Run the scene of the parameters `params` from its initial state, or continue it from
  !! `restart_file` (not '').
  subroutine run_scene(params, cfg, namelist_text, dom, grid, restart_file, status, segment)
    class(scene_params_t), intent(in) :: params      !< the scene's groups (from `cfg`)
    type(config_t), intent(in) :: cfg                !< validated configuration
    character(len=*), intent(in) :: namelist_text    !< resolved input (stored in every file)
    type(domain_t), intent(in), target :: dom        !< decomposition (kept by the scene)
    type(grid_t), intent(in), target :: grid         !< block geometry (kept by the scene)
    character(len=*), intent(in) :: restart_file     !< checkpoint to continue, '' if none
    type(run_status_t), intent(out) :: status        !< how the run ended
    type(run_segment_t), intent(inout), target :: segment  !< carried between segments
    class(scene_t), allocatable :: scene
    type(clock_t) :: clock
    type(progress_t) :: progress
    real(wp) :: dt, dt_limit, slowest_step_s, step_start_s, load_power, energy_peak
    integer :: t_output, signum
    logical :: accepted, stop_for_wall_time, stopped_early, watch_state
    character(len=path_len) :: stop_reason, checkpoint_path

    segment%rebalance_from = ''
    t_output = timer_register(segment%timers, 'output and checkpoint')
    call signals_install()
    call scene_create(params, scene_context_t(dom=dom, grid=grid, timers=segment%timers), scene)
    call clock_from_config(clock, cfg%run, cfg%time)
    call progress_init(progress, cfg%run%progress_interval, 0.0_wp, cfg%run%end_time)
    if (segment%start_s >= 0.0_wp) then
      progress%start_s = segment%start_s
    else
      segment%start_s = progress%start_s
    end if

    ! until the run ends, its status file says 'running': a run that dies on the way (killed, or
    ! an output file that cannot be written) leaves no stale 'stopped' for job scripts to continue
    if (dom%rank == 0 .and. segment%first_step < 0) then
      status%state = 'running'
      status%reason = 'running, or ended without a final state (killed, or an output file ' // &
        'could not be written)'
      call write_status_file(cfg, clock, status)
      status%state = 'finished'
      status%reason = ''
    end if
    call timer_start(segment%timers, t_output)
    if (len_trim(restart_file) > 0) then
      call read_checkpoint(scene, dom, grid, restart_file, clock)
      call clock_resume(clock)
      if (segment%first_step >= 0) clock%first_step = segment%first_step
      call log_info('restarted from ' // trim(restart_file) // ' at step ' // int_text(clock%step) &
        // ', t = ' // real_short_text(clock%time) // ' s')
    else
      call write_state_file(scene, dom, grid, clock, cfg%run%output_dir, cfg%run%name, &
        namelist_text, cfg%output%xdmf, 'dump')
    end if
    call timer_stop(segment%timers, t_output)
    if (segment%first_step < 0) then
      segment%first_step = clock%first_step
      segment%start_time = clock%time
    end if
    clock%rejected = segment%rejected
    progress%start_time = segment%start_time
    watch_state = stops_watch_state(cfg)
    load_power = 0.0_wp
    energy_peak = 0.0_wp
    if (watch_state) call stops_start(scene, clock, load_power)

    slowest_step_s = 0.0_wp
    stopped_early = .false.
    ! a signal that came during start-up (the handler is installed before MPI_Init) stops the run
    ! before its first step, with a checkpoint of the initial (or restored) state
    signum = global_max(dom, signal_received())
    if (signum > 0 .and. .not. clock_finished(clock)) then
      status%reason = 'stopped on ' // signal_name(signum) // ' before step ' // &
        int_text(clock%step + 1)
      stopped_early = .true.
    end if
    do while (.not. clock_finished(clock) .and. .not. stopped_early)
      step_start_s = progress_elapsed(progress)
      dt_limit = scene%stable_dt(clock%cfl)
      stop_reason = stops_check_dt(cfg, clock, dt_limit)
      if (len_trim(stop_reason) > 0) then
        call fail_with_dump(scene, cfg, dom, grid, clock, namelist_text, stop_reason, status)
        exit
      end if
      call clock_next_dt(clock, dt_limit, dt)
      do
        stop_reason = clock_refusal(clock, dt)
        if (len_trim(stop_reason) > 0) exit
        call scene%step(clock%time, dt, accepted)
        if (accepted) exit
        call log_warning('step ' // int_text(clock%step + 1) // ' rejected at dt = ' // &
          real_short_text(dt) // ' s; retrying with dt/2')
        call clock_reject(clock, dt)
      end do
      if (len_trim(stop_reason) > 0) then
        call fail_with_dump(scene, cfg, dom, grid, clock, namelist_text, stop_reason, status)
        exit
      end if

      call clock_accept(clock, dt)

      if (global_any(dom, .not. scene%all_finite())) then
        call fail_with_dump(scene, cfg, dom, grid, clock, namelist_text, 'non-finite values ' &
          // 'at step ' // int_text(clock%step) // ', t = ' // real_short_text(clock%time) // &
          ' s', status)
        exit
      end if
      if (watch_state) then
        call stops_check_state(scene, cfg, clock, load_power, energy_peak, stop_reason)
        if (len_trim(stop_reason) > 0) then
          call fail_with_dump(scene, cfg, dom, grid, clock, namelist_text, stop_reason, status)
          exit
        end if
      end if

      call timer_start(segment%timers, t_output)
      if (clock%output_due .or. clock_finished(clock)) then
        call write_state_file(scene, dom, grid, clock, cfg%run%output_dir, cfg%run%name, &
          namelist_text, cfg%output%xdmf, 'dump')
      end if
      if (clock%checkpoint_due) then
        call write_state_file(scene, dom, grid, clock, cfg%run%output_dir, cfg%run%name, &
          namelist_text, .false., 'checkpoint', checkpoint_path)
        if (cfg%grid%rebalance .and. .not. clock_finished(clock)) then
          if (rebalance_due(cfg, dom, checkpoint_path, segment%block_cells, &
              segment%blocks_report)) then
            segment%rebalance_from = checkpoint_path
          end if
        end if
      end if
      call timer_stop(segment%timers, t_output)
      if (len_trim(segment%rebalance_from) > 0) exit

      slowest_step_s = max(slowest_step_s, progress_elapsed(progress) - step_start_s)
      stop_for_wall_time = .false.
      if (cfg%run%wall_time_limit > 0.0_wp) then
        stop_for_wall_time = progress_elapsed(progress) + 2.0_wp * slowest_step_s &
          + 10.0_wp > cfg%run%wall_time_limit
        call bcast(dom%comm, stop_for_wall_time, 0)
      end if
      if (stop_for_wall_time .and. .not. clock_finished(clock)) then
        status%reason = 'stopped before &run wall_time_limit = ' // &
          real_short_text(cfg%run%wall_time_limit) // ' s'
        stopped_early = .true.
        exit
      end if
      signum = global_max(dom, signal_received())
      if (signum > 0 .and. .not. clock_finished(clock)) then
        status%reason = 'stopped on ' // signal_name(signum)
        stopped_early = .true.
        exit
      end if
      call progress_update(progress, clock%step, clock%time, clock%dt)
    end do

    segment%rejected = clock%rejected
    if (len_trim(segment%rebalance_from) > 0) then
      ! the scene's summary of this segment's steps (its counters start again on the new
      ! blocks); the caller continues the run from that checkpoint
      call log_info('mpmice: the steps on these blocks, to ' // trim(segment%rebalance_from) // &
        ':')
      call scene%summary()
      call scene%free()
      return
    end if
    if (status%exit_code == 0) then
      if (clock%time < cfg%run%end_time .and. .not. stopped_early) then
        stopped_early = .true.
        status%reason = 'stopped at &run max_steps = ' // int_text(cfg%run%max_steps)
      end if
      if (stopped_early) then
        ! leave a continuable state: a dump of where the run stopped and a checkpoint
        call write_state_file(scene, dom, grid, clock, cfg%run%output_dir, cfg%run%name, &
          namelist_text, cfg%output%xdmf, 'dump')
        call write_state_file(scene, dom, grid, clock, cfg%run%output_dir, cfg%run%name, &
          namelist_text, .false., 'checkpoint', status%checkpoint)
        status%state = 'stopped'
        status%reason = trim(status%reason) // '; continue with mpmice --restart ' // &
          trim(status%checkpoint)
      else
        status%reason = 'finished: end time reached'
      end if
    end if
    if (status%exit_code /= 0) status%state = 'failed'
    if (dom%rank == 0) call write_status_file(cfg, clock, status)
    call progress_update(progress, clock%step, clock%time, clock%dt, force=.true.)
    if (clock%rejected > 0) call log_info(int_text(clock%rejected) // ' steps were rejected and retried')
    if (cfg%run%max_energy_growth > 0.0_wp) call log_info('run stops: largest solid energy / ' &
      // 'reference ' // real_short_text(energy_peak) // ' (&run max_energy_growth = ' // &
      real_short_text(cfg%run%max_energy_growth) // ')')
    call scene%summary()
    call log_warning_summary()
    call timer_summary(segment%timers, dom%comm, progress_elapsed(progress))
    call scene%free()
  end subroutine run_scene

  !> Collective: true when the blocks of least modelled cost for the particles in the
  !! checkpoint `path` (`driver_balance%run_block_cells`), returned in `blocks`, differ from
  !! those of `dom`; `report` gives their modelled cost.
  logical function rebalance_due(cfg, dom, path, blocks, report)
    type(config_t), intent(in) :: cfg                !< validated configuration
    type(domain_t), intent(in) :: dom                !< the run's decomposition
    character(len=*), intent(in) :: path             !< checkpoint just written
    integer, intent(out) :: blocks(:, :)             !< (max_blocks_per_dim, 3) the new blocks
    character(len=*), intent(out) :: report          !< the new blocks' modelled cost
    integer :: d, n
    blocks = run_block_cells(cfg, dom%comm, path, report)
    rebalance_due = .false.
    if (len_trim(report) == 0) return   ! nothing to choose: the blocks cannot move
    do d = 1, 3
      n = dom%dims(d)
      if (count(blocks(:, d) > 0) /= n) then
        rebalance_due = .true.
      else if (any(blocks(1:n, d) /= dom%first_cell(1:n, d) - dom%first_cell(0:n - 1, d))) then
        rebalance_due = .true.
      end if
    end do
  end function rebalance_due

  !> A failed run: dump the state to `<name>_failed_<step>.h5`, exit status 3, the reason with
  !! the dump's path.
  subroutine fail_with_dump(scene, cfg, dom, grid, clock, namelist_text, reason, status)
    class(scene_t), intent(inout) :: scene           !< the scene
    type(config_t), intent(in) :: cfg                !< validated configuration
    type(domain_t), intent(in) :: dom                !< decomposition
    type(grid_t), intent(in) :: grid                 !< block geometry
    type(clock_t), intent(in) :: clock               !< run clock
    character(len=*), intent(in) :: namelist_text    !< resolved input
    character(len=*), intent(in) :: reason           !< why the run failed
    type(run_status_t), intent(inout) :: status      !< how the run ended
    character(len=path_len) :: path
    call write_state_file(scene, dom, grid, clock, cfg%run%output_dir, cfg%run%name, &
      namelist_text, cfg%output%xdmf, 'failed', path)
    status%reason = trim(reason) // '; state dumped to ' // trim(path)
    status%exit_code = 3
  end subroutine fail_with_dump

  !> Write `<output_dir>/<name>.status` for job scripts: `key = value` lines `state` (finished,
  !! stopped or failed), `step`, `time`, `checkpoint` (stopped runs) and `reason`.
  subroutine write_status_file(cfg, clock, status)
    type(config_t), intent(in) :: cfg           !< configuration
    type(clock_t), intent(in) :: clock          !< run clock
    type(run_status_t), intent(in) :: status    !< how the run ended
    integer :: unit, ios
    character(len=:), allocatable :: reason
    open(newunit=unit, file=io_join_path(cfg%run%output_dir, trim(cfg%run%name) // '.status'), &
      status='replace', action='write', iostat=ios)
    if (ios /= 0) then
      call log_warning('cannot write the status file in ' // trim(cfg%run%output_dir))
      return
    end if
    write(unit, '(a)') 'state = ' // trim(status%state)
    write(unit, '(a,i0)') 'step = ', clock%step
    write(unit, '(a,es23.16)') 'time = ', clock%time
    write(unit, '(a)') 'checkpoint = ' // trim(status%checkpoint)
    write(unit, '(a)') 'reason = ' // trim(status%reason)
    call io_close_checked(unit, io_join_path(cfg%run%output_dir, trim(cfg%run%name) // &
      '.status'), ios, reason)
    if (ios /= 0) call log_warning('cannot write the status file in ' // &
      trim(cfg%run%output_dir) // ': ' // reason)
  end subroutine write_status_file
end module driver_loop
