!> Layout of the cell deposit `dep(component, i, j, k)` that the particles of a coupled scene
!! build on the ICE cells (paper eq. 28; `mpmice_deposit%solid_deposit` fills it,
!! `mpmice_solid_fields%solid_cell_fields`, `mpmice_rigid_contact%partner_fields` and
!! `mpmice_solid_coupling%surface_body_fraction` read it). The components of `ns` solids:
!!
!! * `deposit_mass`: the particle mass m_p [kg];
!! * `deposit_grain_volume`: the grain volume m_p / rho_s of all solids [m^3];
!! * `deposit_solid_volume(s)`: the grain volume of solid s [m^3];
!!
!! and, in the layout `lay = deposit_layout(ns)` of `ns` solids:
!!
!! * `lay%plane_low(d)`, `lay%plane_high(d)`: the grain fraction on the low and on the high side
!!   (the cell's own side) of the cell's low face plane in direction d [-];
!! * `lay%heat_capacity`: m_p c_s [J/K]; `lay%energy`: m_p c_s T_p [J]; `lay%conductance`: the
!!   grain conductance (m_p / rho_s) k_s [W m^2/K];
!! * `lay%own_high(d)`: the grain fraction on the cell's own (low) side of its high face plane in
!!   direction d [-];
!! * `lay%rigid_low(d)`, `lay%rigid_high(d)`: a sliding rigid body's `plane_low` and
!!   `plane_high` [-];
!! * `lay%half_low(d)`: the grain volume in the cell's low half along direction d [m^3] (the
!!   high half holds the rest of `deposit_grain_volume`).
!!
!! The indices follow in this order, the planes' directions interleaved (low, high, low, ...).
!! `lay%size` = `deposit_size(ns)` components in all; a scene stores those it uses
!! (`deposit_size` with its options). The indices of the three directions of one
!! kind of plane component are 2 apart (low/high sides interleave): `lay%plane_low(1):
!! lay%plane_low(3):2` is the low sides of the three low planes.
module mpmice_deposit_layout
  implicit none
  private

  public :: deposit_layout_t, deposit_layout, deposit_mass, deposit_grain_volume, &
    deposit_solid_volume, deposit_size

  integer, parameter :: deposit_mass = 1          !< particle mass [kg]
  integer, parameter :: deposit_grain_volume = 2  !< grain volume of all solids [m^3]

  !> Indices of the deposit components that depend on the number of solids.
  type :: deposit_layout_t
    integer :: ns = 0               !< number of solids
    integer :: plane_low(3) = 0     !< low side of the cell's low face plane, per direction
    integer :: plane_high(3) = 0    !< high (own) side of the cell's low face plane
    integer :: heat_capacity = 0    !< m_p c_s
    integer :: energy = 0           !< m_p c_s T_p
    integer :: conductance = 0      !< (m_p / rho_s) k_s
    integer :: own_high(3) = 0      !< own (low) side of the cell's high face plane
    integer :: rigid_low(3) = 0     !< a sliding rigid body's plane_low
    integer :: rigid_high(3) = 0    !< a sliding rigid body's plane_high
    integer :: half_low(3) = 0      !< grain volume in the cell's low half, per direction
    integer :: size = 0             !< number of components
  end type deposit_layout_t

contains

  !> The layout of the deposit of `ns` solids.
  pure function deposit_layout(ns) result(lay)
    integer, intent(in) :: ns  !< number of solids
    type(deposit_layout_t) :: lay
    integer :: d
    lay%ns = ns
    do d = 1, 3
      lay%plane_low(d) = deposit_grain_volume + ns + 2 * d - 1
      lay%plane_high(d) = lay%plane_low(d) + 1
    end do
    lay%heat_capacity = lay%plane_high(3) + 1
    lay%energy = lay%heat_capacity + 1
    lay%conductance = lay%energy + 1
    do d = 1, 3
      lay%own_high(d) = lay%conductance + d
    end do
    do d = 1, 3
      lay%rigid_low(d) = lay%own_high(3) + 2 * d - 1
      lay%rigid_high(d) = lay%rigid_low(d) + 1
    end do
    do d = 1, 3
      lay%half_low(d) = lay%rigid_high(3) + d
    end do
    lay%size = lay%half_low(3)
  end function deposit_layout

  !> Grain volume of solid `s` [m^3].
  pure integer function deposit_solid_volume(s) result(idx)
    integer, intent(in) :: s   !< solid
    idx = deposit_grain_volume + s
  end function deposit_solid_volume

  !> Number of deposit components of `ns` solids; a scene without sliding rigid bodies
  !! (`rigid_planes` false) or without the half-cell volumes (`halves` false) stores only the
  !! components before the groups it does not use (they come last: the rigid planes, then the
  !! halves; the other indices are those of `deposit_layout`). Without the optional arguments:
  !! every component.
  pure integer function deposit_size(ns, rigid_planes, halves) result(n)
    integer, intent(in) :: ns                     !< number of solids
    logical, intent(in), optional :: rigid_planes !< a sliding rigid body's plane components
    logical, intent(in), optional :: halves       !< the half-cell grain volumes
    type(deposit_layout_t) :: lay
    logical :: with_rigid, with_halves
    lay = deposit_layout(ns)
    with_rigid = .true.
    with_halves = .true.
    if (present(rigid_planes)) with_rigid = rigid_planes
    if (present(halves)) with_halves = halves
    n = lay%size
    if (with_halves) return
    n = lay%half_low(1) - 1
    if (.not. with_rigid) n = lay%rigid_low(1) - 1
  end function deposit_size
end module mpmice_deposit_layout
