!> Small 3x3 tensor helpers of the MPM kernels: symmetric storage (xx, yy, zz, xy, yz, xz),
!! determinant, polar rotation (eq. 12) and the symmetric eigen-decomposition used by the
!! principal-stress return mapping.
module mpm_tensor
  use mpmice_kinds, only: wp
  implicit none
  private

  public :: sym_to_mat, mat_to_sym, det3, polar_rotation, sym_eigen, rotate_to, rotate_from, mul3
  public :: mean_pressure

contains

  !> Full 3x3 matrix of a symmetric tensor stored as (xx, yy, zz, xy, yz, xz).
  pure function sym_to_mat(s) result(a)
    real(wp), intent(in) :: s(6)  !< symmetric tensor
    real(wp) :: a(3, 3)
    a(1, 1) = s(1)
    a(2, 2) = s(2)
    a(3, 3) = s(3)
    a(1, 2) = s(4)
    a(2, 1) = s(4)
    a(2, 3) = s(5)
    a(3, 2) = s(5)
    a(1, 3) = s(6)
    a(3, 1) = s(6)
  end function sym_to_mat

  !> Symmetric part of a 3x3 matrix as (xx, yy, zz, xy, yz, xz).
  pure function mat_to_sym(a) result(s)
    real(wp), intent(in) :: a(3, 3)  !< matrix
    real(wp) :: s(6)
    s(1) = a(1, 1)
    s(2) = a(2, 2)
    s(3) = a(3, 3)
    s(4) = 0.5_wp * (a(1, 2) + a(2, 1))
    s(5) = 0.5_wp * (a(2, 3) + a(3, 2))
    s(6) = 0.5_wp * (a(1, 3) + a(3, 1))
  end function mat_to_sym

  !> Determinant of a 3x3 matrix.
  pure real(wp) function det3(a) result(d)
    real(wp), intent(in) :: a(3, 3)  !< matrix
    d = a(1, 1) * (a(2, 2) * a(3, 3) - a(2, 3) * a(3, 2)) &
      - a(1, 2) * (a(2, 1) * a(3, 3) - a(2, 3) * a(3, 1)) &
      + a(1, 3) * (a(2, 1) * a(3, 2) - a(2, 2) * a(3, 1))
  end function det3

  !> Mean effective stress p' = -tr(sig) / 3 [Pa] (compression positive) of a stress `sig` in
  !! Voigt order (xx, yy, zz, xy, yz, xz), tension positive.
  pure real(wp) function mean_pressure(sig) result(p)
    real(wp), intent(in) :: sig(6)  !< stress [Pa]
    p = -(sig(1) + sig(2) + sig(3)) / 3.0_wp
  end function mean_pressure

  !> Rotation R of the polar decomposition F = V R = R U (eq. 12), det F > 0. Closed form when F
  !! only mixes x and y (1D/2D); otherwise Higham's scaled Newton iteration R <- (R + R^-T)/2.
  pure function polar_rotation(f) result(r)
    real(wp), intent(in) :: f(3, 3)  !< deformation gradient
    real(wp) :: r(3, 3)
    real(wp) :: a, b, n, x(3, 3), xit(3, 3), d, g
    integer :: it
    if (f(1, 3) == 0.0_wp .and. f(2, 3) == 0.0_wp .and. f(3, 1) == 0.0_wp .and. &
      f(3, 2) == 0.0_wp) then
      a = f(1, 1) + f(2, 2)
      b = f(2, 1) - f(1, 2)
      n = sqrt(a * a + b * b)
      r = 0.0_wp
      r(1, 1) = a / n
      r(2, 2) = a / n
      r(2, 1) = b / n
      r(1, 2) = -b / n
      r(3, 3) = 1.0_wp
      return
    end if
    x = f
    do it = 1, 50
      d = det3(x)
      xit = inv_transpose(x, d)
      g = abs(d)**(-1.0_wp / 3.0_wp)
      r = 0.5_wp * (g * x + xit / g)
      if (maxval(abs(r - x)) < 1.0e-15_wp) exit
      x = r
    end do
  end function polar_rotation

  !> Inverse transpose of a 3x3 matrix with determinant `d`.
  pure function inv_transpose(a, d) result(b)
    real(wp), intent(in) :: a(3, 3)  !< matrix
    real(wp), intent(in) :: d        !< its determinant
    real(wp) :: b(3, 3)
    b(1, 1) = a(2, 2) * a(3, 3) - a(2, 3) * a(3, 2)
    b(1, 2) = a(2, 3) * a(3, 1) - a(2, 1) * a(3, 3)
    b(1, 3) = a(2, 1) * a(3, 2) - a(2, 2) * a(3, 1)
    b(2, 1) = a(1, 3) * a(3, 2) - a(1, 2) * a(3, 3)
    b(2, 2) = a(1, 1) * a(3, 3) - a(1, 3) * a(3, 1)
    b(2, 3) = a(1, 2) * a(3, 1) - a(1, 1) * a(3, 2)
    b(3, 1) = a(1, 2) * a(2, 3) - a(1, 3) * a(2, 2)
    b(3, 2) = a(1, 3) * a(2, 1) - a(1, 1) * a(2, 3)
    b(3, 3) = a(1, 1) * a(2, 2) - a(1, 2) * a(2, 1)
    b = b / d
  end function inv_transpose

  !> R^T S R of a symmetric tensor S (into the rotated frame, eqs. 13-14).
  pure function rotate_to(r, s) result(t)
    real(wp), intent(in) :: r(3, 3)  !< rotation
    real(wp), intent(in) :: s(6)     !< symmetric tensor
    real(wp) :: t(6)
    real(wp) :: rt(3, 3)
    if (planar(r, s)) then
      t = rotate_planar(r, s)
      return
    end if
    ! the transpose in a local: passed as an expression, it was packed into a heap temporary
    ! (`_gfortran_internal_pack`) on every call
    rt = transpose(r)
    t = mat_to_sym(mul3(rt, mul3(sym_to_mat(s), r)))
  end function rotate_to

  !> R S R^T of a symmetric tensor S (back to the current frame, eq. 15).
  pure function rotate_from(r, s) result(t)
    real(wp), intent(in) :: r(3, 3)  !< rotation
    real(wp), intent(in) :: s(6)     !< symmetric tensor
    real(wp) :: t(6)
    real(wp) :: rt(3, 3)
    rt = transpose(r)
    if (planar(r, s)) then
      t = rotate_planar(rt, s)
      return
    end if
    t = mat_to_sym(mul3(r, mul3(sym_to_mat(s), rt)))
  end function rotate_from

  !> True for a rotation about z and a tensor without yz, xz parts (every plane-strain state):
  !! `rotate_planar` then gives the 3 x 3 products' values.
  pure logical function planar(r, s)
    real(wp), intent(in) :: r(3, 3)  !< rotation
    real(wp), intent(in) :: s(6)     !< symmetric tensor
    planar = r(1, 3) == 0.0_wp .and. r(2, 3) == 0.0_wp .and. r(3, 1) == 0.0_wp .and. &
      r(3, 2) == 0.0_wp .and. r(3, 3) == 1.0_wp .and. s(5) == 0.0_wp .and. s(6) == 0.0_wp
  end function planar

  !> Q^T S Q of a symmetric tensor S without yz, xz parts and a rotation Q about z (Q = R in
  !! `rotate_to`, R^T in `rotate_from`): the xy block of their 3 x 3 products with the zero terms
  !! left out (each an exact zero, so the sums are the same), zz unchanged.
  pure function rotate_planar(q, s) result(t)
    real(wp), intent(in) :: q(3, 3)       !< rotation about z
    real(wp), intent(in) :: s(6)          !< symmetric tensor, s(5) = s(6) = 0
    real(wp) :: t(6)
    real(wp) :: m11, m12, m21, m22, t11, t12, t21, t22
    ! M = S Q
    m11 = s(1) * q(1, 1) + s(4) * q(2, 1)
    m12 = s(1) * q(1, 2) + s(4) * q(2, 2)
    m21 = s(4) * q(1, 1) + s(2) * q(2, 1)
    m22 = s(4) * q(1, 2) + s(2) * q(2, 2)
    ! T = Q^T M
    t11 = q(1, 1) * m11 + q(2, 1) * m21
    t12 = q(1, 1) * m12 + q(2, 1) * m22
    t21 = q(1, 2) * m11 + q(2, 2) * m21
    t22 = q(1, 2) * m12 + q(2, 2) * m22
    t = [t11, t22, s(3), 0.5_wp * (t12 + t21), 0.0_wp, 0.0_wp]
  end function rotate_planar

  !> Product a b of 3x3 matrices (explicit loops: no temporaries).
  pure function mul3(a, b) result(c)
    real(wp), intent(in) :: a(3, 3)  !< left factor
    real(wp), intent(in) :: b(3, 3)  !< right factor
    real(wp) :: c(3, 3)
    integer :: i, j
    do j = 1, 3
      do i = 1, 3
        c(i, j) = a(i, 1) * b(1, j) + a(i, 2) * b(2, j) + a(i, 3) * b(3, j)
      end do
    end do
  end function mul3

  !> Eigenvalues `lam` (descending) and orthonormal eigenvectors (columns of `q`) of a symmetric
  !! tensor by cyclic Jacobi rotations: s = q diag(lam) q^T.
  pure subroutine sym_eigen(s, lam, q)
    real(wp), intent(in) :: s(6)        !< symmetric tensor
    real(wp), intent(out) :: lam(3)     !< eigenvalues, lam(1) >= lam(2) >= lam(3)
    real(wp), intent(out) :: q(3, 3)    !< eigenvectors (columns)
    real(wp) :: a(3, 3), off, scale, theta, t, c, sn, tau, apq, tmp(3)
    integer :: sweep, p, qq, k, order(3), i
    a = sym_to_mat(s)
    q = 0.0_wp
    q(1, 1) = 1.0_wp
    q(2, 2) = 1.0_wp
    q(3, 3) = 1.0_wp
    scale = max(maxval(abs(a)), tiny(1.0_wp))
    do sweep = 1, 50
      off = abs(a(1, 2)) + abs(a(1, 3)) + abs(a(2, 3))
      if (off <= 1.0e-17_wp * scale) exit
      do p = 1, 2
        do qq = p + 1, 3
          apq = a(p, qq)
          if (abs(apq) <= 1.0e-300_wp) cycle
          theta = (a(qq, qq) - a(p, p)) / (2.0_wp * apq)
          t = sign(1.0_wp, theta) / (abs(theta) + sqrt(theta * theta + 1.0_wp))
          c = 1.0_wp / sqrt(t * t + 1.0_wp)
          sn = t * c
          tau = sn / (1.0_wp + c)
          a(p, p) = a(p, p) - t * apq
          a(qq, qq) = a(qq, qq) + t * apq
          a(p, qq) = 0.0_wp
          a(qq, p) = 0.0_wp
          do k = 1, 3
            if (k == p .or. k == qq) cycle
            tmp(1) = a(k, p)
            tmp(2) = a(k, qq)
            a(k, p) = tmp(1) - sn * (tmp(2) + tau * tmp(1))
            a(p, k) = a(k, p)
            a(k, qq) = tmp(2) + sn * (tmp(1) - tau * tmp(2))
            a(qq, k) = a(k, qq)
          end do
          do k = 1, 3
            tmp(1) = q(k, p)
            tmp(2) = q(k, qq)
            q(k, p) = tmp(1) - sn * (tmp(2) + tau * tmp(1))
            q(k, qq) = tmp(2) + sn * (tmp(1) - tau * tmp(2))
          end do
        end do
      end do
    end do
    tmp = [a(1, 1), a(2, 2), a(3, 3)]
    order = [1, 2, 3]
    do i = 1, 2
      do k = i + 1, 3
        if (tmp(order(k)) > tmp(order(i))) then
          p = order(i)
          order(i) = order(k)
          order(k) = p
        end if
      end do
    end do
    lam = tmp(order)
    q = q(:, order)
  end subroutine sym_eigen
end module mpm_tensor
