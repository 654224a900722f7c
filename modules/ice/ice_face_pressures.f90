!> Face pressures of the momentum equation (paper eq. 37):
!! p_f = (p_L rho_R + p_R rho_L)/(rho_L + rho_R), rho = sum_m rho_bar_m (per pore volume with a
!! solid phase); the domain faces take the open face's pressure or, at a wall, the inner cell's
!! extrapolated hydrostatically.
module ice_face_pressures
  use mpmice_kinds, only: wp
  use grid_layout, only: grid_t
  use grid_sweep, only: sweep_direction
  use ice_state, only: ice_state_t
  use ice_solid_view, only: ice_solid_view_t
  use ice_face_velocity, only: face_range, held_plane
  use ice_pressure, only: pore_min
  implicit none
  private

  public :: ice_face_pressure

contains

  !> Face pressures of eq. 37 (weights: total bulk density of the fluids of the two cells, per
  !! pore volume 1 - phi_s where a solid phase is present); a wall face takes the pressure of its
  !! inner cell extrapolated hydrostatically, p_c -+ rho_c g dx/2 with the same density, so that
  !! the wall carries the weight of a fluid at rest (in a porous cell the fluid's intrinsic
  !! density: the bulk one left the wall cells of a porous cavity 0.3 g out of balance, whose drag
  !! heated the water by 0.03 K per day). Needs the pressure valid in one ghost layer.
  subroutine ice_face_pressure(state, grid, gravity, solid)
    type(ice_state_t), intent(inout) :: state  !< fluids and pressure fields
    type(grid_t), intent(in) :: grid           !< block geometry
    real(wp), intent(in) :: gravity(3)         !< gravitational acceleration [m/s^2]
    !> the solid phase of a coupled scene: the weights per pore volume
    class(ice_solid_view_t), intent(in), optional :: solid
    call face_pressures(state, grid, gravity, state%work%cell_weight, solid)
  end subroutine ice_face_pressure

  !> `ice_face_pressure` with the cells' weights as an explicit-shape argument (the state's work
  !! storage, not referenced through `state` here): each cell's weight once, then per face.
  subroutine face_pressures(state, grid, gravity, weight, solid)
    type(ice_state_t), intent(inout) :: state  !< fluids and pressure fields
    type(grid_t), intent(in) :: grid           !< block geometry
    real(wp), intent(in) :: gravity(3)         !< gravitational acceleration [m/s^2]
    !> work: the cells' weights rho (`cell_weight`) [kg/m^3]
    real(wp), intent(inout) :: weight(grid%lbc(1):grid%ubc(1), grid%lbc(2):grid%ubc(2), &
      grid%lbc(3):grid%ubc(3))
    !> the solid phase of a coupled scene: the weights per pore volume
    class(ice_solid_view_t), intent(in), optional :: solid
    integer :: d, i, j, k, o(3), r(2, 3), inner(2, 3), side, plane, lo(3), hi(3), s(3)
    real(wp) :: rl, rr, half

    ! the weights of the owned cells and of one ghost layer along the active axes (every face's
    ! two cells)
    lo = merge(grid%lo - 1, grid%lo, grid%active)
    hi = merge(grid%hi + 1, grid%hi, grid%active)
    do k = lo(3), hi(3)
      do j = lo(2), hi(2)
        do i = lo(1), hi(1)
          weight(i, j, k) = cell_weight(state, i, j, k, solid)
        end do
      end do
    end do
    do d = 1, 3
      if (.not. sweep_direction(grid, d, o)) cycle
      r = face_range(grid, d)
      ! inner faces: the faces on a non-periodic domain boundary are done below
      inner = r
      if (.not. grid%periodic(d)) then
        inner(1, d) = max(r(1, d), 2)
        inner(2, d) = min(r(2, d), grid%ncells(d))
      end if
      do k = inner(1, 3), inner(2, 3)
        do j = inner(1, 2), inner(2, 2)
          do i = inner(1, 1), inner(2, 1)
            rl = weight(i - o(1), j - o(2), k - o(3))
            rr = weight(i, j, k)
            state%pface(i, j, k, d) = (state%pressure(i - o(1), j - o(2), k - o(3)) * rr + &
              state%pressure(i, j, k) * rl) / (rl + rr)
          end do
        end do
      end do
      do side = 1, 2
        if (.not. held_plane(grid, d, r, side, lo, hi)) cycle
        plane = 2 * d - 2 + side
        if (.not. state%closed(plane)) then
          state%pface(lo(1):hi(1), lo(2):hi(2), lo(3):hi(3), d) = state%p_boundary(plane)
          cycle
        end if
        ! a wall: the inner cell (face - s) extrapolated by half a cell, -+ rho g dx / 2
        s = merge(0, 1, side == 1) * o
        half = merge(-0.5_wp, 0.5_wp, side == 1)
        do k = lo(3), hi(3)
          do j = lo(2), hi(2)
            do i = lo(1), hi(1)
              rl = weight(i - o(1), j - o(2), k - o(3))
              rr = weight(i, j, k)
              state%pface(i, j, k, d) = state%pressure(i - s(1), j - s(2), k - s(3)) + &
                half * merge(rr, rl, side == 1) * gravity(d) * grid%dx(d)
            end do
          end do
        end do
      end do
    end do
  end subroutine face_pressures

  !> Weight of cell (i, j, k) in the face pressures [kg/m^3]: the fluids' total bulk density
  !! sum_m rho_bar_m, per pore volume max(1 - phi_s, `pore_min`) where a solid phase is present
  !! (the pore pressure at rest carries the weight of the fluid alone, rho_f g; the skeleton's
  !! weight is borne by its stress).
  pure real(wp) function cell_weight(state, i, j, k, solid) result(w)
    type(ice_state_t), intent(in) :: state  !< fluids
    integer, intent(in) :: i, j, k          !< cell
    class(ice_solid_view_t), intent(in), optional :: solid !< solid phase of a coupled scene
    integer :: m
    w = 0.0_wp
    do m = 1, state%nfluids
      w = w + state%fluid(m)%rho(i, j, k)
    end do
    if (present(solid)) w = w / max(1.0_wp - solid%vfrac(i, j, k), pore_min)
  end function cell_weight
end module ice_face_pressures
