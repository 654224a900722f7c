!> Surface loads on a solid (`&solid traction`, `traction_lower/upper`, `traction_ramp_time`): the
!! traction t [Pa] acts on the particles inside the load box as the body force t V_p / h, h the
!! box's extent along the axis of the largest |t| component, so the total force is t times the
!! box face area when the box is one particle layer thick (e.g. the load of a consolidation test).
!! The force is scattered to the nodes as part of the external force of eq. 40.
module mpm_loads
  use mpmice_kinds, only: wp
  use grid_layout, only: grid_t
  use particles_store, only: particles_t
  use mpm_shape, only: particle_stencil, max_stencil
  use mpm_nodes, only: node_force
  implicit none
  private

  public :: surface_load_t, surface_load_init, surface_load_scatter, surface_load_power

  !> A traction on the particles of one solid inside a box.
  type :: surface_load_t
    logical :: active = .false.             !< a nonzero traction is given
    real(wp) :: traction(3) = 0.0_wp        !< t [Pa]
    real(wp) :: lower(3) = 0.0_wp           !< box low corner [m]
    real(wp) :: upper(3) = 0.0_wp           !< box high corner [m]
    real(wp) :: thickness = 1.0_wp          !< h [m]
    real(wp) :: ramp_time = 0.0_wp          !< linear growth time [s] (0: step at t = 0)
  end type surface_load_t

contains

  !> The load of a `&solid` group (validated by the configuration); inactive dimensions of the
  !! grid do not restrict the box.
  pure function surface_load_init(traction, lower, upper, ramp_time, grid) result(load)
    real(wp), intent(in) :: traction(3)   !< t [Pa]
    real(wp), intent(in) :: lower(3)      !< box low corner [m]
    real(wp), intent(in) :: upper(3)      !< box high corner [m]
    real(wp), intent(in) :: ramp_time     !< ramp [s]
    type(grid_t), intent(in) :: grid      !< block geometry
    type(surface_load_t) :: load
    integer :: axis
    load%traction = merge(traction, 0.0_wp, grid%active)
    load%active = any(load%traction /= 0.0_wp)
    if (.not. load%active) return
    load%lower = merge(lower, -huge(1.0_wp), grid%active)
    load%upper = merge(upper, huge(1.0_wp), grid%active)
    axis = maxloc(abs(load%traction), dim=1)
    load%thickness = upper(axis) - lower(axis)
    load%ramp_time = ramp_time
  end function surface_load_init

  !> Add the load at time `time` [s] to the node forces q(node_force:node_force + 2) (local
  !! scatter; the caller sums
  !! the halo afterwards).
  subroutine surface_load_scatter(load, p, q, kind, grid, time)
    type(surface_load_t), intent(in) :: load     !< load
    type(particles_t), intent(in) :: p           !< particles of the loaded solid
    type(grid_t), intent(in) :: grid             !< block geometry
    real(wp), intent(inout) :: q(:, grid%lbn(1):, grid%lbn(2):, grid%lbn(3):) !< node fields
    integer, intent(in) :: kind                  !< shape function kind
    real(wp), intent(in) :: time                 !< time of the force [s]
    integer :: ip, a, b, c, first(3), nn(3)
    real(wp) :: w(max_stencil, 3), dw(max_stencil, 3), f(3), ramp, s
    if (.not. load%active) return
    ramp = 1.0_wp
    if (load%ramp_time > 0.0_wp) ramp = min(1.0_wp, time / load%ramp_time)
    do ip = 1, p%np
      if (any(p%x(:, ip) < load%lower) .or. any(p%x(:, ip) > load%upper)) cycle
      f = ramp * load%traction * p%volume(ip) / load%thickness
      call particle_stencil(kind, grid, p%x(:, ip), p%half_width, first, nn, w, dw)
      do c = 1, nn(3)
        do b = 1, nn(2)
          do a = 1, nn(1)
            s = w(a, 1) * w(b, 2) * w(c, 3)
            associate (qf => q(node_force:node_force + 2, first(1) + a - 1, first(2) + b - 1, &
              first(3) + c - 1))
              qf = qf + s * f
            end associate
          end do
        end do
      end do
    end do
  end subroutine surface_load_scatter

  !> This rank's power of the load at time `time` [s] on the particles' velocities [W].
  pure real(wp) function surface_load_power(load, p, time) result(power)
    type(surface_load_t), intent(in) :: load     !< load
    type(particles_t), intent(in) :: p           !< particles of the loaded solid
    real(wp), intent(in) :: time                 !< time of the force [s]
    integer :: ip
    real(wp) :: ramp
    power = 0.0_wp
    if (.not. load%active) return
    ramp = 1.0_wp
    if (load%ramp_time > 0.0_wp) ramp = min(1.0_wp, time / load%ramp_time)
    do ip = 1, p%np
      if (any(p%x(:, ip) < load%lower) .or. any(p%x(:, ip) > load%upper)) cycle
      power = power + ramp * p%volume(ip) / load%thickness * dot_product(load%traction, &
        p%v(:, ip))
    end do
  end function surface_load_power
end module mpm_loads
