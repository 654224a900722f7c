!> Direct line of a symmetric positive definite tridiagonal line (cyclic when periodic): the
!! fast path of `solver_pressure` when the whole operator is one line on one rank (one active grid
!! dimension and one rank). The operator is factorised (LDL^T, Sherman-Morrison for the periodic
!! corner) once per operator and solved directly: the true relative residual, with one step of
!! iterative refinement if it is above the tolerance. `ready` stays false when the factorisation
!! meets a non-positive or non-finite pivot, and the caller falls back to hypre.
module solver_line
  use mpmice_kinds, only: wp
  implicit none
  private

  public :: line_solver_t, line_init, line_free, line_factor, line_solve

  !> The factorisation of one tridiagonal line and its work vectors.
  type :: line_solver_t
    logical :: ready = .false.          !< the factorisation of the current operator is valid
    integer :: n = 0                    !< cells on the line
    logical :: periodic = .false.       !< the line is periodic (corner coupling)
    real(wp) :: corner = 0.0_wp         !< A(1,n) = A(n,1) = -(low-face coefficient of cell 1)
    real(wp) :: sm_denominator = 1.0_wp !< Sherman-Morrison 1 + gamma u.z (periodic)
    real(wp), allocatable :: diag(:)    !< (n) diagonal of A
    real(wp), allocatable :: off(:)     !< (n) A(m,m+1), m < n
    real(wp), allocatable :: fac_d(:)   !< (n) LDL^T pivots of T
    real(wp), allocatable :: fac_l(:)   !< (n) LDL^T multipliers of T
    real(wp), allocatable :: sm_z(:)    !< (n) T^{-1} (e_1 - e_n) (periodic)
    real(wp), allocatable :: x(:)       !< (n) solution
    real(wp), allocatable :: r(:)       !< (n) residual / correction work vector
  end type line_solver_t

contains

  !> Allocate a line of `n` cells (freed first); no factorisation yet.
  subroutine line_init(line, n, periodic)
    type(line_solver_t), intent(inout) :: line  !< line solver
    integer, intent(in) :: n                    !< cells on the line
    logical, intent(in) :: periodic             !< corner coupling present
    call line_free(line)
    line%n = n
    line%periodic = periodic
    allocate(line%diag(n), line%off(n), line%fac_d(n), line%fac_l(n), line%sm_z(n), &
      line%x(n), line%r(n))
  end subroutine line_init

  !> Release the line's arrays.
  subroutine line_free(line)
    type(line_solver_t), intent(inout) :: line  !< line solver
    if (allocated(line%diag)) deallocate(line%diag, line%off, line%fac_d, &
      line%fac_l, line%sm_z, line%x, line%r)
    line%ready = .false.
    line%n = 0
  end subroutine line_free

  !> Factorise the line operator `values` (centre, then the low-neighbour entry
  !! -coef of hypre dimension 1, per cell in line order). Non-periodic: A = T, tridiagonal.
  !! Periodic: A = T + gamma u u^T with u = e_1 - e_n and gamma = -A(1,n) (the low-face
  !! coefficient of cell 1), so T is A without the corner couplings and with gamma taken off
  !! A(1,1) and A(n,n); T keeps A's row sums, so it is SPD when A is (diagonally dominant with a
  !! wall or reaction term). T = L D L^T; `ready` stays false on a non-positive or
  !! non-finite pivot (the caller then falls back to hypre).
  subroutine line_factor(line, values, ne)
    type(line_solver_t), intent(inout) :: line  !< line solver (allocated)
    real(wp), intent(in) :: values(:)             !< operator values (ne per cell)
    integer, intent(in) :: ne                     !< stored entries per cell
    integer :: m, n
    real(wp) :: gamma, dm

    n = line%n
    do m = 1, n
      line%diag(m) = real(values((m - 1) * ne + 1), wp)
    end do
    do m = 1, n - 1
      line%off(m) = real(values(m * ne + 2), wp)
    end do
    line%off(n) = 0.0_wp
    line%corner = 0.0_wp
    if (line%periodic .and. n > 1) line%corner = real(values(2), wp)
    gamma = -line%corner

    line%ready = .false.
    do m = 1, n
      dm = line%diag(m)
      if (m == 1 .or. m == n) dm = dm - gamma
      if (m > 1) then
        line%fac_l(m - 1) = line%off(m - 1) / line%fac_d(m - 1)
        dm = dm - line%fac_l(m - 1) * line%off(m - 1)
      end if
      if (.not. (dm > 0.0_wp .and. dm <= huge(dm))) return
      line%fac_d(m) = dm
    end do
    line%fac_l(n) = 0.0_wp
    line%sm_denominator = 1.0_wp
    if (line%periodic .and. n > 1) then
      line%sm_z = 0.0_wp
      line%sm_z(1) = 1.0_wp
      line%sm_z(n) = -1.0_wp
      call ldlt_solve(n, line%fac_d, line%fac_l, line%sm_z)
      line%sm_denominator = 1.0_wp + gamma * (line%sm_z(1) - line%sm_z(n))
      if (.not. (line%sm_denominator > 0.0_wp .and. &
        line%sm_denominator <= huge(1.0_wp))) return
    end if
    line%ready = .true.
  end subroutine line_factor

  !> y = T^{-1} y with T = L D L^T (unit lower bidiagonal L, multipliers `l`, pivots `d`).
  pure subroutine ldlt_solve(n, d, l, y)
    integer, intent(in) :: n            !< unknowns
    real(wp), intent(in) :: d(:), l(:)  !< pivots (n), multipliers (n - 1)
    real(wp), intent(inout) :: y(:)     !< right-hand side in, solution out
    integer :: m
    do m = 2, n
      y(m) = y(m) - l(m - 1) * y(m - 1)
    end do
    do m = 1, n
      y(m) = y(m) / d(m)
    end do
    do m = n - 1, 1, -1
      y(m) = y(m) - l(m) * y(m + 1)
    end do
  end subroutine ldlt_solve

  !> y = A^{-1} y on the line (Sherman-Morrison correction for the periodic corner).
  pure subroutine line_apply_inverse(n, periodic, corner, denominator, d, l, z, y)
    integer, intent(in) :: n                  !< unknowns
    logical, intent(in) :: periodic           !< corner coupling present
    real(wp), intent(in) :: corner            !< A(1,n)
    real(wp), intent(in) :: denominator       !< 1 + gamma u.z
    real(wp), intent(in) :: d(:), l(:), z(:)  !< LDL^T factors of T, z = T^{-1} u
    real(wp), intent(inout) :: y(:)           !< right-hand side in, solution out
    real(wp) :: s
    call ldlt_solve(n, d, l, y)
    if (periodic .and. n > 1) then
      s = -corner * (y(1) - y(n)) / denominator
      y(1:n) = y(1:n) - s * z(1:n)
    end if
  end subroutine line_apply_inverse

  !> r = b - A x on the line.
  pure subroutine line_residual(n, periodic, corner, diag, off, b, x, r)
    integer, intent(in) :: n                    !< unknowns
    logical, intent(in) :: periodic             !< corner coupling present
    real(wp), intent(in) :: corner              !< A(1,n)
    real(wp), intent(in) :: diag(:), off(:)     !< A(m,m), A(m,m+1)
    real(wp), intent(in) :: b(:), x(:)          !< right-hand side, solution
    real(wp), intent(out) :: r(:)               !< residual
    integer :: m
    do m = 1, n
      r(m) = b(m) - diag(m) * x(m)
    end do
    do m = 1, n - 1
      r(m) = r(m) - off(m) * x(m + 1)
      r(m + 1) = r(m + 1) - off(m) * x(m)
    end do
    if (periodic .and. n > 1) then
      r(1) = r(1) - corner * x(n)
      r(n) = r(n) - corner * x(1)
    end if
  end subroutine line_residual

  !> Direct solve on the line: `x` = A^{-1} b and the true relative residual, with one step of
  !! iterative refinement when that is above `tolerance`. A zero right-hand side gives x = 0.
  subroutine line_solve(line, b, tolerance, relative_residual)
    type(line_solver_t), intent(inout) :: line  !< factorised line (solution in `x`)
    real(wp), intent(in) :: b(:)                  !< right-hand side (n)
    real(wp), intent(in) :: tolerance             !< relative residual that needs no refinement
    real(wp), intent(out) :: relative_residual    !< ||b - A x||_2 / ||b||_2
    real(wp) :: bnorm
    integer :: n

    n = line%n
    bnorm = sqrt(dot_product(b, b))
    if (bnorm == 0.0_wp) then
      line%x = 0.0_wp
      relative_residual = 0.0_wp
      return
    end if
    line%x = b
    call line_apply_inverse(n, line%periodic, line%corner, line%sm_denominator, &
      line%fac_d, line%fac_l, line%sm_z, line%x)
    call line_residual(n, line%periodic, line%corner, line%diag, &
      line%off, b, line%x, line%r)
    relative_residual = sqrt(dot_product(line%r, line%r)) / bnorm
    if (relative_residual > tolerance) then
      ! one step of iterative refinement: x <- x + A^{-1} (b - A x)
      call line_apply_inverse(n, line%periodic, line%corner, line%sm_denominator, &
        line%fac_d, line%fac_l, line%sm_z, line%r)
      line%x = line%x + line%r
      call line_residual(n, line%periodic, line%corner, line%diag, &
        line%off, b, line%x, line%r)
      relative_residual = sqrt(dot_product(line%r, line%r)) / bnorm
    end if
  end subroutine line_solve
end module solver_line
