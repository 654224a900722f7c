!> Bracketed scalar root finding by the Illinois variant of regula falsi, shared by the return
!! mappings of the critical-state models (`mpm_cam_clay`, `mpm_critical_state_sand`): the caller
!! keeps a bracket [lo, hi] whose residuals have opposite signs, takes `illinois_point` as the next
!! trial and hands its residual to `illinois_update`.
module mpm_illinois
  use mpmice_kinds, only: wp
  implicit none
  private

  public :: illinois_point, illinois_update

contains

  !> The next trial point: the secant through the bracket's ends, or its midpoint once
  !! `iteration` exceeds `falsi_iterations` (a guaranteed bisection tail).
  pure real(wp) function illinois_point(lo, f_lo, hi, f_hi, iteration, falsi_iterations) &
    result(x)
    real(wp), intent(in) :: lo, f_lo, hi, f_hi   !< bracket ends and their residuals
    integer, intent(in) :: iteration              !< iteration count, from 1
    integer, intent(in) :: falsi_iterations       !< secant steps before bisection
    x = (lo * f_hi - hi * f_lo) / (f_hi - f_lo)
    if (iteration > falsi_iterations) x = 0.5_wp * (lo + hi)
  end function illinois_point

  !> Replace the bracket end whose residual has the sign of `fx` by (`x`, `fx`); when the same
  !! end is replaced twice running, halve the other end's residual (Illinois). `side` records the
  !! end replaced last: -1 `lo`, +1 `hi`, 0 none yet. Call only with a non-zero `fx` (a zero
  !! residual is a root: the caller stops before).
  pure subroutine illinois_update(x, fx, lo, f_lo, hi, f_hi, side)
    real(wp), intent(in) :: x, fx                 !< trial point and its residual
    real(wp), intent(inout) :: lo, f_lo, hi, f_hi !< bracket ends and their residuals
    integer, intent(inout) :: side                !< end replaced last
    if ((fx > 0.0_wp) .eqv. (f_lo > 0.0_wp)) then
      lo = x
      f_lo = fx
      if (side == -1) f_hi = 0.5_wp * f_hi
      side = -1
    else
      hi = x
      f_hi = fx
      if (side == 1) f_lo = 0.5_wp * f_lo
      side = 1
    end if
  end subroutine illinois_update
end module mpm_illinois
