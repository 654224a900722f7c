!> Settings of the PFMG multigrid preconditioner of the pressure solve (`solver_pressure`): the
!! relaxation, the coarse operators and the cycle chosen per grid (docs/hypre.md).
module solver_pfmg
  use, intrinsic :: iso_c_binding, only: c_int
  use mpmice_kinds, only: wp
  use grid_layout, only: grid_t
  implicit none
  private

  public :: pfmg_relax_type, pfmg_rap_type, pfmg_cycle

  !> PFMG relaxation: 2 = red-black Gauss-Seidel, forward before and backward after the coarse-grid
  !! correction (a symmetric V-cycle). Weighted Jacobi (1, with Galerkin coarse operators) took
  !! 20 instead of 16.7 PCG iterations per solve on the ICE 50^3 benchmark and twice the time.
  integer(c_int), parameter :: pfmg_relax_type = 2_c_int
  !> PFMG coarse operators: 1 = non-Galerkin (PARFLOW formula, 7-point in 3D), the ones red-black
  !! relaxation works with; 0 = Galerkin (R A P, 15- to 27-point coarse stencils in 3D).
  integer(c_int), parameter :: pfmg_rap_type = 1_c_int
  !> Relaxation sweeps before and after the coarse-grid correction (equal: symmetric cycle), and
  !! whether hypre skips the relaxation on some levels (1, its shortcut for isotropic problems)
  !! or relaxes on every level (0). Set per solver at init (`pfmg_cycle`): three active
  !! dimensions 2 + 2 sweeps and no skip (the two-fluid ICE 50^3 benchmark: 10.4 instead of
  !! 16.2 PCG iterations per solve, 15-20 % less solve time); two active dimensions with square
  !! cells 1 + 1 sweeps with the skip (the coupled 2D benchmark: 7.6 instead of 6.8 iterations,
  !! 15 % less solve time); otherwise 1 + 1 sweeps on every level (docs/hypre.md).
  integer(c_int), parameter :: pfmg_sweeps_3d = 2_c_int

contains

  !> The PFMG cycle of a grid (the parameters above): 2 + 2 sweeps on every level with three
  !! active dimensions; 1 + 1 with hypre's level skipping with two whose cell widths agree to
  !! 1 % (an isotropic operator where the coefficients are); 1 + 1 on every level otherwise.
  subroutine pfmg_cycle(grid, sweeps, skip_relax)
    type(grid_t), intent(in) :: grid          !< block geometry
    integer(c_int), intent(out) :: sweeps     !< sweeps before and after the coarse correction
    integer(c_int), intent(out) :: skip_relax !< 1: skip the relaxation on some levels
    real(wp) :: wmin, wmax
    sweeps = 1_c_int
    skip_relax = 0_c_int
    if (count(grid%active) == 3) then
      sweeps = pfmg_sweeps_3d
    else if (count(grid%active) == 2) then
      wmin = minval(grid%dx, mask=grid%active)
      wmax = maxval(grid%dx, mask=grid%active)
      if (wmax <= 1.01_wp * wmin) skip_relax = 1_c_int
    end if
  end subroutine pfmg_cycle

end module solver_pfmg
