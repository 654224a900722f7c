!> The coupling parameters of one solid material: the per-solid parameters the pressure equation,
!! the exchange and the heat of a coupled scene need, and what the face-plane components of the
!! cell deposit (paper eq. 28; layout `mpmice_deposit_layout`) say about the body in a cell
!! (`surface_body_fraction`).
module mpmice_solid_coupling
  use mpmice_kinds, only: wp
  use grid_layout, only: grid_t
  use mpmice_deposit_layout, only: deposit_layout_t, deposit_layout
  implicit none
  private

  public :: solid_coupling_t, surface_body_fraction, surface_drag_scale

  !> Coupling parameters of one solid material.
  type :: solid_coupling_t
    integer :: drag_law = 1                 !< exchange_drag law id
    real(wp) :: grain_size = 1.0e-3_wp      !< d [m]
    real(wp) :: drag_coefficient = 0.0_wp   !< K of the constant law [kg/m^3/s]
    real(wp) :: forchheimer_a = 150.0_wp    !< linear coefficient of the Forchheimer law [-]
    real(wp) :: forchheimer_b = 1.75_wp     !< quadratic coefficient of the Forchheimer law [-]
    real(wp) :: grain_kappa = 0.0_wp        !< 1 / grain bulk modulus [1/Pa] (0: incompressible)
    real(wp) :: grain_density = 2650.0_wp   !< rho_s of the grains [kg/m^3]
    real(wp) :: heat_capacity = 800.0_wp    !< c_s [J/kg/K]
    real(wp) :: conductivity = 0.4_wp       !< k_s of the grains [W/m/K]
    logical :: rigid = .false.              !< a rigid (prescribed-motion) body
    logical :: surface_drag_parallel = .false.  !< surface cells: the body's drag in parallel
                                            !! (flow along the surface), not in series
    !> a suspended particle is no looser than its cell's grain fraction (`mpmice_suspension`)
    logical :: suspension_cell_bound = .false.
    !> the grains of a suspended particle settle inside it (`mpmice_suspension`)
    logical :: suspension_settling = .false.
  end type solid_coupling_t

contains

  !> Solid fraction of the body in cell c: where one of the cell's face planes carries no grains
  !! on the cell's side and another carries more than the cell average `phi` (a free surface of
  !! the soil crosses the cell, e.g. the top cell of a settling column), the largest plane
  !! fraction; otherwise `phi`. The drag of such a cell is that of the body over the share
  !! phi / phi_body of the cell it fills: R_cell = (phi / phi_body) R(phi_body), R = phi_s c /
  !! phi_f the resistance of eq. 18 per length. With the cell average instead, the Kozeny-Carman
  !! resistance of the top cell of the consolidation column fell to 0.61 of the body's once it
  !! had settled by 7 % of a cell, draining the column 0.7 % too fast. That series resistance
  !! holds for flow across the surface; for flow along it (`&solid surface_drag_parallel`) the
  !! body's part of the cell drags in parallel with the free fluid beside it:
  !! phi_f phi c = phi n_body c(phi_body), see `surface_drag_scale`.
  pure real(wp) function surface_body_fraction(grid, dep, ns, c, phi, max_fraction) &
    result(phi_body)
    type(grid_t), intent(in) :: grid            !< block geometry
    real(wp), intent(in) :: dep(:, grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !< deposits
    integer, intent(in) :: ns                   !< number of solids
    integer, intent(in) :: c(3)                 !< cell
    real(wp), intent(in) :: phi                 !< cell solid fraction
    real(wp), intent(in) :: max_fraction        !< cap of the fraction
    integer :: d
    real(wp) :: lo_side, hi_side, fmin, fmax
    type(deposit_layout_t) :: lay
    lay = deposit_layout(ns)
    phi_body = phi
    fmin = huge(1.0_wp)
    fmax = 0.0_wp
    do d = 1, 3
      if (.not. grid%active(d)) cycle
      ! the cell's own side of its low plane and of its high plane
      lo_side = dep(lay%plane_high(d), c(1), c(2), c(3))
      hi_side = dep(lay%own_high(d), c(1), c(2), c(3))
      fmin = min(fmin, lo_side, hi_side)
      fmax = max(fmax, lo_side, hi_side)
    end do
    if (fmin <= 1.0e-12_wp .and. fmax > phi + 1.0e-9_wp) phi_body = min(fmax, max_fraction)
  end function surface_body_fraction

  !> Factor on c(phi_body) that gives a surface cell's reduced drag coefficient (per the cell
  !! fraction phi): in series (flow across the surface, the default) (1 - phi) / (1 - phi_body),
  !! so that the cell's resistance per length is (phi / phi_body) R(phi_body); in parallel (flow
  !! along the surface) (1 - phi_body) / (1 - phi), the drag of the body's share phi / phi_body
  !! of the cell at the cell's slip, phi_f phi c = (phi / phi_body) phi_body n_body c(phi_body).
  !! 1 where phi_body = phi.
  elemental real(wp) function surface_drag_scale(phi, phi_body, parallel) result(scale)
    real(wp), intent(in) :: phi       !< cell solid fraction [-]
    real(wp), intent(in) :: phi_body  !< the body's own fraction [-] (`surface_body_fraction`)
    logical, intent(in) :: parallel   !< flow along the surface
    if (parallel) then
      scale = (1.0_wp - phi_body) / (1.0_wp - phi)
    else
      scale = (1.0_wp - phi) / (1.0_wp - phi_body)
    end if
  end function surface_drag_scale
end module mpmice_solid_coupling
