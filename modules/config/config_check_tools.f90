!> Building blocks of configuration validation: the error record and range checks that stop at
!! the first problem (each check does nothing once `err%found`).
module config_check_tools
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use mpmice_kinds, only: wp
  use config_text, only: real_repr, reals_repr, ints_repr, quoted, join_names
  implicit none
  private

  public :: config_error_t, set_error, check_real, check_int, check_choice, check_finite, check_nonblank
  public :: occurrence_label

  !> The first problem found in a configuration.
  type :: config_error_t
    logical :: found = .false.                  !< a problem was found
    character(len=:), allocatable :: group      !< group name without `&`
    character(len=:), allocatable :: variable   !< variable name
    character(len=:), allocatable :: value      !< offending value as namelist text
    character(len=:), allocatable :: allowed    !< allowed range or values
  end type config_error_t

contains

  !> `group(k)`: the name of occurrence `k` of a repeated group in messages.
  pure function occurrence_label(group, k) result(label)
    character(len=*), intent(in) :: group  !< group name without `&`
    integer, intent(in) :: k               !< occurrence
    character(len=:), allocatable :: label
    character(len=16) :: number
    write(number, '(i0)') k
    label = group // '(' // trim(number) // ')'
  end function occurrence_label

  !> Record a problem.
  subroutine set_error(err, group, variable, value, allowed)
    type(config_error_t), intent(inout) :: err  !< problem record
    character(len=*), intent(in) :: group       !< group name
    character(len=*), intent(in) :: variable    !< variable name
    character(len=*), intent(in) :: value       !< value as text
    character(len=*), intent(in) :: allowed     !< allowed range
    err%found = .true.
    err%group = group
    err%variable = variable
    err%value = value
    err%allowed = allowed
  end subroutine set_error

  !> Check a real scalar: finite and inside the given bounds (`*_open` excludes the bound).
  subroutine check_real(err, group, variable, x, allowed, min_value, max_value, min_open, max_open)
    type(config_error_t), intent(inout) :: err   !< problem record
    character(len=*), intent(in) :: group        !< group name
    character(len=*), intent(in) :: variable     !< variable name
    real(wp), intent(in) :: x                    !< value
    character(len=*), intent(in) :: allowed      !< allowed range as text
    real(wp), intent(in), optional :: min_value  !< lower bound
    real(wp), intent(in), optional :: max_value  !< upper bound
    logical, intent(in), optional :: min_open    !< lower bound excluded
    logical, intent(in), optional :: max_open    !< upper bound excluded
    logical :: ok
    if (err%found) return
    ok = ieee_is_finite(x)
    if (ok .and. present(min_value)) then
      if (present(min_open)) then
        if (min_open) ok = x > min_value
      end if
      ok = ok .and. x >= min_value
    end if
    if (ok .and. present(max_value)) then
      if (present(max_open)) then
        if (max_open) ok = x < max_value
      end if
      ok = ok .and. x <= max_value
    end if
    if (.not. ok) then
      if (ieee_is_finite(x)) then
        call set_error(err, group, variable, real_repr(x), allowed)
      else
        call set_error(err, group, variable, real_repr(x), 'a finite number, ' // allowed)
      end if
    end if
  end subroutine check_real

  !> Check an integer scalar against inclusive bounds.
  subroutine check_int(err, group, variable, n, allowed, min_value, max_value)
    type(config_error_t), intent(inout) :: err  !< problem record
    character(len=*), intent(in) :: group       !< group name
    character(len=*), intent(in) :: variable    !< variable name
    integer, intent(in) :: n                    !< value
    character(len=*), intent(in) :: allowed     !< allowed range as text
    integer, intent(in), optional :: min_value  !< lower bound
    integer, intent(in), optional :: max_value  !< upper bound
    logical :: ok
    if (err%found) return
    ok = .true.
    if (present(min_value)) ok = ok .and. n >= min_value
    if (present(max_value)) ok = ok .and. n <= max_value
    if (.not. ok) call set_error(err, group, variable, ints_repr([n]), allowed)
  end subroutine check_int

  !> Check that `value` (trimmed) is one of `names`.
  subroutine check_choice(err, group, variable, value, names)
    type(config_error_t), intent(inout) :: err  !< problem record
    character(len=*), intent(in) :: group       !< group name
    character(len=*), intent(in) :: variable    !< variable name
    character(len=*), intent(in) :: value       !< value
    character(len=*), intent(in) :: names(:)    !< allowed values
    if (err%found) return
    if (.not. any(names == value)) then
      call set_error(err, group, variable, quoted(value), 'one of ' // join_names(names, ', ', ''))
    end if
  end subroutine check_choice

  !> `value` not blank; `allowed` says what is (the message's allowed part).
  subroutine check_nonblank(err, group, variable, value, allowed)
    type(config_error_t), intent(inout) :: err  !< problem record
    character(len=*), intent(in) :: group       !< group label
    character(len=*), intent(in) :: variable    !< variable name
    character(len=*), intent(in) :: value       !< value
    character(len=*), intent(in) :: allowed     !< what is allowed
    if (err%found) return
    if (len_trim(value) == 0) call set_error(err, group, variable, quoted(value), allowed)
  end subroutine check_nonblank

  !> Every entry of `x` finite.
  subroutine check_finite(err, group, variable, x, unit)
    type(config_error_t), intent(inout) :: err  !< problem record
    character(len=*), intent(in) :: group       !< group label
    character(len=*), intent(in) :: variable    !< variable name
    real(wp), intent(in) :: x(:)                !< values
    character(len=*), intent(in) :: unit        !< unit text, e.g. ' [m]'
    if (err%found) return
    if (.not. all(ieee_is_finite(x))) then
      call set_error(err, group, variable, reals_repr(x), 'finite numbers' // unit)
    end if
  end subroutine check_finite
end module config_check_tools
