!> Face-centred fluid velocities before the pressure correction (paper eqs. 30-31): the
!! mass-weighted average of the two cell velocities, the equilibration-pressure gradient scaled
!! by the harmonic mean of the intrinsic specific volumes, and gravity. The viscous term of
!! eq. 30 is zero at faces (as the paper and Uintah's computeVelFace take it; errata E4 moot).
!!
!! Faces on a non-periodic domain boundary (`&boundary`, `ice_bc`): 'wall' and 'free_slip' carry
!! zero normal velocity; 'inflow' the normal component of the prescribed velocity for every
!! fluid; 'outflow' and 'pressure' faces are computed like inner faces from the ghost cells
!! (even for outflow). Without the face conditions (`bc` absent) every closed face gets zero.
!! Departure: where a fluid has mass on one side of a face only, its face specific volume is that
!! side's (not the harmonic mean with the EOS value of the empty side); this keeps a fluid at
!! rest across an air-water interface that lies on a face in exact discrete balance (the
!! hydrostatic initialisation of `ice_initial` uses the mixture densities of the two cells).
module ice_face_velocity
  use mpmice_kinds, only: wp
  use grid_layout, only: grid_t
  use ice_state, only: ice_state_t
  use ice_bc, only: ice_bc_t, bc_inflow, bc_outflow
  use grid_sweep, only: sweep_direction
  implicit none
  private

  public :: ice_face_velocities, boundary_face, closed_face, face_index, face_range, upwind
  public :: open_face_range, open_face_sweep, held_plane

contains

  !> u*_f for every fluid on the faces of the owned cells (faces lo..hi+1 in each active
  !! direction), and the face specific volume v_hat = 2 v_L v_R / (v_L + v_R) (eq. 31).
  !! Needs the cell fields (and pressure) valid in one ghost layer. `bc`: the face conditions;
  !! without them every closed boundary face (`closed_face`) has zero velocity. `advect`
  !! (default false): the face velocity is the prediction at time n + dt of the velocity at the
  !! face, so it also carries the advective change -dt (u.grad) u_d (departure from eq. 30, used
  !! with `time_theta` < 1, where dt is theta times the step: docs/ice.md): the normal part from
  !! the compact difference across the face, the transverse parts from the mean of the two
  !! cells' central differences and velocities; only where the fluid has mass on both sides.
  subroutine ice_face_velocities(state, grid, dt, gravity, bc, advect)
    type(ice_state_t), intent(inout) :: state   !< fluids (uface, vface written)
    type(grid_t), intent(in) :: grid            !< block geometry
    real(wp), intent(in) :: dt                  !< time over which the face velocity acts [s]
    real(wp), intent(in) :: gravity(3)          !< gravitational acceleration [m/s^2]
    type(ice_bc_t), intent(in), optional :: bc  !< conditions of the domain faces
    logical, intent(in), optional :: advect     !< add the advective change (see above)
    integer :: d, m, i, j, k, o(3), r(2, 3), fb, e, oe(3), plane_lo(3), plane_hi(3), face_kind
    real(wp) :: rl, rr, vl, vr, vhat, convect, u_closed
    logical :: with_advection

    with_advection = .false.
    if (present(advect)) with_advection = advect

    do d = 1, 3
      if (.not. sweep_direction(grid, d, o)) cycle
      r = face_range(grid, d)
      do m = 1, state%nfluids
        associate (f => state%fluid(m))
          do k = r(1, 3), r(2, 3)
            do j = r(1, 2), r(2, 2)
              do i = r(1, 1), r(2, 1)
                vl = f%spvol(i - o(1), j - o(2), k - o(3))
                vr = f%spvol(i, j, k)
                rl = f%rho(i - o(1), j - o(2), k - o(3))
                rr = f%rho(i, j, k)
                ! a fluid absent on one side takes the specific volume of the side it fills
                if (rl > 0.0_wp .and. rr <= 0.0_wp) then
                  vhat = vl
                else if (rr > 0.0_wp .and. rl <= 0.0_wp) then
                  vhat = vr
                else
                  vhat = 2.0_wp * vl * vr / (vl + vr)
                end if
                f%vface(i, j, k, d) = vhat
                if (rl + rr > 0.0_wp) then
                  f%uface(i, j, k, d) = (rl * f%vel(i - o(1), j - o(2), k - o(3), d) + &
                    rr * f%vel(i, j, k, d)) / (rl + rr)
                else
                  f%uface(i, j, k, d) = 0.0_wp
                end if
                if (with_advection .and. rl > 0.0_wp .and. rr > 0.0_wp) then
                  ! - dt (u.grad) u_d at the face
                  convect = f%uface(i, j, k, d) * (f%vel(i, j, k, d) - &
                    f%vel(i - o(1), j - o(2), k - o(3), d)) / grid%dx(d)
                  do e = 1, 3
                    if (e == d .or. .not. grid%active(e)) cycle
                    oe = 0
                    oe(e) = 1
                    convect = convect + 0.5_wp * (f%vel(i, j, k, e) + &
                      f%vel(i - o(1), j - o(2), k - o(3), e)) * 0.25_wp * &
                      (f%vel(i + oe(1), j + oe(2), k + oe(3), d) - &
                      f%vel(i - oe(1), j - oe(2), k - oe(3), d) + &
                      f%vel(i - o(1) + oe(1), j - o(2) + oe(2), k - o(3) + oe(3), d) - &
                      f%vel(i - o(1) - oe(1), j - o(2) - oe(2), k - o(3) - oe(3), d)) / grid%dx(e)
                  end do
                  f%uface(i, j, k, d) = f%uface(i, j, k, d) - dt * convect
                end if
                ! eq. 31: - dt v_hat (p_R - p_L)/dx + dt g
                f%uface(i, j, k, d) = f%uface(i, j, k, d) + dt * (-vhat * (state%pressure(i, j, k) &
                  - state%pressure(i - o(1), j - o(2), k - o(3))) / grid%dx(d) + gravity(d))
              end do
            end do
          end do
          ! closed domain faces (whole planes, computed like inner faces above): 'inflow' takes
          ! the prescribed velocity, the same for every fluid (the pressure does not correct
          ! it); 'outflow' stays an inner face with the (even) ghost state; any other is 0
          do e = 1, 2
            fb = 2 * d - 2 + e
            if (grid%periodic(d) .or. .not. state%closed(fb)) cycle
            plane_lo = r(1, :)
            plane_hi = r(2, :)
            plane_lo(d) = merge(1, grid%ncells(d) + 1, e == 1)
            plane_hi(d) = plane_lo(d)
            if (plane_lo(d) < r(1, d) .or. plane_lo(d) > r(2, d)) cycle
            face_kind = 0
            if (present(bc)) face_kind = bc%fluid(fb)
            if (face_kind == bc_outflow) cycle
            u_closed = 0.0_wp
            if (face_kind == bc_inflow) u_closed = bc%u_in(d, fb)
            f%uface(plane_lo(1):plane_hi(1), plane_lo(2):plane_hi(2), &
              plane_lo(3):plane_hi(3), d) = u_closed
          end do
        end associate
      end do
    end do
  end subroutine ice_face_velocities

  !> Index range (lower/upper, per dimension) of the faces in direction `d` of the owned cells.
  pure function face_range(grid, d) result(r)
    type(grid_t), intent(in) :: grid  !< block geometry
    integer, intent(in) :: d          !< face direction
    integer :: r(2, 3)
    r(1, :) = grid%lo
    r(2, :) = grid%hi
    r(2, d) = grid%hi(d) + 1
  end function face_range

  !> `face_range` without the closed domain planes (`closed_face`): the open faces of direction
  !! `d` of the owned cells (empty where none).
  pure function open_face_range(state, grid, d) result(r)
    type(ice_state_t), intent(in) :: state  !< fluids (closed faces)
    type(grid_t), intent(in) :: grid        !< block geometry
    integer, intent(in) :: d                !< face direction
    integer :: r(2, 3)
    r = face_range(grid, d)
    if (grid%periodic(d)) return
    if (state%closed(2 * d - 1) .and. r(1, d) == 1) r(1, d) = 2
    if (state%closed(2 * d) .and. r(2, d) == grid%ncells(d) + 1) r(2, d) = grid%ncells(d)
  end function open_face_range

  !> True when direction `d` is active (`sweep_direction`): sets its unit offset `o` and the
  !! range `r` of its open faces (`open_face_range`), so that a sweep over the open faces reads
  !! `do d = 1, 3`, `if (.not. open_face_sweep(state, grid, d, o, r)) cycle` and the loops over
  !! `r` (the face (i,j,k) lies between cells (i,j,k) - o and (i,j,k)).
  logical function open_face_sweep(state, grid, d, o, r) result(active)
    type(ice_state_t), intent(in) :: state  !< fluids (closed faces)
    type(grid_t), intent(in) :: grid        !< block geometry
    integer, intent(in) :: d                !< face direction
    integer, intent(out) :: o(3)            !< unit offset of d
    integer, intent(out) :: r(2, 3)         !< range of the open faces
    active = sweep_direction(grid, d, o)
    r = open_face_range(state, grid, d)
  end function open_face_sweep

  !> True when the non-periodic domain plane of direction `d` on `side` (1 low, 2 high) lies in
  !! this rank's face range `r` and, if `flags` is given, its domain face (1..6, `face_index`)
  !! is flagged (e.g. open: `.not. ice_state_t%closed`; a loading platen:
  !! `ice_solid_view_t%platen`); `lo`, `hi`: its faces (else the whole range).
  logical function held_plane(grid, d, r, side, lo, hi, flags)
    type(grid_t), intent(in) :: grid        !< block geometry
    integer, intent(in) :: d                !< face direction
    integer, intent(in) :: r(2, 3)          !< face range of this rank
    integer, intent(in) :: side             !< 1: low plane, 2: high plane
    integer, intent(out) :: lo(3), hi(3)    !< face range of the plane
    logical, intent(in), optional :: flags(6)  !< the domain faces that count
    integer :: idx
    held_plane = .false.
    lo = r(1, :)
    hi = r(2, :)
    if (grid%periodic(d)) return
    idx = merge(1, grid%ncells(d) + 1, side == 1)
    if (idx < r(1, d) .or. idx > r(2, d)) return
    lo(d) = idx
    hi(d) = idx
    held_plane = .true.
    if (present(flags)) held_plane = flags(2 * d - 2 + side)
  end function held_plane

  !> True for a face in direction `d` at index `idx` that lies on a non-periodic domain boundary.
  pure logical function boundary_face(grid, d, idx)
    type(grid_t), intent(in) :: grid  !< block geometry
    integer, intent(in) :: d          !< face direction
    integer, intent(in) :: idx(3)     !< face index (low face of cell idx)
    boundary_face = .not. grid%periodic(d) .and. (idx(d) == 1 .or. idx(d) == grid%ncells(d) + 1)
  end function boundary_face

  !> Domain face 1..6 (x-, x+, y-, y+, z-, z+) of a boundary face in direction `d` at `idx`.
  pure integer function face_index(d, idx)
    integer, intent(in) :: d          !< face direction
    integer, intent(in) :: idx(3)     !< face index
    face_index = 2 * d - 1
    if (idx(d) /= 1) face_index = 2 * d
  end function face_index

  !> True for a boundary face whose velocity the pressure correction leaves alone (homogeneous
  !! Neumann on dp, the face absent from the operator of eq. 35): 'wall', 'free_slip' (no fluid
  !! crosses), 'inflow' (prescribed velocity) and 'outflow' (zero gradient); false inside the
  !! domain and on an open ('pressure') face.
  pure logical function closed_face(state, grid, d, idx)
    type(ice_state_t), intent(in) :: state  !< fluids (closed faces)
    type(grid_t), intent(in) :: grid        !< block geometry
    integer, intent(in) :: d                !< face direction
    integer, intent(in) :: idx(3)           !< face index
    closed_face = .false.
    if (boundary_face(grid, d, idx)) closed_face = state%closed(face_index(d, idx))
  end function closed_face

  !> Upwind value of a face quantity: `left` for u >= 0, `right` otherwise.
  pure real(wp) function upwind(u, left, right)
    real(wp), intent(in) :: u      !< face velocity [m/s]
    real(wp), intent(in) :: left   !< value in the low cell
    real(wp), intent(in) :: right  !< value in the high cell
    if (u >= 0.0_wp) then
      upwind = left
    else
      upwind = right
    end if
  end function upwind
end module ice_face_velocity
