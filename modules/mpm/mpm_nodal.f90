!> Nodal solve of one solid material (eqs. 40-41 and 69): velocity v^n = p_i / m_i, acceleration
!! a = (f_int + m g - local damping) / m, v^L = v^n + a dt, then the boundary conditions on the
!! domain faces, and a = (v^L - v^n) / dt (eq. 69) so that G2P sees the constrained motion.
!!
!! Boundary conditions per face (`&boundary solid`): fixed (v = 0), roller (normal component 0,
!! free slip), free (nothing), velocity (v = prescribed), applied on the face nodes and on the
!! ghost nodes beyond the face. Inactive dimensions carry no motion. A prescribed velocity is
!! constant (`solid_velocity`) or a piecewise-linear history in time (`solid_velocity_times`,
!! `solid_velocity_history`), evaluated by `nodal_bc_at_time` at the end of the step, t + dt,
!! so that v^L and a = (v^L - v^n)/dt carry the face to its velocity at t + dt.
!! Nodes touched by a rigid material (`q(node_rigid_mass) > 0`) take its velocity before the face
!! conditions (`&mpm rigid_contact = 'no_slip'`), or, with 'friction', keep the deformable material's velocity
!! except where it approaches the rigid body: then the normal relative velocity is removed and the
!! tangential one reduced by Coulomb friction mu |dv_n| (stick when smaller), the normal the rigid
!! body's grad m / |grad m|, with `&mpm contact_normal = 'smoothed'` smoothed over the
!! neighbouring nodes (`contact_normal`, `rigid_contact_velocity`).
!! Local (Cundall) damping: f <- f - alpha |f| sign(v) per component, in `nodal_solve` on the
!! solid's internal force and weight, or in `nodal_damp` on a node's whole velocity increment of
!! the step (the coupled scene's `&mpm local_damping_force = 'total'`, after the fluids' forces).
!! Every allocated node is solved (ghost copies hold global values after the reverse halo), so no
!! exchange follows.
module mpm_nodal
  use mpmice_kinds, only: wp
  use grid_layout, only: grid_t
  use mpm_nodes, only: mpm_nodes_t, node_mass, node_momentum, node_force, node_rigid_mass, &
    node_rigid_momentum, node_rigid_gradient
  implicit none
  private

  public :: nodal_bc_t, nodal_solve, nodal_finish, bc_kind_from_name, rigid_contact_velocity
  public :: face_load_power, nodal_bc_at_time, history_velocity, nodal_damp
  public :: bc_fixed, bc_roller, bc_free, bc_velocity, bc_traction

  integer, parameter :: bc_fixed = 1     !< no motion
  integer, parameter :: bc_roller = 2    !< no normal motion
  integer, parameter :: bc_free = 3      !< traction free
  integer, parameter :: bc_velocity = 4  !< prescribed velocity
  integer, parameter :: bc_traction = 5  !< prescribed surface load, otherwise free
  !> the `&boundary solid` names of the conditions, in their order
  character(len=*), parameter :: bc_names(5) = [character(len=8) :: 'fixed', 'roller', 'free', &
    'velocity', 'traction']

  integer, parameter :: max_points = 64  !< most points of a velocity history
  !> A rigid mass gradient below this times m / dx is round-off, not a surface (`contact_normal`)
  real(wp), parameter :: normal_floor = 1.0e-10_wp

  !> Solid boundary conditions on the six faces (x-, x+, y-, y+, z-, z+).
  type :: nodal_bc_t
    integer :: kind(6) = bc_fixed              !< condition per face
    real(wp) :: velocity(3, 6) = 0.0_wp        !< prescribed velocity per face [m/s]
    integer :: npoints(6) = 0                  !< points of the face's velocity history (0: the
                                               !! constant `velocity`)
    real(wp) :: times(max_points, 6) = 0.0_wp  !< history times per face [s]
    real(wp) :: history(3, max_points, 6) = 0.0_wp !< history velocities per face [m/s]
    real(wp) :: traction(3, 6) = 0.0_wp        !< surface load per face [Pa]
    logical :: friction_contact = .false.      !< frictional contact with rigid bodies (else
                                               !! no-slip)
    real(wp) :: friction = 0.0_wp              !< Coulomb coefficient mu of that contact [-]
    logical :: smoothed_normal = .false.       !< the contact's normal smoothed over the
                                               !! neighbouring nodes (`contact_normal`)
  end type nodal_bc_t

contains

  !> Condition id of a `&boundary solid` value (unknown names: fixed).
  pure integer function bc_kind_from_name(name) result(kind)
    character(len=*), intent(in) :: name  !< namelist value
    kind = max(findloc(bc_names, name, dim=1), bc_fixed)
  end function bc_kind_from_name

  !> Velocity [m/s] of a piecewise-linear history at time `t`: linear between the points
  !! (`times` strictly increasing), held at the first value before `times(1)` and at the last
  !! after `times(n)`.
  pure function history_velocity(times, values, t) result(v)
    real(wp), intent(in) :: times(:)      !< history times, n >= 1 [s]
    real(wp), intent(in) :: values(:, :)  !< velocity at each time, (3, n) [m/s]
    real(wp), intent(in) :: t             !< time [s]
    real(wp) :: v(3)
    integer :: n, j
    real(wp) :: w
    n = size(times)
    if (t <= times(1)) then
      v = values(:, 1)
      return
    end if
    if (t >= times(n)) then
      v = values(:, n)
      return
    end if
    j = 1
    do while (times(j + 1) < t)
      j = j + 1
    end do
    w = (t - times(j)) / (times(j + 1) - times(j))
    v = (1.0_wp - w) * values(:, j) + w * values(:, j + 1)
  end function history_velocity

  !> The prescribed velocities of the faces with a velocity history set to their value at `t`
  !! (the end of the step); faces without one keep their constant velocity.
  pure subroutine nodal_bc_at_time(bc, t)
    type(nodal_bc_t), intent(inout) :: bc  !< boundary conditions
    real(wp), intent(in) :: t              !< time [s]
    integer :: face, n
    do face = 1, 6
      n = bc%npoints(face)
      if (n < 1) cycle
      bc%velocity(:, face) = history_velocity(bc%times(1:n, face), bc%history(:, 1:n, face), t)
    end do
  end subroutine nodal_bc_at_time

  !> Solve every allocated node: `nodes%q` (after P2G) gives `vel`, `vel_l`, `acc`. With
  !! `contact_dv` (the coupled scene, frictional contact) a contact node only loses the normal
  !! velocity with which it approaches the rigid body here, and `contact_dv` records what was
  !! removed: the friction follows in `nodal_finish` once the fluid's forces are known. With
  !! `contact_accel` (the acceleration the fluid's pressure is expected to add) the approach is
  !! judged on v + dt a, so that the face velocities the pressure equation sees already obey
  !! the contact (a buoyant soil resting on the bed neither lifts nor sinks there).
  pure subroutine nodal_solve(nodes, grid, gravity, damping, dt, bc, min_mass, contact_dv, &
    contact_accel)
    type(mpm_nodes_t), intent(inout) :: nodes  !< node fields
    type(grid_t), intent(in) :: grid           !< block geometry
    real(wp), intent(in) :: gravity(3)         !< body acceleration at this step [m/s^2]
    real(wp), intent(in) :: damping            !< local damping factor alpha [-]
    real(wp), intent(in) :: dt                 !< step [s]
    type(nodal_bc_t), intent(in) :: bc         !< boundary conditions
    real(wp), intent(in) :: min_mass           !< nodes lighter than this are empty [kg]
    real(wp), intent(inout), optional :: contact_dv(:, grid%lbn(1):, grid%lbn(2):, &
      grid%lbn(3):)                            !< velocity removed by the contact [m/s]
    real(wp), intent(in), optional :: contact_accel(:, grid%lbn(1):, grid%lbn(2):, &
      grid%lbn(3):)                            !< expected fluid acceleration [m/s^2]
    integer :: i, j, k
    real(wp) :: m, v(3), f(3), vl(3), on(3), mu, vt(3)
    on = merge(1.0_wp, 0.0_wp, grid%active)
    mu = bc%friction
    if (present(contact_dv)) then
      contact_dv = 0.0_wp
      mu = 0.0_wp
    end if
    do k = grid%lbn(3), grid%ubn(3)
      do j = grid%lbn(2), grid%ubn(2)
        do i = grid%lbn(1), grid%ubn(1)
          m = nodes%q(node_mass, i, j, k)
          if (m <= min_mass .and. nodes%q(node_rigid_mass, i, j, k) <= min_mass) then
            nodes%vel(:, i, j, k) = 0.0_wp
            nodes%vel_l(:, i, j, k) = 0.0_wp
            nodes%acc(:, i, j, k) = 0.0_wp
            cycle
          end if
          if (m > min_mass) then
            v = nodes%q(node_momentum:node_momentum + 2, i, j, k) / m
            f = nodes%q(node_force:node_force + 2, i, j, k) + m * gravity + &   ! eq. 40
              face_load(grid, bc, [i, j, k])
            if (damping > 0.0_wp) f = f - cundall_damping(damping, f, v)
            vl = (v + f / m * dt) * on                               ! eq. 41
          else
            v = 0.0_wp
            vl = 0.0_wp
          end if
          ! a node touched by a rigid body moves with it (no-slip contact) or slides on it
          if (nodes%q(node_rigid_mass, i, j, k) > min_mass) then
            if (bc%friction_contact .and. m > min_mass) then
              f = 0.0_wp
              if (present(contact_accel)) f = dt * contact_accel(:, i, j, k) * on
              vt = vl
              vl = rigid_contact_velocity(vl + f, nodes%q(node_rigid_momentum: &
                node_rigid_momentum + 2, i, j, k) / nodes%q(node_rigid_mass, i, j, k) * on, &
                contact_normal(nodes%q, grid, [i, j, k], bc%smoothed_normal) * on, &
                mu) - f
              if (present(contact_dv)) contact_dv(:, i, j, k) = vt - vl
            else
              vl = nodes%q(node_rigid_momentum:node_rigid_momentum + 2, i, j, k) / &
                nodes%q(node_rigid_mass, i, j, k) * on
            end if
          end if
          call apply_face_bc(grid, bc, [i, j, k], on, vl)
          nodes%vel(:, i, j, k) = v
          nodes%vel_l(:, i, j, k) = vl
          nodes%acc(:, i, j, k) = (vl - v) / dt                    ! eq. 69
        end do
      end do
    end do
  end subroutine nodal_solve

  !> Local (Cundall) damping of the whole increment v^L - v^n of the step, after the coupled
  !! scene has added the fluids' pressure force and drag to v^L: with the node's unbalanced
  !! force f = m (v^L - v^n) / dt, v^L <- v^L - alpha |f| sign(v^n) dt / m per component, i.e.
  !! v^L <- v^L - alpha |v^L - v^n| sign(v^n),
  !! the force of `nodal_solve`'s damping, which then vanishes where the node is at rest under
  !! all its forces (a submerged soil: its effective stress, weight, buoyancy and drag). Nodes
  !! that a rigid body moves are left alone; `nodal_finish` applies the boundary conditions.
  pure subroutine nodal_damp(nodes, grid, alpha, min_mass)
    type(mpm_nodes_t), intent(inout) :: nodes  !< node fields (vel, vel_l)
    type(grid_t), intent(in) :: grid           !< block geometry
    real(wp), intent(in) :: alpha              !< local damping factor [-]
    real(wp), intent(in) :: min_mass           !< nodes lighter than this are empty [kg]
    integer :: i, j, k
    real(wp) :: v(3), dv(3)
    do k = grid%lbn(3), grid%ubn(3)
      do j = grid%lbn(2), grid%ubn(2)
        do i = grid%lbn(1), grid%ubn(1)
          if (nodes%q(node_mass, i, j, k) <= min_mass) cycle
          if (nodes%q(node_rigid_mass, i, j, k) > min_mass) cycle
          v = nodes%vel(:, i, j, k)
          dv = nodes%vel_l(:, i, j, k) - v
          nodes%vel_l(:, i, j, k) = nodes%vel_l(:, i, j, k) - cundall_damping(alpha, dv, v)
        end do
      end do
    end do
  end subroutine nodal_damp

  !> Local (Cundall) damping of `x` (a nodal force or velocity increment) against the node's
  !! velocity v, per component: alpha |x| sign(v), 0 where v = 0.
  elemental real(wp) function cundall_damping(alpha, x, v) result(damp)
    real(wp), intent(in) :: alpha  !< local damping factor [-]
    real(wp), intent(in) :: x      !< damped quantity
    real(wp), intent(in) :: v      !< velocity [m/s]
    damp = alpha * abs(x) * merge(sign(1.0_wp, v), 0.0_wp, v /= 0.0_wp)
  end function cundall_damping

  !> After velocity increments were added to v^L (the coupled scene's pressure and drag,
  !! eqs. 66-67 with E5): the face conditions again and eq. 69 a = (v^L - v^n)/dt, on every
  !! node that holds deformable mass and no rigid mass. With `contact_dv` (frictional contact,
  !! `nodal_solve`) the contact nodes too: the velocity the first pass removed is added back and
  !! the contact applied once to the velocity with every force, so that the friction sees the
  !! full normal load (the buoyant weight under water: the fluid's pressure force lifts).
  !! `contact_force` gets the force the deformable material exerts on the rigid bodies there,
  !! m (v - v_contact) / dt (zero elsewhere).
  pure subroutine nodal_finish(nodes, grid, dt, bc, min_mass, contact_dv, contact_force)
    type(mpm_nodes_t), intent(inout) :: nodes  !< node fields
    type(grid_t), intent(in) :: grid           !< block geometry
    real(wp), intent(in) :: dt                 !< step [s]
    type(nodal_bc_t), intent(in) :: bc         !< boundary conditions
    real(wp), intent(in) :: min_mass           !< nodes lighter than this are empty [kg]
    real(wp), intent(in), optional :: contact_dv(:, grid%lbn(1):, grid%lbn(2):, &
      grid%lbn(3):)                            !< velocity removed by `nodal_solve` [m/s]
    real(wp), intent(out), optional :: contact_force(:, grid%lbn(1):, grid%lbn(2):, &
      grid%lbn(3):)                            !< force on the rigid bodies per node [N]
    integer :: i, j, k
    real(wp) :: on(3), vl(3), vt(3)
    logical :: contact
    on = merge(1.0_wp, 0.0_wp, grid%active)
    contact = present(contact_dv) .and. bc%friction_contact
    if (present(contact_force)) contact_force = 0.0_wp
    do k = grid%lbn(3), grid%ubn(3)
      do j = grid%lbn(2), grid%ubn(2)
        do i = grid%lbn(1), grid%ubn(1)
          if (nodes%q(node_mass, i, j, k) <= min_mass) cycle
          if (nodes%q(node_rigid_mass, i, j, k) > min_mass) then
            if (.not. contact) cycle
            vt = (nodes%vel_l(:, i, j, k) + contact_dv(:, i, j, k)) * on
            vl = rigid_contact_velocity(vt, nodes%q(node_rigid_momentum: &
              node_rigid_momentum + 2, i, j, k) / nodes%q(node_rigid_mass, i, j, k) * on, &
              contact_normal(nodes%q, grid, [i, j, k], bc%smoothed_normal) * on, &
              bc%friction)
            if (present(contact_force)) contact_force(:, i, j, k) = nodes%q(node_mass, i, j, k) * &
              (vt - vl) / dt
          else
            vl = nodes%vel_l(:, i, j, k) * on
          end if
          call apply_face_bc(grid, bc, [i, j, k], on, vl)
          nodes%vel_l(:, i, j, k) = vl
          nodes%acc(:, i, j, k) = (vl - nodes%vel(:, i, j, k)) / dt
        end do
      end do
    end do
  end subroutine nodal_finish

  !> This rank's power [W] of the domain-face surface loads (`&boundary solid = 'traction'`) on
  !! the velocities v^L of the owned nodes (those of the last step).
  pure real(wp) function face_load_power(nodes, grid, bc, min_mass) result(power)
    type(mpm_nodes_t), intent(in) :: nodes     !< node fields
    type(grid_t), intent(in) :: grid           !< block geometry
    type(nodal_bc_t), intent(in) :: bc         !< boundary conditions
    real(wp), intent(in) :: min_mass           !< nodes lighter than this are empty [kg]
    integer :: i, j, k
    power = 0.0_wp
    if (.not. any(bc%kind == bc_traction)) return
    do k = grid%nlo(3), grid%nhi(3)
      do j = grid%nlo(2), grid%nhi(2)
        do i = grid%nlo(1), grid%nhi(1)
          if (nodes%q(node_mass, i, j, k) <= min_mass) cycle
          power = power + dot_product(face_load(grid, bc, [i, j, k]), nodes%vel_l(:, i, j, k))
        end do
      end do
    end do
  end function face_load_power

  !> External force [N] on node `idx` from the surface loads of the domain faces it lies on:
  !! traction times the node's share of the face area (halved at the face's edges).
  pure function face_load(grid, bc, idx) result(f)
    type(grid_t), intent(in) :: grid           !< block geometry
    type(nodal_bc_t), intent(in) :: bc         !< boundary conditions
    integer, intent(in) :: idx(3)              !< node index
    real(wp) :: f(3)
    integer :: face, d, e
    real(wp) :: area
    f = 0.0_wp
    do face = 1, 6
      if (bc%kind(face) /= bc_traction) cycle
      d = (face + 1) / 2
      if (.not. grid%active(d) .or. grid%periodic(d)) cycle
      if (mod(face, 2) == 1) then
        if (idx(d) /= 1) cycle
      else
        if (idx(d) /= grid%ncells(d) + 1) cycle
      end if
      area = 1.0_wp
      do e = 1, 3
        if (e == d) cycle
        area = area * grid%dx(e)
        if (grid%active(e) .and. .not. grid%periodic(e) .and. (idx(e) == 1 .or. &
          idx(e) == grid%ncells(e) + 1)) area = 0.5_wp * area
      end do
      f = f + bc%traction(:, face) * area * merge(1.0_wp, 0.0_wp, grid%active)
    end do
  end function face_load

  !> Contact normal direction [kg/m] (not normalised) at node `idx`: the rigid mass gradient
  !! grad m_i = sum_p m_p grad S_i(x_p), with `smoothed` (`&mpm contact_normal = 'smoothed'`)
  !! smoothed over the node's neighbours with the weights
  !! (1, 2, 1) per active dimension, n_i = sum_{|d| <= 1} w_d grad m_{i+d} (the 3 x 3 nodes in 2D),
  !! neighbours outside a non-periodic domain left out. A rigid body seeded as particles on a
  !! surface not aligned with the grid has a staircase of particles along it, and the nodal
  !! gradient's direction scatters about the surface normal by ~20 deg RMS; the smoothed one by
  !! ~2 deg (docs/validation/mpm_friction.md, postproc/mpm_slope_contact.py). On a surface along
  !! the grid the neighbours' gradients are parallel and the direction is the node's own. Every
  !! node a particle reads has its neighbours within the ghost layers (ng >= 1 linear, 2 GIMP).
  !! Inside a rigid body the particles' gradients cancel: grad m is zero but for round-off
  !! (~1e-15 m / dx), whose direction depends on the order of the sum (on the ranks' cut). A
  !! gradient below `normal_floor` m / dx (m the rigid mass summed with the same weights, dx the
  !! smallest active cell size) is taken as no normal, so that such a node is not judged against
  !! a random direction; a surface node's |grad m| is of order m / dx.
  pure function contact_normal(q, grid, idx, smoothed) result(n)
    type(grid_t), intent(in) :: grid           !< block geometry
    real(wp), intent(in) :: q(:, grid%lbn(1):, grid%lbn(2):, grid%lbn(3):) !< node fields
    integer, intent(in) :: idx(3)              !< node index
    logical, intent(in) :: smoothed            !< smooth (else the node's own grad m)
    real(wp) :: n(3)
    real(wp), parameter :: weight(-1:1) = [1.0_wp, 2.0_wp, 1.0_wp]
    integer :: lo(3), hi(3), d, i, j, k
    real(wp) :: m, w
    if (.not. smoothed) then
      n = q(node_rigid_gradient:node_rigid_gradient + 2, idx(1), idx(2), idx(3))
      m = q(node_rigid_mass, idx(1), idx(2), idx(3))
    else
      do d = 1, 3
        lo(d) = idx(d)
        hi(d) = idx(d)
        if (.not. grid%active(d)) cycle
        lo(d) = max(idx(d) - 1, grid%lbn(d))
        hi(d) = min(idx(d) + 1, grid%ubn(d))
        if (grid%periodic(d)) cycle
        lo(d) = max(lo(d), 1)
        hi(d) = min(hi(d), grid%ncells(d) + 1)
      end do
      n = 0.0_wp
      m = 0.0_wp
      do k = lo(3), hi(3)
        do j = lo(2), hi(2)
          do i = lo(1), hi(1)
            w = weight(i - idx(1)) * weight(j - idx(2)) * weight(k - idx(3))
            n = n + w * q(node_rigid_gradient:node_rigid_gradient + 2, i, j, k)
            m = m + w * q(node_rigid_mass, i, j, k)
          end do
        end do
      end do
    end if
    if (norm2(n) <= normal_floor * m / minval(grid%dx, mask=grid%active)) n = 0.0_wp
  end function contact_normal

  !> Velocity [m/s] of a deformable node in frictional contact with a rigid body: trial velocity
  !! `v`, rigid velocity `v_rigid`, rigid mass gradient `grad_m` = sum_p m_p grad S_i(x_p) (it
  !! points out of the body: S_i grows toward its node), so the outward normal is
  !! n = grad_m / |grad_m|; Coulomb coefficient `mu`. Approaching (dv . n < 0, dv = v - v_rigid):
  !! dv_n is removed and the tangential part dv_t shrinks by mu |dv . n| (to zero: stick);
  !! separating or without a normal: `v` unchanged.
  pure function rigid_contact_velocity(v, v_rigid, grad_m, mu) result(vc)
    real(wp), intent(in) :: v(3)        !< trial velocity of the deformable material [m/s]
    real(wp), intent(in) :: v_rigid(3)  !< rigid body velocity [m/s]
    real(wp), intent(in) :: grad_m(3)   !< rigid mass gradient [kg/m]
    real(wp), intent(in) :: mu          !< friction coefficient [-]
    real(wp) :: vc(3)
    real(wp) :: n(3), dv(3), dvn, dvt(3), st
    vc = v
    if (norm2(grad_m) <= 0.0_wp) return
    n = grad_m / norm2(grad_m)
    dv = v - v_rigid
    dvn = dot_product(dv, n)
    if (dvn >= 0.0_wp) return
    dvt = dv - dvn * n
    st = norm2(dvt)
    if (st <= mu * abs(dvn)) then
      vc = v_rigid
    else
      vc = v_rigid + dvt * (1.0_wp - mu * abs(dvn) / st)
    end if
  end function rigid_contact_velocity

  !> The `&boundary solid` conditions of the domain faces node `idx` lies on, applied to `vl`.
  pure subroutine apply_face_bc(grid, bc, idx, on, vl)
    type(grid_t), intent(in) :: grid           !< block geometry
    type(nodal_bc_t), intent(in) :: bc         !< boundary conditions
    integer, intent(in) :: idx(3)              !< node index
    real(wp), intent(in) :: on(3)              !< 1 in active dimensions, else 0
    real(wp), intent(inout) :: vl(3)           !< nodal velocity [m/s]
    integer :: face, d
    do face = 1, 6
      d = (face + 1) / 2
      if (.not. grid%active(d) .or. grid%periodic(d)) cycle
      if (mod(face, 2) == 1) then
        if (idx(d) > 1) cycle
      else
        if (idx(d) < grid%ncells(d) + 1) cycle
      end if
      select case (bc%kind(face))
      case (bc_fixed)
        vl = 0.0_wp
      case (bc_roller)
        vl(d) = 0.0_wp
      case (bc_velocity)
        vl = bc%velocity(:, face) * on
      case default
      end select
    end do
  end subroutine apply_face_bc
end module mpm_nodal
