!> Small dense linear systems a x = b (the implicit exchange's N x N matrices, N <= 9): Gaussian
!! elimination without pivoting for N = 3, LAPACK dgesv (LU with partial pivoting) otherwise.
module solver_dense
  use mpmice_kinds, only: wp
  implicit none
  private

  public :: dense_solve

  interface
    subroutine dgesv(n, nrhs, a, lda, ipiv, b, ldb, info)
      import :: wp
      integer, intent(in) :: n, nrhs, lda, ldb
      real(wp), intent(inout) :: a(lda, *), b(ldb, *)
      integer, intent(out) :: ipiv(*), info
    end subroutine dgesv
  end interface

contains

  !> Solve a x = b in place for `nrhs` columns (x holds b on entry): n = 3 by elimination
  !! without pivoting (`a` must be strictly diagonally dominant by rows, as the exchange matrix
  !! is, so no pivot vanishes and the elimination is stable; a dgesv call per face and cell cost
  !! more than the step's face exchange itself), otherwise LAPACK dgesv. `a` is overwritten;
  !! `info` /= 0: a singular matrix (dgesv's code).
  subroutine dense_solve(n, a, lda, x, nrhs, info)
    integer, intent(in) :: n                    !< order of the system
    integer, intent(in) :: lda                  !< leading dimension of a and x (>= n)
    real(wp), intent(inout) :: a(lda, n)        !< matrix (overwritten)
    integer, intent(in) :: nrhs                 !< columns of x
    real(wp), intent(inout) :: x(lda, nrhs)     !< right-hand sides in, solutions out
    integer, intent(out) :: info                !< 0: solved
    integer :: ipiv(n)
    if (n == 3) then
      call solve_3(a, lda, x, nrhs)
      info = 0
    else
      call dgesv(n, nrhs, a, lda, ipiv, x, lda, info)
    end if
  end subroutine dense_solve

  !> The 3 x 3 system a x = b in place (x holds b on entry, `nrhs` columns) by Gaussian
  !! elimination without pivoting; `a` strictly diagonally dominant by rows. `a` is overwritten.
  pure subroutine solve_3(a, lda, x, nrhs)
    integer, intent(in) :: lda                  !< leading dimension (>= 3)
    real(wp), intent(inout) :: a(lda, 3)        !< matrix
    integer, intent(in) :: nrhs                 !< columns
    real(wp), intent(inout) :: x(lda, nrhs)     !< right-hand sides in, solutions out
    real(wp) :: f21, f31, f32
    integer :: c
    f21 = a(2, 1) / a(1, 1)
    f31 = a(3, 1) / a(1, 1)
    a(2, 2:3) = a(2, 2:3) - f21 * a(1, 2:3)
    a(3, 2:3) = a(3, 2:3) - f31 * a(1, 2:3)
    f32 = a(3, 2) / a(2, 2)
    a(3, 3) = a(3, 3) - f32 * a(2, 3)
    do c = 1, nrhs
      x(2, c) = x(2, c) - f21 * x(1, c)
      x(3, c) = x(3, c) - f31 * x(1, c) - f32 * x(2, c)
      x(3, c) = x(3, c) / a(3, 3)
      x(2, c) = (x(2, c) - a(2, 3) * x(3, c)) / a(2, 2)
      x(1, c) = (x(1, c) - a(1, 2) * x(2, c) - a(1, 3) * x(3, c)) / a(1, 1)
    end do
  end subroutine solve_3
end module solver_dense
