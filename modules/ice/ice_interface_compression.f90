!> Interface compression between two fluids (`&ice interface_compression`, opt-in): after the
!! advection, a counter-flux at each face moves fluid a from the side poorer in a to the side
!! richer in it and the same volume of fluid b back, undoing part of the advection's numerical
!! diffusion of a free surface (the algebraic compression of volume-of-fluid codes, u_c =
!! C |u| n, written donor-acceptor so that it stays bounded):
!!
!!   F = min(C |u_f| dt / dx |n_d| phi_f (1 - phi_f), 0.8 min(phi_a,D, phi_b,A) / (2 n_dim)) V
!!
!! F [m^3] is the volume exchanged through the face, |u_f| the flow speed there (the larger of
!! the two fluids' mean cell speeds |u| of the two cells: the whole velocity, not its face-normal
!! part, so that an interface carried along itself, a free surface under a horizontal flow, is
!! compressed too), n_d the face-normal component of the unit normal of the interface (the gradient of
!! phi_a, its normal part from the two cells, the tangential parts their mean central
!! differences), phi_f the mean of the two cells' fractions of a, D the donor of a (the cell
!! with less a) and A the acceptor (the other, the donor of b). The cap vanishes where either
!! cell is pure in the fluid it would give, so nothing is created, and keeps the volume leaving
!! a cell through all its faces below 80 % of its content. Fluid a leaves D with D's density, velocity, temperature and specific
!! volume, fluid b leaves A with A's: mass and momentum are conserved exactly, the volume of
!! each cell to the fluids' compressibility (both move at their donor's density). The internal
!! energy moves with the mass; the potential energy that the exchange releases in a gravity
!! field is not added (the ICE scene's total-energy balance holds only with C = 0).
!! Free fluid only: faces with solid on either side are skipped (the pores keep the plain
!! advection). Needs the post-advection primitives valid in one ghost layer; leaves them on
!! the owned cells (the caller exchanges the halos again). Uses `cons` and the fluids' `lag`
!! as scratch (both are free after the advection).
module ice_interface_compression
  use mpmice_kinds, only: wp
  use grid_layout, only: grid_t
  use grid_sweep, only: sweep_direction
  use ice_state, only: ice_state_t
  use ice_solid_view, only: ice_solid_view_t
  implicit none
  private

  public :: compress_interface

contains

  !> Exchange the compression volumes (module header) between fluids 1 (a) and 2 (b).
  subroutine compress_interface(state, grid, dt, coefficient, solid)
    type(ice_state_t), intent(inout) :: state  !< fluids (primitives updated on owned cells)
    type(grid_t), intent(in) :: grid           !< block geometry
    real(wp), intent(in) :: dt                 !< time step [s]
    real(wp), intent(in) :: coefficient        !< C [-]
    !> the solid phase of a coupled scene: no compression next to it
    class(ice_solid_view_t), intent(in), optional :: solid
    integer :: i, j, k, d, m, o(3), nd, side, c(3), donor(3)
    real(wp) :: vol, cap, flux, dm, sgn, mass

    if (coefficient <= 0.0_wp .or. state%nfluids /= 2) return
    vol = grid%cell_volume
    nd = count(grid%active)
    ! at most 80 % of a donor's content leaves through all its faces together: the full
    ! content (1 / (2 n_dim) per face) left round-off negatives (-1.6e-24 kg/m^3 of a water
    ! mist of 2.7e-8), which broke the next equilibration
    cap = 0.4_wp / real(nd, wp)
    ! the volume of a moving from the low to the high cell of each low face (negative: from
    ! high to low), stored at the face's high cell: cons(:, :, :, d)
    state%cons(:, :, :, 1:3) = 0.0_wp
    do d = 1, 3
      if (.not. sweep_direction(grid, d, o)) cycle
      do k = grid%lo(3), grid%hi(3) + o(3)
        do j = grid%lo(2), grid%hi(2) + o(2)
          do i = grid%lo(1), grid%hi(1) + o(1)
            state%cons(i, j, k, d) = face_volume(state, grid, [i, j, k], d, o, dt, &
              coefficient, cap, solid) * vol
          end do
        end do
      end do
    end do
    ! old mass and specific values of every fluid (cells and ghosts) before any update
    do m = 1, 2
      associate (f => state%fluid(m))
        f%lag(:, :, :, 1:3) = f%vel
        f%lag(:, :, :, 4) = f%temp
        f%lag(:, :, :, 5) = f%spvol
        state%cons(:, :, :, 3 + m) = f%rho * vol
      end associate
    end do
    do m = 1, 2
      ! fluid a moves with +F, fluid b with -F
      sgn = merge(1.0_wp, -1.0_wp, m == 1)
      associate (f => state%fluid(m))
        do k = grid%lo(3), grid%hi(3)
          do j = grid%lo(2), grid%hi(2)
            do i = grid%lo(1), grid%hi(1)
              mass = state%cons(i, j, k, 3 + m)
              f%rho(i, j, k) = mass
              f%vel(i, j, k, :) = mass * f%lag(i, j, k, 1:3)
              f%temp(i, j, k) = mass * f%lag(i, j, k, 4)
              f%spvol(i, j, k) = mass * f%lag(i, j, k, 5)
              do d = 1, 3
                if (.not. grid%active(d)) cycle
                o = 0
                o(d) = 1
                do side = 0, 1
                  ! the low face (side 0) and the high face (side 1) of the cell
                  c = [i, j, k] + side * o
                  flux = sgn * state%cons(c(1), c(2), c(3), d)
                  if (flux == 0.0_wp) cycle
                  ! flux > 0: this fluid goes from the face's low cell to its high cell
                  donor = merge(c - o, c, flux > 0.0_wp)
                  dm = abs(flux) / f%lag(donor(1), donor(2), donor(3), 5)
                  ! into the cell through its low face / out of it through its high face
                  if ((side == 0) .eqv. (flux > 0.0_wp)) then
                    call carry(dm)
                  else
                    call carry(-dm)
                  end if
                end do
              end do
              mass = f%rho(i, j, k)
              if (mass > 0.0_wp) then
                f%vel(i, j, k, :) = f%vel(i, j, k, :) / mass
                f%temp(i, j, k) = f%temp(i, j, k) / mass
                f%spvol(i, j, k) = f%spvol(i, j, k) / mass
              else
                f%vel(i, j, k, :) = f%lag(i, j, k, 1:3)
                f%temp(i, j, k) = f%lag(i, j, k, 4)
                f%spvol(i, j, k) = f%lag(i, j, k, 5)
              end if
              f%rho(i, j, k) = mass / vol
            end do
          end do
        end do
      end associate
    end do

  contains

    !> Add the mass `dmass` [kg] (negative: remove it) with the donor's specific values to the
    !! cell's running totals (mass in rho, momentum in vel, mass x temperature in temp, volume
    !! in spvol).
    subroutine carry(dmass)
      real(wp), intent(in) :: dmass
      associate (f => state%fluid(m))
        f%rho(i, j, k) = f%rho(i, j, k) + dmass
        f%vel(i, j, k, :) = f%vel(i, j, k, :) + dmass * f%lag(donor(1), donor(2), donor(3), 1:3)
        f%temp(i, j, k) = f%temp(i, j, k) + dmass * f%lag(donor(1), donor(2), donor(3), 4)
        f%spvol(i, j, k) = f%spvol(i, j, k) + dmass * f%lag(donor(1), donor(2), donor(3), 5)
      end associate
    end subroutine carry
  end subroutine compress_interface

  !> The compression volume of the low face of cell c along d, over the cell volume (module
  !! header): > 0 moves fluid 1 from c - o to c. 0 at a domain face, next to solid, or where
  !! either cell is pure.
  real(wp) function face_volume(state, grid, c, d, o, dt, coefficient, cap, solid) &
    result(share)
    type(ice_state_t), intent(in) :: state  !< fluids
    type(grid_t), intent(in) :: grid        !< block geometry
    integer, intent(in) :: c(3)             !< the face's high cell
    integer, intent(in) :: d                !< face direction
    integer, intent(in) :: o(3)             !< unit offset along d
    real(wp), intent(in) :: dt              !< time step [s]
    real(wp), intent(in) :: coefficient     !< C [-]
    real(wp), intent(in) :: cap             !< 0.8 / (2 n_dim)
    class(ice_solid_view_t), intent(in), optional :: solid !< solid phase of a coupled scene
    real(wp), parameter :: trace = 1.0e-9_wp  !< smallest fraction jump compressed
    integer :: e, l(3)
    real(wp) :: a_lo, a_hi, grad(3), speed, normal
    share = 0.0_wp
    l = c - o
    if (.not. grid%periodic(d) .and. (c(d) == 1 .or. c(d) == grid%ncells(d) + 1)) return
    if (present(solid)) then
      if (solid%vfrac(l(1), l(2), l(3)) > 0.0_wp .or. &
        solid%vfrac(c(1), c(2), c(3)) > 0.0_wp) return
    end if
    a_lo = fraction_of(state, 1, l)
    a_hi = fraction_of(state, 1, c)
    ! no interface here (traces of 1e-9 and less are left to the advection)
    if (abs(a_hi - a_lo) <= trace) return
    grad = 0.0_wp
    grad(d) = (a_hi - a_lo) / grid%dx(d)
    do e = 1, 3
      if (e == d .or. .not. grid%active(e)) cycle
      grad(e) = 0.25_wp * (central(e, l) + central(e, c)) / grid%dx(e)
    end do
    normal = abs(grad(d)) / norm2(grad)
    speed = 0.0_wp
    do e = 1, 2
      speed = max(speed, 0.5_wp * (norm2(state%fluid(e)%vel(l(1), l(2), l(3), :)) + &
        norm2(state%fluid(e)%vel(c(1), c(2), c(3), :))))
    end do
    ! the compressive flux phi_f (1 - phi_f) C |u| n_d dt A (phi_f the face mean), at most
    ! the cap's share of fluid 1 in its donor and of fluid 2 in its donor
    share = min(coefficient * speed * dt / grid%dx(d) * normal * 0.5_wp * (a_lo + a_hi) * &
      (1.0_wp - 0.5_wp * (a_lo + a_hi)), cap * min(merge(a_lo, a_hi, a_hi > a_lo), &
      merge(fraction_of(state, 2, c), fraction_of(state, 2, l), a_hi > a_lo)))
    if (a_hi < a_lo) share = -share

  contains

    !> phi_1(x + e) - phi_1(x - e) around cell x along dimension e.
    real(wp) function central(e, x)
      integer, intent(in) :: e, x(3)
      integer :: u(3)
      u = 0
      u(e) = 1
      central = fraction_of(state, 1, x + u) - fraction_of(state, 1, x - u)
    end function central
  end function face_volume

  !> Volume fraction of fluid m in cell x after the advection: rho_bar v, in [0, 1].
  pure real(wp) function fraction_of(state, m, x) result(phi)
    type(ice_state_t), intent(in) :: state  !< fluids
    integer, intent(in) :: m                !< fluid
    integer, intent(in) :: x(3)             !< cell
    phi = min(max(state%fluid(m)%rho(x(1), x(2), x(3)) * state%fluid(m)%spvol(x(1), x(2), &
      x(3)), 0.0_wp), 1.0_wp)
  end function fraction_of
end module ice_interface_compression
