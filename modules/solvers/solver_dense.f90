!> Small dense linear systems a x = b: the implicit exchange's systems (one per cell or face, at most `max_n` materials)
!! without LAPACK: a call into a threaded BLAS per cell woke its worker threads every time
!! (OpenBLAS's dgesv/dgetrs hand even a 1 x 1 system to the thread pool, whose idle threads then
!! spin in sched_yield), which cost more than the whole step in scenes with one fluid.
module solver_dense
  use mpmice_kinds, only: wp
  implicit none
  private

  public :: solve_3, solve_pivoted

contains

  !> Solve the 3 x 3 system a x = b in place (x holds b on entry, `nrhs` columns) by Gaussian
  !! elimination without pivoting; `a` strictly diagonally dominant by rows (so no pivot
  !! vanishes and the elimination is stable). `a` is overwritten.
  pure subroutine solve_3(lda, a, x, nrhs)
    integer, intent(in) :: lda                !< leading dimension of a and x
    real(wp), intent(inout) :: a(lda, lda)    !< matrix (first 3 x 3)
    real(wp), intent(inout) :: x(lda, *)      !< right-hand sides in, solutions out
    integer, intent(in) :: nrhs               !< columns
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

  !> Solve the n x n system a x = b in place (x holds b on entry, `nrhs` columns) by Gaussian
  !! elimination with partial (row) pivoting, the algorithm of LAPACK's dgetf2 + dgetrs.
  !! `a` is overwritten; `singular` is true (and x undefined) where a pivot is exactly zero.
  pure subroutine solve_pivoted(n, lda, a, x, nrhs, singular)
    integer, intent(in) :: n                  !< order
    integer, intent(in) :: lda                !< leading dimension of a and x
    real(wp), intent(inout) :: a(lda, lda)    !< matrix (first n x n)
    real(wp), intent(inout) :: x(lda, *)      !< right-hand sides in, solutions out
    integer, intent(in) :: nrhs               !< columns
    logical, intent(out) :: singular          !< a zero pivot was met
    real(wp) :: row(lda), f
    integer :: col, r, p, c

    singular = .false.
    do col = 1, n
      p = col - 1 + maxloc(abs(a(col:n, col)), dim=1)
      if (a(p, col) == 0.0_wp) then
        singular = .true.
        return
      end if
      if (p /= col) then
        row(1:n) = a(col, 1:n)
        a(col, 1:n) = a(p, 1:n)
        a(p, 1:n) = row(1:n)
        do c = 1, nrhs
          f = x(col, c)
          x(col, c) = x(p, c)
          x(p, c) = f
        end do
      end if
      do r = col + 1, n
        f = a(r, col) / a(col, col)
        a(r, col + 1:n) = a(r, col + 1:n) - f * a(col, col + 1:n)
        x(r, 1:nrhs) = x(r, 1:nrhs) - f * x(col, 1:nrhs)
      end do
    end do
    do c = 1, nrhs
      do r = n, 1, -1
        x(r, c) = (x(r, c) - sum(a(r, r + 1:n) * x(r + 1:n, c))) / a(r, r)
      end do
    end do
  end subroutine solve_pivoted
end module solver_dense
