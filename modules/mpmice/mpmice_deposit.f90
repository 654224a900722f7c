!> The particles' deposit on the ICE cells (paper eq. 28, departure C2 of docs/mpmice.md): every
!! particle spreads its grain volume m_p/rho_s, mass and heat over the cells its deformed domain
!! overlaps (half-widths sum_k |F_dk| l_k, l the uGIMP half-width, at most dx/2), clipped to the
!! domain, and its grain fraction over the face planes its domain reaches (the layout:
!! `mpmice_deposit_layout`); the grain volume in each cell is also split between the cell's
!! two halves along each direction (`low_half_shares`). A column seeded with one particle per cell therefore has a sharp
!! edge, which Darcy flow needs (a node-averaged fraction smears the edge over two cells and
!! changes the column's resistance by ~17 % at 20 cells). Local: the caller sums the deposits
!! that reach the neighbouring block with a reverse halo.
module mpmice_deposit
  use mpmice_kinds, only: wp
  use grid_layout, only: grid_t
  use particles_store, only: particles_t
  use mpmice_solid_coupling, only: solid_coupling_t
  use mpmice_deposit_layout, only: deposit_layout_t, deposit_layout, deposit_mass, &
    deposit_grain_volume, deposit_solid_volume
  use mpmice_rigid_contact, only: wall_fraction, wall_neighbours, wall_plane
  use mpm_shape, only: nearest_integer
  implicit none
  private

  public :: solid_deposit, overlap_weights, deformed_half_widths, low_half_shares

  !> unit_offset(:, d): the index offset of one cell along dimension d.
  integer, parameter :: unit_offset(3, 3) = reshape([1, 0, 0, 0, 1, 0, 0, 0, 1], [3, 3])

contains

  !> Deposit of the particles of solid `s` into `dep(:, i, j, k)` (local, no communication; the
  !! components: `mpmice_deposit_layout`): mass, grain volume m_p / rho_s (a particle's volume V_p
  !! is that of the mixture it stands for; its grains fill m_p / rho_s of it), the grain volume of
  !! solid s, the grain fraction on the low and high side of the cell's low face plane in each
  !! direction and on the cell's own side of its high face plane, the grain volume in the cell's
  !! low half along each direction, the heat capacity, energy and grain conductance. With `sliding`
  !! (rigid bodies slide past the deformable solids) a rigid body's plane fractions go to the rigid
  !! plane components instead (the own-side component is not kept for them), and a deformable
  !! particle's cell share over a wall cell (`wall_frac` >= `wall_fraction`, the rigid fraction of
  !! the previous deposit) goes to that cell's face neighbours outside the wall, by inverse
  !! distance from the particle (`wall_neighbours`): sliding along a staircase bed, a particle's
  !! domain reaches into the wall's cells, where the cap of the fraction would hide its grains from
  !! the fluids (the tracked solid volume of a block sliding 1.5 cm on a 45 deg slope fell by 0.05
  !! cell volumes, which a closed box of water turned into -230 kPa), and the soil's lowest
  !! particles pass through them.
  subroutine solid_deposit(p, s, nsolids, solid, grid, dep, sliding, wall_frac, dt, halves)
    type(particles_t), intent(in) :: p          !< particles of solid s
    integer, intent(in) :: s                    !< solid index
    integer, intent(in) :: nsolids              !< number of solids
    type(solid_coupling_t), intent(in) :: solid !< its grain density and thermal parameters
    type(grid_t), intent(in) :: grid            !< block geometry
    real(wp), intent(inout) :: dep(:, grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !< deposits
    logical, intent(in), optional :: sliding    !< rigid bodies slide (own plane components)
    real(wp), intent(in), optional :: wall_frac(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !<
                                                !! rigid fraction of the cells (previous deposit)
    real(wp), intent(in), optional :: dt        !< step [s]: plane fractions swept over it
    logical, intent(in), optional :: halves     !< the half-cell grain volumes too (the
                                                !! face-plane drag; without it they stay 0)
    integer :: ip, d, k, a, b, c, first(3), nc(3), nf(3), ff(3), e, cb(3), nt, tgt(3, 6)
    integer :: ci, cj, ck
    integer :: ilo(3), ihi(3), iown(3), ivol, icap, iene, icond, ihalf(3), idx(3)
    type(deposit_layout_t) :: lay
    real(wp) :: w(2, 3), wt, vg, l(3), lo, hi, wf, mc, tw(6), step, sup, sdn, wlo, whi, wlo0, whi0
    real(wp) :: r(2, 3)
    logical :: own_planes, redirect, sweep, own, with_halves
    with_halves = .false.
    if (present(halves)) with_halves = halves
    own_planes = .false.
    if (present(sliding)) own_planes = sliding .and. solid%rigid
    redirect = .false.
    if (present(sliding) .and. present(wall_frac)) redirect = sliding .and. .not. solid%rigid
    ! the plane components this solid writes, and its cell components
    lay = deposit_layout(nsolids)
    ilo = merge(lay%rigid_low, lay%plane_low, own_planes)
    ihi = merge(lay%rigid_high, lay%plane_high, own_planes)
    iown = lay%own_high
    ihalf = lay%half_low
    ivol = deposit_solid_volume(s)
    icap = lay%heat_capacity
    iene = lay%energy
    icond = lay%conductance
    ! not on the planes of a wall cell of a sliding rigid body: the contact corrects the nodal
    ! velocity, not the particle's (the 40 mm debris flow: +367 / -6.6 kPa in a contact cell at
    ! 0.1 s when the sweep reached the bed's planes)
    step = 0.0_wp
    if (present(dt) .and. .not. own_planes) step = dt
    do ip = 1, p%np
      vg = p%mass(ip) / solid%grain_density
      mc = p%mass(ip) * solid%heat_capacity
      l = deformed_half_widths(p, ip, grid)
      do d = 1, 3
        call overlap_weights(grid, d, p%x(d, ip), l(d), first(d), nc(d), w(:, d))
        if (with_halves) r(:, d) = low_half_shares(grid, d, p%x(d, ip), l(d), first(d), nc(d))
      end do
      ! the grain fraction V_g / (2 l A_face) the particle puts on each face plane its domain
      ! [lo, hi] (in cells) reaches, on the plane's low side (lo < k <= hi) and on its high side
      ! (lo <= k < hi), shared tangentially like the cell deposit: particles that tile the
      ! column exactly give both sides, a free surface on the plane only one
      do d = 1, 3
        if (.not. grid%active(d)) cycle
        ! domain ends within round-off of a plane are on it (particles seeded to tile the cells
        ! end exactly on the planes: a 1e-16 overshoot would put their grains on both sides)
        lo = snap_to_plane((p%x(d, ip) - l(d) - grid%lower(d)) / grid%dx(d))
        hi = snap_to_plane((p%x(d, ip) + l(d) - grid%lower(d)) / grid%dx(d))
        wf = vg * grid%dx(d) / (2.0_wp * l(d) * grid%cell_volume)
        ! swept over the step (departure 16): the low side carries the grains of the slab
        ! [k - sup, k] that cross the plane at the particle's velocity (sup = u dt / dx > 0),
        ! the high side those of [k, k + sdn] (u < 0); without a step, the plane itself
        sup = max(p%v(d, ip), 0.0_wp) * step / grid%dx(d)
        sdn = max(-p%v(d, ip), 0.0_wp) * step / grid%dx(d)
        do k = ceiling(lo - sdn), floor(hi + sup)
          wlo = swept_share(lo, hi, real(k, wp) - sup, real(k, wp), lo < real(k, wp) .and. &
            real(k, wp) <= hi)
          whi = swept_share(lo, hi, real(k, wp), real(k, wp) + sdn, lo <= real(k, wp) .and. &
            real(k, wp) < hi)
          wlo0 = merge(1.0_wp, 0.0_wp, lo < real(k, wp) .and. real(k, wp) <= hi)
          whi0 = merge(1.0_wp, 0.0_wp, lo <= real(k, wp) .and. real(k, wp) < hi)
          if (max(wlo, whi, wlo0, whi0) <= 0.0_wp) cycle
          ff = first
          nf = nc
          ff(d) = k + 1
          nf(d) = 1
          if (k + 1 < grid%lbc(d) .or. k + 1 > grid%ubc(d)) cycle
          ! the cell below the plane keeps its own side too
          own = lo < real(k, wp) .and. real(k, wp) <= hi .and. .not. own_planes
          do c = 1, nf(3)
            do b = 1, nf(2)
              do a = 1, nf(1)
                ! wf times the tangential weights, in the order of the directions
                wt = wf
                if (d /= 1) wt = wt * w(a, 1)
                if (d /= 2) wt = wt * w(b, 2)
                if (d /= 3) wt = wt * w(c, 3)
                ci = ff(1) + a - 1
                cj = ff(2) + b - 1
                ck = ff(3) + c - 1
                sweep = .true.
                if (redirect) sweep = .not. wall_plane(wall_frac, grid, [ci, cj, ck], d)
                dep(ilo(d), ci, cj, ck) = dep(ilo(d), ci, cj, ck) + merge(wlo, wlo0, sweep) * wt
                dep(ihi(d), ci, cj, ck) = dep(ihi(d), ci, cj, ck) + merge(whi, whi0, sweep) * wt
                if (.not. own) cycle
                ci = ci - unit_offset(1, d)
                cj = cj - unit_offset(2, d)
                ck = ck - unit_offset(3, d)
                dep(iown(d), ci, cj, ck) = dep(iown(d), ci, cj, ck) + wt
              end do
            end do
          end do
        end do
      end do
      if (redirect) then
        ! the share over a wall cell of a rigid body goes to its face neighbours outside the
        ! wall, by inverse distance from the particle (continuous as it moves)
        do c = 1, nc(3)
          do b = 1, nc(2)
            do a = 1, nc(1)
              wt = w(a, 1) * w(b, 2) * w(c, 3)
              cb = [first(1) + a - 1, first(2) + b - 1, first(3) + c - 1]
              idx = [a, b, c]
              nt = 1
              tgt(:, 1) = cb
              tw(1) = 1.0_wp
              if (wall_frac(cb(1), cb(2), cb(3)) >= wall_fraction) call wall_neighbours(grid, &
                wall_frac, cb, p%x(:, ip), nt, tgt, tw)
              do e = 1, nt
                call add_cell_share(dep(:, tgt(1, e), tgt(2, e), tgt(3, e)), tw(e) * wt)
              end do
            end do
          end do
        end do
      else
        do c = 1, nc(3)
          do b = 1, nc(2)
            do a = 1, nc(1)
              idx = [a, b, c]
              call add_cell_share(dep(:, first(1) + a - 1, first(2) + b - 1, first(3) + c - 1), &
                w(a, 1) * w(b, 2) * w(c, 3))
            end do
          end do
        end do
      end if
    end do
  contains
    !> The particle's cell deposit with the share `wt` of it into the components `q` of a cell.
    subroutine add_cell_share(q, wt)
      real(wp), intent(inout) :: q(:)  !< the cell's deposit components
      real(wp), intent(in) :: wt       !< share [-]
      integer :: h
      q(deposit_mass) = q(deposit_mass) + wt * p%mass(ip)
      q(deposit_grain_volume) = q(deposit_grain_volume) + wt * vg
      q(ivol) = q(ivol) + wt * vg
      q(icap) = q(icap) + wt * mc
      q(iene) = q(iene) + wt * mc * p%temperature(ip)
      q(icond) = q(icond) + wt * vg * solid%conductivity
      if (with_halves) then
        do h = 1, 3
          q(ihalf(h)) = q(ihalf(h)) + wt * vg * r(idx(h), h)
        end do
      end if
    end subroutine add_cell_share
  end subroutine solid_deposit

  !> Share of the slab [a, b] (in cells) that the particle domain [lo, hi] covers, over the slab's
  !! width; a slab of zero width (no step or no motion that way) gives 1 where the domain reaches
  !! the plane (`on_plane`), else 0.
  pure real(wp) function swept_share(lo, hi, a, b, on_plane) result(share)
    real(wp), intent(in) :: lo, hi   !< particle domain [cells]
    real(wp), intent(in) :: a, b     !< slab, a <= b [cells]
    logical, intent(in) :: on_plane  !< the plane's side test for a zero-width slab
    if (b - a <= 0.0_wp) then
      share = merge(1.0_wp, 0.0_wp, on_plane)
    else
      share = max(0.0_wp, min(hi, b) - max(lo, a)) / (b - a)
    end if
  end function swept_share

  !> Share of the particle domain's part in each cell of `overlap_weights` (along d, the same
  !! clipping) that lies in the cell's low half, so that the cell deposit splits between the
  !! cell's two halves by the domain's length in each; a domain of zero width goes to the half
  !! holding its centre. 1/2 along an inactive dimension (one cell, no halves).
  pure function low_half_shares(grid, d, x, l, first, n) result(r)
    type(grid_t), intent(in) :: grid   !< block geometry
    integer, intent(in) :: d           !< dimension
    real(wp), intent(in) :: x          !< particle coordinate [m]
    real(wp), intent(in) :: l          !< half-width [m]
    integer, intent(in) :: first       !< first cell index (`overlap_weights`)
    integer, intent(in) :: n           !< cells overlapped (`overlap_weights`)
    real(wp) :: r(2)                   !< low-half share per cell overlapped [-]
    real(wp) :: a, b, lo, mid, inside
    integer :: c
    r = 0.5_wp
    if (.not. grid%active(d)) return
    call domain_in_cells(grid, d, x, l, a, b)
    r = 0.0_wp
    do c = 1, n
      ! cell first + c - 1 spans [lo, lo + 1] in cells
      lo = real(first + c - 2, wp)
      mid = lo + 0.5_wp
      inside = min(b, lo + 1.0_wp) - max(a, lo)
      if (inside > 0.0_wp) then
        r(c) = max(0.0_wp, min(b, mid) - max(a, lo)) / inside
      else
        r(c) = merge(1.0_wp, 0.0_wp, 0.5_wp * (a + b) < mid)
      end if
    end do
  end function low_half_shares

  !> A coordinate in cells, put on the nearest plane when it lies within 1e-9 cells of it.
  pure real(wp) function snap_to_plane(x) result(y)
    real(wp), intent(in) :: x  !< coordinate [cells]
    real(wp) :: n
    n = real(nearest_integer(x), wp)   ! anint(x), without its library call
    y = x
    if (abs(x - n) < 1.0e-9_wp) y = n
  end function snap_to_plane

  !> Half-widths [m] along the axes of particle `ip`'s deformed domain F [-l0, l0] (its bounding
  !! box), at most dx/2, so that the domain's faces move with the material (a compressed particle
  !! does not shed solid); 0 along an inactive dimension (one cell: `overlap_weights` and
  !! `low_half_shares` do not read it there).
  pure function deformed_half_widths(p, ip, grid) result(l)
    type(particles_t), intent(in) :: p          !< particles
    integer, intent(in) :: ip                   !< particle
    type(grid_t), intent(in) :: grid            !< block geometry
    real(wp) :: l(3)
    integer :: d, k
    do d = 1, 3
      l(d) = 0.0_wp
      if (.not. grid%active(d)) cycle
      do k = 1, 3
        if (grid%active(k)) l(d) = l(d) + abs(p%f(d + 3 * (k - 1), ip)) * p%half_width(k)
      end do
      l(d) = min(l(d), 0.5_wp * grid%dx(d))
    end do
  end function deformed_half_widths

  !> Cells (at most 2: l <= dx/2) overlapped along `d` by the particle domain [x - l, x + l] and
  !! their fractions of it, clipped to the domain in a non-periodic dimension (fractions renormalised).
  pure subroutine overlap_weights(grid, d, x, l, first, n, w)
    type(grid_t), intent(in) :: grid   !< block geometry
    integer, intent(in) :: d           !< dimension
    real(wp), intent(in) :: x          !< particle coordinate [m]
    real(wp), intent(in) :: l          !< half-width [m]
    integer, intent(out) :: first      !< first cell index
    integer, intent(out) :: n          !< cells overlapped (1 or 2)
    real(wp), intent(out) :: w(2)      !< fractions
    real(wp) :: a, b, xb, total
    integer :: last
    w = 0.0_wp
    if (.not. grid%active(d)) then
      first = 1
      n = 1
      w(1) = 1.0_wp
      return
    end if
    call domain_in_cells(grid, d, x, l, a, b)
    first = floor(a) + 1
    last = min(floor(b) + 1, first + 1)
    if (b <= real(first, wp)) last = first
    n = last - first + 1
    if (n == 1) then
      w(1) = 1.0_wp
    else
      xb = real(first, wp)
      total = b - a
      w(1) = (xb - a) / total
      w(2) = (b - xb) / total
    end if
  end subroutine overlap_weights

  !> The particle domain [x - l, x + l] along d in cells from the domain's low face, [a, b],
  !! clipped to the domain where it is not periodic.
  pure subroutine domain_in_cells(grid, d, x, l, a, b)
    type(grid_t), intent(in) :: grid   !< block geometry
    integer, intent(in) :: d           !< dimension
    real(wp), intent(in) :: x          !< particle coordinate [m]
    real(wp), intent(in) :: l          !< half-width [m]
    real(wp), intent(out) :: a, b      !< the domain's ends [cells]
    a = (x - l - grid%lower(d)) / grid%dx(d)
    b = (x + l - grid%lower(d)) / grid%dx(d)
    if (.not. grid%periodic(d)) then
      a = max(a, 0.0_wp)
      b = min(b, real(grid%ncells(d), wp))
    end if
  end subroutine domain_in_cells
end module mpmice_deposit
