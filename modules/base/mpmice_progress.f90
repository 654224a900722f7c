!> Progress line for long runs: step, time, dt, percentage done, wall time and ETA (rank 0 prints).
module mpmice_progress
  use mpmice_kinds, only: wp
  use mpmice_log, only: log_info
  use mpmice_timers, only: wall_clock_s
  implicit none
  private

  public :: progress_t, progress_init, progress_update, progress_elapsed, progress_line

  !> State of the progress reporter.
  type :: progress_t
    real(wp) :: start_s = 0.0_wp       !< wall clock at start [s]
    real(wp) :: last_print_s = 0.0_wp  !< wall clock of the last line [s]
    real(wp) :: interval_s = 10.0_wp   !< wall time between lines [s]; 0 prints every step
    real(wp) :: start_time = 0.0_wp    !< simulated time at start (restarts) [s]
    real(wp) :: end_time = 1.0_wp      !< simulated end time [s]
  end type progress_t

contains

  !> Start the clock.
  subroutine progress_init(progress, interval_s, start_time, end_time)
    type(progress_t), intent(out) :: progress  !< reporter
    real(wp), intent(in) :: interval_s         !< wall time between lines [s]
    real(wp), intent(in) :: start_time         !< simulated time at start [s]
    real(wp), intent(in) :: end_time           !< simulated end time [s]
    progress%start_s = wall_clock_s()
    progress%last_print_s = progress%start_s
    progress%interval_s = interval_s
    progress%start_time = start_time
    progress%end_time = end_time
  end subroutine progress_init

  !> Wall time since progress_init [s].
  function progress_elapsed(progress) result(seconds)
    type(progress_t), intent(in) :: progress  !< reporter
    real(wp) :: seconds
    seconds = wall_clock_s() - progress%start_s
  end function progress_elapsed

  !> Print a progress line if the interval has passed (or `force`).
  subroutine progress_update(progress, step, time, dt, force)
    type(progress_t), intent(inout) :: progress  !< reporter
    integer, intent(in) :: step                  !< step number
    real(wp), intent(in) :: time                 !< simulated time [s]
    real(wp), intent(in) :: dt                   !< last time step [s]
    logical, intent(in), optional :: force       !< print regardless of the interval
    real(wp) :: now
    logical :: print_now
    now = wall_clock_s()
    print_now = now - progress%last_print_s >= progress%interval_s
    if (present(force)) print_now = print_now .or. force
    if (.not. print_now) return
    progress%last_print_s = now
    call log_info(progress_line(progress, step, time, dt, now - progress%start_s))
  end subroutine progress_update

  !> The progress text: `step N  t = .. s  dt = .. s  P%  wall .. s  ETA .. s`.
  pure function progress_line(progress, step, time, dt, wall_s) result(line)
    type(progress_t), intent(in) :: progress  !< reporter
    integer, intent(in) :: step               !< step number
    real(wp), intent(in) :: time              !< simulated time [s]
    real(wp), intent(in) :: dt                !< last time step [s]
    real(wp), intent(in) :: wall_s            !< wall time since start [s]
    character(len=160) :: line
    real(wp) :: fraction, eta_s
    fraction = 1.0_wp
    if (progress%end_time > progress%start_time) then
      fraction = (time - progress%start_time) / (progress%end_time - progress%start_time)
    end if
    fraction = min(max(fraction, 0.0_wp), 1.0_wp)
    eta_s = 0.0_wp
    if (fraction > 0.0_wp) eta_s = wall_s * (1.0_wp - fraction) / fraction
    write(line, '(a,i9,a,es11.4,a,es10.3,a,f6.1,a,f10.1,a,f10.1,a)') 'step ', step, '  t = ', time, &
      ' s  dt = ', dt, ' s  ', 100.0_wp * fraction, '%  wall ', wall_s, ' s  ETA ', eta_s, ' s'
  end function progress_line
end module mpmice_progress
