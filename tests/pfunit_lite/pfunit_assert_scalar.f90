!> Scalar assertions of pfunit-lite (pFUnit's names and argument order; the generic interfaces
!! live in module `pfunit`). Equality of reals uses an absolute tolerance (default 0, i.e. exact);
!! a NaN never compares equal.
module pfunit_assert_scalar
  use, intrinsic :: iso_fortran_env, only: real64, int32, int64
  use, intrinsic :: ieee_arithmetic, only: ieee_is_nan, ieee_is_finite
  use pfunit_core, only: SourceLocation, pf_fail, pf_real_text, pf_int_text, pf_logical_text
  implicit none
  private

  public :: assert_equal_i4, assert_equal_i8, assert_equal_i4_i8, assert_equal_r, &
    assert_equal_i4_r, assert_equal_l, assert_equal_c, assert_relatively_equal_r
  public :: assert_true, assert_false, assert_true_1d, assert_false_1d
  public :: assert_less_than_i, assert_less_than_r, assert_less_equal_i, assert_less_equal_r, &
    assert_greater_than_i, assert_greater_than_r, assert_greater_equal_i, assert_greater_equal_r
  public :: assert_is_nan_r, assert_is_finite_r

  integer, parameter :: dp = real64

contains

  !> Fail unless two default integers are equal.
  subroutine assert_equal_i4(expected, actual, message, location)
    integer(int32), intent(in) :: expected                  !< expected value
    integer(int32), intent(in) :: actual                    !< value found
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    call equal_int(int(expected, int64), int(actual, int64), message, location)
  end subroutine assert_equal_i4

  !> Fail unless two 64-bit integers are equal.
  subroutine assert_equal_i8(expected, actual, message, location)
    integer(int64), intent(in) :: expected                  !< expected value
    integer(int64), intent(in) :: actual                    !< value found
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    call equal_int(expected, actual, message, location)
  end subroutine assert_equal_i8

  !> Fail unless a 64-bit integer equals the expected default integer.
  subroutine assert_equal_i4_i8(expected, actual, message, location)
    integer(int32), intent(in) :: expected                  !< expected value
    integer(int64), intent(in) :: actual                    !< value found
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    call equal_int(int(expected, int64), actual, message, location)
  end subroutine assert_equal_i4_i8

  !> Fail unless two integers (widened to 64 bits) are equal.
  subroutine equal_int(expected, actual, message, location)
    integer(int64), intent(in) :: expected                  !< expected value
    integer(int64), intent(in) :: actual                    !< value found
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    if (expected /= actual) then
      call pf_fail('assertEqual', 'expected: ' // pf_int_text(expected) // ', actual: ' &
        // pf_int_text(actual), message, location)
    end if
  end subroutine equal_int

  !> Fail unless |expected - actual| <= tolerance (absolute; default 0).
  subroutine assert_equal_r(expected, actual, tolerance, message, location)
    real(dp), intent(in) :: expected                        !< expected value
    real(dp), intent(in) :: actual                          !< value found
    real(dp), intent(in), optional :: tolerance             !< absolute tolerance
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    real(dp) :: tol
    logical :: ok
    tol = 0.0_dp
    if (present(tolerance)) tol = tolerance
    ok = .not. (ieee_is_nan(expected) .or. ieee_is_nan(actual))
    if (ok) ok = abs(expected - actual) <= tol
    if (.not. ok) then
      call pf_fail('assertEqual', 'expected: ' // pf_real_text(expected) // ', actual: ' &
        // pf_real_text(actual) // ', |difference|: ' // pf_real_text(abs(expected - actual)) &
        // ' > tolerance ' // pf_real_text(tol), message, location)
    end if
  end subroutine assert_equal_r

  !> Fail unless a real is within `tolerance` of an expected integer.
  subroutine assert_equal_i4_r(expected, actual, tolerance, message, location)
    integer(int32), intent(in) :: expected                  !< expected value
    real(dp), intent(in) :: actual                          !< value found
    real(dp), intent(in), optional :: tolerance             !< absolute tolerance
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    call assert_equal_r(real(expected, dp), actual, tolerance, message, location)
  end subroutine assert_equal_i4_r

  !> Fail unless two logicals are equal.
  subroutine assert_equal_l(expected, actual, message, location)
    logical, intent(in) :: expected                         !< expected value
    logical, intent(in) :: actual                           !< value found
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    if (expected .neqv. actual) then
      call pf_fail('assertEqual', 'expected: ' // pf_logical_text(expected) // ', actual: ' &
        // pf_logical_text(actual), message, location)
    end if
  end subroutine assert_equal_l

  !> Fail unless two strings are equal (trailing blanks ignored, as Fortran's `==`).
  subroutine assert_equal_c(expected, actual, message, location)
    character(len=*), intent(in) :: expected                !< expected text
    character(len=*), intent(in) :: actual                  !< text found
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    if (expected /= actual) then
      call pf_fail('assertEqual', 'expected: "' // trim(expected) // '"' // new_line('a') &
        // '    actual:   "' // trim(actual) // '"', message, location)
    end if
  end subroutine assert_equal_c

  !> Fail unless |expected - actual| <= tolerance * |expected| (relative tolerance).
  subroutine assert_relatively_equal_r(expected, actual, tolerance, message, location)
    real(dp), intent(in) :: expected                        !< expected value
    real(dp), intent(in) :: actual                          !< value found
    real(dp), intent(in) :: tolerance                       !< relative tolerance
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    logical :: ok
    ok = .not. (ieee_is_nan(expected) .or. ieee_is_nan(actual))
    if (ok) ok = abs(expected - actual) <= tolerance * abs(expected)
    if (.not. ok) then
      call pf_fail('assertRelativelyEqual', 'expected: ' // pf_real_text(expected) &
        // ', actual: ' // pf_real_text(actual) // ', |difference|: ' &
        // pf_real_text(abs(expected - actual)) // ' > tolerance * |expected| = ' &
        // pf_real_text(tolerance * abs(expected)), message, location)
    end if
  end subroutine assert_relatively_equal_r

  !> Fail unless `condition` is true.
  subroutine assert_true(condition, message, location)
    logical, intent(in) :: condition                        !< condition to check
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    if (.not. condition) call pf_fail('assertTrue', 'expected: .true., actual: .false.', &
      message, location)
  end subroutine assert_true

  !> Fail unless `condition` is false.
  subroutine assert_false(condition, message, location)
    logical, intent(in) :: condition                        !< condition to check
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    if (condition) call pf_fail('assertFalse', 'expected: .false., actual: .true.', &
      message, location)
  end subroutine assert_false

  !> Fail unless every element of `conditions` is true.
  subroutine assert_true_1d(conditions, message, location)
    logical, intent(in) :: conditions(:)                    !< conditions to check
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    if (.not. all(conditions)) call pf_fail('assertTrue', pf_int_text(int(count(.not. &
      conditions), int64)) // ' of ' // pf_int_text(int(size(conditions), int64)) &
      // ' elements are .false.; first at ' // pf_int_text(int(findloc(conditions, .false., &
      dim=1), int64)), message, location)
  end subroutine assert_true_1d

  !> Fail unless every element of `conditions` is false.
  subroutine assert_false_1d(conditions, message, location)
    logical, intent(in) :: conditions(:)                    !< conditions to check
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    if (any(conditions)) call pf_fail('assertFalse', pf_int_text(int(count(conditions), &
      int64)) // ' of ' // pf_int_text(int(size(conditions), int64)) &
      // ' elements are .true.; first at ' // pf_int_text(int(findloc(conditions, .true., &
      dim=1), int64)), message, location)
  end subroutine assert_false_1d

  !> Report a failed ordering between two integers.
  subroutine order_fail_i(name, relation, a, b, message, location)
    character(len=*), intent(in) :: name                    !< assertion name
    character(len=*), intent(in) :: relation                !< relation that should hold
    integer(int64), intent(in) :: a                         !< left operand
    integer(int64), intent(in) :: b                         !< right operand
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    call pf_fail(name, 'expected ' // pf_int_text(a) // ' ' // relation // ' ' // pf_int_text(b), &
      message, location)
  end subroutine order_fail_i

  !> Report a failed ordering between two reals.
  subroutine order_fail_r(name, relation, a, b, message, location)
    character(len=*), intent(in) :: name                    !< assertion name
    character(len=*), intent(in) :: relation                !< relation that should hold
    real(dp), intent(in) :: a                               !< left operand
    real(dp), intent(in) :: b                               !< right operand
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    call pf_fail(name, 'expected ' // pf_real_text(a) // ' ' // relation // ' ' &
      // pf_real_text(b), message, location)
  end subroutine order_fail_r

  !> Fail unless a < b.
  subroutine assert_less_than_i(a, b, message, location)
    integer(int32), intent(in) :: a                         !< left operand
    integer(int32), intent(in) :: b                         !< right operand
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    if (.not. (a < b)) call order_fail_i('assertLessThan', '<', int(a, int64), int(b, int64), &
      message, location)
  end subroutine assert_less_than_i

  !> Fail unless a < b.
  subroutine assert_less_than_r(a, b, message, location)
    real(dp), intent(in) :: a                               !< left operand
    real(dp), intent(in) :: b                               !< right operand
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    if (.not. (a < b)) call order_fail_r('assertLessThan', '<', a, b, message, location)
  end subroutine assert_less_than_r

  !> Fail unless a <= b.
  subroutine assert_less_equal_i(a, b, message, location)
    integer(int32), intent(in) :: a                         !< left operand
    integer(int32), intent(in) :: b                         !< right operand
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    if (.not. (a <= b)) call order_fail_i('assertLessThanOrEqual', '<=', int(a, int64), &
      int(b, int64), message, location)
  end subroutine assert_less_equal_i

  !> Fail unless a <= b.
  subroutine assert_less_equal_r(a, b, message, location)
    real(dp), intent(in) :: a                               !< left operand
    real(dp), intent(in) :: b                               !< right operand
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    if (.not. (a <= b)) call order_fail_r('assertLessThanOrEqual', '<=', a, b, message, location)
  end subroutine assert_less_equal_r

  !> Fail unless a > b.
  subroutine assert_greater_than_i(a, b, message, location)
    integer(int32), intent(in) :: a                         !< left operand
    integer(int32), intent(in) :: b                         !< right operand
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    if (.not. (a > b)) call order_fail_i('assertGreaterThan', '>', int(a, int64), &
      int(b, int64), message, location)
  end subroutine assert_greater_than_i

  !> Fail unless a > b.
  subroutine assert_greater_than_r(a, b, message, location)
    real(dp), intent(in) :: a                               !< left operand
    real(dp), intent(in) :: b                               !< right operand
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    if (.not. (a > b)) call order_fail_r('assertGreaterThan', '>', a, b, message, location)
  end subroutine assert_greater_than_r

  !> Fail unless a >= b.
  subroutine assert_greater_equal_i(a, b, message, location)
    integer(int32), intent(in) :: a                         !< left operand
    integer(int32), intent(in) :: b                         !< right operand
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    if (.not. (a >= b)) call order_fail_i('assertGreaterThanOrEqual', '>=', int(a, int64), &
      int(b, int64), message, location)
  end subroutine assert_greater_equal_i

  !> Fail unless a >= b.
  subroutine assert_greater_equal_r(a, b, message, location)
    real(dp), intent(in) :: a                               !< left operand
    real(dp), intent(in) :: b                               !< right operand
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    if (.not. (a >= b)) call order_fail_r('assertGreaterThanOrEqual', '>=', a, b, message, &
      location)
  end subroutine assert_greater_equal_r

  !> Fail unless `x` is a NaN.
  subroutine assert_is_nan_r(x, message, location)
    real(dp), intent(in) :: x                               !< value
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    if (.not. ieee_is_nan(x)) call pf_fail('assertIsNan', 'expected NaN, actual: ' &
      // pf_real_text(x), message, location)
  end subroutine assert_is_nan_r

  !> Fail unless `x` is finite (neither infinite nor NaN).
  subroutine assert_is_finite_r(x, message, location)
    real(dp), intent(in) :: x                               !< value
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    if (.not. ieee_is_finite(x)) call pf_fail('assertIsFinite', 'expected a finite value, ' &
      // 'actual: ' // pf_real_text(x), message, location)
  end subroutine assert_is_finite_r
end module pfunit_assert_scalar
