!> Geostatic effective stress of a porous solid under a fluid (coupled scene). The seeding
!! (`particles_seeding`, `&solid geostatic`) gives each particle sigma_v = -(1 - n) rho_s |g| d, the
!! weight of the grains over its depth d below the solid's surface, and K0 sigma_v across. Under
!! a hydrostatic pore fluid (`&physics hydrostatic_init`) the skeleton carries only the grains'
!! submerged weight: sigma'_v = -(1 - n) (rho_s - rho_f) |g| d (Terzaghi), the fluid's pressure
!! gradient carrying the rest (the buoyancy -phi_s grad p of the coupled momentum balance). Here
!! rho_f is the pore fluid's density in the particle's cell at the start, sum over the fluids of
!! their bulk densities over the cell's porosity: water for a submerged soil, about 1.2 kg/m^3
!! for a dry one. It is taken for the whole column above the particle (a soil whose pores hold
!! water below and air above a level inside it is not resolved).
module mpmice_geostatic
  use mpmice_kinds, only: wp
  use grid_layout, only: grid_t, clamped_cell
  use ice_state, only: ice_state_t
  use particles_store, only: particles_t
  implicit none
  private

  public :: buoyant_geostatic_stress

contains

  !> Scale the geostatic stress of the particles `p` (grains of density `grain_density`
  !! [kg/m^3]) by (rho_s - rho_f) / rho_s with the pore fluid's density rho_f in each
  !! particle's cell (module header). Owned particles; called once, after the initial
  !! equilibration of the fluids with the solid.
  subroutine buoyant_geostatic_stress(p, state, grid, grain_density)
    type(particles_t), intent(inout) :: p    !< particles of one solid (stress scaled)
    type(ice_state_t), intent(in) :: state   !< fluids at the start (bulk densities, fractions)
    type(grid_t), intent(in) :: grid         !< block geometry
    real(wp), intent(in) :: grain_density    !< rho_s [kg/m^3]
    integer :: n, m, c(3)
    real(wp) :: mass, volume, factor
    do n = 1, p%np
      c = clamped_cell(grid, p%x(:, n), grid%lo, grid%hi)
      mass = 0.0_wp
      volume = 0.0_wp
      do m = 1, state%nfluids
        mass = mass + state%fluid(m)%rho(c(1), c(2), c(3))
        volume = volume + state%fluid(m)%vfrac(c(1), c(2), c(3))
      end do
      if (volume <= 0.0_wp) cycle
      factor = 1.0_wp - mass / volume / grain_density
      p%stress(:, n) = factor * p%stress(:, n)
      p%stress_unrot(:, n) = factor * p%stress_unrot(:, n)
    end do
  end subroutine buoyant_geostatic_stress
end module mpmice_geostatic
