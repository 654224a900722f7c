!> Root-only logging to standard output.
!!
!! Only rank 0 of the run's communicator prints. The rank flag and verbosity are the module's only
!! state (allowed exception: every routine of the program logs, and passing a logger through every
!! call would obscure the physics interfaces).
module mpmice_log
  use, intrinsic :: iso_fortran_env, only: output_unit, error_unit
  implicit none
  private

  public :: log_init, log_info, log_warning, log_debug, log_is_root, log_set_verbosity

  !> Module state (allowed exception): true on the rank that prints.
  logical :: is_root = .true.
  !> Module state (allowed exception): 0 quiet, 1 normal, 2 debug.
  integer :: verbosity = 1

contains

  !> Set which rank prints (call once after MPI start-up with `rank == 0`).
  subroutine log_init(root)
    logical, intent(in) :: root  !< this rank prints
    is_root = root
  end subroutine log_init

  !> Set the verbosity: 0 quiet, 1 normal, 2 debug.
  subroutine log_set_verbosity(level)
    integer, intent(in) :: level  !< new verbosity
    verbosity = level
  end subroutine log_set_verbosity

  !> True on the printing rank.
  logical function log_is_root()
    log_is_root = is_root
  end function log_is_root

  !> An informational line (rank 0, verbosity >= 1).
  subroutine log_info(message)
    character(len=*), intent(in) :: message  !< text to print
    if (is_root .and. verbosity >= 1) then
      write(output_unit, '(a)') trim(message)
      flush(output_unit)
    end if
  end subroutine log_info

  !> A warning line on standard error (rank 0).
  subroutine log_warning(message)
    character(len=*), intent(in) :: message  !< text to print
    if (is_root) then
      write(error_unit, '(a)') 'mpmice: warning: ' // trim(message)
      flush(error_unit)
    end if
  end subroutine log_warning

  !> A debug line (rank 0, verbosity >= 2).
  subroutine log_debug(message)
    character(len=*), intent(in) :: message  !< text to print
    if (is_root .and. verbosity >= 2) then
      write(output_unit, '(a)') trim(message)
      flush(output_unit)
    end if
  end subroutine log_debug
end module mpmice_log
