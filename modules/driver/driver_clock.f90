!> Simulated-time bookkeeping of a run and its whole time-step policy: time, step, the next time
!! step (Courant number `cfl` handed to the scene's stability limit, `dt_min`/`dt_max`, growth
!! limit, halvings of a rejected step), and the output and checkpoint events the steps are
!! clipped to land on exactly. The run loop asks the clock for each step (`clock_next_dt`),
!! reports a rejected one (`clock_reject`), asks whether a step may still be tried
!! (`clock_refusal`) and accounts for the accepted one (`clock_accept`).
!!
!! The clock is the part of the run state a checkpoint must carry so that a restarted run takes the
!! very same steps (bitwise-identical continuation): `time`, `step`, `dt_next`, `output_index`,
!! `checkpoint_index`.
module driver_clock
  use mpmice_kinds, only: wp, path_len
  use mpmice_errors, only: int_text, real_short_text
  use config_types, only: run_params_t, time_params_t
  implicit none
  private

  public :: clock_t, clock_init, clock_propose_dt, clock_advance, clock_finished, clock_resume
  public :: clock_from_config, clock_next_dt, clock_reject, clock_refusal, clock_accept

  real(wp), parameter :: event_slack = 1.0e-9_wp  !< relative slack for landing on an event time
  !> a gap to the next event below this many proposed steps is taken in two equal steps
  real(wp), parameter :: balance_ratio = 1.5_wp
  integer, parameter :: max_step_retries = 8  !< halvings of dt before a rejected step is fatal
  real(wp), parameter :: retry_factor = 0.5_wp  !< a rejected step is retried with this times dt

  !> Run clock.
  type :: clock_t
    real(wp) :: time = 0.0_wp                 !< simulated time [s]
    integer :: step = 0                       !< steps taken
    real(wp) :: dt = 0.0_wp                   !< last step taken [s]
    real(wp) :: dt_next = 0.0_wp              !< step proposed before event clipping [s]
    real(wp) :: end_time = 0.0_wp             !< simulated end time [s]
    real(wp) :: output_interval = 0.0_wp      !< dump interval [s] (0: none between first and last)
    real(wp) :: checkpoint_interval = 0.0_wp  !< checkpoint interval [s] (0: none)
    integer :: output_index = 0               !< dumps written at interval times so far
    integer :: checkpoint_index = 0           !< checkpoints written at interval times so far
    integer :: max_steps = 0                  !< steps allowed in this invocation (0: no limit)
    integer :: first_step = 0                 !< step number at the start of this invocation
    real(wp) :: dt_max = huge(1.0_wp)         !< largest step [s]
    real(wp) :: dt_growth = 1.1_wp            !< largest ratio of successive proposed steps
    real(wp) :: cfl = 0.5_wp                  !< Courant number of the scenes' stability limits
    real(wp) :: dt_min = 0.0_wp               !< smallest step tried; below it the run fails [s]
    real(wp) :: dt_limit = huge(1.0_wp)       !< stability limit of the step being tried [s]
    real(wp) :: dt_rejected = 0.0_wp          !< last rejected step [s] (0: none this step)
    integer :: retries = 0                    !< rejections of the step being tried
    integer :: rejected = 0                   !< steps rejected (and retried) in this invocation
    real(wp) :: energy_reference = -1.0_wp    !< solids' energy at t = 0 [J] (< 0: not yet set)
    real(wp) :: load_work = 0.0_wp            !< work put in by gravity and loads so far [J]
    real(wp) :: dt_reference = 0.0_wp         !< first step's stability limit [s] (0: not set)
    logical :: output_due = .false.           !< the last step landed on an output time
    logical :: checkpoint_due = .false.       !< the last step landed on a checkpoint time
  end type clock_t

contains

  !> Start a clock at t = 0.
  subroutine clock_init(clock, end_time, output_interval, checkpoint_interval, max_steps, dt_init, &
      dt_max, dt_growth, cfl, dt_min)
    type(clock_t), intent(out) :: clock          !< clock to start
    real(wp), intent(in) :: end_time             !< simulated end time [s]
    real(wp), intent(in) :: output_interval      !< dump interval [s]
    real(wp), intent(in) :: checkpoint_interval  !< checkpoint interval [s]
    integer, intent(in) :: max_steps             !< step limit (0: none)
    real(wp), intent(in) :: dt_init              !< first step [s]
    real(wp), intent(in) :: dt_max               !< largest step [s]
    real(wp), intent(in) :: dt_growth            !< largest ratio of successive steps
    real(wp), intent(in), optional :: cfl        !< Courant number (default 0.5)
    real(wp), intent(in), optional :: dt_min     !< smallest step [s] (default 0)
    clock%end_time = end_time
    clock%output_interval = output_interval
    clock%checkpoint_interval = checkpoint_interval
    clock%max_steps = max_steps
    clock%dt_next = min(dt_init, dt_max)
    clock%dt_max = dt_max
    clock%dt_growth = dt_growth
    if (present(cfl)) clock%cfl = cfl
    if (present(dt_min)) clock%dt_min = dt_min
  end subroutine clock_init

  !> Start a clock at t = 0 with the run's `&run` end, intervals and step limit and its `&time`
  !! step policy.
  subroutine clock_from_config(clock, run, time)
    type(clock_t), intent(out) :: clock       !< clock to start
    type(run_params_t), intent(in) :: run     !< `&run`
    type(time_params_t), intent(in) :: time   !< `&time`
    call clock_init(clock, run%end_time, run%output_interval, run%checkpoint_interval, &
      run%max_steps, time%dt_init, time%dt_max, time%dt_growth, time%cfl, time%dt_min)
  end subroutine clock_from_config

  !> First try of the next step: `dt` [s] from clock_propose_dt for the scene's stability limit
  !! `dt_limit` [s] (huge when none), which the clock keeps for the retries and clock_accept.
  subroutine clock_next_dt(clock, dt_limit, dt)
    type(clock_t), intent(inout) :: clock  !< run clock
    real(wp), intent(in) :: dt_limit       !< scene stability limit [s]
    real(wp), intent(out) :: dt            !< step to try [s]
    clock%dt_limit = dt_limit
    clock%retries = 0
    clock%dt_rejected = 0.0_wp
    dt = clock_propose_dt(clock, dt_limit)
  end subroutine clock_next_dt

  !> The scene rejected the step `dt` [s]: retry with `retry_factor` dt, which also bounds the
  !! stability limit the next step grows from.
  subroutine clock_reject(clock, dt)
    type(clock_t), intent(inout) :: clock  !< run clock
    real(wp), intent(inout) :: dt          !< rejected step on entry, the retry on exit [s]
    clock%retries = clock%retries + 1
    clock%rejected = clock%rejected + 1
    clock%dt_rejected = dt
    dt = retry_factor * dt
    clock%dt_limit = min(clock%dt_limit, dt)
  end subroutine clock_reject

  !> Why the step `dt` [s] may not be tried: below `dt_min`, or the step was rejected
  !! `max_step_retries + 1` times (every try put back its changes, so a dump shows the last
  !! accepted state); '' when it may be tried.
  function clock_refusal(clock, dt) result(reason)
    type(clock_t), intent(in) :: clock  !< run clock
    real(wp), intent(in) :: dt          !< step to try [s]
    character(len=path_len) :: reason
    reason = ''
    if (dt < clock%dt_min) then
      reason = 'time step ' // real_short_text(dt) // ' s fell below &time dt_min = ' // &
        real_short_text(clock%dt_min) // ' s at t = ' // real_short_text(clock%time) // ' s'
    else if (clock%retries > max_step_retries) then
      reason = 'step ' // int_text(clock%step + 1) // ' rejected ' // &
        int_text(max_step_retries + 1) // ' times, the last at dt = ' // &
        real_short_text(clock%dt_rejected) // ' s, at t = ' // real_short_text(clock%time) // ' s'
    end if
  end function clock_refusal

  !> Account for the accepted step `dt` [s] (clock_advance with the stability limit kept by
  !! clock_next_dt and clock_reject).
  subroutine clock_accept(clock, dt)
    type(clock_t), intent(inout) :: clock  !< run clock
    real(wp), intent(in) :: dt             !< step taken [s]
    call clock_advance(clock, dt, clock%dt_limit)
  end subroutine clock_accept

  !> The next step [s]: the proposed step limited by `dt_limit` (stability limit of the scene, pass
  !! huge when none), then shortened to land exactly on the next output, checkpoint or end time.
  !!
  !! The last two steps before an event are balanced: when a full step would leave less than
  !! half a step to the event (more than round-off), the gap is taken in two equal halves
  !! instead. No step before an event is then shorter than half the proposed one; a step of
  !! 1/30 of the others spiked the pressure of a moving porous body in the dump that followed it
  !! (the per-step solid-fraction relaxation has no time to drain; docs/mpmice.md).
  pure function clock_propose_dt(clock, dt_limit) result(dt)
    type(clock_t), intent(in) :: clock  !< run clock
    real(wp), intent(in) :: dt_limit    !< scene stability limit [s]
    real(wp) :: dt
    real(wp) :: t_event, gap
    dt = min(clock%dt_next, dt_limit)
    t_event = next_event_time(clock)
    gap = t_event - clock%time
    if (dt < gap .and. gap < balance_ratio * dt) then
      if (.not. reached(t_event, clock%time + dt, dt)) dt = 0.5_wp * gap
    end if
    dt = min(dt, gap)
  end function clock_propose_dt

  !> Time of the next event (output, checkpoint or end) after the current time [s].
  pure function next_event_time(clock) result(t_event)
    type(clock_t), intent(in) :: clock  !< run clock
    real(wp) :: t_event
    t_event = clock%end_time
    if (clock%output_interval > 0.0_wp) then
      t_event = min(t_event, real(clock%output_index + 1, wp) * clock%output_interval)
    end if
    if (clock%checkpoint_interval > 0.0_wp) then
      t_event = min(t_event, real(clock%checkpoint_index + 1, wp) * clock%checkpoint_interval)
    end if
  end function next_event_time

  !> Account for a step of `dt` [s] (as returned by clock_propose_dt, possibly reduced by the
  !! scene) whose unclipped value was limited by `dt_limit`; sets `output_due`/`checkpoint_due`.
  subroutine clock_advance(clock, dt, dt_limit)
    type(clock_t), intent(inout) :: clock  !< run clock
    real(wp), intent(in) :: dt             !< step taken [s]
    real(wp), intent(in) :: dt_limit       !< scene stability limit used for this step [s]
    real(wp) :: t_event, unclipped
    t_event = next_event_time(clock)
    unclipped = min(clock%dt_next, dt_limit)
    clock%step = clock%step + 1
    clock%dt = dt
    ! land on the event when the gap left is round-off: relative to the step, or to the time
    ! itself (a fixed dt summed over many steps misses a decimal event time by ~N eps t)
    if (reached(t_event, clock%time + dt, dt)) then
      clock%time = t_event
    else
      clock%time = clock%time + dt
    end if
    ! the end time too: a checkpoint series may land round-off short of it (3 x 0.15 =
    ! 0.45 - 6e-17 s), which left a last step of 6e-17 s (below dt_min: the run failed at its end)
    if (reached(clock%end_time, clock%time, dt)) clock%time = max(clock%time, clock%end_time)
    ! an event counts as reached within the same round-off: the output and checkpoint series
    ! hit "the same" time by different products (60 x 0.01 = 0.6 but 6 x 0.1 = 0.6 + 1e-16),
    ! which left a step of 1e-16 s to the second one (below dt_min: the run stopped)
    clock%output_due = .false.
    clock%checkpoint_due = .false.
    if (clock%output_interval > 0.0_wp) then
      if (reached(real(clock%output_index + 1, wp) * clock%output_interval, clock%time, dt)) then
        clock%output_index = clock%output_index + 1
        clock%output_due = .true.
      end if
    end if
    if (clock%checkpoint_interval > 0.0_wp) then
      if (reached(real(clock%checkpoint_index + 1, wp) * clock%checkpoint_interval, &
        clock%time, dt)) then
        clock%checkpoint_index = clock%checkpoint_index + 1
        clock%checkpoint_due = .true.
      end if
    end if
    ! Grow from the step the scene allowed, not from an event-clipped one.
    clock%dt_next = min(clock%dt_max, clock%dt_growth * max(unclipped, dt))
    if (dt < unclipped) clock%dt_next = min(clock%dt_next, unclipped)
  end subroutine clock_advance

  !> True when `time` [s], reached by a step of `dt` [s], is at or past `t_event` [s] up to
  !! round-off (relative to the step, or to the time itself).
  pure logical function reached(t_event, time, dt)
    real(wp), intent(in) :: t_event  !< event time [s]
    real(wp), intent(in) :: time     !< time [s]
    real(wp), intent(in) :: dt       !< the step that led there [s]
    reached = t_event - time <= max(event_slack * dt, 1.0e-12_wp * abs(t_event))
  end function reached

  !> After a restart: the output and checkpoint counters of the checkpoint count events of the
  !! intervals it was written with; where `--set` changed an interval they are recounted from the
  !! current time (the next event is the first multiple of the new interval after it), so that
  !! the next event lies ahead (a dump interval cut from 0.05 to 0.001 s at t = 0.5 s asked for
  !! the dump at 0.006 s: a negative step). Unchanged intervals keep their counters (the
  !! continuation stays bitwise identical).
  pure subroutine clock_resume(clock)
    type(clock_t), intent(inout) :: clock  !< clock read from a checkpoint, intervals set anew
    clock%output_index = resumed_index(clock%output_index, clock%output_interval, clock%time)
    clock%checkpoint_index = resumed_index(clock%checkpoint_index, clock%checkpoint_interval, &
      clock%time)
  end subroutine clock_resume

  !> Event counter `index` of `interval` [s] checked against `time` [s]: kept when the next event
  !! lies ahead and the last one not, else the number of whole intervals up to `time`.
  pure integer function resumed_index(index, interval, time) result(resumed)
    integer, intent(in) :: index      !< counter from the checkpoint
    real(wp), intent(in) :: interval  !< event interval [s] (0: none)
    real(wp), intent(in) :: time      !< current time [s]
    resumed = index
    if (interval <= 0.0_wp) return
    if (real(index + 1, wp) * interval > time .and. &
      real(index, wp) * interval <= time * (1.0_wp + event_slack)) return
    resumed = floor(time / interval * (1.0_wp + event_slack))
  end function resumed_index

  !> True when the end time or this invocation's step limit is reached.
  pure function clock_finished(clock) result(finished)
    type(clock_t), intent(in) :: clock  !< run clock
    logical :: finished
    finished = clock%time >= clock%end_time
    if (clock%max_steps > 0) then
      finished = finished .or. clock%step - clock%first_step >= clock%max_steps
    end if
  end function clock_finished
end module driver_clock
