!> The solid skeleton on the ICE cells and faces (paper eqs. 28, 32-33, 48, 52, 66-69 with E5):
!! what the pressure equation and the exchange of a coupled scene see of the MPM particles, and the
!! way their results go back to the MPM nodes.
!!
!! * Cell deposit (eq. 28): every particle spreads its grain volume m_p/rho_s and mass over the
!!   cells its deformed domain overlaps (half-widths sum_k |F_dk| l_k, l the uGIMP half-width,
!!   at most dx/2), clipped to the domain; a reverse
!!   halo sums deposits that reach the neighbouring block. A column seeded with one particle per
!!   cell therefore has a sharp edge, which Darcy flow needs (a node-averaged fraction smears the
!!   edge over two cells and changes the column's resistance by ~17 % at 20 cells).
!! * Tracked fraction: the fluids see a solid fraction phi_s that evolves with the same fluxes
!!   as the pressure equation (-dt div(phi_s u_s) - phi_s kappa_s dp), so sum phi = 1 holds to
!!   the outer tolerance; the difference to the particles' fraction enters the next step's
!!   pressure equation as a volume source (`ice_solid_phase_t%source`), so fluid is pushed out
!!   instead of compressed (no pressure noise from the particle representation).
!! * Face velocity (eqs. 32-33): the mass-weighted mean of the MPM velocities v^{L-} (eq. 41,
!!   effective stress, gravity and loads) of the face's nodes, minus dt v_s grad p (v_s the grain
!!   specific volume); then the face exchange (eq. 34) and the outer pressure iteration correct
!!   it. Departure from eq. 33: the stress term comes from the nodes (the same forces MPM uses)
!!   instead of the cell-centred stress difference.
!! * Back to the nodes (eqs. 52, 66-67 with errata E5): each node adds the mean increment
!!   (final - nodal face velocity) of the faces it belongs to, then the solid boundary
!!   conditions and eq. 69 a = (v^L - v^n)/dt. In 1D a face is a node, so the particles move
!!   exactly with the velocities the pressure equation used.
module mpmice_solid_cells
  use mpmice_kinds, only: wp
  use grid_layout, only: grid_t
  use parallel_domain, only: domain_t
  use parallel_halo, only: halo_t, halo_reverse_cell_vec, halo_exchange_node_vec
  use mpm_particles, only: particles_t
  use mpm_nodes, only: mpm_nodes_t
  use ice_state, only: ice_state_t
  use ice_face_velocity, only: face_range, closed_face, face_index, upwind
  use ice_pressure, only: solid_face_fraction
  use exchange_drag, only: drag_reduced_coefficient, drag_impermeable
  use mpmice_solid_coupling, only: solid_coupling_t, surface_body_fraction
  use mpmice_rigid_contact, only: wall_fraction, body_face, wall_neighbours, wall_plane, &
    partner_fields
  implicit none
  private


  public :: solid_deposit, solid_cell_fields, solid_face_predictor, &
    solid_face_to_nodes, solid_track_fraction, solid_cell_velocity, solid_pore_pressure, &
    fluid_face_blend, fluid_face_predictor_porous, overlap_weights, deformed_half_widths

  !> unit_offset(:, d): the index offset of one cell along dimension d.
  integer, parameter :: unit_offset(3, 3) = reshape([1, 0, 0, 0, 1, 0, 0, 0, 1], [3, 3])

contains

  !> Deposit of the particles of solid `s` into `dep(:, i, j, k)` (local, no communication):
  !! component 1 mass [kg], 2 grain volume m_p / rho_s [m^3] (a particle's volume V_p is that of
  !! the mixture it stands for; its grains fill m_p / rho_s of it), 2 + s the grain volume of
  !! solid s, and 2 + nsolids + 2 d - 1 / 2 d the grain fraction on the low / high side of the
  !! cell's low face plane in direction d; then (`heat_components`) 9 + nsolids the heat capacity
  !! m_p c_s [J/K], 10 + nsolids the energy m_p c_s T_p [J], 11 + nsolids the grain conductance
  !! (m_p / rho_s) k_s [W m^2/K]; 11 + nsolids + d the grain fraction on the cell's own (low) side
  !! of its high face plane in direction d (the value 1 + nsolids + 2 d holds in the next cell,
  !! kept here too so that every cell carries its own planes: out-of-domain ghost cells beyond
  !! a wall are not exchanged between blocks). With `sliding` (rigid bodies slide past the
  !! deformable solids) a rigid body's plane fractions go to 13 + nsolids + 2 d (low side) and
  !! 14 + nsolids + 2 d (high side) instead (the own-side component is not kept for them), and
  !! a deformable particle's cell share over a wall cell (`wall_frac` >= `wall_fraction`, the
  !! rigid fraction of the previous deposit) goes to that cell's face neighbours outside the wall,
  !! by inverse distance from the particle (`wall_neighbours`): sliding along a staircase bed, a
  !! particle's domain reaches into the wall's cells, where the cap of the fraction would hide its
  !! grains from the fluids (the tracked solid volume of a block sliding 1.5 cm on a 45 deg slope
  !! fell by 0.05 cell volumes, which a closed box of water turned into -230 kPa), and the soil's
  !! lowest particles pass through them. `deposit_size` components in all.
  subroutine solid_deposit(p, s, nsolids, solid, grid, dep, sliding, wall_frac, dt)
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
    integer :: ip, d, k, a, b, c, first(3), nc(3), nf(3), ff(3), e, nbase, cb(3), nt, tgt(3, 6)
    real(wp) :: w(2, 3), wt, vg, l(3), lo, hi, wf, mc, tw(6), step, sup, sdn, wlo, whi, wlo0, whi0
    logical :: own_planes, redirect, sweep
    own_planes = .false.
    if (present(sliding)) own_planes = sliding .and. solid%rigid
    redirect = .false.
    if (present(sliding) .and. present(wall_frac)) redirect = sliding .and. .not. solid%rigid
    nbase = 2 + nsolids
    if (own_planes) nbase = 14 + nsolids
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
          do c = 1, nf(3)
            do b = 1, nf(2)
              do a = 1, nf(1)
                wt = wf
                do e = 1, 3
                  if (e == d) cycle
                  wt = wt * w(merge(a, merge(b, c, e == 2), e == 1), e)
                end do
                cb = [ff(1) + a - 1, ff(2) + b - 1, ff(3) + c - 1]
                sweep = .true.
                if (redirect) sweep = .not. wall_plane(wall_frac, grid, cb, d)
                associate (q => dep(:, cb(1), cb(2), cb(3)))
                  q(nbase + 2 * d - 1) = q(nbase + 2 * d - 1) + merge(wlo, wlo0, sweep) * wt
                  q(nbase + 2 * d) = q(nbase + 2 * d) + merge(whi, whi0, sweep) * wt
                end associate
                if (lo < real(k, wp) .and. real(k, wp) <= hi .and. .not. own_planes) then
                  ! the cell below the plane keeps its own side too
                  cb = [ff(1) + a - 1, ff(2) + b - 1, ff(3) + c - 1] - unit_offset(:, d)
                  dep(11 + nsolids + d, cb(1), cb(2), cb(3)) = &
                    dep(11 + nsolids + d, cb(1), cb(2), cb(3)) + wt
                end if
              end do
            end do
          end do
        end do
      end do
      do c = 1, nc(3)
        do b = 1, nc(2)
          do a = 1, nc(1)
            wt = w(a, 1) * w(b, 2) * w(c, 3)
            cb = [first(1) + a - 1, first(2) + b - 1, first(3) + c - 1]
            nt = 1
            tgt(:, 1) = cb
            tw(1) = 1.0_wp
            ! the share over a wall cell of a rigid body goes to its face neighbours outside
            ! the wall, by inverse distance from the particle (continuous as it moves)
            if (redirect) then
              if (wall_frac(cb(1), cb(2), cb(3)) >= wall_fraction) call wall_neighbours(grid, &
                wall_frac, cb, p%x(:, ip), nt, tgt, tw)
            end if
            do e = 1, nt
              associate (q => dep(:, tgt(1, e), tgt(2, e), tgt(3, e)))
                q(1) = q(1) + tw(e) * wt * p%mass(ip)
                q(2) = q(2) + tw(e) * wt * vg
                q(2 + s) = q(2 + s) + tw(e) * wt * vg
                q(9 + nsolids) = q(9 + nsolids) + tw(e) * wt * mc
                q(10 + nsolids) = q(10 + nsolids) + tw(e) * wt * mc * p%temperature(ip)
                q(11 + nsolids) = q(11 + nsolids) + tw(e) * wt * vg * solid%conductivity
              end associate
            end do
          end do
        end do
      end do
    end do
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

  !> A coordinate in cells, put on the nearest plane when it lies within 1e-9 cells of it.
  pure real(wp) function snap_to_plane(x) result(y)
    real(wp), intent(in) :: x  !< coordinate [cells]
    y = x
    if (abs(x - anint(x)) < 1.0e-9_wp) y = anint(x)
  end function snap_to_plane

  !> Half-widths [m] along the axes of particle `ip`'s deformed domain F [-l0, l0] (its bounding
  !! box), at most dx/2, so that the domain's faces move with the material (a compressed particle
  !! does not shed solid).
  pure function deformed_half_widths(p, ip, grid) result(l)
    type(particles_t), intent(in) :: p          !< particles
    integer, intent(in) :: ip                   !< particle
    type(grid_t), intent(in) :: grid            !< block geometry
    real(wp) :: l(3)
    integer :: d, k
    do d = 1, 3
      l(d) = 0.0_wp
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
    a = (x - l - grid%lower(d)) / grid%dx(d)
    b = (x + l - grid%lower(d)) / grid%dx(d)
    if (.not. grid%periodic(d)) then
      a = max(a, 0.0_wp)
      b = min(b, real(grid%ncells(d), wp))
    end if
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

  !> From the summed deposits (valid in ghost cells too): the particles' solid fraction
  !! (capped at `max_fraction`), bulk density, grain specific volume and compressibility, and
  !! the reduced drag coefficient per fluid (slip from the velocities of time n); the heat
  !! capacity per volume, conductance phi_s k_s and mass-weighted temperature of the solid.
  subroutine solid_cell_fields(state, grid, dep, solids, max_fraction, phi_p)
    type(ice_state_t), intent(inout) :: state   !< fluids; solid phase written
    type(grid_t), intent(in) :: grid            !< block geometry
    real(wp), intent(in) :: dep(:, grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !< deposits
    type(solid_coupling_t), intent(in) :: solids(:) !< coupling parameters per solid
    real(wp), intent(in) :: max_fraction        !< largest solid fraction [-]
    real(wp), intent(out) :: phi_p(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !< particle fraction
    integer :: i, j, k, s, m, ns
    real(wp) :: vol, phi, cs, rho_f, slip, wsum, phi_body, scale, vol_imp, phi_imp
    logical :: mixed
    ns = size(solids)
    associate (sp => state%solid)
      sp%face_fraction = 0.0_wp
      sp%face_fraction_hi = 0.0_wp
      do k = grid%lbc(3), grid%ubc(3)
        do j = grid%lbc(2), grid%ubc(2)
          do i = grid%lbc(1), grid%ubc(1)
            sp%face_fraction(i, j, k, :) = min(dep(3 + ns:7 + ns:2, i, j, k), max_fraction)
            sp%face_fraction_hi(i, j, k, :) = min(dep(4 + ns:8 + ns:2, i, j, k), max_fraction)
            if (sp%sliding) then
              sp%rigid_fraction(i, j, k, :) = min(dep(15 + ns:19 + ns:2, i, j, k), max_fraction)
              sp%rigid_fraction_hi(i, j, k, :) = min(dep(16 + ns:20 + ns:2, i, j, k), &
                max_fraction)
            end if
          end do
        end do
      end do
      do k = grid%lbc(3), grid%ubc(3)
        do j = grid%lbc(2), grid%ubc(2)
          do i = grid%lbc(1), grid%ubc(1)
            vol = dep(2, i, j, k)
            phi = min(vol / grid%cell_volume, max_fraction)
            phi_p(i, j, k) = phi
            sp%rho(i, j, k) = dep(1, i, j, k) / grid%cell_volume
            sp%spvol(i, j, k) = 0.0_wp
            sp%kappa(i, j, k) = 0.0_wp
            sp%drag(i, j, k, :) = 0.0_wp
            sp%frac_def(i, j, k) = 0.0_wp
            sp%frac_rigid(i, j, k) = 0.0_wp
            sp%xfrac(i, j, k) = 0.0_wp
            sp%heat_cap(i, j, k) = dep(9 + ns, i, j, k) / grid%cell_volume
            sp%conductance(i, j, k) = dep(11 + ns, i, j, k) / grid%cell_volume
            sp%temp(i, j, k) = 0.0_wp
            if (dep(9 + ns, i, j, k) > 0.0_wp) sp%temp(i, j, k) = dep(10 + ns, i, j, k) / &
              dep(9 + ns, i, j, k)
            if (vol <= 0.0_wp .or. dep(1, i, j, k) <= 0.0_wp) cycle
            do s = 1, ns
              sp%kappa(i, j, k) = sp%kappa(i, j, k) + dep(2 + s, i, j, k) / vol * &
                solids(s)%grain_kappa
            end do
            if (sp%sliding) then
              call partner_fields(state, grid, dep, solids, max_fraction, [i, j, k])
              cycle
            end if
            sp%spvol(i, j, k) = vol / dep(1, i, j, k)
            ! impermeable solids share the cell with permeable ones (a soil on a structure whose
            ! face cuts the cell): the pore fluid lies in the permeable part, (1 - phi_imp) of
            ! the cell, at its own fraction phi_k = phi_perm / (1 - phi_imp); the drag is the
            ! permeable solids' c(phi_k) / (1 - phi_imp) per phi_perm, the impermeable ones only
            ! take volume (the same pressure drop per length as that part: phi_perm c = phi_k
            ! c(phi_k)). Weighted by the impermeable solids' share too, the drag was theirs,
            ! 1e15: it sealed the soil's pores in the cell, whose water then kept every volume
            ! change as pressure (+0.65 MPa stuck in the layer over the shaking base).
            vol_imp = 0.0_wp
            do s = 1, ns
              if (solids(s)%drag_law == drag_impermeable) vol_imp = vol_imp + dep(2 + s, i, j, k)
            end do
            mixed = vol_imp > 0.0_wp .and. vol_imp < vol
            if (mixed) then
              phi_imp = min(vol_imp / grid%cell_volume, max_fraction)
              phi_body = min((vol - vol_imp) / grid%cell_volume / (1.0_wp - phi_imp), &
                max_fraction)
              scale = 1.0_wp / (1.0_wp - phi_imp)
            else
              ! a cell crossed by the soil's surface: the drag of the body's fraction over the
              ! share phi / phi_body of the cell the body fills (series resistance, below)
              phi_body = surface_body_fraction(grid, dep, ns, [i, j, k], phi, max_fraction)
              scale = (1.0_wp - phi) / (1.0_wp - phi_body)
            end if
            do m = 1, state%nfluids
              associate (f => state%fluid(m))
                rho_f = 1.0_wp / max(f%spvol(i, j, k), tiny(1.0_wp))
                slip = norm2(sp%vel(i, j, k, :) - f%vel(i, j, k, :))
                cs = 0.0_wp
                wsum = 0.0_wp
                do s = 1, ns
                  if (dep(2 + s, i, j, k) <= 0.0_wp) cycle
                  wsum = wsum + dep(2 + s, i, j, k)
                  if (mixed .and. solids(s)%drag_law == drag_impermeable) cycle
                  cs = cs + dep(2 + s, i, j, k) * scale * drag_reduced_coefficient( &
                    solids(s)%drag_law, phi_body, solids(s)%grain_size, f%viscosity, rho_f, &
                    slip, solids(s)%drag_coefficient, solids(s)%forchheimer_a, &
                    solids(s)%forchheimer_b)
                end do
                sp%drag(i, j, k, m) = cs / wsum
              end associate
            end do
          end do
        end do
      end do
    end associate
  end subroutine solid_cell_fields

  !> Solid cell velocity for the cell exchange (eqs. 28, 51): mass-weighted mean of the corner
  !! nodes' final velocities v^L (after the pressure force and drag of the faces). The fluids are
  !! dragged toward it with the solid's row of the exchange held fixed, so the drag the fluid
  !! feels is consistent with the motion the solid actually makes.
  subroutine solid_cell_velocity(state, grid, nodes, min_mass)
    type(ice_state_t), intent(inout) :: state   !< solid phase vel written (owned cells)
    type(grid_t), intent(in) :: grid            !< block geometry
    type(mpm_nodes_t), intent(in) :: nodes      !< node fields
    real(wp), intent(in) :: min_mass            !< empty-node threshold [kg]
    integer :: i, j, k, a, b, e, top(3)
    real(wp) :: m, mv(3), mi
    top = merge(1, 0, grid%active)
    associate (sp => state%solid)
      do k = grid%lo(3), grid%hi(3)
        do j = grid%lo(2), grid%hi(2)
          do i = grid%lo(1), grid%hi(1)
            m = 0.0_wp
            mv = 0.0_wp
            do e = 0, top(3)
              do b = 0, top(2)
                do a = 0, top(1)
                  associate (q => nodes%q(:, i + a, j + b, k + e))
                    if (sp%sliding) then
                      ! the partner: the deformable solid where the cell holds any (its velocity
                      ! at contact nodes), else the rigid body's momentum
                      if (sp%frac_def(i, j, k) > 0.0_wp) then
                        if (q(1) <= min_mass) cycle
                        m = m + q(1)
                        mv = mv + q(1) * nodes%vel_l(:, i + a, j + b, k + e)
                      else
                        if (q(8) <= min_mass) cycle
                        m = m + q(8)
                        mv = mv + q(9:11)
                      end if
                      cycle
                    end if
                    mi = q(1) + q(8)
                  end associate
                  if (mi <= min_mass) cycle
                  m = m + mi
                  mv = mv + mi * nodes%vel_l(:, i + a, j + b, k + e)
                end do
              end do
            end do
            sp%vel(i, j, k, :) = 0.0_wp
            if (m > 0.0_wp) sp%vel(i, j, k, :) = mv / m
          end do
        end do
      end do
    end associate
  end subroutine solid_cell_velocity

  !> Nodal face velocity u_s,f0 (mass-weighted mean of the face nodes' v^{L-}), the predictor
  !! u_s,f = u_s,f0 - dt v_s (p_R - p_L)/dx (eq. 33, pressure part) on faces where the solid
  !! moves freely, and the rigid-face flags. Faces of the owned cells. With sliding rigid bodies
  !! (`ice_solid_phase_t%sliding`) a face next to a wall cell, or with solid but none of it
  !! deformable (`mpmice_rigid_contact%body_face`), is a wall that moves with the rigid body
  !! (prescribed: the fluids cannot enter the body, whose cells have almost no pore volume); any
  !! other face carries the deformable solid (its mass-weighted nodal velocity); the rigid
  !! bodies' volume flux phi_r,f u_r,f (upwind plane fraction, rigid momentum over mass at the
  !! face's nodes) is kept apart in `rigid_flux`. On a loading platen
  !! (`ice_solid_phase_t%platen`) the face nodes get the pore fluid's share of the load.
  subroutine solid_face_predictor(state, grid, nodes, dt, min_mass)
    type(ice_state_t), intent(inout) :: state   !< solid phase face fields written
    type(grid_t), intent(in) :: grid            !< block geometry
    type(mpm_nodes_t), intent(in) :: nodes      !< node fields (vel_l = v^{L-})
    real(wp), intent(in) :: dt                  !< time step [s]
    real(wp), intent(in) :: min_mass            !< empty-node threshold [kg]
    integer :: d, i, j, k, o(3), r(2, 3), span(3), a, b, e, n(3), face, inner(3)
    real(wp) :: m, mv, mi, vl, vr, v, mr, mvr, ur
    logical :: rigid
    associate (sp => state%solid)
      do d = 1, 3
        if (.not. grid%active(d)) cycle
        o = 0
        o(d) = 1
        span = merge(1, 0, grid%active)
        span(d) = 0
        r = face_range(grid, d)
        do k = r(1, 3), r(2, 3)
          do j = r(1, 2), r(2, 2)
            do i = r(1, 1), r(2, 1)
              m = 0.0_wp
              mv = 0.0_wp
              mr = 0.0_wp
              mvr = 0.0_wp
              rigid = .false.
              do e = 0, span(3)
                do b = 0, span(2)
                  do a = 0, span(1)
                    n = [i + a, j + b, k + e]
                    if (nodes%q(8, n(1), n(2), n(3)) > min_mass) rigid = .true.
                    if (sp%sliding) then
                      if (nodes%q(8, n(1), n(2), n(3)) > min_mass) then
                        mr = mr + nodes%q(8, n(1), n(2), n(3))
                        mvr = mvr + nodes%q(8 + d, n(1), n(2), n(3))
                      end if
                      mi = nodes%q(1, n(1), n(2), n(3))
                    else
                      mi = nodes%q(1, n(1), n(2), n(3)) + nodes%q(8, n(1), n(2), n(3))
                    end if
                    if (mi <= min_mass) cycle
                    m = m + mi
                    mv = mv + mi * nodes%vel_l(d, n(1), n(2), n(3))
                  end do
                end do
              end do
              sp%uface0(i, j, k, d) = 0.0_wp
              if (m > 0.0_wp) sp%uface0(i, j, k, d) = mv / m
              if (sp%sliding) then
                ur = 0.0_wp
                if (mr > 0.0_wp) ur = mvr / mr
                ! a face next to a wall cell, or with solid but no deformable solid on either
                ! side, moves with the rigid body
                rigid = body_face(sp, [i, j, k] - o, [i, j, k])
                if (rigid) sp%uface0(i, j, k, d) = ur
                sp%rigid_flux(i, j, k, d) = 0.0_wp
                if (.not. closed_face(state, grid, d, [i, j, k])) sp%rigid_flux(i, j, k, d) = &
                  ur * merge(sp%rigid_fraction(i, j, k, d), sp%rigid_fraction_hi(i, j, k, d), &
                  ur >= 0.0_wp)
              end if
              sp%uface(i, j, k, d) = sp%uface0(i, j, k, d)
              sp%rigid_face(i, j, k, d) = merge(1.0_wp, 0.0_wp, rigid)
              sp%vface(i, j, k, d) = 0.0_wp
              sp%platen_coef(i, j, k, d) = 0.0_wp
              if (.not. rigid .and. m > 0.0_wp .and. closed_face(state, grid, d, [i, j, k])) then
                face = face_index(d, [i, j, k])
                if (sp%platen(face)) then
                  ! a loading platen: the inner cell's pore pressure above the outside pressure
                  ! pushes the face's nodes outward (the pore fluid's share of the load), with
                  ! acceleration (p - p_b) A / M, M the face's share of its nodes' mass
                  ! (`platen_face_mass`); dp implicitly (ice_pressure)
                  inner = [i, j, k] - merge(o, 0, mod(face, 2) == 0)
                  sp%platen_coef(i, j, k, d) = grid%cell_volume / grid%dx(d) / &
                    platen_face_mass(sp%sliding, grid, nodes, d, [i, j, k], span, min_mass)
                  sp%uface(i, j, k, d) = sp%uface(i, j, k, d) + merge(1.0_wp, -1.0_wp, &
                    mod(face, 2) == 0) * dt * sp%platen_coef(i, j, k, d) * &
                    (state%pressure(inner(1), inner(2), inner(3)) - state%p_boundary(face))
                end if
              end if
              if (rigid .or. closed_face(state, grid, d, [i, j, k])) cycle
              vl = sp%spvol(i - o(1), j - o(2), k - o(3))
              vr = sp%spvol(i, j, k)
              if (sp%sliding) then
                ! the deformable solid's grains only
                if (sp%frac_def(i - o(1), j - o(2), k - o(3)) <= 0.0_wp) vl = 0.0_wp
                if (sp%frac_def(i, j, k) <= 0.0_wp) vr = 0.0_wp
              end if
              if (vl > 0.0_wp .and. vr > 0.0_wp) then
                v = 0.5_wp * (vl + vr)
              else
                v = max(vl, vr)
              end if
              sp%vface(i, j, k, d) = v
              sp%uface(i, j, k, d) = sp%uface(i, j, k, d) - dt * v * &
                (state%pressure(i, j, k) - state%pressure(i - o(1), j - o(2), k - o(3))) / &
                grid%dx(d)
            end do
          end do
        end do
      end do
    end associate
  end subroutine solid_face_predictor

  !> Mass [kg] a loading platen's face (direction d, index c) pushes: each of its nodes' solid
  !! mass shared equally among the domain faces of that plane the node belongs to (1 in 1D, up
  !! to 2 in 2D, 4 in 3D), so the faces of a plane share its nodes' mass exactly and a uniform
  !! pressure gives every node the same acceleration (p - p_b) A / M, edges included.
  pure real(wp) function platen_face_mass(sliding, grid, nodes, d, c, span, min_mass) &
    result(mass)
    logical, intent(in) :: sliding              !< rigid bodies slide (deformable mass only)
    type(grid_t), intent(in) :: grid            !< block geometry
    type(mpm_nodes_t), intent(in) :: nodes      !< node fields
    integer, intent(in) :: d                    !< face direction
    integer, intent(in) :: c(3)                 !< face index
    integer, intent(in) :: span(3)              !< node offsets across the face (0 or 1)
    real(wp), intent(in) :: min_mass            !< empty-node threshold [kg]
    integer :: a, b, e, n(3), t, faces
    real(wp) :: mi
    mass = 0.0_wp
    do e = 0, span(3)
      do b = 0, span(2)
        do a = 0, span(1)
          n = c + [a, b, e]
          mi = nodes%q(1, n(1), n(2), n(3))
          if (.not. sliding) mi = mi + nodes%q(8, n(1), n(2), n(3))
          if (mi <= min_mass) cycle
          faces = 1
          do t = 1, 3
            if (t == d .or. .not. grid%active(t)) cycle
            if (grid%periodic(t)) then
              faces = faces * 2
            else
              faces = faces * (count([n(t) - 1, n(t)] >= 1 .and. [n(t) - 1, n(t)] <= &
                grid%ncells(t)))
            end if
          end do
          mass = mass + mi / real(max(faces, 1), wp)
        end do
      end do
    end do
  end function platen_face_mass

  !> Eqs. 52, 66-67 (E5) through the faces: every node with solid mass adds the mean of the
  !! increments u_s,f - u_s,f0 of the faces it belongs to. `du` is node-shaped scratch
  !! (3, lbn..ubn): the face of direction d with index i along d and cell indices across sits at
  !! node index (i, j, k), so the node halo exchange fills it everywhere in the domain, domain
  !! faces included. The caller applies the boundary conditions and eq. 69 afterwards. With
  !! sliding rigid bodies the nodes touching one (contact nodes) take the increments too, and
  !! faces that carry the rigid body (prescribed, flag in du(3 + d)) do not count in the mean.
  subroutine solid_face_to_nodes(state, grid, dom, halo, nodes, du, min_mass)
    type(ice_state_t), intent(in) :: state      !< solid phase face velocities
    type(grid_t), intent(in) :: grid            !< block geometry
    type(domain_t), intent(in) :: dom           !< decomposition
    type(halo_t), intent(inout) :: halo         !< halo buffers (>= 3 components)
    type(mpm_nodes_t), intent(inout) :: nodes   !< vel_l updated
    real(wp), intent(inout) :: du(:, grid%lbn(1):, grid%lbn(2):, grid%lbn(3):) !< scratch
                                                !! (6 components)
    real(wp), intent(in) :: min_mass            !< empty-node threshold [kg]
    integer :: d, i, j, k, r(2, 3), span(3), a, b, e, c(3), cnt
    real(wp) :: s
    logical :: sliding
    sliding = state%solid%sliding
    du = 0.0_wp
    do d = 1, 3
      if (.not. grid%active(d)) cycle
      r = face_range(grid, d)
      do k = r(1, 3), r(2, 3)
        do j = r(1, 2), r(2, 2)
          do i = r(1, 1), r(2, 1)
            du(d, i, j, k) = state%solid%uface(i, j, k, d) - state%solid%uface0(i, j, k, d)
            du(3 + d, i, j, k) = state%solid%rigid_face(i, j, k, d)
          end do
        end do
      end do
    end do
    call halo_exchange_node_vec(halo, dom, grid, du)
    do d = 1, 3
      if (.not. grid%active(d)) cycle
      span = merge(1, 0, grid%active)
      span(d) = 0
      do k = grid%lbn(3), grid%ubn(3)
        do j = grid%lbn(2), grid%ubn(2)
          do i = grid%lbn(1), grid%ubn(1)
            if (nodes%q(1, i, j, k) <= min_mass) cycle
            if (nodes%q(8, i, j, k) > min_mass .and. .not. sliding) cycle
            s = 0.0_wp
            cnt = 0
            do e = 0, span(3)
              do b = 0, span(2)
                do a = 0, span(1)
                  c = [i - a, j - b, k - e]
                  if (.not. face_exists(grid, d, c)) cycle
                  if (sliding .and. du(3 + d, c(1), c(2), c(3)) > 0.5_wp) cycle
                  s = s + du(d, c(1), c(2), c(3))
                  cnt = cnt + 1
                end do
              end do
            end do
            if (cnt > 0) nodes%vel_l(d, i, j, k) = nodes%vel_l(d, i, j, k) + s / real(cnt, wp)
          end do
        end do
      end do
    end do
  end subroutine solid_face_to_nodes

  !> True when the face (direction d, index c: node index along d, cell indices across) lies in
  !! the domain and in the node allocation.
  pure logical function face_exists(grid, d, c) result(ok)
    type(grid_t), intent(in) :: grid  !< block geometry
    integer, intent(in) :: d          !< face direction
    integer, intent(in) :: c(3)       !< face index
    integer :: e
    ok = .true.
    do e = 1, 3
      if (.not. grid%active(e)) cycle
      if (c(e) < grid%lbn(e) .or. c(e) > grid%ubn(e)) ok = .false.
      if (grid%periodic(e)) cycle
      if (e == d) then
        if (c(e) < 1 .or. c(e) > grid%ncells(e) + 1) ok = .false.
      else
        if (c(e) < 1 .or. c(e) > grid%ncells(e)) ok = .false.
      end if
    end do
  end function face_exists

  !> Tracked solid fraction at the end of the step, with exactly the volume terms of the
  !! pressure equation: phi_s += source - dt/V sum_faces A phi_s,up u_s,f - phi_s kappa_s dp.
  subroutine solid_track_fraction(state, grid, dt, max_fraction)
    type(ice_state_t), intent(inout) :: state   !< solid phase (vfrac updated, owned cells)
    type(grid_t), intent(in) :: grid            !< block geometry
    real(wp), intent(in) :: dt                  !< time step [s]
    real(wp), intent(in) :: max_fraction        !< largest solid fraction [-]
    integer :: i, j, k, d, o(3)
    real(wp) :: flux, phi_l, phi_r, area
    associate (sp => state%solid)
      do k = grid%lo(3), grid%hi(3)
        do j = grid%lo(2), grid%hi(2)
          do i = grid%lo(1), grid%hi(1)
            flux = 0.0_wp
            do d = 1, 3
              if (.not. grid%active(d)) cycle
              o = 0
              o(d) = 1
              area = grid%cell_volume / grid%dx(d)
              phi_r = solid_face_fraction(state, d, o, i + o(1), j + o(2), k + o(3))
              phi_l = solid_face_fraction(state, d, o, i, j, k)
              flux = flux + area * (phi_r * sp%uface(i + o(1), j + o(2), k + o(3), d) - &
                phi_l * sp%uface(i, j, k, d) + sp%rigid_flux(i + o(1), j + o(2), k + o(3), d) - &
                sp%rigid_flux(i, j, k, d))
            end do
            sp%source(i, j, k) = sp%vfrac(i, j, k) + sp%source(i, j, k) - dt * flux / &
              grid%cell_volume - sp%vfrac(i, j, k) * sp%kappa(i, j, k) * state%dp_total(i, j, k)
          end do
        end do
      end do
      ! (source used as scratch so that every flux above reads the old fractions)
      do k = grid%lo(3), grid%hi(3)
        do j = grid%lo(2), grid%hi(2)
          do i = grid%lo(1), grid%hi(1)
            sp%vfrac(i, j, k) = min(max(sp%source(i, j, k), 0.0_wp), max_fraction)
            sp%source(i, j, k) = 0.0_wp
          end do
        end do
      end do
    end associate
  end subroutine solid_track_fraction

  !> Advective part of the fluid face predictor (eq. 31) at faces next to solid: the face's own
  !! final velocity of the previous step instead of the mass-weighted mean of the two cell
  !! velocities (a staggered momentum there; departure from eq. 31). A fluid's cell velocity in
  !! a porous cell is its pore velocity, which jumps with the porosity while the flux is
  !! continuous, and ICE's cell momentum sees only the two-cell-wide pressure difference of the
  !! face pressures (eq. 37): the cell mean is wrong at the edge of a porous body (a 20-cell
  !! Darcy column had a 7 % too fast pore velocity and an odd-even velocity pattern in the free
  !! water) and lags in a consolidating column. The drag makes the face inertia negligible
  !! there, so the face momentum is not advected. The pressure and gravity terms stay.
  subroutine fluid_face_predictor_porous(state, grid, previous)
    type(ice_state_t), intent(inout) :: state   !< fluids (uface updated)
    type(grid_t), intent(in) :: grid            !< block geometry
    real(wp), intent(in) :: previous(:, grid%lbc(1):, grid%lbc(2):, grid%lbc(3):, :) !< last
                                                !! step's final face velocities (3, cells, fluid)
    integer :: m, i, j, k, d, o(3), r(2, 3)
    real(wp) :: rl, rr, mean
    do d = 1, 3
      if (.not. grid%active(d)) cycle
      o = 0
      o(d) = 1
      r = face_range(grid, d)
      do k = r(1, 3), r(2, 3)
        do j = r(1, 2), r(2, 2)
          do i = r(1, 1), r(2, 1)
            if (closed_face(state, grid, d, [i, j, k])) cycle
            if (state%solid%vfrac(i - o(1), j - o(2), k - o(3)) <= 0.0_wp .and. &
              state%solid%vfrac(i, j, k) <= 0.0_wp) cycle
            do m = 1, state%nfluids
              associate (f => state%fluid(m))
                rl = f%rho(i - o(1), j - o(2), k - o(3))
                rr = f%rho(i, j, k)
                if (rl + rr <= 0.0_wp) cycle
                mean = (rl * f%vel(i - o(1), j - o(2), k - o(3), d) + rr * f%vel(i, j, k, d)) / &
                  (rl + rr)
                f%uface(i, j, k, d) = f%uface(i, j, k, d) - mean + previous(d, i, j, k, m)
              end associate
            end do
          end do
        end do
      end do
    end do
  end subroutine fluid_face_predictor_porous

  !> Near solid (a cell holding solid or next to one), the Lagrangian cell velocity of every
  !! fluid becomes the flux-consistent mean of its two final face velocities, component by
  !! component: u_c = (n_up,lo u_lo + n_up,hi u_hi) / (2 n_c) with the pore fractions
  !! n = 1 - phi_s (upwind at the faces). Departure from eqs. 42-51 for the normal components
  !! there: the faces carry the fluid's momentum next to solid (`fluid_face_predictor_porous`),
  !! and fluid leaving a porous body at the pore velocity would otherwise push an odd-even
  !! velocity pattern into the free fluid, a null mode of ICE's cell momentum that nothing
  !! restores. The pore fractions, not the fluid's own: with one fluid they are the same, but
  !! at a free surface next to the bed the fluid's fraction jumps from a full cell to a partly
  !! filled one, and n_up u / (2 phi_c) with phi_c < n_up / 2 amplified the face velocity (the
  !! 40 mm debris flow's water over the shelf edge: ten-fold per millisecond, then failure).
  subroutine fluid_face_blend(state, grid)
    type(ice_state_t), intent(inout) :: state   !< fluids (lag(:,:,:,1:3) updated, owned cells)
    type(grid_t), intent(in) :: grid            !< block geometry
    integer :: m, i, j, k, d, o(3)
    real(wp) :: flo, fhi, ulo, uhi
    do m = 1, state%nfluids
      associate (f => state%fluid(m), phi_s => state%solid%vfrac)
        do d = 1, 3
          if (.not. grid%active(d)) cycle
          o = 0
          o(d) = 1
          do k = grid%lo(3), grid%hi(3)
            do j = grid%lo(2), grid%hi(2)
              do i = grid%lo(1), grid%hi(1)
                if (f%rho(i, j, k) <= 0.0_wp .or. f%vfrac(i, j, k) <= 0.0_wp) cycle
                if (.not. near_solid(state, grid, [i, j, k])) cycle
                ulo = f%uface(i, j, k, d)
                uhi = f%uface(i + o(1), j + o(2), k + o(3), d)
                flo = 1.0_wp - upwind(ulo, phi_s(i - o(1), j - o(2), k - o(3)), phi_s(i, j, k))
                fhi = 1.0_wp - upwind(uhi, phi_s(i, j, k), phi_s(i + o(1), j + o(2), k + o(3)))
                f%lag(i, j, k, d) = 0.5_wp * (flo * ulo + fhi * uhi) / (1.0_wp - phi_s(i, j, k))
              end do
            end do
          end do
        end do
      end associate
    end do
  end subroutine fluid_face_blend

  !> True when cell c or one of its face neighbours holds solid.
  pure logical function near_solid(state, grid, c) result(near)
    type(ice_state_t), intent(in) :: state  !< solid phase
    type(grid_t), intent(in) :: grid        !< block geometry
    integer, intent(in) :: c(3)             !< cell
    integer :: d, o(3)
    near = state%solid%vfrac(c(1), c(2), c(3)) > 0.0_wp
    do d = 1, 3
      if (near) return
      if (.not. grid%active(d)) cycle
      o = 0
      o(d) = 1
      near = state%solid%vfrac(c(1) - o(1), c(2) - o(2), c(3) - o(3)) > 0.0_wp .or. &
        state%solid%vfrac(c(1) + o(1), c(2) + o(2), c(3) + o(3)) > 0.0_wp
    end do
  end function near_solid

  !> Pore pressure of the particles: the pressure of the cell holding each particle [Pa].
  subroutine solid_pore_pressure(p, grid, pressure)
    type(particles_t), intent(inout) :: p       !< particles (pore_pressure written)
    type(grid_t), intent(in) :: grid            !< block geometry
    real(wp), intent(in) :: pressure(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !< cell pressure
    integer :: ip, d, c(3)
    do ip = 1, p%np
      c = 1
      do d = 1, 3
        if (grid%active(d)) c(d) = min(max(floor((p%x(d, ip) - grid%lower(d)) / grid%dx(d)) + 1, &
          grid%lbc(d)), grid%ubc(d))
      end do
      p%pore_pressure(ip) = pressure(c(1), c(2), c(3))
    end do
  end subroutine solid_pore_pressure
end module mpmice_solid_cells
