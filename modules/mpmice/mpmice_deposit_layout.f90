!> Layout of the cell deposit `dep(component, i, j, k)` that the particles of a coupled scene
!! build on the ICE cells (paper eq. 28; `mpmice_deposit%solid_deposit` fills it,
!! `mpmice_solid_fields%solid_cell_fields`, `mpmice_rigid_contact%partner_fields` and
!! `mpmice_solid_coupling%surface_body_fraction` read it). The components of `ns` solids:
!!
!! * `deposit_mass`: the particle mass m_p [kg];
!! * `deposit_grain_volume`: the grain volume m_p / rho_s of all solids [m^3];
!! * `deposit_solid_volume(s)`: the grain volume of solid s [m^3];
!! * `deposit_plane_low(ns, d)`, `deposit_plane_high(ns, d)`: the grain fraction on the low and
!!   on the high side (the cell's own side) of the cell's low face plane in direction d [-];
!! * `deposit_heat_capacity(ns)`: m_p c_s [J/K]; `deposit_energy(ns)`: m_p c_s T_p [J];
!!   `deposit_conductance(ns)`: the grain conductance (m_p / rho_s) k_s [W m^2/K];
!! * `deposit_own_high(ns, d)`: the grain fraction on the cell's own (low) side of its high face
!!   plane in direction d [-];
!! * `deposit_rigid_low(ns, d)`, `deposit_rigid_high(ns, d)`: a sliding rigid body's
!!   `deposit_plane_low` and `deposit_plane_high` [-].
!!
!! The indices follow in this order, the planes' directions interleaved (low, high, low, ...).
!! `deposit_size(ns)` components in all. The indices of the three directions of one kind of plane
!! component are 2 apart (low/high sides interleave): `deposit_plane_low(ns, 1):
!! deposit_plane_low(ns, 3):2` is the low sides of the three low planes.
module mpmice_deposit_layout
  implicit none
  private

  public :: deposit_mass, deposit_grain_volume, deposit_solid_volume, deposit_plane_low, &
    deposit_plane_high, deposit_heat_capacity, deposit_energy, deposit_conductance, &
    deposit_own_high, deposit_rigid_low, deposit_rigid_high, deposit_size

  integer, parameter :: deposit_mass = 1          !< particle mass [kg]
  integer, parameter :: deposit_grain_volume = 2  !< grain volume of all solids [m^3]

contains

  !> Grain volume of solid `s` [m^3].
  pure integer function deposit_solid_volume(s) result(idx)
    integer, intent(in) :: s   !< solid
    idx = deposit_grain_volume + s
  end function deposit_solid_volume

  !> Grain fraction on the low side of the cell's low face plane in direction `d` [-].
  pure integer function deposit_plane_low(ns, d) result(idx)
    integer, intent(in) :: ns  !< number of solids
    integer, intent(in) :: d   !< direction
    idx = deposit_grain_volume + ns + 2 * d - 1
  end function deposit_plane_low

  !> Grain fraction on the high side (the cell's own side) of its low face plane in direction
  !! `d` [-].
  pure integer function deposit_plane_high(ns, d) result(idx)
    integer, intent(in) :: ns  !< number of solids
    integer, intent(in) :: d   !< direction
    idx = deposit_plane_low(ns, d) + 1
  end function deposit_plane_high

  !> Heat capacity m_p c_s [J/K].
  pure integer function deposit_heat_capacity(ns) result(idx)
    integer, intent(in) :: ns  !< number of solids
    idx = deposit_plane_high(ns, 3) + 1
  end function deposit_heat_capacity

  !> Energy m_p c_s T_p [J].
  pure integer function deposit_energy(ns) result(idx)
    integer, intent(in) :: ns  !< number of solids
    idx = deposit_heat_capacity(ns) + 1
  end function deposit_energy

  !> Grain conductance (m_p / rho_s) k_s [W m^2/K].
  pure integer function deposit_conductance(ns) result(idx)
    integer, intent(in) :: ns  !< number of solids
    idx = deposit_heat_capacity(ns) + 2
  end function deposit_conductance

  !> Grain fraction on the cell's own (low) side of its high face plane in direction `d` [-]
  !! (the next cell's `deposit_plane_low`, kept here too so that every cell carries its own
  !! planes: out-of-domain ghost cells beyond a wall are not exchanged between blocks).
  pure integer function deposit_own_high(ns, d) result(idx)
    integer, intent(in) :: ns  !< number of solids
    integer, intent(in) :: d   !< direction
    idx = deposit_conductance(ns) + d
  end function deposit_own_high

  !> A sliding rigid body's grain fraction on the low side of the cell's low face plane in
  !! direction `d` [-].
  pure integer function deposit_rigid_low(ns, d) result(idx)
    integer, intent(in) :: ns  !< number of solids
    integer, intent(in) :: d   !< direction
    idx = deposit_own_high(ns, 3) + 2 * d - 1
  end function deposit_rigid_low

  !> A sliding rigid body's grain fraction on the high side of the cell's low face plane in
  !! direction `d` [-].
  pure integer function deposit_rigid_high(ns, d) result(idx)
    integer, intent(in) :: ns  !< number of solids
    integer, intent(in) :: d   !< direction
    idx = deposit_rigid_low(ns, d) + 1
  end function deposit_rigid_high

  !> Number of deposit components of `ns` solids.
  pure integer function deposit_size(ns) result(n)
    integer, intent(in) :: ns  !< number of solids
    n = deposit_rigid_high(ns, 3)
  end function deposit_size
end module mpmice_deposit_layout
