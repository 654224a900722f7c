!> Text helpers for the configuration: values as namelist text and small string utilities.
!!
!! Reals are written with the fewest significant digits that read back to the same value, so a
!! configuration written as text and read again is bitwise identical.
module config_text
  use, intrinsic :: ieee_arithmetic, only: ieee_is_nan, ieee_is_finite
  use, intrinsic :: ieee_exceptions, only: ieee_get_halting_mode, ieee_set_halting_mode, &
    ieee_get_flag, ieee_set_flag, ieee_overflow, ieee_underflow, ieee_flag_type
  use mpmice_kinds, only: wp
  implicit none
  private

  public :: real_repr, reals_repr, ints_repr, logicals_repr, quoted, unquoted, lower_case
  public :: is_identifier_char, join_names, replaced

contains

  !> Shortest namelist text of `x` that reads back to exactly `x` (e.g. `300.0`, `1.0e-12`).
  function real_repr(x) result(text)
    real(wp), intent(in) :: x  !< value
    character(len=:), allocatable :: text
    character(len=40) :: buffer, fmt
    character(len=20) :: digits
    real(wp) :: y
    integer :: d, ios, epos, expo, ndig, k
    logical :: negative, halting(2), flags(2)
    type(ieee_flag_type), parameter :: traps(2) = [ieee_overflow, ieee_underflow]

    if (ieee_is_nan(x)) then
      text = 'NaN'
      return
    else if (.not. ieee_is_finite(x)) then
      if (x > 0.0_wp) then
        text = 'Infinity'
      else
        text = '-Infinity'
      end if
      return
    else if (x == 0.0_wp) then
      text = '0.0'
      return
    end if

    ! reading a rounded value near huge() overflows: no trap while searching
    call ieee_get_halting_mode(traps, halting)
    call ieee_get_flag(traps, flags)
    call ieee_set_halting_mode(traps, .false.)
    do d = 1, 17
      write(fmt, '(a,i0,a)') '(es30.', d - 1, 'e4)'
      write(buffer, fmt) x
      read(buffer, *, iostat=ios) y
      if (ios == 0 .and. y == x) exit
    end do
    call ieee_set_flag(traps, flags)
    call ieee_set_halting_mode(traps, halting)
    ! buffer holds [-]D.DDDDE+XXXX: collect the digits and the decimal exponent of the first one
    buffer = adjustl(buffer)
    negative = buffer(1:1) == '-'
    epos = index(buffer, 'E')
    read(buffer(epos + 1:), *) expo
    digits = ''
    ndig = 0
    do k = 1, epos - 1
      if (buffer(k:k) >= '0' .and. buffer(k:k) <= '9') then
        ndig = ndig + 1
        digits(ndig:ndig) = buffer(k:k)
      end if
    end do
    do while (ndig > 1 .and. digits(ndig:ndig) == '0')
      ndig = ndig - 1
    end do

    if (expo >= 0 .and. expo < 15) then
      if (ndig > expo + 1) then
        text = digits(1:expo + 1) // '.' // digits(expo + 2:ndig)
      else
        text = digits(1:ndig) // repeat('0', expo + 1 - ndig) // '.0'
      end if
    else if (expo < 0 .and. expo >= -4) then
      text = '0.' // repeat('0', -expo - 1) // digits(1:ndig)
    else
      if (ndig > 1) then
        text = digits(1:1) // '.' // digits(2:ndig)
      else
        text = digits(1:1) // '.0'
      end if
      write(buffer, '(i0)') expo
      text = text // 'e' // trim(buffer)
    end if
    if (negative) text = '-' // text
  end function real_repr

  !> Comma-separated `real_repr` of each entry.
  function reals_repr(x) result(text)
    real(wp), intent(in) :: x(:)  !< values
    character(len=:), allocatable :: text
    integer :: i
    text = ''
    do i = 1, size(x)
      if (i > 1) text = text // ', '
      text = text // real_repr(x(i))
    end do
  end function reals_repr

  !> Comma-separated integers.
  function ints_repr(n) result(text)
    integer, intent(in) :: n(:)  !< values
    character(len=:), allocatable :: text
    character(len=16) :: buffer
    integer :: i
    text = ''
    do i = 1, size(n)
      if (i > 1) text = text // ', '
      write(buffer, '(i0)') n(i)
      text = text // trim(buffer)
    end do
  end function ints_repr

  !> Comma-separated logicals as `.true.`/`.false.`.
  function logicals_repr(flags) result(text)
    logical, intent(in) :: flags(:)  !< values
    character(len=:), allocatable :: text
    integer :: i
    text = ''
    do i = 1, size(flags)
      if (i > 1) text = text // ', '
      if (flags(i)) then
        text = text // '.true.'
      else
        text = text // '.false.'
      end if
    end do
  end function logicals_repr

  !> `s` (trailing blanks removed) between apostrophes, inner apostrophes doubled.
  function quoted(s) result(text)
    character(len=*), intent(in) :: s  !< string
    character(len=:), allocatable :: text
    text = "'" // replaced(s(1:len_trim(s)), "'", "''") // "'"
  end function quoted

  !> `s` with every character `from` replaced by the text `to`.
  pure function replaced(s, from, to) result(text)
    character(len=*), intent(in) :: s     !< string
    character(len=1), intent(in) :: from  !< character to replace
    character(len=*), intent(in) :: to    !< its replacement
    character(len=:), allocatable :: text
    integer :: i
    text = ''
    do i = 1, len(s)
      if (s(i:i) == from) then
        text = text // to
      else
        text = text // s(i:i)
      end if
    end do
  end function replaced

  !> The content of a namelist string constant `'...'` or `"..."` (doubled quotes undone).
  !! `ok` is false when `s` is not exactly one delimited string.
  subroutine unquoted(s, content, ok)
    character(len=*), intent(in) :: s                     !< trimmed value text
    character(len=:), allocatable, intent(out) :: content !< string content
    logical, intent(out) :: ok                            !< `s` is one well-formed string
    character :: q
    integer :: i, n
    content = ''
    ok = .false.
    n = len_trim(s)
    if (n < 2) return
    q = s(1:1)
    if (q /= "'" .and. q /= '"') return
    i = 2
    do while (i <= n)
      if (s(i:i) == q) then
        if (i == n) then
          ok = .true.
          return
        else if (s(i + 1:i + 1) == q) then
          content = content // q
          i = i + 2
        else
          return
        end if
      else
        content = content // s(i:i)
        i = i + 1
      end if
    end do
  end subroutine unquoted

  !> `s` with ASCII upper-case letters turned to lower case.
  pure function lower_case(s) result(text)
    character(len=*), intent(in) :: s  !< string
    character(len=len(s)) :: text
    integer :: i, c
    text = s
    do i = 1, len(s)
      c = iachar(s(i:i))
      if (c >= iachar('A') .and. c <= iachar('Z')) text(i:i) = achar(c + 32)
    end do
  end function lower_case

  !> True for a letter, digit or underscore.
  pure logical function is_identifier_char(c)
    character, intent(in) :: c  !< character
    is_identifier_char = (c >= 'a' .and. c <= 'z') .or. (c >= 'A' .and. c <= 'Z') &
      .or. (c >= '0' .and. c <= '9') .or. c == '_'
  end function is_identifier_char

  !> Trimmed entries of `names` joined by `separator`, each prefixed by `prefix`.
  function join_names(names, separator, prefix) result(text)
    character(len=*), intent(in) :: names(:)   !< entries
    character(len=*), intent(in) :: separator  !< text between entries
    character(len=*), intent(in) :: prefix     !< text before each entry
    character(len=:), allocatable :: text
    integer :: i
    text = ''
    do i = 1, size(names)
      if (i > 1) text = text // separator
      text = text // prefix // trim(names(i))
    end do
  end function join_names
end module config_text
