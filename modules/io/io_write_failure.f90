!> A failed write of an output file (dump, checkpoint): the run ends with one line naming the
!! file and the system's reason (`strerror(errno)`, e.g. "No space left on device"), the partly
!! written file removed, and exit status 3 (a run failure, docs/io.md).
!!
!! The HDF5 layer calls `io_write_failed` when a call on a file open for writing fails; the
!! dump and checkpoint writers write under a temporary name (`.tmp`) and rename, so no partly
!! written file is ever left under a final name. The fault injection
!! `MPMICE_FAULT=enospc_dump_step:N` (`mpmice_faults`, docs/testing.md) makes the dump of step N
!! fail as on a full disk, for tests where no small file system can be mounted.
module io_write_failure
  use, intrinsic :: iso_c_binding, only: c_int, c_null_char
  use io_posix, only: c_unlink, posix_errno, posix_error_text
  use, intrinsic :: iso_fortran_env, only: error_unit, output_unit
  use mpmice_errors, only: int_text
  use parallel_comm, only: world_ranks, abort_world
  implicit none
  private

  public :: io_system_error, io_system_error_text, io_remove_file, io_write_failed, io_check_size
  public :: io_close_checked
  public :: enospc

  integer, parameter :: enospc = 28  !< errno of a full file system (Linux)
  integer, parameter :: enoent = 2   !< errno of a missing file

  interface
    !> POSIX _exit(): end the process without the atexit handlers (HDF5's would close a file
    !! that failed to write through MPI-IO after MPI_Finalize and crash).
    subroutine c_exit(status) bind(c, name='_exit')
      import :: c_int
      integer(c_int), value :: status
    end subroutine c_exit
  end interface

contains

  !> The current errno of the calling thread (read it right after the failing call).
  function io_system_error() result(code)
    integer :: code
    code = posix_errno()
  end function io_system_error

  !> strerror(code) as Fortran text ('' for code 0).
  function io_system_error_text(code) result(text)
    integer, intent(in) :: code  !< errno value
    character(len=:), allocatable :: text
    text = posix_error_text(code)
  end function io_system_error_text

  !> Remove the file `path` if it exists (errors ignored).
  subroutine io_remove_file(path)
    character(len=*), intent(in) :: path  !< file to remove
    integer(c_int) :: status
    status = c_unlink(trim(path) // c_null_char)
  end subroutine io_remove_file

  !> Check the file `path` just closed after writing `expected` bytes: gfortran reports no
  !! error when a write fails for a full disk, so the size on disk tells. Returns `stat` 0 when
  !! complete, else 1 with `reason` (`strerror(errno)`, or 'incomplete write').
  subroutine io_check_size(path, expected, stat, reason)
    character(len=*), intent(in) :: path                   !< file written and closed
    integer, intent(in) :: expected                        !< bytes written
    integer, intent(out) :: stat                           !< 0 complete, 1 not
    character(len=:), allocatable, intent(out) :: reason   !< why not
    integer :: code, nbytes
    code = io_system_error()
    reason = ''
    stat = 0
    inquire(file=path, size=nbytes)
    if (nbytes == expected) return
    stat = 1
    reason = io_system_error_text(code)
    if (code /= enospc .and. code /= 122) reason = ''   ! ENOSPC or EDQUOT, else unknown
    if (len(reason) == 0) reason = 'incomplete write (' // int_text(nbytes) // ' of ' // &
      int_text(expected) // ' bytes)'
    reason = lower_first(reason)
  end subroutine io_check_size

  !> Close the unit `unit`, open for writing `path`, and check that everything written reached
  !! the file (`io_check_size`; gfortran stays silent on a full disk). `stat` 0 when complete,
  !! else 1 with `reason`.
  subroutine io_close_checked(unit, path, stat, reason)
    integer, intent(in) :: unit                            !< open unit
    character(len=*), intent(in) :: path                   !< its file
    integer, intent(out) :: stat                           !< 0 complete, 1 not
    character(len=:), allocatable, intent(out) :: reason   !< why not
    character(len=256) :: iomsg
    integer :: expected, ios, ios_close
    flush(unit, iostat=ios, iomsg=iomsg)
    inquire(unit=unit, size=expected)
    close(unit, iostat=ios_close, iomsg=iomsg)
    if (ios == 0) ios = ios_close
    call io_check_size(path, expected, stat, reason)
    if (stat == 0 .and. ios /= 0) then
      stat = 1
      reason = trim(iomsg)
    end if
  end subroutine io_close_checked

  !> End the run after a failed write of `written` (the temporary file, removed here) meant for
  !! `final` (named in the message): one line on standard error, exit status 3. A run on one rank
  !! exits; on several ranks the others may be inside a collective call, so the job ends with
  !! `MPI_Abort(..., 3)` (the launcher adds its own lines).
  subroutine io_write_failed(written, final, operation, code, message)
    character(len=*), intent(in) :: written    !< file being written (removed)
    character(len=*), intent(in) :: final      !< the file's final name
    character(len=*), intent(in) :: operation  !< the failing operation
    integer, intent(in) :: code                !< errno after the failure (0: unknown)
    character(len=*), intent(in), optional :: message !< the reason as text, instead of `code`
    character(len=:), allocatable :: reason
    integer :: nranks
    flush(output_unit)
    reason = io_system_error_text(code)
    if (present(message)) reason = trim(message)
    if (len(reason) == 0) reason = 'write failed'
    nranks = world_ranks()
    ! on several ranks, a rank that finds the file gone (ENOENT) failed after another removed it
    if (nranks == 1 .or. code /= enoent) then
      write(error_unit, '(a)') 'mpmice: run failed: cannot write ' // trim(final) // ': ' // &
        trim(lower_first(reason)) // ' (' // operation // '); the partial file was removed'
      flush(error_unit)
    end if
    call io_remove_file(written)
    if (nranks > 1) call abort_world(3)
    ! not MPI_Finalize: HDF5 1.10 closes its open files in a finalize callback, and closing the
    ! file that failed crashes there
    call c_exit(3_c_int)
  end subroutine io_write_failed

  !> `text` with its first letter in lower case ("No space" -> "no space").
  pure function lower_first(text) result(lowered)
    character(len=*), intent(in) :: text  !< text
    character(len=len(text)) :: lowered
    lowered = text
    if (len(text) == 0) return
    if (text(1:1) >= 'A' .and. text(1:1) <= 'Z') lowered(1:1) = achar(iachar(text(1:1)) + 32)
  end function lower_first
end module io_write_failure
