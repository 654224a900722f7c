!> The C library calls the output layer needs and Fortran 2008 lacks: `mkdir`, `access`,
!! `rename`, `unlink`, `setenv`, and the reason of a failure (`errno` through glibc's and musl's
!! `__errno_location`, its text through `strerror`). One set of interfaces for `io_files`,
!! `io_paths` and `io_write_failure`.
module io_posix
  use, intrinsic :: iso_c_binding, only: c_char, c_int, c_ptr, c_null_char, c_associated, &
    c_f_pointer
  implicit none
  private

  public :: c_mkdir, c_access, c_rename, c_unlink, c_setenv
  public :: posix_errno, posix_error_text, c_string

  interface
    !> `int mkdir(const char *path, mode_t mode)` (mode_t is a 32-bit unsigned int on Linux).
    function c_mkdir(path, mode) result(status) bind(c, name='mkdir')
      import :: c_char, c_int
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int), value :: mode
      integer(c_int) :: status
    end function c_mkdir

    !> `int access(const char *path, int mode)`.
    function c_access(path, mode) result(status) bind(c, name='access')
      import :: c_char, c_int
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int), value :: mode
      integer(c_int) :: status
    end function c_access

    !> `int rename(const char *old, const char *new)`.
    function c_rename(old, new) result(status) bind(c, name='rename')
      import :: c_char, c_int
      character(kind=c_char), intent(in) :: old(*)
      character(kind=c_char), intent(in) :: new(*)
      integer(c_int) :: status
    end function c_rename

    !> `int unlink(const char *path)`.
    function c_unlink(path) result(status) bind(c, name='unlink')
      import :: c_char, c_int
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int) :: status
    end function c_unlink

    !> `int setenv(const char *name, const char *value, int overwrite)`.
    function c_setenv(name, value, overwrite) result(status) bind(c, name='setenv')
      import :: c_char, c_int
      character(kind=c_char), intent(in) :: name(*)
      character(kind=c_char), intent(in) :: value(*)
      integer(c_int), value :: overwrite
      integer(c_int) :: status
    end function c_setenv

    !> `int *__errno_location(void)`: the calling thread's `errno`.
    function c_errno_location() result(location) bind(c, name='__errno_location')
      import :: c_ptr
      type(c_ptr) :: location
    end function c_errno_location

    !> `char *strerror(int errnum)`.
    function c_strerror(errnum) result(text) bind(c, name='strerror')
      import :: c_int, c_ptr
      integer(c_int), value :: errnum
      type(c_ptr) :: text
    end function c_strerror
  end interface

contains

  !> The current errno of the calling thread (read it right after the failing call; 0 unknown).
  function posix_errno() result(code)
    integer :: code
    integer(c_int), pointer :: errno_value
    type(c_ptr) :: p
    code = 0
    p = c_errno_location()
    if (.not. c_associated(p)) return
    call c_f_pointer(p, errno_value)
    code = int(errno_value)
  end function posix_errno

  !> strerror(code) as Fortran text ('' for code 0 or when the C library gives none).
  function posix_error_text(code) result(text)
    integer, intent(in) :: code  !< errno value
    character(len=:), allocatable :: text
    character(kind=c_char), pointer :: chars(:)
    type(c_ptr) :: p
    integer :: n, k
    text = ''
    if (code == 0) return
    p = c_strerror(int(code, c_int))
    if (.not. c_associated(p)) return
    call c_f_pointer(p, chars, [1024])
    n = 0
    do while (n < 1024)
      if (chars(n + 1) == c_null_char) exit
      n = n + 1
    end do
    text = repeat(' ', n)
    do k = 1, n
      text(k:k) = chars(k)
    end do
  end function posix_error_text

  !> A Fortran string as a NUL-terminated C character array.
  pure function c_string(text) result(cs)
    character(len=*), intent(in) :: text  !< text without trailing NUL
    character(kind=c_char) :: cs(len(text) + 1)
    integer :: i
    do i = 1, len(text)
      cs(i) = text(i:i)
    end do
    cs(len(text) + 1) = c_null_char
  end function c_string
end module io_posix
