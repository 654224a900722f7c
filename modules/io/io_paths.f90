!> Checks of an output folder before a run writes anything: can it be created and written, and
!! why not (the operating system's reason). Rank 0 calls these; they act on the calling rank.
!!
!! The C library gives `mkdir`, `access` and the reason of a failure (`errno` through glibc's and
!! musl's `__errno_location`, text through `strerror`); Fortran 2008 has neither.
module io_paths
  use, intrinsic :: iso_c_binding, only: c_int
  use io_posix, only: c_mkdir, c_access, c_string, posix_errno, posix_error_text
  use mpmice_errors, only: int_text
  use io_files, only: io_directory_exists, io_file_exists
  implicit none
  private

  public :: io_make_output_directory, io_check_output_directory

  integer, parameter :: name_max = 255            !< longest file-name component (Linux NAME_MAX)
  integer, parameter :: path_max = 4095           !< longest path (Linux PATH_MAX - 1)
  integer(c_int), parameter :: directory_mode = int(o'755', c_int)  !< permissions of new folders
  integer(c_int), parameter :: access_write = 2_c_int               !< `W_OK` of `access(2)`
  integer(c_int), parameter :: access_search = 1_c_int              !< `X_OK` of `access(2)`


contains

  !> Can the folder `path` be used for output? `stat` = 1 and `reason` (one line) when a path
  !! component is too long, a part of the path is a file, or the folder exists but cannot be
  !! written. Creates nothing; a folder that does not exist yet is fine here.
  subroutine io_check_output_directory(path, stat, reason)
    character(len=*), intent(in) :: path                  !< folder (absolute or relative)
    integer, intent(out) :: stat                          !< 0 usable
    character(len=:), allocatable, intent(out) :: reason  !< why not
    character(len=:), allocatable :: full
    integer :: i, start
    logical :: is_file
    stat = 1
    full = trim(path)
    if (len(full) == 0) full = '.'
    if (len(full) > path_max) then
      reason = 'the path is longer than ' // int_text(path_max) // ' characters'
      return
    end if
    start = 1
    do i = 1, len(full) + 1
      if (i <= len(full)) then
        if (full(i:i) /= '/') cycle
      end if
      if (i - start > name_max) then
        reason = 'the path component ''' // full(start:start + 19) // '...'' is longer than ' &
          // int_text(name_max) // ' characters'
        return
      end if
      if (i > 1) then
        ! every existing part of the path must be a folder
        is_file = .false.
        if (io_file_exists(full(1:i - 1))) is_file = .not. io_directory_exists(full(1:i - 1))
        if (is_file) then
          if (i > len(full)) then
            reason = '''' // full // ''' exists and is a file, not a folder'
          else
            reason = '''' // full(1:i - 1) // ''' is a file, not a folder'
          end if
          return
        end if
      end if
      start = i + 1
    end do
    if (io_directory_exists(full)) then
      if (c_access(c_string(full), ior(access_write, access_search)) /= 0_c_int) then
        reason = 'the folder is not writable: ' // last_error()
        return
      end if
    end if
    stat = 0
    reason = ''
  end subroutine io_check_output_directory

  !> Create the folder `path` and its missing parents (`mkdir -p`); an existing folder is fine.
  !! `stat` = 1 and `reason` (the operating system's reason, naming the folder that could not be
  !! created) on failure.
  subroutine io_make_output_directory(path, stat, reason)
    character(len=*), intent(in) :: path                  !< folder (absolute or relative)
    integer, intent(out) :: stat                          !< 0 ok
    character(len=:), allocatable, intent(out) :: reason  !< why not
    character(len=:), allocatable :: full
    integer :: i
    stat = 0
    reason = ''
    full = trim(path)
    if (len(full) == 0) full = '.'
    do i = 2, len(full) + 1
      if (i <= len(full)) then
        if (full(i:i) /= '/' .or. full(i - 1:i - 1) == '/') cycle
      end if
      if (io_directory_exists(full(1:i - 1))) cycle
      if (c_mkdir(c_string(full(1:i - 1)), directory_mode) /= 0_c_int) then
        if (io_directory_exists(full(1:i - 1))) cycle  ! made by someone else meanwhile
        stat = 1
        reason = 'cannot create the folder ''' // full(1:i - 1) // ''': ' // last_error()
        return
      end if
    end do
    if (c_access(c_string(full), ior(access_write, access_search)) /= 0_c_int) then
      stat = 1
      reason = 'the folder is not writable: ' // last_error()
    end if
  end subroutine io_make_output_directory

  !> The C library's text for the current `errno`.
  function last_error() result(text)
    character(len=:), allocatable :: text
    integer :: code
    code = posix_errno()
    text = posix_error_text(code)
    if (len(text) == 0) text = 'error ' // int_text(code)
  end function last_error
end module io_paths
