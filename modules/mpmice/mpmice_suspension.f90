!> Packing of the stress-free suspended particles of a coupled scene. A particle dilated past
!! its loosest packing (`&solid max_porosity`, `material_t%j_loose`) carries no effective
!! stress, so nothing in the skeleton opposes its kinematic volume change J = det F (eq. 75).
!! Where such particles crowd into part of a cell, the cell's velocity gradient can still
!! dilate them: their volumes then overlap, and each reports a packing far looser than the
!! grains its cell holds (the grain fraction the fluids see through the deposit, eq. 28).
!! `suspension_packing` bounds a suspended particle's J by its cell's grain fraction phi_c of
!! the same solid: J <= max(phi_0 / phi_c, j_loose), the volume gained beyond it is taken back
!! isotropically in the active directions. A particle whose cell holds the loosest packing or
!! more returns to j_loose (grains in contact at zero stress) and carries stress again once
!! compressed. Particles in contact (J <= j_loose) are not touched.
!!
!! `suspension_settling` lets the grains of a suspended particle settle inside it. A suspended
!! particle's volume follows the velocity field (eq. 75), which a layer of suspension thinner
!! than a cell does not resolve: on a bed or the floor its grains would sink through their pore
!! fluid and pack, yet its J stays. The grains of a cell sink relative to the fluids at the
!! hindered settling velocity of the drag law, w_s = (rho_s - rho_f) |g| / sum_m phi_m c_m (the
!! buoyant weight phi_s (rho_s - rho_f) g balanced by the drag phi_m phi_s c_m w of eq. 18,
!! `exchange_drag`); where the solid moves down relative to the fluids more slowly than that,
!! the particle is held by what lies below it, and the top of its grains descends at the
!! deficit w = w_s - (u_s - u_f) . g / |g| (Kynch's interface of a settling suspension):
!! dJ/dt = -J max(w, 0) / h, h = l_0 J^(1/d) its height (l_0 its initial size in the d active
!! directions). A particle falling freely through its fluid (w = 0) or lifted by an upward
!! flow (w < 0) keeps its J; none is taken past j_loose.

module mpmice_suspension
  use mpmice_kinds, only: wp
  use grid_layout, only: grid_t, clamped_cell
  use particles_store, only: particles_t
  use mpm_constitutive, only: material_t
  use mpm_tensor, only: det3
  use mpmice_deposit_layout, only: deposit_solid_volume
  use ice_state, only: ice_state_t
  use exchange_solid_phase, only: solid_phase_t
  implicit none
  private

  public :: suspension_packing, suspension_settling, settling_deficit, settled_jacobian

contains

  !> Bound the volume of solid `s`'s suspended particles by their cell's grain fraction (module
  !! header). `dep` is the deposit of the particles at their present positions, complete in the
  !! owned cells (after the reverse halo sum); the particles lie in owned cells.
  subroutine suspension_packing(p, mat, s, grid, dep)
    type(particles_t), intent(inout) :: p      !< particles of solid s
    type(material_t), intent(in) :: mat        !< their material
    integer, intent(in) :: s                   !< solid index in the deposit
    type(grid_t), intent(in) :: grid           !< block geometry
    real(wp), intent(in) :: dep(:, grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !< deposits
    integer :: ip, c(3), idx, nact
    real(wp) :: jac, phi_c, j_bound
    if (mat%j_loose >= huge(1.0_wp)) return
    idx = deposit_solid_volume(s)
    nact = count(grid%active)
    do ip = 1, p%np
      jac = det3(reshape(p%f(:, ip), [3, 3]))
      if (jac <= mat%j_loose) cycle
      c = clamped_cell(grid, p%x(:, ip), grid%lo, grid%hi)
      phi_c = dep(idx, c(1), c(2), c(3)) / grid%cell_volume
      if (phi_c <= 0.0_wp) cycle
      j_bound = max(mat%solid_fraction0 / phi_c, mat%j_loose)
      if (j_bound >= jac) cycle
      call rescale_particle(p, ip, grid%active, nact, jac, j_bound)
    end do
  end subroutine suspension_packing

  !> Settling of the grains inside solid `s`'s suspended particles over the step dt (module
  !! header), from the fields at the start of the step: the fluids' fractions, densities and
  !! velocities, the solid's cell velocity and its reduced drag coefficients. The particles lie
  !! in owned cells.
  subroutine suspension_settling(p, mat, grid, solid, state, grain_density, gravity, dt)
    type(particles_t), intent(inout) :: p      !< particles of one solid
    type(material_t), intent(in) :: mat        !< their material
    type(grid_t), intent(in) :: grid           !< block geometry
    type(solid_phase_t), intent(in) :: solid   !< solid phase (vel, drag)
    type(ice_state_t), intent(in) :: state     !< fluids (vfrac, spvol, vel)
    real(wp), intent(in) :: grain_density      !< rho_s of the grains [kg/m^3]
    real(wp), intent(in) :: gravity(3)         !< gravitational acceleration [m/s^2]
    real(wp), intent(in) :: dt                 !< step [s]
    integer :: ip, c(3), m, nact
    real(wp) :: jac, j_new, vol, rho_vol, cw, cu(3), w, thickness, phi_m
    if (mat%j_loose >= huge(1.0_wp) .or. norm2(gravity) <= 0.0_wp) return
    nact = count(grid%active)
    ! the particle's extent along the inactive directions (its volume per active size)
    thickness = product(grid%dx, mask=.not. grid%active)
    do ip = 1, p%np
      jac = det3(reshape(p%f(:, ip), [3, 3]))
      if (jac <= mat%j_loose) cycle
      c = clamped_cell(grid, p%x(:, ip), grid%lo, grid%hi)
      vol = 0.0_wp
      rho_vol = 0.0_wp
      cw = 0.0_wp
      cu = 0.0_wp
      do m = 1, state%nfluids
        associate (f => state%fluid(m))
          phi_m = f%vfrac(c(1), c(2), c(3))
          vol = vol + phi_m
          rho_vol = rho_vol + phi_m / f%spvol(c(1), c(2), c(3))
          cw = cw + phi_m * solid%drag(c(1), c(2), c(3), m)
          cu = cu + phi_m * solid%drag(c(1), c(2), c(3), m) * f%vel(c(1), c(2), c(3), :)
        end associate
      end do
      w = settling_deficit(grain_density, gravity, vol, rho_vol, cw, cu, &
        solid%vel(c(1), c(2), c(3), :))
      j_new = settled_jacobian(jac, mat%j_loose, w, &
        (p%volume0(ip) / thickness)**(1.0_wp / real(nact, wp)), nact, dt)
      if (j_new < jac) call rescale_particle(p, ip, grid%active, nact, jac, j_new)
    end do
  end subroutine suspension_settling

  !> Settling deficit w [m/s] of the grains of a cell (module header): their hindered settling
  !! velocity under the drag, w_s = (rho_s - rho_f) |g| / sum_m phi_m c_m, less their velocity
  !! relative to the drag-weighted fluid velocity along gravity. 0 without fluid or drag.
  pure real(wp) function settling_deficit(grain_density, gravity, vol, rho_vol, cw, cu, u_s) &
    result(w)
    real(wp), intent(in) :: grain_density  !< rho_s [kg/m^3]
    real(wp), intent(in) :: gravity(3)     !< gravitational acceleration [m/s^2]
    real(wp), intent(in) :: vol            !< sum_m phi_m, the fluids' fraction of the cell [-]
    real(wp), intent(in) :: rho_vol        !< sum_m phi_m rho_m [kg/m^3]
    real(wp), intent(in) :: cw             !< sum_m phi_m c_m [kg/m^3/s]
    real(wp), intent(in) :: cu(3)          !< sum_m phi_m c_m u_m [kg/m^2/s^2]
    real(wp), intent(in) :: u_s(3)         !< the solid's cell velocity [m/s]
    real(wp) :: g
    w = 0.0_wp
    g = norm2(gravity)
    if (vol <= 0.0_wp .or. cw <= 0.0_wp .or. g <= 0.0_wp) return
    w = (grain_density - rho_vol / vol) * g / cw - dot_product(u_s - cu / cw, gravity) / g
  end function settling_deficit

  !> J after a step dt of settling at the deficit w [m/s] (module header): dJ/dt = -J w / h with
  !! h = l0 J^(1/d) is d(J^(1/d))/dt = -w / (d l0), integrated exactly over the step:
  !! J_new^(1/d) = J^(1/d) - w dt / (d l0); not below j_loose, unchanged for w <= 0.
  pure real(wp) function settled_jacobian(jac, j_loose, w, l0, nact, dt) result(j_new)
    real(wp), intent(in) :: jac      !< J at the start [-]
    real(wp), intent(in) :: j_loose  !< the loosest packing's J [-]
    real(wp), intent(in) :: w        !< settling deficit [m/s]
    real(wp), intent(in) :: l0       !< the particle's initial size [m]
    integer, intent(in) :: nact      !< active directions d
    real(wp), intent(in) :: dt       !< step [s]
    real(wp) :: root
    j_new = jac
    if (w <= 0.0_wp .or. jac <= j_loose) return
    root = jac**(1.0_wp / real(nact, wp)) - w * dt / (real(nact, wp) * l0)
    if (root <= 0.0_wp) then
      j_new = j_loose
    else
      j_new = max(root**nact, j_loose)
    end if
  end function settled_jacobian

  !> Particle ip to J = j_new from J = jac: the rows of F scaled isotropically in the active
  !! directions (det(S F) = det(S) det(F); an isotropic S keeps the polar frame's rotation),
  !! its volume j_new V_0.
  subroutine rescale_particle(p, ip, active, nact, jac, j_new)
    type(particles_t), intent(inout) :: p  !< particles
    integer, intent(in) :: ip              !< the particle
    logical, intent(in) :: active(3)       !< active directions
    integer, intent(in) :: nact            !< their number
    real(wp), intent(in) :: jac            !< its J now [-]
    real(wp), intent(in) :: j_new          !< its J after [-]
    real(wp) :: scale
    integer :: a
    scale = (j_new / jac)**(1.0_wp / real(nact, wp))
    do a = 1, 3
      ! row a of F (column-major: f(a), f(a + 3), f(a + 6))
      if (active(a)) p%f(a:9:3, ip) = scale * p%f(a:9:3, ip)
    end do
    p%volume(ip) = j_new * p%volume0(ip)
  end subroutine rescale_particle
end module mpmice_suspension
