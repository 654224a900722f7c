!> Error handling: fatal aborts and input-validation errors.
!!
!! Two kinds of failure exist in MPMICE:
!! * programming or runtime failures (`fatal`): the message is printed by the calling rank on
!!   standard error and the whole job ends with `MPI_Abort`;
!! * input errors (`input_error_text` + `exit_cleanly`): every rank knows the input is bad, rank 0
!!   prints one line naming file, namelist group, variable, value and allowed range, all ranks
!!   finalize MPI and the program exits with status 1 before any output is written.
!!
!! Aborts go through a procedure pointer so that unit tests can replace them by a recorder.
!! base/ sits below parallel/ and does not call MPI itself: `parallel_comm%mpi_start` installs
!! the MPI ends of the abort and of the clean exit (`set_exit_hooks`); before it (and in
!! programs that never call it) both only end the process.
module mpmice_errors
  use, intrinsic :: iso_c_binding, only: c_int
  use, intrinsic :: iso_fortran_env, only: error_unit
  use mpmice_kinds, only: wp, i8, msg_len
  implicit none
  private

  public :: fatal, fatal_handler_t, set_fatal_handler, reset_fatal_handler
  public :: abort_hook_t, finalize_hook_t, set_exit_hooks
  public :: input_error_text, exit_cleanly, real_text, real_short_text, int_text, logical_text

  !> `int_text(n)`: an integer (default or 64-bit) as text.
  interface int_text
    module procedure int_text_default, int_text_i8
  end interface int_text

  abstract interface
    !> Signature of a fatal-error handler.
    subroutine fatal_handler_t(message)
      character(len=*), intent(in) :: message  !< full error message
    end subroutine fatal_handler_t

    !> Signature of the hook that aborts every rank with an exit status (`parallel_comm`).
    subroutine abort_hook_t(code)
      integer, intent(in) :: code  !< exit status
    end subroutine abort_hook_t

    !> Signature of the hook that finalizes MPI before a clean exit (`parallel_comm`).
    subroutine finalize_hook_t()
    end subroutine finalize_hook_t
  end interface

  !> Module state (allowed exception): the active fatal handler, replaced only by unit tests.
  procedure(fatal_handler_t), pointer :: active_handler => null()
  !> Module state (allowed exception, like the communicator it stands for): the MPI ends of
  !! `fatal` and `exit_cleanly`, installed once by `parallel_comm%mpi_start`.
  procedure(abort_hook_t), pointer :: abort_hook => null()
  procedure(finalize_hook_t), pointer :: finalize_hook => null()

  interface
    !> C library exit(), used to leave with a status code without a compiler STOP banner.
    subroutine c_exit(status) bind(c, name='exit')
      import :: c_int
      integer(c_int), value :: status
    end subroutine c_exit
  end interface

contains

  !> Stop the whole run: message (with source location when given) on standard error, then
  !! `MPI_Abort` with error code 2, or the installed test handler.
  subroutine fatal(message, file, line)
    character(len=*), intent(in) :: message        !< what went wrong
    character(len=*), intent(in), optional :: file !< source file (use __FILE__ in .F90)
    integer, intent(in), optional :: line          !< source line (use __LINE__ in .F90)
    character(len=msg_len) :: full
    if (present(file) .and. present(line)) then
      write(full, '(a,a,a,a,i0,a)') 'mpmice: error: ', trim(message), ' (', trim(file), line, ')'
    else
      full = 'mpmice: error: ' // trim(message)
    end if
    if (associated(active_handler)) then
      call active_handler(trim(full))
    else
      call default_fatal(trim(full))
    end if
  end subroutine fatal

  !> Default handler: print and abort every rank (the abort hook, when installed).
  subroutine default_fatal(message)
    character(len=*), intent(in) :: message  !< full error message
    write(error_unit, '(a)') message
    flush(error_unit)
    if (associated(abort_hook)) call abort_hook(2)
    call c_exit(2_c_int)
  end subroutine default_fatal

  !> Install the MPI ends of `fatal` (abort every rank) and `exit_cleanly` (finalize); each
  !! does nothing unless MPI runs.
  subroutine set_exit_hooks(abort, finalize)
    procedure(abort_hook_t) :: abort        !< aborts every rank with the given status
    procedure(finalize_hook_t) :: finalize  !< finalizes MPI
    abort_hook => abort
    finalize_hook => finalize
  end subroutine set_exit_hooks

  !> Install a handler for fatal errors (unit tests use this to record instead of aborting).
  subroutine set_fatal_handler(handler)
    procedure(fatal_handler_t) :: handler  !< replacement handler
    active_handler => handler
  end subroutine set_fatal_handler

  !> Restore the default abort behaviour.
  subroutine reset_fatal_handler()
    active_handler => null()
  end subroutine reset_fatal_handler

  !> The one-line text of an input error:
  !! `mpmice: input error: FILE: &GROUP VARIABLE = VALUE: ALLOWED`.
  pure function input_error_text(file, group, variable, value, allowed) result(text)
    character(len=*), intent(in) :: file      !< namelist file (or `--set`)
    character(len=*), intent(in) :: group     !< namelist group without `&`
    character(len=*), intent(in) :: variable  !< variable name
    character(len=*), intent(in) :: value     !< offending value as text
    character(len=*), intent(in) :: allowed   !< allowed range or values
    character(len=:), allocatable :: text
    text = 'mpmice: input error: ' // trim(file) // ': &' // trim(group) // ' ' // trim(variable) &
      // ' = ' // trim(adjustl(value)) // ': ' // trim(allowed)
  end function input_error_text

  !> Finalize MPI (if running: the finalize hook) and exit the process with `status`, printing
  !! nothing. Collective: every rank must call it.
  subroutine exit_cleanly(status)
    integer, intent(in) :: status  !< process exit status
    flush(error_unit)
    if (associated(finalize_hook)) call finalize_hook()
    call c_exit(int(status, c_int))
  end subroutine exit_cleanly

  !> A real as compact text (for messages).
  pure function real_text(x) result(text)
    real(wp), intent(in) :: x  !< value
    character(len=:), allocatable :: text
    text = formatted_real(x, '(g0)')
  end function real_text

  !> A real with 6 significant digits (for log lines; `real_text` keeps every digit).
  pure function real_short_text(x) result(text)
    real(wp), intent(in) :: x  !< value
    character(len=:), allocatable :: text
    text = formatted_real(x, '(1pg13.6)')
  end function real_short_text

  !> A real written with the edit descriptor `form`, without the blanks around it.
  pure function formatted_real(x, form) result(text)
    real(wp), intent(in) :: x             !< value
    character(len=*), intent(in) :: form  !< format, e.g. '(g0)'
    character(len=:), allocatable :: text
    character(len=32) :: buffer
    write(buffer, form) x
    text = trim(adjustl(buffer))
  end function formatted_real

  !> An integer as text (for messages).
  pure function int_text_default(n) result(text)
    integer, intent(in) :: n  !< value
    character(len=:), allocatable :: text
    text = int_text_i8(int(n, i8))
  end function int_text_default

  !> A 64-bit integer as text (for messages).
  pure function int_text_i8(n) result(text)
    integer(i8), intent(in) :: n  !< value
    character(len=:), allocatable :: text
    character(len=24) :: buffer
    write(buffer, '(i0)') n
    text = trim(buffer)
  end function int_text_i8

  !> A logical as namelist text.
  pure function logical_text(flag) result(text)
    logical, intent(in) :: flag  !< value
    character(len=:), allocatable :: text
    if (flag) then
      text = '.true.'
    else
      text = '.false.'
    end if
  end function logical_text
end module mpmice_errors
