!> Rigid bodies that the deformable solids slide on in a coupled scene (`&mpm rigid_contact =
!! 'friction'`, `solid_phase_t%sliding`; docs/mpmice.md, departure 15): how the grid's solid
!! phase is split where the fluids meet a rigid body and a soil in contact with it.
!!
!! * Wall cells: a cell the rigid bodies fill to at least `wall_fraction` belongs to the wall the
!!   fluids see; the faces next to it move with the body (`body_face`).
!! * Overlap redirect: a soil particle's deposit over a wall cell goes to the cell's face
!!   neighbours outside the wall (`wall_neighbours`, called by `mpmice_solid_cells%solid_deposit`).
!! * Exchange partner of the fluids per cell (`partner_fields`): the deformable solid where the
!!   cell holds any, the rigid body in a wall cell, none at a body's edge.
!! * Contact nodes: the acceleration the fluid's pressure is expected to add there
!!   (`contact_pressure_accel`), on which the nodal contact is judged.
!! * The fluids' pressure force on each rigid body (`fluid_pressure_force`), written with the
!!   contact force by `mpmice_scene`.
module mpmice_rigid_contact
  use mpmice_kinds, only: wp
  use grid_layout, only: grid_t
  use grid_sweep, only: unit_offset
  use mpm_nodes, only: mpm_nodes_t, node_mass, node_rigid_mass
  use ice_state, only: ice_state_t
  use exchange_solid_phase, only: solid_phase_t
  use exchange_drag, only: drag_reduced_coefficient
  use mpmice_solid_coupling, only: solid_coupling_t, surface_body_fraction, surface_drag_scale
  use mpmice_deposit_layout, only: deposit_solid_volume
  implicit none
  private

  public :: wall_fraction, body_face, wall_neighbours, wall_plane, partner_fields, &
    contact_pressure_accel, fluid_pressure_force

  !> Sliding rigid bodies: a cell the rigid solid fills to at least this fraction is part of the
  !! wall the fluids see (`partner_fields`).
  real(wp), parameter :: wall_fraction = 0.5_wp

contains

  !> True when cell c belongs to the wall of a sliding rigid body: the body fills at least
  !! `wall_fraction` of it.
  pure logical function wall_cell(sp, c)
    type(solid_phase_t), intent(in) :: sp  !< solid phase
    integer, intent(in) :: c(3)                !< cell
    wall_cell = sp%frac_rigid(c(1), c(2), c(3)) >= wall_fraction
  end function wall_cell

  !> True when the face between cells `lo` and `hi` moves with the rigid body (prescribed): it is
  !! next to a wall cell (`wall_cell`), or it has solid but no deformable solid on either side.
  pure logical function body_face(sp, lo, hi)
    type(solid_phase_t), intent(in) :: sp  !< solid phase
    integer, intent(in) :: lo(3)               !< cell on the face's low side
    integer, intent(in) :: hi(3)               !< cell on the face's high side
    body_face = wall_cell(sp, lo) .or. wall_cell(sp, hi) .or. &
      (sp%frac_def(lo(1), lo(2), lo(3)) <= 0.0_wp .and. &
      sp%frac_def(hi(1), hi(2), hi(3)) <= 0.0_wp .and. (sp%xfrac(lo(1), lo(2), lo(3)) &
      > 0.0_wp .or. sp%xfrac(hi(1), hi(2), hi(3)) > 0.0_wp))
  end function body_face

  !> True when the low face plane of cell `c` in direction `d` borders a wall cell (rigid
  !! fraction `wall_frac` >= `wall_fraction`) on either side.
  pure logical function wall_plane(wall_frac, grid, c, d) result(wall)
    type(grid_t), intent(in) :: grid     !< block geometry
    real(wp), intent(in) :: wall_frac(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !< rigid fraction
    integer, intent(in) :: c(3)          !< cell above the plane
    integer, intent(in) :: d             !< direction
    integer :: b(3)
    b = c
    b(d) = c(d) - 1
    wall = wall_frac(c(1), c(2), c(3)) >= wall_fraction
    if (b(d) >= grid%lbc(d)) wall = wall .or. wall_frac(b(1), b(2), b(3)) >= wall_fraction
  end function wall_plane

  !> The face neighbours of wall cell `c` that lie in the domain and outside the wall, with
  !! weights proportional to 1 / (distance from `x` to their centres) summing to 1; `c` itself
  !! (weight 1) when there is none.
  pure subroutine wall_neighbours(grid, wall_frac, c, x, n, tgt, tw)
    type(grid_t), intent(in) :: grid            !< block geometry
    real(wp), intent(in) :: wall_frac(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !< rigid fraction
    integer, intent(in) :: c(3)                 !< wall cell
    real(wp), intent(in) :: x(3)                !< particle position [m]
    integer, intent(out) :: n                   !< number of targets
    integer, intent(out) :: tgt(3, 6)           !< target cells
    real(wp), intent(out) :: tw(6)              !< their weights
    integer :: d, side, nb(3), e
    real(wp) :: dist, centre
    n = 0
    do d = 1, 3
      if (.not. grid%active(d)) cycle
      do side = -1, 1, 2
        nb = c
        nb(d) = c(d) + side
        if (nb(d) < grid%lbc(d) .or. nb(d) > grid%ubc(d)) cycle
        if (.not. grid%periodic(d) .and. (nb(d) < 1 .or. nb(d) > grid%ncells(d))) cycle
        if (wall_frac(nb(1), nb(2), nb(3)) >= wall_fraction) cycle
        dist = 0.0_wp
        do e = 1, 3
          if (.not. grid%active(e)) cycle
          centre = grid%lower(e) + (real(nb(e), wp) - 0.5_wp) * grid%dx(e)
          dist = dist + (x(e) - centre)**2
        end do
        n = n + 1
        tgt(:, n) = nb
        tw(n) = 1.0_wp / max(sqrt(dist), 1.0e-12_wp * grid%dx(d))
      end do
    end do
    if (n == 0) then
      n = 1
      tgt(:, 1) = c
      tw(1) = 1.0_wp
    else
      tw(1:n) = tw(1:n) / sum(tw(1:n))
    end if
  end subroutine wall_neighbours

  !> Sliding rigid bodies (`solid_phase_t%sliding`): the fields of the fluids' exchange
  !! partner in cell c. Where the cell holds deformable solid, the partner is that solid alone:
  !! its fraction phi_d, grain specific volume and drag; the rigid body's fraction phi_r only
  !! takes volume from the pores, so the deformable solid's own region (1 - phi_r) V has the
  !! fraction phi_k = phi_d / (1 - phi_r) and c = c(phi_k) / (1 - phi_r) per phi_d (the same
  !! pressure drop per length as the region: phi_d c = phi_k c(phi_k)); without rigid body in the
  !! cell, phi_k is the surface body fraction as without sliding. Where the rigid body fills at
  !! least half of the cell (`wall_fraction`, a wall cell) the partner is the rigid body
  !! (impermeable: the fluid moves with it) and deformable solid there is not seen by the
  !! fluids (frac_def = 0): a soil sliding along a staircase bed reaches into the bed's cells by
  !! a fraction of a particle, and the trace of pore volume there (1 - max_fraction) would turn
  !! that overlap into GPa of pressure. A cell with less rigid solid and no deformable one has no
  !! partner (xfrac = 0): the body's edge only takes pore volume. Dragged to the body, the water
  !! of those cells was frozen and sealed the corner a sliding block leaves behind (the pore
  !! water was sucked backwards through the block: over 0.12 s it reached 0.554 instead of 0.581
  !! of the drained block's acceleration).
  subroutine partner_fields(state, solid, grid, dep, solids, max_fraction, c)
    type(ice_state_t), intent(inout) :: state   !< solid phase (spvol, drag, frac_def, xfrac)
    type(solid_phase_t), intent(inout) :: solid !< solid phase
    type(grid_t), intent(in) :: grid            !< block geometry
    real(wp), intent(in) :: dep(:, grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !< deposits
    type(solid_coupling_t), intent(in) :: solids(:) !< coupling parameters per solid
    real(wp), intent(in) :: max_fraction        !< largest solid fraction [-]
    integer, intent(in) :: c(3)                 !< cell
    integer :: s, m, ns
    real(wp) :: vol_d, vol_r, mass_d, mass_r, phi_d, phi_r, phi_k, scale, rho_f, slip, cs, wsum
    real(wp) :: fs
    logical :: deformable, surface
    ns = size(solids)
    vol_d = 0.0_wp
    vol_r = 0.0_wp
    mass_d = 0.0_wp
    mass_r = 0.0_wp
    do s = 1, ns
      if (solids(s)%rigid) then
        vol_r = vol_r + dep(deposit_solid_volume(s), c(1), c(2), c(3))
        mass_r = mass_r + dep(deposit_solid_volume(s), c(1), c(2), c(3)) * solids(s)%grain_density
      else
        vol_d = vol_d + dep(deposit_solid_volume(s), c(1), c(2), c(3))
        mass_d = mass_d + dep(deposit_solid_volume(s), c(1), c(2), c(3)) * solids(s)%grain_density
      end if
    end do
    phi_d = min(vol_d / grid%cell_volume, max_fraction)
    phi_r = min(vol_r / grid%cell_volume, max_fraction)
    deformable = vol_d > 0.0_wp .and. phi_r < wall_fraction
    surface = .false.
    if (.not. deformable) phi_d = 0.0_wp
    associate (sp => solid)
      sp%frac_def(c(1), c(2), c(3)) = phi_d
      sp%frac_rigid(c(1), c(2), c(3)) = phi_r
      if (deformable) then
        sp%xfrac(c(1), c(2), c(3)) = phi_d
        sp%spvol(c(1), c(2), c(3)) = vol_d / mass_d
        if (phi_r > 0.0_wp) then
          phi_k = min(phi_d / (1.0_wp - phi_r), max_fraction)
          scale = 1.0_wp / (1.0_wp - phi_r)
        else
          phi_k = surface_body_fraction(grid, dep, ns, c, phi_d, max_fraction)
          scale = surface_drag_scale(phi_d, phi_k, .false.)
          surface = .true.
        end if
      else if (phi_r >= wall_fraction) then
        sp%xfrac(c(1), c(2), c(3)) = phi_r
        sp%spvol(c(1), c(2), c(3)) = vol_r / max(mass_r, tiny(1.0_wp))
        phi_k = phi_r
        scale = 1.0_wp
      else
        ! a rigid body's edge without deformable solid: only volume, no partner
        sp%spvol(c(1), c(2), c(3)) = vol_r / max(mass_r, tiny(1.0_wp))
        return
      end if
      do m = 1, state%nfluids
        associate (f => state%fluid(m))
          rho_f = 1.0_wp / max(f%spvol(c(1), c(2), c(3)), tiny(1.0_wp))
          slip = norm2(sp%vel(c(1), c(2), c(3), :) - f%vel(c(1), c(2), c(3), :))
          cs = 0.0_wp
          wsum = 0.0_wp
          do s = 1, ns
            if (solids(s)%rigid .eqv. deformable) cycle
            if (dep(deposit_solid_volume(s), c(1), c(2), c(3)) <= 0.0_wp) cycle
            fs = scale
            if (surface .and. solids(s)%surface_drag_parallel) fs = surface_drag_scale(phi_d, &
              phi_k, .true.)
            cs = cs + dep(deposit_solid_volume(s), c(1), c(2), c(3)) * fs * &
              drag_reduced_coefficient(solids(s)%drag_law, phi_k, solids(s)%grain_size, f%viscosity, rho_f, slip, &
              solids(s)%drag_coefficient, solids(s)%forchheimer_a, solids(s)%forchheimer_b)
            wsum = wsum + dep(deposit_solid_volume(s), c(1), c(2), c(3))
          end do
          sp%drag(c(1), c(2), c(3), m) = 0.0_wp
          if (wsum > 0.0_wp) sp%drag(c(1), c(2), c(3), m) = cs / wsum
        end associate
      end do
    end associate
  end subroutine partner_fields

  !> Sliding rigid bodies: the acceleration -v_s grad p [m/s^2] the fluid's pressure is expected
  !! to give the deformable solid at every node with deformable and rigid mass (a contact node),
  !! zero elsewhere: grad p the mean of the cell differences around the node, v_s the mean grain
  !! specific volume of the surrounding cells with deformable solid. `nodal_solve` judges the
  !! contact on v + dt a, so that the face velocities of the pressure equation obey it.
  subroutine contact_pressure_accel(state, solid, grid, nodes, min_mass, accel)
    type(ice_state_t), intent(in) :: state      !< pressure (ghosts filled) and solid phase
    type(solid_phase_t), intent(in) :: solid !< solid phase
    type(grid_t), intent(in) :: grid            !< block geometry
    type(mpm_nodes_t), intent(in) :: nodes      !< node fields (after P2G)
    real(wp), intent(in) :: min_mass            !< empty-node threshold [kg]
    real(wp), intent(out) :: accel(:, grid%lbn(1):, grid%lbn(2):, grid%lbn(3):) !< [m/s^2]
    integer :: i, j, k, a, b, e, d, top(3), c(3), lo(3)
    real(wp) :: g(3), vs, wsum, w
    top = merge(1, 0, grid%active)
    accel = 0.0_wp
    associate (sp => solid)
      do k = grid%lbn(3) + top(3), grid%ubn(3) - top(3)
        do j = grid%lbn(2) + top(2), grid%ubn(2) - top(2)
          do i = grid%lbn(1) + top(1), grid%ubn(1) - top(1)
            if (nodes%q(node_mass, i, j, k) <= min_mass .or. &
              nodes%q(node_rigid_mass, i, j, k) <= min_mass) cycle
            g = 0.0_wp
            vs = 0.0_wp
            wsum = 0.0_wp
            lo = [i, j, k] - top
            do e = 0, top(3)
              do b = 0, top(2)
                do a = 0, top(1)
                  c = lo + [a, b, e]
                  ! the cell's pressure enters each difference with +- its offset
                  do d = 1, 3
                    if (.not. grid%active(d)) cycle
                    w = merge(1.0_wp, -1.0_wp, c(d) > lo(d))
                    g(d) = g(d) + w * state%pressure(c(1), c(2), c(3)) / grid%dx(d)
                  end do
                  if (sp%frac_def(c(1), c(2), c(3)) > 0.0_wp) then
                    vs = vs + sp%spvol(c(1), c(2), c(3))
                    wsum = wsum + 1.0_wp
                  end if
                end do
              end do
            end do
            if (wsum <= 0.0_wp) cycle
            ! each difference was summed over the 2^(ndim-1) cell pairs across it
            g = g / real(product(top + 1) / 2, wp)
            accel(:, i, j, k) = -vs / wsum * g
          end do
        end do
      end do
    end associate
  end subroutine contact_pressure_accel
  !> The fluids' pressure force [N] on rigid body `s`: F = -oint p n dA over the body's surface,
  !! discretely (summation by parts of -int phi_b grad p dV) F_d = sum over the faces normal to
  !! d of p_f (phi_b,hi - phi_b,lo) A_f, phi_b the body's own cell fraction (`frac`), A_f the
  !! face area (per the grid's depth in an inactive dimension). Where phi_b jumps, p_f is the
  !! pressure of the fluid on the body's outer side (the cell with less of the body), carried
  !! hydrostatically to the face, p_c + rho_c g_d (x_f - x_c), rho_c the fluids' intrinsic
  !! density (bulk over porosity) - as eq. 37 does at a closed domain face. The cell pressure
  !! inside the body is not used: the faces next to a wall cell move with the body
  !! (`body_face`), so the pressure equation barely couples the body's trace of pore fluid to
  !! the outside and its pressure keeps its initial value (eq. 37's face mean would carry half
  !! of it). An outer cell that is itself a wall cell (rigid fraction >= `wall_fraction`, e.g.
  !! the body's half-filled edge cell) is stepped over to the next cell outward when it holds
  !! some of this body; when that one is a wall cell too, or the first was another body's wall,
  !! or the step leaves the domain, the face has no fluid and no force. Faces on a non-periodic
  !! domain face get no force (no fluid beyond). Absolute pressure: a body on the floor carries
  !! the full load p A of the fluid above it. Faces of the owned cells (the low face of each;
  !! needs `frac` and the pressure in two ghost layers); the caller sums over the ranks.
  pure function fluid_pressure_force(state, solid, grid, frac, s, gravity) result(force)
    type(ice_state_t), intent(in) :: state      !< pressure (ghosts filled) and fluids
    type(solid_phase_t), intent(in) :: solid !< solid phase
    type(grid_t), intent(in) :: grid            !< block geometry
    real(wp), intent(in) :: frac(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):, :) !< each solid's
                                                !! cell fraction (zero for deformable solids)
    integer, intent(in) :: s                    !< the rigid body (solid index)
    real(wp), intent(in) :: gravity(3)          !< gravitational acceleration [m/s^2]
    real(wp) :: force(3)
    integer :: i, j, k, d, m, o(3), lo(3), hi(3), c(3), step, walked
    real(wp) :: jump, area, p, rho, porosity
    force = 0.0_wp
    do d = 1, 3
      if (.not. grid%active(d)) cycle
      o = unit_offset(d)
      area = grid%cell_volume / grid%dx(d)
      do k = grid%lo(3), grid%hi(3)
        do j = grid%lo(2), grid%hi(2)
          do i = grid%lo(1), grid%hi(1)
            hi = [i, j, k]
            lo = hi - o
            if (.not. grid%periodic(d) .and. hi(d) == 1) cycle
            jump = frac(hi(1), hi(2), hi(3), s) - frac(lo(1), lo(2), lo(3), s)
            if (jump == 0.0_wp) cycle
            ! the outer side: the cell with less of the body
            if (jump < 0.0_wp) then
              c = hi
              step = 1
            else
              c = lo
              step = -1
            end if
            walked = 0
            if (sum(frac(c(1), c(2), c(3), :)) >= wall_fraction) then
              if (frac(c(1), c(2), c(3), s) <= 0.0_wp) cycle
              c(d) = c(d) + step
              walked = 1
              if (.not. grid%periodic(d) .and. (c(d) < 1 .or. c(d) > grid%ncells(d))) cycle
              if (sum(frac(c(1), c(2), c(3), :)) >= wall_fraction) cycle
            end if
            rho = 0.0_wp
            porosity = 1.0_wp - solid%vfrac(c(1), c(2), c(3))
            if (porosity > 0.0_wp) then
              do m = 1, state%nfluids
                rho = rho + state%fluid(m)%rho(c(1), c(2), c(3))
              end do
              rho = rho / porosity
            end if
            ! x_f - x_c = -step (1/2 + walked) dx
            p = state%pressure(c(1), c(2), c(3)) - rho * gravity(d) * real(step, wp) * &
              (0.5_wp + real(walked, wp)) * grid%dx(d)
            force(d) = force(d) + p * jump * area
          end do
        end do
      end do
    end do
  end function fluid_pressure_force
end module mpmice_rigid_contact
