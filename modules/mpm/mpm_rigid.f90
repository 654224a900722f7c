!> Rigid / prescribed-motion material (`&solid model = 'rigid'`): beds, walls, shaking tables.
!!
!! The body moves with the prescribed history v(t) = v0 + integral of a, a(t) = A sin(2 pi f t)
!! (`prescribed_velocity` v0, `acceleration_amplitude` A, `acceleration_frequency` f), i.e.
!!   v(t) = v0 + A (1 - cos(2 pi f t)) / (2 pi f),
!!   x(t) = x0 + v0 t + A / (2 pi f) (t - sin(2 pi f t) / (2 pi f)),
!! integrated exactly by `rigid_displacement`. With `acceleration_duration` T > 0 the acceleration
!! stops at t = T and the body keeps v(T) (after whole cycles, v0), so x grows by v(T) (t - T).
!! With `acceleration_start` t_s > 0 the acceleration starts at t_s instead of 0 (t - t_s in
!! place of t above, a = 0 before; T counted from t_s), e.g. after a geostatic settle.
!! Its particles do not enter the deformable P2G; they
!! scatter their mass and momentum into separate node components, and every node they touch takes
!! the rigid velocity (no-slip contact with the deformable material, `mpm_nodal`).
module mpm_rigid
  use mpmice_kinds, only: wp
  implicit none
  private

  public :: rigid_motion_t, rigid_velocity, rigid_displacement, rigid_is_static

  real(wp), parameter :: two_pi = 2.0_wp * acos(-1.0_wp)  !< 2 pi

  !> Prescribed motion of a rigid body.
  type :: rigid_motion_t
    real(wp) :: velocity(3) = 0.0_wp       !< v0 [m/s]
    real(wp) :: amplitude(3) = 0.0_wp      !< A [m/s^2]
    real(wp) :: frequency = 0.0_wp         !< f [Hz]
    real(wp) :: duration = 0.0_wp          !< T: a = 0 for t > t_s + T [s] (0: no end)
    real(wp) :: start = 0.0_wp             !< t_s: a = 0 for t < t_s [s]
  end type rigid_motion_t

contains

  !> The body never moves: no initial velocity and no shaking (v = 0 for all t).
  elemental logical function rigid_is_static(m)
    type(rigid_motion_t), intent(in) :: m  !< motion
    rigid_is_static = all(m%velocity == 0.0_wp) .and. &
      (m%frequency == 0.0_wp .or. all(m%amplitude == 0.0_wp))
  end function rigid_is_static

  !> Velocity [m/s] at time `t` [s].
  pure function rigid_velocity(m, t) result(v)
    type(rigid_motion_t), intent(in) :: m  !< motion
    real(wp), intent(in) :: t              !< time [s]
    real(wp) :: v(3)
    real(wp) :: w
    v = m%velocity
    if (m%frequency > 0.0_wp) then
      w = two_pi * m%frequency
      v = v + m%amplitude * (1.0_wp - cos(w * shaking_time(m, t))) / w
    end if
  end function rigid_velocity

  !> Displacement [m] from `t` to `t + dt` [s] (exact integral of `rigid_velocity`).
  pure function rigid_displacement(m, t, dt) result(dx)
    type(rigid_motion_t), intent(in) :: m  !< motion
    real(wp), intent(in) :: t              !< start time [s]
    real(wp), intent(in) :: dt             !< step [s]
    real(wp) :: dx(3)
    real(wp) :: w
    dx = m%velocity * dt
    if (m%frequency > 0.0_wp) then
      w = two_pi * m%frequency
      if (m%start > 0.0_wp .or. (m%duration > 0.0_wp .and. t + dt > m%duration)) then
        dx = dx + shaking_position(m, w, t + dt) - shaking_position(m, w, t)
      else
        dx = dx + m%amplitude / w * (dt - (sin(w * (t + dt)) - sin(w * t)) / w)
      end if
    end if
  end function rigid_displacement

  !> Time [s] for which the acceleration has acted at time `t`: min(max(t - t_s, 0), T), or
  !! max(t - t_s, 0) without an end.
  pure real(wp) function shaking_time(m, t) result(ts)
    type(rigid_motion_t), intent(in) :: m  !< motion
    real(wp), intent(in) :: t              !< time [s]
    ts = max(t - m%start, 0.0_wp)
    if (m%duration > 0.0_wp) ts = min(ts, m%duration)
  end function shaking_time

  !> Displacement [m] of the acceleration's part of the motion from 0 to `t` (w = 2 pi f):
  !! A/w (t_a - sin(w t_a)/w) + A (1 - cos(w t_a))/w (t - t_s - t_a), t_a = `shaking_time`
  !! (0 before the start t_s).
  pure function shaking_position(m, w, t) result(x)
    type(rigid_motion_t), intent(in) :: m  !< motion
    real(wp), intent(in) :: w              !< angular frequency [1/s]
    real(wp), intent(in) :: t              !< time [s]
    real(wp) :: x(3)
    real(wp) :: ts
    ts = shaking_time(m, t)
    x = m%amplitude / w * (ts - sin(w * ts) / w) + m%amplitude * (1.0_wp - cos(w * ts)) / w * &
      max(t - m%start - ts, 0.0_wp)
  end function shaking_position
end module mpm_rigid
