!> Wall-clock timers per pipeline stage, with an end-of-run summary (rank 0 prints).
!! With the environment variable MPMICE_CPU_TIMERS=1 the stages measure the process's CPU time
!! (user + system, Fortran `cpu_time`) instead: on a machine shared with other jobs the wall
!! time of a stage includes the time the process waited for a core, its CPU time does not.
!!
!! Stages are registered once (`timer_register` returns an id) and timed with `timer_start` /
!! `timer_stop`; nothing is allocated after registration. The summary (`timer_table`, given the
!! ranks' maxima and sums by `parallel_timers%timer_summary`) reports, per stage, the number of
!! calls and the maximum and mean total time over ranks.
module mpmice_timers
  use mpmice_kinds, only: wp, i8, name_len
  use mpmice_errors, only: fatal
  use mpmice_log, only: log_info
  implicit none
  private

  public :: timer_set_t, timer_register, timer_start, timer_stop, timer_total, timer_calls, &
    timer_table, wall_clock_s, max_stages

  integer, parameter :: max_stages = 48  !< capacity of a timer set

  !> A set of named stage timers.
  type :: timer_set_t
    integer :: nstages = 0                         !< registered stages
    character(len=name_len) :: names(max_stages) = ''  !< stage names
    real(wp) :: total_s(max_stages) = 0.0_wp       !< accumulated wall time [s]
    real(wp) :: started_s(max_stages) = -1.0_wp    !< start time of a running stage [s], -1 idle
    integer :: calls(max_stages) = 0               !< completed start/stop pairs
    logical :: cpu = .false.                       !< CPU time instead of wall time
  end type timer_set_t

contains

  !> Register a stage (or find it if already registered) and return its id.
  function timer_register(timers, name) result(id)
    type(timer_set_t), intent(inout) :: timers  !< timer set
    character(len=*), intent(in) :: name        !< stage name
    integer :: id, length, status
    character(len=8) :: value
    do id = 1, timers%nstages
      if (timers%names(id) == name) return
    end do
    if (timers%nstages == max_stages) call fatal('timer_register: too many stages')
    if (timers%nstages == 0) then
      call get_environment_variable('MPMICE_CPU_TIMERS', value, length, status)
      timers%cpu = status == 0 .and. length > 0 .and. value /= '0'
    end if
    timers%nstages = timers%nstages + 1
    id = timers%nstages
    timers%names(id) = name
  end function timer_register

  !> Start timing stage `id`.
  subroutine timer_start(timers, id)
    type(timer_set_t), intent(inout) :: timers  !< timer set
    integer, intent(in) :: id                   !< stage id from timer_register
    timers%started_s(id) = clock_s(timers)
  end subroutine timer_start

  !> Stop timing stage `id` and accumulate the elapsed time.
  subroutine timer_stop(timers, id)
    type(timer_set_t), intent(inout) :: timers  !< timer set
    integer, intent(in) :: id                   !< stage id from timer_register
    if (timers%started_s(id) < 0.0_wp) return
    timers%total_s(id) = timers%total_s(id) + (clock_s(timers) - timers%started_s(id))
    timers%started_s(id) = -1.0_wp
    timers%calls(id) = timers%calls(id) + 1
  end subroutine timer_stop

  !> The clock of the set [s]: wall time, or the process's CPU time (`timers%cpu`).
  function clock_s(timers) result(seconds)
    type(timer_set_t), intent(in) :: timers  !< timer set
    real(wp) :: seconds
    if (timers%cpu) then
      call cpu_time(seconds)
    else
      seconds = wall_clock_s()
    end if
  end function clock_s

  !> Wall clock of this process [s] (monotonic, from an arbitrary origin).
  function wall_clock_s() result(seconds)
    real(wp) :: seconds
    integer(i8) :: count, rate
    call system_clock(count, rate)
    seconds = real(count, wp) / real(rate, wp)
  end function wall_clock_s

  !> Accumulated time [s] of stage `id` on this rank.
  pure function timer_total(timers, id) result(seconds)
    type(timer_set_t), intent(in) :: timers  !< timer set
    integer, intent(in) :: id                !< stage id
    real(wp) :: seconds
    seconds = timers%total_s(id)
  end function timer_total

  !> Completed calls of stage `id`.
  pure function timer_calls(timers, id) result(n)
    type(timer_set_t), intent(in) :: timers  !< timer set
    integer, intent(in) :: id                !< stage id
    integer :: n
    n = timers%calls(id)
  end function timer_calls

  !> Print the per-stage table (rank 0 prints) from the ranks' maximum `tmax` and sum `tsum` of
  !! each stage's total over `nranks` ranks. `run_s` is the wall time of the whole run used for
  !! the percentage column.
  subroutine timer_table(timers, tmax, tsum, nranks, run_s)
    type(timer_set_t), intent(in) :: timers  !< timer set (same stages on every rank)
    real(wp), intent(in) :: tmax(:)          !< (nstages) largest total over the ranks [s]
    real(wp), intent(in) :: tsum(:)          !< (nstages) sum of the totals over the ranks [s]
    integer, intent(in) :: nranks            !< ranks of the run
    real(wp), intent(in) :: run_s            !< wall time of the run [s]
    integer :: id
    character(len=160) :: line
    if (timers%cpu) then
      call log_info('timers (CPU seconds, MPMICE_CPU_TIMERS; max and mean over ranks)')
    else
      call log_info('timers (wall seconds; max and mean over ranks)')
    end if
    write(line, '(a32, a10, a12, a12, a8, a14)') 'stage', 'calls', 'max [s]', 'mean [s]', '%', &
      'per call [ms]'
    call log_info(line)
    do id = 1, timers%nstages
      write(line, '(a32, i10, f12.4, f12.4, f8.1, f14.4)') adjustr(timers%names(id)(1:32)), &
        timers%calls(id), tmax(id), tsum(id) / real(nranks, wp), &
        100.0_wp * tmax(id) / max(run_s, tiny(1.0_wp)), &
        1000.0_wp * tmax(id) / real(max(timers%calls(id), 1), wp)
      call log_info(line)
    end do
    write(line, '(a32, 10x, f12.4)') adjustr('total run'), run_s
    call log_info(line)
  end subroutine timer_table
end module mpmice_timers
