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
module mpmice_suspension
  use mpmice_kinds, only: wp
  use grid_layout, only: grid_t, clamped_cell
  use particles_store, only: particles_t
  use mpm_constitutive, only: material_t
  use mpm_tensor, only: det3
  use mpmice_deposit_layout, only: deposit_solid_volume
  implicit none
  private

  public :: suspension_packing

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
    integer :: ip, c(3), idx, a, nact
    real(wp) :: jac, phi_c, j_bound, scale
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
      ! row a of F (column-major: f(a), f(a + 3), f(a + 6)) scaled in the active directions:
      ! det(S F) = det(S) det(F); an isotropic S keeps the polar frame's rotation
      scale = (j_bound / jac)**(1.0_wp / real(nact, wp))
      do a = 1, 3
        if (grid%active(a)) p%f(a:9:3, ip) = scale * p%f(a:9:3, ip)
      end do
      p%volume(ip) = j_bound * p%volume0(ip)
    end do
  end subroutine suspension_packing
end module mpmice_suspension
