!> Batch-system signals: SIGTERM and SIGUSR1 ask the run to write a checkpoint and stop cleanly.
!!
!! The handler only records the signal number; the time loop polls `signal_received` after every
!! step (reduced over ranks, so a signal delivered to one rank stops all of them at the same step).
!! Under `mpirun`, prefer SIGUSR1 (Open MPI forwards it to the ranks; a SIGTERM to mpirun makes it
!! terminate the ranks itself): e.g. Slurm `#SBATCH --signal=USR1@300`.
module mpmice_signals
  use, intrinsic :: iso_c_binding, only: c_int, c_funptr, c_funloc
  implicit none
  private

  public :: signals_install, signal_received, signal_name, sigterm, sigusr1

  integer(c_int), parameter :: sigterm = 15_c_int  !< SIGTERM (POSIX)
  integer(c_int), parameter :: sigusr1 = 10_c_int  !< SIGUSR1 (Linux)

  !> Module state (allowed exception): the last signal received, set asynchronously by the
  !! handler; a signal handler can communicate in no other way.
  integer(c_int), volatile :: last_signal = 0_c_int

  interface
    !> C library signal(): install `handler` for `signum`.
    function c_signal(signum, handler) result(previous) bind(c, name='signal')
      import :: c_int, c_funptr
      integer(c_int), value :: signum
      type(c_funptr), value :: handler
      type(c_funptr) :: previous
    end function c_signal
  end interface

contains

  !> Install the handler for SIGTERM and SIGUSR1.
  subroutine signals_install()
    type(c_funptr) :: previous
    previous = c_signal(sigterm, c_funloc(on_signal))
    previous = c_signal(sigusr1, c_funloc(on_signal))
  end subroutine signals_install

  !> The handler: remember the signal.
  subroutine on_signal(signum) bind(c)
    integer(c_int), value :: signum  !< signal number
    last_signal = signum
  end subroutine on_signal

  !> The last signal received (0: none).
  function signal_received() result(signum)
    integer :: signum
    signum = int(last_signal)
  end function signal_received

  !> Name of a signal number, for messages.
  pure function signal_name(signum) result(name)
    integer, intent(in) :: signum  !< signal number
    character(len=:), allocatable :: name
    select case (signum)
    case (int(sigterm))
      name = 'SIGTERM'
    case (int(sigusr1))
      name = 'SIGUSR1'
    case default
      name = 'signal'
    end select
  end function signal_name
end module mpmice_signals
