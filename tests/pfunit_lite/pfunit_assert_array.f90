!> Array assertions of pfunit-lite for ranks 1 to 3 (the generic interfaces live in module
!! `pfunit`). The expected value is an array of the same shape or a scalar applied to every
!! element. Failures report how many elements differ, the first one (subscripts counted from 1)
!! and the largest difference.
module pfunit_assert_array
  use, intrinsic :: iso_fortran_env, only: real64, int32, int64
  use, intrinsic :: ieee_arithmetic, only: ieee_is_nan, ieee_is_finite
  use pfunit_core, only: SourceLocation, pf_fail, pf_real_text, pf_int_text, pf_index_text
  implicit none
  private

  public :: assert_equal_r1, assert_equal_r2, assert_equal_r3
  public :: assert_equal_r0_r1, assert_equal_r0_r2, assert_equal_r0_r3
  public :: assert_relatively_equal_r1, assert_relatively_equal_r2, assert_relatively_equal_r3
  public :: assert_equal_i1, assert_equal_i2, assert_equal_i3
  public :: assert_equal_i0_i1, assert_equal_i0_i2, assert_equal_i0_i3
  public :: assert_is_finite_r1, assert_is_finite_r2, assert_is_finite_r3

  integer, parameter :: dp = real64
  integer, parameter :: no_shape(0) = [integer ::]

contains

  !> Text of a shape, e.g. `[3,4]`.
  function shape_text(shp) result(text)
    integer, intent(in) :: shp(:)  !< shape
    character(len=:), allocatable :: text
    integer :: d
    text = '['
    do d = 1, size(shp)
      text = text // pf_int_text(int(shp(d), int64))
      if (d < size(shp)) text = text // ','
    end do
    text = text // ']'
  end function shape_text

  !> True (after reporting) when an expected array's shape differs from the actual one.
  logical function shape_differs(assertion, eshape, ashape, message, location)
    character(len=*), intent(in) :: assertion               !< assertion name
    integer, intent(in) :: eshape(:)                        !< expected shape (empty: scalar)
    integer, intent(in) :: ashape(:)                        !< actual shape
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    shape_differs = .false.
    if (size(eshape) == 0) return
    shape_differs = size(eshape) /= size(ashape)
    if (.not. shape_differs) shape_differs = any(eshape /= ashape)
    if (shape_differs) call pf_fail(assertion, 'shape mismatch: expected ' // shape_text(eshape) &
      // ', actual ' // shape_text(ashape), message, location)
  end function shape_differs

  !> Compare flattened real arrays element by element (absolute or relative tolerance).
  subroutine check_real(assertion, expected, actual, eshape, ashape, tol, relative, message, &
      location)
    character(len=*), intent(in) :: assertion               !< assertion name
    real(dp), intent(in) :: expected(:)                     !< expected values (1 if scalar)
    real(dp), intent(in) :: actual(:)                       !< values found
    integer, intent(in) :: eshape(:)                        !< expected shape (empty: scalar)
    integer, intent(in) :: ashape(:)                        !< actual shape
    real(dp), intent(in) :: tol                             !< tolerance
    logical, intent(in) :: relative                         !< tolerance is relative to |expected|
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    integer :: i, nbad, first
    real(dp) :: e, diff, worst
    logical :: bad
    if (shape_differs(assertion, eshape, ashape, message, location)) return
    nbad = 0
    first = 0
    worst = 0.0_dp
    do i = 1, size(actual)
      e = expected(1)
      if (size(eshape) > 0) e = expected(i)
      if (ieee_is_nan(e) .or. ieee_is_nan(actual(i))) then
        bad = .true.
      else
        diff = abs(e - actual(i))
        worst = max(worst, diff)
        if (relative) then
          bad = diff > tol * abs(e)
        else
          bad = diff > tol
        end if
      end if
      if (bad) then
        nbad = nbad + 1
        if (first == 0) first = i
      end if
    end do
    if (nbad == 0) return
    e = expected(1)
    if (size(eshape) > 0) e = expected(first)
    call pf_fail(assertion, pf_int_text(int(nbad, int64)) // ' of ' &
      // pf_int_text(int(size(actual), int64)) // ' elements differ; first at ' &
      // pf_index_text(first, ashape) // ': expected ' // pf_real_text(e) // ', actual ' &
      // pf_real_text(actual(first)) // '; largest |difference| ' // pf_real_text(worst) &
      // tolerance_label(relative) // pf_real_text(tol), message, location)
  end subroutine check_real

  !> Label of the tolerance in failure messages.
  function tolerance_label(relative) result(text)
    logical, intent(in) :: relative  !< tolerance is relative
    character(len=:), allocatable :: text
    if (relative) then
      text = ', relative tolerance '
    else
      text = ', tolerance '
    end if
  end function tolerance_label

  !> Compare flattened integer arrays element by element.
  subroutine check_int(expected, actual, eshape, ashape, message, location)
    integer(int32), intent(in) :: expected(:)               !< expected values (1 if scalar)
    integer(int32), intent(in) :: actual(:)                 !< values found
    integer, intent(in) :: eshape(:)                        !< expected shape (empty: scalar)
    integer, intent(in) :: ashape(:)                        !< actual shape
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    integer :: i, nbad, first
    integer(int32) :: e
    if (shape_differs('assertEqual', eshape, ashape, message, location)) return
    nbad = 0
    first = 0
    do i = 1, size(actual)
      e = expected(1)
      if (size(eshape) > 0) e = expected(i)
      if (e /= actual(i)) then
        nbad = nbad + 1
        if (first == 0) first = i
      end if
    end do
    if (nbad == 0) return
    e = expected(1)
    if (size(eshape) > 0) e = expected(first)
    call pf_fail('assertEqual', pf_int_text(int(nbad, int64)) // ' of ' &
      // pf_int_text(int(size(actual), int64)) // ' elements differ; first at ' &
      // pf_index_text(first, ashape) // ': expected ' // pf_int_text(int(e, int64)) &
      // ', actual ' // pf_int_text(int(actual(first), int64)), message, location)
  end subroutine check_int

  !> Report non-finite elements of a flattened real array.
  subroutine check_finite(actual, ashape, message, location)
    real(dp), intent(in) :: actual(:)                       !< values found
    integer, intent(in) :: ashape(:)                        !< actual shape
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    integer :: first
    if (all(ieee_is_finite(actual))) return
    first = findloc(ieee_is_finite(actual), .false., dim=1)
    call pf_fail('assertIsFinite', pf_int_text(int(count(.not. ieee_is_finite(actual)), int64)) &
      // ' of ' // pf_int_text(int(size(actual), int64)) // ' elements are not finite; first at ' &
      // pf_index_text(first, ashape) // ': ' // pf_real_text(actual(first)), message, location)
  end subroutine check_finite

  !> Absolute tolerance or 0.
  pure real(dp) function tol_or_zero(tolerance)
    real(dp), intent(in), optional :: tolerance  !< tolerance given by the caller
    tol_or_zero = 0.0_dp
    if (present(tolerance)) tol_or_zero = tolerance
  end function tol_or_zero

  !> Fail unless two rank-1 real arrays agree within the absolute `tolerance` (default 0).
  subroutine assert_equal_r1(expected, actual, tolerance, message, location)
    real(dp), intent(in) :: expected(:), actual(:)          !< expected values, values found
    real(dp), intent(in), optional :: tolerance             !< absolute tolerance
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    call check_real('assertEqual', expected, actual, shape(expected), shape(actual), &
      tol_or_zero(tolerance), .false., message, location)
  end subroutine assert_equal_r1

  !> Fail unless two rank-2 real arrays agree within the absolute `tolerance` (default 0).
  subroutine assert_equal_r2(expected, actual, tolerance, message, location)
    real(dp), intent(in) :: expected(:, :), actual(:, :)    !< expected values, values found
    real(dp), intent(in), optional :: tolerance             !< absolute tolerance
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    call check_real('assertEqual', reshape(expected, [size(expected)]), &
      reshape(actual, [size(actual)]), shape(expected), shape(actual), tol_or_zero(tolerance), &
      .false., message, location)
  end subroutine assert_equal_r2

  !> Fail unless two rank-3 real arrays agree within the absolute `tolerance` (default 0).
  subroutine assert_equal_r3(expected, actual, tolerance, message, location)
    real(dp), intent(in) :: expected(:, :, :), actual(:, :, :)  !< expected values, values found
    real(dp), intent(in), optional :: tolerance             !< absolute tolerance
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    call check_real('assertEqual', reshape(expected, [size(expected)]), &
      reshape(actual, [size(actual)]), shape(expected), shape(actual), tol_or_zero(tolerance), &
      .false., message, location)
  end subroutine assert_equal_r3

  !> Fail unless every element of a rank-1 real array is within `tolerance` of `expected`.
  subroutine assert_equal_r0_r1(expected, actual, tolerance, message, location)
    real(dp), intent(in) :: expected, actual(:)             !< expected value, values found
    real(dp), intent(in), optional :: tolerance             !< absolute tolerance
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    call check_real('assertEqual', [expected], actual, no_shape, shape(actual), &
      tol_or_zero(tolerance), .false., message, location)
  end subroutine assert_equal_r0_r1

  !> Fail unless every element of a rank-2 real array is within `tolerance` of `expected`.
  subroutine assert_equal_r0_r2(expected, actual, tolerance, message, location)
    real(dp), intent(in) :: expected, actual(:, :)          !< expected value, values found
    real(dp), intent(in), optional :: tolerance             !< absolute tolerance
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    call check_real('assertEqual', [expected], reshape(actual, [size(actual)]), no_shape, &
      shape(actual), tol_or_zero(tolerance), .false., message, location)
  end subroutine assert_equal_r0_r2

  !> Fail unless every element of a rank-3 real array is within `tolerance` of `expected`.
  subroutine assert_equal_r0_r3(expected, actual, tolerance, message, location)
    real(dp), intent(in) :: expected, actual(:, :, :)       !< expected value, values found
    real(dp), intent(in), optional :: tolerance             !< absolute tolerance
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    call check_real('assertEqual', [expected], reshape(actual, [size(actual)]), no_shape, &
      shape(actual), tol_or_zero(tolerance), .false., message, location)
  end subroutine assert_equal_r0_r3

  !> Fail unless |expected - actual| <= tolerance |expected| element by element (rank 1).
  subroutine assert_relatively_equal_r1(expected, actual, tolerance, message, location)
    real(dp), intent(in) :: expected(:), actual(:)          !< expected values, values found
    real(dp), intent(in) :: tolerance                       !< relative tolerance
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    call check_real('assertRelativelyEqual', expected, actual, shape(expected), shape(actual), &
      tolerance, .true., message, location)
  end subroutine assert_relatively_equal_r1

  !> Fail unless |expected - actual| <= tolerance |expected| element by element (rank 2).
  subroutine assert_relatively_equal_r2(expected, actual, tolerance, message, location)
    real(dp), intent(in) :: expected(:, :), actual(:, :)    !< expected values, values found
    real(dp), intent(in) :: tolerance                       !< relative tolerance
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    call check_real('assertRelativelyEqual', reshape(expected, [size(expected)]), &
      reshape(actual, [size(actual)]), shape(expected), shape(actual), tolerance, .true., &
      message, location)
  end subroutine assert_relatively_equal_r2

  !> Fail unless |expected - actual| <= tolerance |expected| element by element (rank 3).
  subroutine assert_relatively_equal_r3(expected, actual, tolerance, message, location)
    real(dp), intent(in) :: expected(:, :, :), actual(:, :, :)  !< expected values, values found
    real(dp), intent(in) :: tolerance                       !< relative tolerance
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    call check_real('assertRelativelyEqual', reshape(expected, [size(expected)]), &
      reshape(actual, [size(actual)]), shape(expected), shape(actual), tolerance, .true., &
      message, location)
  end subroutine assert_relatively_equal_r3

  !> Fail unless two rank-1 integer arrays are equal.
  subroutine assert_equal_i1(expected, actual, message, location)
    integer(int32), intent(in) :: expected(:), actual(:)    !< expected values, values found
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    call check_int(expected, actual, shape(expected), shape(actual), message, location)
  end subroutine assert_equal_i1

  !> Fail unless two rank-2 integer arrays are equal.
  subroutine assert_equal_i2(expected, actual, message, location)
    integer(int32), intent(in) :: expected(:, :), actual(:, :)  !< expected values, values found
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    call check_int(reshape(expected, [size(expected)]), reshape(actual, [size(actual)]), &
      shape(expected), shape(actual), message, location)
  end subroutine assert_equal_i2

  !> Fail unless two rank-3 integer arrays are equal.
  subroutine assert_equal_i3(expected, actual, message, location)
    integer(int32), intent(in) :: expected(:, :, :), actual(:, :, :)  !< expected, found
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    call check_int(reshape(expected, [size(expected)]), reshape(actual, [size(actual)]), &
      shape(expected), shape(actual), message, location)
  end subroutine assert_equal_i3

  !> Fail unless every element of a rank-1 integer array equals `expected`.
  subroutine assert_equal_i0_i1(expected, actual, message, location)
    integer(int32), intent(in) :: expected, actual(:)       !< expected value, values found
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    call check_int([expected], actual, no_shape, shape(actual), message, location)
  end subroutine assert_equal_i0_i1

  !> Fail unless every element of a rank-2 integer array equals `expected`.
  subroutine assert_equal_i0_i2(expected, actual, message, location)
    integer(int32), intent(in) :: expected, actual(:, :)    !< expected value, values found
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    call check_int([expected], reshape(actual, [size(actual)]), no_shape, shape(actual), &
      message, location)
  end subroutine assert_equal_i0_i2

  !> Fail unless every element of a rank-3 integer array equals `expected`.
  subroutine assert_equal_i0_i3(expected, actual, message, location)
    integer(int32), intent(in) :: expected, actual(:, :, :) !< expected value, values found
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    call check_int([expected], reshape(actual, [size(actual)]), no_shape, shape(actual), &
      message, location)
  end subroutine assert_equal_i0_i3

  !> Fail unless every element of a rank-1 real array is finite.
  subroutine assert_is_finite_r1(x, message, location)
    real(dp), intent(in) :: x(:)                            !< values
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    call check_finite(x, shape(x), message, location)
  end subroutine assert_is_finite_r1

  !> Fail unless every element of a rank-2 real array is finite.
  subroutine assert_is_finite_r2(x, message, location)
    real(dp), intent(in) :: x(:, :)                         !< values
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    call check_finite(reshape(x, [size(x)]), shape(x), message, location)
  end subroutine assert_is_finite_r2

  !> Fail unless every element of a rank-3 real array is finite.
  subroutine assert_is_finite_r3(x, message, location)
    real(dp), intent(in) :: x(:, :, :)                      !< values
    character(len=*), intent(in), optional :: message       !< shown on failure
    type(SourceLocation), intent(in), optional :: location  !< file and line
    call check_finite(reshape(x, [size(x)]), shape(x), message, location)
  end subroutine assert_is_finite_r3
end module pfunit_assert_array
