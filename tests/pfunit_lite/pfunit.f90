!> pfunit-lite: the part of pFUnit's `pfunit` module that MPMICE's unit tests use.
!!
!! Test modules write `use pfunit` exactly as with the real pFUnit (built with
!! `ENABLE_MPI_F08=YES`); `pf2f90.py` expands the `@assert...` macros into calls of the generic
!! procedures below, with `location=SourceLocation(file, line)`. The `pf_*` names are used only by
!! the generated drivers.
module pfunit
  use pfunit_core, only: SourceLocation, MpiTestMethod, anyExceptions, pf_runner_t, &
    pf_runner_init, pf_test_start, pf_test_end, pf_runner_finish
  use pfunit_assert_scalar, only: assert_equal_i4, assert_equal_i8, assert_equal_i4_i8, &
    assert_equal_r, assert_equal_i4_r, assert_equal_l, assert_equal_c, &
    assert_relatively_equal_r, assert_true, assert_false, assert_true_1d, assert_false_1d, &
    assert_less_than_i, assert_less_than_r, assert_less_equal_i, assert_less_equal_r, &
    assert_greater_than_i, assert_greater_than_r, assert_greater_equal_i, &
    assert_greater_equal_r, assert_is_nan_r, assert_is_finite_r
  use pfunit_assert_array, only: assert_equal_r1, assert_equal_r2, assert_equal_r3, &
    assert_equal_r0_r1, assert_equal_r0_r2, assert_equal_r0_r3, assert_relatively_equal_r1, &
    assert_relatively_equal_r2, assert_relatively_equal_r3, assert_equal_i1, assert_equal_i2, &
    assert_equal_i3, assert_equal_i0_i1, assert_equal_i0_i2, assert_equal_i0_i3, &
    assert_is_finite_r1, assert_is_finite_r2, assert_is_finite_r3
  implicit none
  private

  public :: SourceLocation, MpiTestMethod, anyExceptions
  public :: assertEqual, assertRelativelyEqual, assertTrue, assertFalse, assertLessThan, &
    assertLessThanOrEqual, assertGreaterThan, assertGreaterThanOrEqual, assertIsNan, &
    assertIsFinite
  public :: pf_runner_t, pf_runner_init, pf_test_start, pf_test_end, pf_runner_finish

  !> `assertEqual(expected, actual [, tolerance] [, message] [, location])`: integers, reals
  !! (absolute tolerance, default 0), logicals, strings; real and integer arrays of rank 1-3
  !! against an array of the same shape or a scalar.
  interface assertEqual
    module procedure assert_equal_i4, assert_equal_i8, assert_equal_i4_i8, assert_equal_r, &
      assert_equal_i4_r, assert_equal_l, assert_equal_c
    module procedure assert_equal_r1, assert_equal_r2, assert_equal_r3, assert_equal_r0_r1, &
      assert_equal_r0_r2, assert_equal_r0_r3
    module procedure assert_equal_i1, assert_equal_i2, assert_equal_i3, assert_equal_i0_i1, &
      assert_equal_i0_i2, assert_equal_i0_i3
  end interface assertEqual

  !> `assertRelativelyEqual(expected, actual, tolerance [, message] [, location])`:
  !! |expected - actual| <= tolerance |expected|, reals of rank 0-3.
  interface assertRelativelyEqual
    module procedure assert_relatively_equal_r, assert_relatively_equal_r1, &
      assert_relatively_equal_r2, assert_relatively_equal_r3
  end interface assertRelativelyEqual

  !> `assertTrue(condition [, message] [, location])`, scalar or rank-1 logical.
  interface assertTrue
    module procedure assert_true, assert_true_1d
  end interface assertTrue

  !> `assertFalse(condition [, message] [, location])`, scalar or rank-1 logical.
  interface assertFalse
    module procedure assert_false, assert_false_1d
  end interface assertFalse

  !> `assertLessThan(a, b [, message] [, location])`: a < b (integers or reals).
  interface assertLessThan
    module procedure assert_less_than_i, assert_less_than_r
  end interface assertLessThan

  !> `assertLessThanOrEqual(a, b [, message] [, location])`: a <= b.
  interface assertLessThanOrEqual
    module procedure assert_less_equal_i, assert_less_equal_r
  end interface assertLessThanOrEqual

  !> `assertGreaterThan(a, b [, message] [, location])`: a > b.
  interface assertGreaterThan
    module procedure assert_greater_than_i, assert_greater_than_r
  end interface assertGreaterThan

  !> `assertGreaterThanOrEqual(a, b [, message] [, location])`: a >= b.
  interface assertGreaterThanOrEqual
    module procedure assert_greater_equal_i, assert_greater_equal_r
  end interface assertGreaterThanOrEqual

  !> `assertIsNan(x [, message] [, location])`.
  interface assertIsNan
    module procedure assert_is_nan_r
  end interface assertIsNan

  !> `assertIsFinite(x [, message] [, location])`, reals of rank 0-3.
  interface assertIsFinite
    module procedure assert_is_finite_r, assert_is_finite_r1, assert_is_finite_r2, &
      assert_is_finite_r3
  end interface assertIsFinite
end module pfunit
