!> Root-only logging to standard output (information) and standard error (warnings), each line
!! also copied to the run's log file `<output_dir>/<name>.log` once it is open.
!!
!! Only rank 0 of the run's communicator prints. The rank flag, verbosity and log-file unit are the
!! module's only state (allowed exception: every routine of the program logs, and passing a logger
!! through every call would obscure the physics interfaces).
module mpmice_log
  use, intrinsic :: iso_fortran_env, only: output_unit, error_unit
  implicit none
  private

  public :: log_init, log_info, log_warning, log_debug, log_is_root, log_set_verbosity
  public :: log_open_file, log_close_file

  !> Module state (allowed exception): true on the rank that prints.
  logical :: is_root = .true.
  !> Module state (allowed exception): 0 quiet, 1 normal, 2 debug.
  integer :: verbosity = 1
  !> Module state (allowed exception): unit of the log file on rank 0 and whether it is open.
  integer :: file_unit = 0
  logical :: file_open = .false.

contains

  !> Set which rank prints (call once after MPI start-up with `rank == 0`).
  subroutine log_init(root)
    logical, intent(in) :: root  !< this rank prints
    is_root = root
  end subroutine log_init

  !> Open the log file `path` on rank 0 (a new run replaces it, a restart appends to it so that a
  !! restart chain keeps one log). `stat` /= 0 and `errmsg` say why it could not be opened.
  subroutine log_open_file(path, append, stat, errmsg)
    character(len=*), intent(in) :: path                  !< log file
    logical, intent(in) :: append                         !< continue an existing log
    integer, intent(out) :: stat                          !< 0 ok
    character(len=:), allocatable, intent(out) :: errmsg  !< reason when stat /= 0
    character(len=256) :: iomsg
    stat = 0
    errmsg = ''
    if (.not. is_root) return
    call log_close_file()
    if (append) then
      open(newunit=file_unit, file=path, status='unknown', position='append', action='write', &
        iostat=stat, iomsg=iomsg)
    else
      open(newunit=file_unit, file=path, status='replace', action='write', iostat=stat, &
        iomsg=iomsg)
    end if
    file_open = stat == 0
    if (stat /= 0) errmsg = trim(iomsg)
  end subroutine log_open_file

  !> Close the log file (if open).
  subroutine log_close_file()
    if (file_open) close(file_unit)
    file_open = .false.
  end subroutine log_close_file

  !> Write one line to the log file (if open).
  subroutine to_file(line)
    character(len=*), intent(in) :: line  !< text
    if (.not. file_open) return
    write(file_unit, '(a)') line
    flush(file_unit)
  end subroutine to_file

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
      call to_file(trim(message))
    end if
  end subroutine log_info

  !> A warning line on standard error (rank 0).
  subroutine log_warning(message)
    character(len=*), intent(in) :: message  !< text to print
    if (is_root) then
      write(error_unit, '(a)') 'mpmice: warning: ' // trim(message)
      flush(error_unit)
      call to_file('mpmice: warning: ' // trim(message))
    end if
  end subroutine log_warning

  !> A debug line (rank 0, verbosity >= 2).
  subroutine log_debug(message)
    character(len=*), intent(in) :: message  !< text to print
    if (is_root .and. verbosity >= 2) then
      write(output_unit, '(a)') trim(message)
      flush(output_unit)
      call to_file(trim(message))
    end if
  end subroutine log_debug
end module mpmice_log
