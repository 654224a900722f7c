!> The solid phase's cell fields of a coupled scene (paper eqs. 28, 51): what the pressure
!! equation and the exchange see of the MPM particles in each cell, from their summed deposits
!! (`mpmice_deposit`) and the MPM nodes.
!!
!! * Tracked fraction: the fluids see a solid fraction phi_s that evolves with the same fluxes
!!   as the pressure equation (-dt div(phi_s u_s) - phi_s kappa_s dp), so sum phi = 1 holds to
!!   the outer tolerance; the difference to the particles' fraction enters the next step's
!!   pressure equation as a volume source (`solid_phase_t%source`), so fluid is pushed out
!!   instead of compressed (no pressure noise from the particle representation).
!! * The particles' pore pressure: the pressure of the cell holding each particle.
module mpmice_solid_fields
  use mpmice_kinds, only: wp
  use grid_layout, only: grid_t, clamped_cell
  use particles_store, only: particles_t
  use mpm_nodes, only: mpm_nodes_t, node_mass, node_rigid_mass, node_rigid_momentum
  use ice_state, only: ice_state_t
  use exchange_solid_phase, only: solid_phase_t
  use ice_pressure, only: solid_face_fraction
  use exchange_drag, only: drag_reduced_coefficient, drag_impermeable
  use mpmice_solid_coupling, only: solid_coupling_t, surface_body_fraction, surface_drag_scale
  use mpmice_deposit_layout, only: deposit_layout_t, deposit_layout, deposit_mass, &
    deposit_grain_volume, deposit_solid_volume
  use mpmice_rigid_contact, only: partner_fields
  implicit none
  private

  public :: solid_cell_fields, solid_cell_velocity, solid_track_fraction, solid_pore_pressure

  !> Least permeable solids' grain volume, per cell volume, that makes a cell with an
  !! impermeable solid a mixed one (`solid_cell_fields`).
  real(wp), parameter :: min_permeable_share = 1.0e-10_wp

contains

  !> From the summed deposits (valid in ghost cells too): the particles' solid fraction
  !! (capped at `max_fraction`), bulk density, grain specific volume and compressibility, and
  !! the reduced drag coefficient per fluid (slip from the velocities of time n); the heat
  !! capacity per volume, conductance phi_s k_s and mass-weighted temperature of the solid.
  subroutine solid_cell_fields(state, solid, grid, dep, solids, max_fraction, phi_p)
    type(ice_state_t), intent(inout) :: state   !< fluids; solid phase written
    type(solid_phase_t), intent(inout) :: solid !< solid phase
    type(grid_t), intent(in) :: grid            !< block geometry
    real(wp), intent(in) :: dep(:, grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !< deposits
    type(solid_coupling_t), intent(in) :: solids(:) !< coupling parameters per solid
    real(wp), intent(in) :: max_fraction        !< largest solid fraction [-]
    real(wp), intent(out) :: phi_p(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !< particle fraction
    integer :: i, j, k, s, m, ns, ilo(2), ihi(2), irlo(2), irhi(2), icap, iene, icond, d
    type(deposit_layout_t) :: lay
    real(wp) :: vol, phi, cs, rho_f, slip, wsum, phi_body, scale, vol_imp, vol_perm, phi_imp, fs
    logical :: mixed
    ns = size(solids)
    ! first and last (direction 1 and 3) of the plane components, 2 apart
    lay = deposit_layout(ns)
    ilo = lay%plane_low(1:3:2)
    ihi = lay%plane_high(1:3:2)
    irlo = lay%rigid_low(1:3:2)
    irhi = lay%rigid_high(1:3:2)
    icap = lay%heat_capacity
    iene = lay%energy
    icond = lay%conductance
    associate (sp => solid)
      sp%face_fraction = 0.0_wp
      sp%face_fraction_hi = 0.0_wp
      do k = grid%lbc(3), grid%ubc(3)
        do j = grid%lbc(2), grid%ubc(2)
          do i = grid%lbc(1), grid%ubc(1)
            sp%face_fraction(i, j, k, :) = min(dep(ilo(1):ilo(2):2, i, j, k), max_fraction)
            sp%face_fraction_hi(i, j, k, :) = min(dep(ihi(1):ihi(2):2, i, j, k), max_fraction)
            ! the solid fraction in each half of the cell along d: its grain volume there over
            ! the half cell's volume (the two halves average to the particles' cell fraction);
            ! only the face-plane drag reads them
            if (sp%plane_drag) then
              do d = 1, 3
                vol = dep(lay%half_low(d), i, j, k)
                sp%half_low(i, j, k, d) = min(max(2.0_wp * vol / grid%cell_volume, 0.0_wp), &
                  max_fraction)
                vol = dep(deposit_grain_volume, i, j, k) - vol
                sp%half_high(i, j, k, d) = min(max(2.0_wp * vol / grid%cell_volume, 0.0_wp), &
                  max_fraction)
              end do
            end if
            if (sp%sliding) then
              sp%rigid_fraction(i, j, k, :) = min(dep(irlo(1):irlo(2):2, i, j, k), max_fraction)
              sp%rigid_fraction_hi(i, j, k, :) = min(dep(irhi(1):irhi(2):2, i, j, k), &
                max_fraction)
            end if
          end do
        end do
      end do
      do k = grid%lbc(3), grid%ubc(3)
        do j = grid%lbc(2), grid%ubc(2)
          do i = grid%lbc(1), grid%ubc(1)
            vol = dep(deposit_grain_volume, i, j, k)
            phi = min(vol / grid%cell_volume, max_fraction)
            phi_p(i, j, k) = phi
            sp%rho(i, j, k) = dep(deposit_mass, i, j, k) / grid%cell_volume
            sp%spvol(i, j, k) = 0.0_wp
            sp%kappa(i, j, k) = 0.0_wp
            sp%drag(i, j, k, :) = 0.0_wp
            sp%frac_def(i, j, k) = 0.0_wp
            sp%frac_rigid(i, j, k) = 0.0_wp
            sp%xfrac(i, j, k) = 0.0_wp
            sp%heat_cap(i, j, k) = dep(icap, i, j, k) / grid%cell_volume
            sp%conductance(i, j, k) = dep(icond, i, j, k) / grid%cell_volume
            sp%temp(i, j, k) = 0.0_wp
            if (dep(icap, i, j, k) > 0.0_wp) sp%temp(i, j, k) = dep(iene, i, j, k) / &
              dep(icap, i, j, k)
            if (vol <= 0.0_wp .or. dep(deposit_mass, i, j, k) <= 0.0_wp) cycle
            do s = 1, ns
              sp%kappa(i, j, k) = sp%kappa(i, j, k) + dep(deposit_solid_volume(s), i, j, k) / &
                vol * solids(s)%grain_kappa
            end do
            if (sp%sliding) then
              call partner_fields(state, solid, grid, dep, solids, max_fraction, [i, j, k])
              cycle
            end if
            sp%spvol(i, j, k) = vol / dep(deposit_mass, i, j, k)
            ! impermeable solids share the cell with permeable ones (a soil on a structure whose
            ! face cuts the cell): the pore fluid lies in the permeable part, (1 - phi_imp) of
            ! the cell, at its own fraction phi_k = phi_perm / (1 - phi_imp); the drag is the
            ! permeable solids' c(phi_k) / (1 - phi_imp) per phi_perm, the impermeable ones only
            ! take volume (the same pressure drop per length as that part: phi_perm c = phi_k
            ! c(phi_k)). Weighted by the impermeable solids' share too, the drag was theirs,
            ! 1e15: it sealed the soil's pores in the cell, whose water then kept every volume
            ! change as pressure (+0.65 MPa stuck in the layer over the shaking base).
            ! A permeable share below `min_permeable_share` of the cell is no soil: the edge of
            ! a particle's domain over a structure's cell by round-off (a sand on a shaken base:
            ! 2.5e-16 of the cell), which decided by the order of the sums whether the water in
            ! the structure's cells moved with it or was free, and so differed between ranks.
            vol_imp = 0.0_wp
            vol_perm = 0.0_wp
            do s = 1, ns
              if (solids(s)%drag_law == drag_impermeable) then
                vol_imp = vol_imp + dep(deposit_solid_volume(s), i, j, k)
              else
                vol_perm = vol_perm + dep(deposit_solid_volume(s), i, j, k)
              end if
            end do
            mixed = vol_imp > 0.0_wp .and. vol_perm > min_permeable_share * grid%cell_volume
            if (mixed) then
              phi_imp = min(vol_imp / grid%cell_volume, max_fraction)
              phi_body = min((vol - vol_imp) / grid%cell_volume / (1.0_wp - phi_imp), &
                max_fraction)
              scale = 1.0_wp / (1.0_wp - phi_imp)
            else
              ! a cell crossed by the soil's surface: the drag of the body's fraction over the
              ! share phi / phi_body of the cell the body fills (series resistance, below)
              phi_body = surface_body_fraction(grid, dep, ns, [i, j, k], phi, max_fraction)
              scale = surface_drag_scale(phi, phi_body, .false.)
            end if
            do m = 1, state%nfluids
              associate (f => state%fluid(m))
                rho_f = 1.0_wp / max(f%spvol(i, j, k), tiny(1.0_wp))
                slip = norm2(sp%vel(i, j, k, :) - f%vel(i, j, k, :))
                cs = 0.0_wp
                wsum = 0.0_wp
                do s = 1, ns
                  if (dep(deposit_solid_volume(s), i, j, k) <= 0.0_wp) cycle
                  wsum = wsum + dep(deposit_solid_volume(s), i, j, k)
                  if (mixed .and. solids(s)%drag_law == drag_impermeable) cycle
                  fs = scale
                  if (.not. mixed .and. solids(s)%surface_drag_parallel) fs = &
                    surface_drag_scale(phi, phi_body, .true.)
                  cs = cs + dep(deposit_solid_volume(s), i, j, k) * fs * &
                    drag_reduced_coefficient(solids(s)%drag_law, phi_body, &
                    solids(s)%grain_size, f%viscosity, rho_f, slip, solids(s)%drag_coefficient, &
                    solids(s)%forchheimer_a, solids(s)%forchheimer_b)
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
  subroutine solid_cell_velocity(solid, grid, nodes, min_mass)
    type(solid_phase_t), intent(inout) :: solid !< solid phase
    type(grid_t), intent(in) :: grid            !< block geometry
    type(mpm_nodes_t), intent(in) :: nodes      !< node fields
    real(wp), intent(in) :: min_mass            !< empty-node threshold [kg]
    integer :: i, j, k, a, b, e, top(3)
    real(wp) :: m, mv(3), mi
    top = merge(1, 0, grid%active)
    associate (sp => solid)
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
                        if (q(node_mass) <= min_mass) cycle
                        m = m + q(node_mass)
                        mv = mv + q(node_mass) * nodes%vel_l(:, i + a, j + b, k + e)
                      else
                        if (q(node_rigid_mass) <= min_mass) cycle
                        m = m + q(node_rigid_mass)
                        mv = mv + q(node_rigid_momentum:node_rigid_momentum + 2)
                      end if
                      cycle
                    end if
                    mi = q(node_mass) + q(node_rigid_mass)
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

  !> Tracked solid fraction at the end of the step, with exactly the volume terms of the
  !! pressure equation: phi_s += source - dt/V sum_faces A phi_s,up u_s,f - phi_s kappa_s dp.
  subroutine solid_track_fraction(state, solid, grid, dt, max_fraction)
    type(ice_state_t), intent(inout) :: state   !< solid phase (vfrac updated, owned cells)
    type(solid_phase_t), intent(inout) :: solid !< solid phase
    type(grid_t), intent(in) :: grid            !< block geometry
    real(wp), intent(in) :: dt                  !< time step [s]
    real(wp), intent(in) :: max_fraction        !< largest solid fraction [-]
    integer :: i, j, k, d, o(3)
    real(wp) :: flux, phi_l, phi_r, area
    ! the x faces' upwind fractions of a row, each face once (a cell's high face is the next
    ! cell's low face)
    real(wp) :: phi_x(grid%lo(1):grid%hi(1) + 1)
    associate (sp => solid)
      do k = grid%lo(3), grid%hi(3)
        do j = grid%lo(2), grid%hi(2)
          if (grid%active(1)) then
            do i = grid%lo(1), grid%hi(1) + 1
              phi_x(i) = solid_face_fraction(solid, 1, [1, 0, 0], i, j, k)
            end do
          end if
          do i = grid%lo(1), grid%hi(1)
            flux = 0.0_wp
            do d = 1, 3
              if (.not. grid%active(d)) cycle
              o = 0
              o(d) = 1
              area = grid%cell_volume / grid%dx(d)
              if (d == 1) then
                phi_r = phi_x(i + 1)
                phi_l = phi_x(i)
              else
                phi_r = solid_face_fraction(solid, d, o, i + o(1), j + o(2), k + o(3))
                phi_l = solid_face_fraction(solid, d, o, i, j, k)
              end if
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

  !> Pore pressure of the particles: the pressure of the cell holding each particle [Pa].
  subroutine solid_pore_pressure(p, grid, pressure)
    type(particles_t), intent(inout) :: p       !< particles (pore_pressure written)
    type(grid_t), intent(in) :: grid            !< block geometry
    real(wp), intent(in) :: pressure(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !< cell pressure
    integer :: ip, c(3)
    do ip = 1, p%np
      c = clamped_cell(grid, p%x(:, ip), grid%lbc, grid%ubc)
      p%pore_pressure(ip) = pressure(c(1), c(2), c(3))
    end do
  end subroutine solid_pore_pressure
end module mpmice_solid_fields
