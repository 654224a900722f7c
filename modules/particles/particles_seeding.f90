!> Particle seeding of one solid from its `&solid` shape: `particles_per_cell` particles per cell
!! and dimension at the centres of the equal sub-cells of every owned cell, kept when the centre
!! lies inside the shape (box with optional rotation about z around its centre, polygon in x-y
!! given inline or read from `polygon_file`, half-space {x : (x - plane_point) . plane_normal
!! <= 0}, or the band between profiles read from files, `geometry_shapes`). Inactive dimensions
!! are ignored by the shape tests.
!!
!! Each particle gets volume V_c / prod(ppc), mass (1 - porosity) density V, the initial velocity
!! (uniform, or shaped by `velocity_wavenumber`),
!! temperature, F = I, the GIMP half-width dx/(2 ppc) and a global id from its global cell and
!! sub-cell index (the same at any rank count). With `geostatic`, the initial effective stress is
!! sigma_v = -(1 - n) rho |g| d along the gravity direction v, d the depth of the particle below
!! the shape's surface straight above it (`depth_below_surface`), and K0 sigma_v across it
!! (K0 = nu/(1-nu) when k0 < 0). The coupled scene then takes the pore fluid's buoyancy off
!! (mpmice `buoyant_geostatic_stress`).
module particles_seeding
  use mpmice_kinds, only: wp, i8
  use grid_layout, only: grid_t
  use config_materials, only: solid_params_t
  use particles_store, only: particles_t, particles_reserve, identity_f
  use geometry_shapes, only: file_shape_contains, shape_kind_polygon, shape_kind_profile
  implicit none
  private

  public :: seed_solid, inside_shape, seed_point

contains

  !> Seed the particles of solid `s` in this block's owned cells (appends to `p`).
  subroutine seed_solid(p, s, grid, gravity)
    type(particles_t), intent(inout) :: p      !< particle store
    type(solid_params_t), intent(in) :: s      !< `&solid` parameters
    type(grid_t), intent(in) :: grid           !< block geometry
    real(wp), intent(in) :: gravity(3)         !< gravitational acceleration [m/s^2]
    integer :: ppc(3), sub(3), i, j, k, m, n, dv, dd
    integer(i8) :: cell_id, nsub
    real(wp) :: xp(3), vol, rho, sv, k0, gmag
    call particles_reserve(p, max(p%np, 1))   ! arrays allocated even on a rank without particles
    ppc = merge(s%particles_per_cell, 1, grid%active)
    nsub = int(product(ppc), i8)
    vol = grid%cell_volume / real(product(ppc), wp)
    rho = (1.0_wp - s%porosity) * s%density
    p%half_width = 0.5_wp * grid%dx / real(ppc, wp)
    dv = maxloc(abs(gravity), dim=1)
    gmag = sqrt(sum(gravity**2))
    k0 = s%k0
    if (k0 < 0.0_wp) k0 = s%poisson_ratio / (1.0_wp - s%poisson_ratio)
    do k = grid%lo(3), grid%hi(3)
      do j = grid%lo(2), grid%hi(2)
        do i = grid%lo(1), grid%hi(1)
          cell_id = (int(k - 1, i8) * grid%ncells(2) + int(j - 1, i8)) * grid%ncells(1) + (i - 1)
          do m = 1, product(ppc)
            sub = sub_point(m, ppc)
            xp = seed_point(grid%lower, grid%dx, [i, j, k], sub, ppc)
            if (.not. inside_shape(s, grid%active, xp)) cycle
            call particles_reserve(p, p%np + 1)
            n = p%np + 1
            p%np = n
            p%x(:, n) = xp
            p%v(:, n) = merge(s%velocity, 0.0_wp, grid%active) * velocity_profile(s, xp)
            p%volume(n) = vol
            p%volume0(n) = vol
            p%mass(n) = rho * vol
            p%f(:, n) = identity_f
            p%stress(:, n) = 0.0_wp
            p%plastic_strain(n) = 0.0_wp
            if (p%has_hardening) p%hardening(n) = 0.0_wp
            if (p%has_cyclic) p%cyclic(:, n) = 0.0_wp
            if (p%has_gap) p%gap(n) = 0.0_wp
            if (p%has_affine) p%affine(:, n) = 0.0_wp
            p%temperature(n) = s%temperature
            p%pore_pressure(n) = 0.0_wp
            p%id(n) = cell_id * nsub + int(m, i8)
            if (s%geostatic .and. gmag > 0.0_wp) then
              sv = -rho * gmag * depth_below_surface(s, grid, xp, dv, gravity(dv) < 0.0_wp)
              do dd = 1, 3
                p%stress(dd, n) = merge(sv, k0 * sv, dd == dv)
              end do
            end if
            p%stress_unrot(:, n) = p%stress(:, n)
          end do
        end do
      end do
    end do
  end subroutine seed_solid

  !> Position of sub-point `sub` (1..ppc per dimension) of cell `cell` (global 1-based indices)
  !! of a grid with lower corner `lower` and spacing `dx`: the centres of a ppc(1) x ppc(2) x
  !! ppc(3) subdivision of the cell, where `seed_solid` puts its particles.
  pure function seed_point(lower, dx, cell, sub, ppc) result(xp)
    real(wp), intent(in) :: lower(3)  !< the grid's lower corner [m]
    real(wp), intent(in) :: dx(3)     !< cell size [m]
    integer, intent(in) :: cell(3)    !< global cell indices
    integer, intent(in) :: sub(3)     !< sub-point indices
    integer, intent(in) :: ppc(3)     !< particles per cell per dimension
    real(wp) :: xp(3)
    integer :: d
    do d = 1, 3
      xp(d) = lower(d) + (real(cell(d) - 1, wp) + (real(sub(d), wp) - 0.5_wp) / ppc(d)) * dx(d)
    end do
  end function seed_point

  !> Indices (1..ppc per dimension) of sub-point `m` (1..product(ppc)) of a cell: the first
  !! dimension fastest, so that `m` numbers the sub-points in the order `seed_solid` seeds them.
  pure function sub_point(m, ppc) result(sub)
    integer, intent(in) :: m       !< sub-point number
    integer, intent(in) :: ppc(3)  !< particles per cell per dimension
    integer :: sub(3)
    sub(1) = mod(m - 1, ppc(1)) + 1
    sub(2) = mod((m - 1) / ppc(1), ppc(2)) + 1
    sub(3) = (m - 1) / (ppc(1) * ppc(2)) + 1
  end function sub_point

  !> Factor of the initial velocity at `x`: the product of sin(k_d (x_d - lower_d)) over the
  !! entries k_d /= 0 of `velocity_wavenumber` (1 when all are 0).
  pure real(wp) function velocity_profile(s, x) result(factor)
    type(solid_params_t), intent(in) :: s   !< `&solid` parameters
    real(wp), intent(in) :: x(3)            !< point [m]
    integer :: d
    factor = 1.0_wp
    do d = 1, 3
      if (s%velocity_wavenumber(d) /= 0.0_wp) factor = factor * &
        sin(s%velocity_wavenumber(d) * (x(d) - s%lower(d)))
    end do
  end function velocity_profile

  !> True when `x` lies inside the shape of solid `s` (only `active` dimensions are tested).
  pure logical function inside_shape(s, active, x) result(inside)
    type(solid_params_t), intent(in) :: s   !< `&solid` parameters
    logical, intent(in) :: active(3)        !< active dimensions
    real(wp), intent(in) :: x(3)            !< point [m]
    real(wp) :: y(3), centre(3), th, cs, sn
    integer :: n, i, j
    select case (trim(s%shape))
    case ('box')
      y = x
      if (s%rotation_deg /= 0.0_wp) then
        ! rotate the point back by -rotation about the box centre (z axis)
        centre = 0.5_wp * (s%lower + s%upper)
        th = s%rotation_deg * acos(-1.0_wp) / 180.0_wp
        cs = cos(th)
        sn = sin(th)
        y(1) = centre(1) + cs * (x(1) - centre(1)) + sn * (x(2) - centre(2))
        y(2) = centre(2) - sn * (x(1) - centre(1)) + cs * (x(2) - centre(2))
      end if
      inside = all(.not. active .or. (y >= s%lower .and. y <= s%upper))
    case ('polygon')
      if (s%geometry%kind == shape_kind_polygon) then   ! vertices from polygon_file
        inside = file_shape_contains(s%geometry, x)
        return
      end if
      ! even-odd rule in the x-y plane
      n = s%npoints
      inside = .false.
      j = n
      do i = 1, n
        if ((s%polygon_y(i) > x(2)) .neqv. (s%polygon_y(j) > x(2))) then
          if (x(1) < (s%polygon_x(j) - s%polygon_x(i)) * (x(2) - s%polygon_y(i)) / &
            (s%polygon_y(j) - s%polygon_y(i)) + s%polygon_x(i)) inside = .not. inside
        end if
        j = i
      end do
    case ('profile')
      inside = s%geometry%kind == shape_kind_profile
      if (inside) inside = file_shape_contains(s%geometry, x)
    case ('half_space')
      inside = sum(merge(x - s%plane_point, 0.0_wp, active) * s%plane_normal) <= 0.0_wp
    case default
      inside = .false.
    end select
  end function inside_shape

  !> Depth [m] of the point `x` (inside the shape) below the shape's surface straight above it
  !! along dimension `dv`, "above" being against gravity (`up`: towards higher coordinates):
  !! the first point of the vertical through `x` that leaves the shape, or the domain's face. An
  !! axis-aligned box gives its upper (lower) face exactly; other shapes are walked in steps of
  !! a quarter of the particle spacing (so a layer thinner than that may be stepped over) and
  !! the crossing is bisected to 1e-9 of the cell size. The depth is that within the shape
  !! alone: another solid resting on it does not load it.
  pure real(wp) function depth_below_surface(s, grid, x, dv, up) result(depth)
    type(solid_params_t), intent(in) :: s   !< `&solid` parameters
    type(grid_t), intent(in) :: grid        !< block geometry (domain bounds, cell size)
    real(wp), intent(in) :: x(3)            !< point inside the shape [m]
    integer, intent(in) :: dv               !< dimension of gravity
    logical, intent(in) :: up               !< gravity points to lower coordinates
    real(wp) :: y(3), step, limit, inside_at, outside_at, mid
    integer :: ppc
    if (trim(s%shape) == 'box' .and. s%rotation_deg == 0.0_wp) then
      depth = merge(min(s%upper(dv), grid%upper(dv)) - x(dv), &
        x(dv) - max(s%lower(dv), grid%lower(dv)), up)
      depth = max(depth, 0.0_wp)
      return
    end if
    ppc = max(s%particles_per_cell(dv), 1)
    step = merge(1.0_wp, -1.0_wp, up) * 0.25_wp * grid%dx(dv) / real(ppc, wp)
    limit = merge(grid%upper(dv), grid%lower(dv), up)
    y = x
    inside_at = x(dv)
    do
      outside_at = inside_at + step
      if ((up .and. outside_at >= limit) .or. (.not. up .and. outside_at <= limit)) then
        outside_at = limit
        y(dv) = limit
        if (inside_shape(s, grid%active, y)) then
          depth = abs(limit - x(dv))
          return
        end if
        exit
      end if
      y(dv) = outside_at
      if (.not. inside_shape(s, grid%active, y)) exit
      inside_at = outside_at
    end do
    do while (abs(outside_at - inside_at) > 1.0e-9_wp * grid%dx(dv))
      mid = 0.5_wp * (inside_at + outside_at)
      y(dv) = mid
      if (inside_shape(s, grid%active, y)) then
        inside_at = mid
      else
        outside_at = mid
      end if
    end do
    depth = abs(0.5_wp * (inside_at + outside_at) - x(dv))
  end function depth_below_surface
end module particles_seeding
