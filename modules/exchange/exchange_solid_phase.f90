!> The solid phase of a coupled scene on the fluid grid (all solid materials of a cell
!! together) and the implicit fluid-solid exchange: what ICE's stages see of it
!! (`ice_solid_view_t`: fraction, compressibility, face volume flux, platens) extended with the
!! drag, heat and sliding-contact fields of the exchange, which the submodule
!! `exchange_fluid_solid` implements (paper eqs. 34 and 50-55). Filled by the coupling
!! (`mpmice_solid_cells`) each step and handed by the coupled scene to ICE's stages; an ICE-only
!! run has none.
module exchange_solid_phase
  use mpmice_kinds, only: wp
  use grid_layout, only: grid_t
  use ice_state, only: ice_state_t
  use ice_solid_view, only: ice_solid_view_t
  implicit none
  private

  public :: solid_phase_t, solid_phase_alloc, solid_phase_free

  !> The solid phase of a coupled (MPMICE) scene as the pressure equation and the exchange see it:
  !! all solid materials of a cell together (they share one MPM velocity field). Face fields use
  !! the layout of `ice_fluid_t%uface` (cells lbc..ubc, faces up to ubc + 1).
  type, extends(ice_solid_view_t) :: solid_phase_t
    real(wp), allocatable :: rho(:, :, :)       !< solid bulk density m_s / V [kg/m^3]
    real(wp), allocatable :: spvol(:, :, :)     !< grain specific volume phi_s / rho_bar_s [m^3/kg]
    real(wp), allocatable :: vel(:, :, :, :)    !< cell velocity of the solid (i,j,k,component)
                                                !! [m/s]
    real(wp), allocatable :: drag(:, :, :, :)   !< reduced drag coefficient c per fluid (i,j,k,m):
                                                !! drag per volume phi_m phi_s c du [kg/m^3/s]
    real(wp), allocatable :: uface0(:, :, :, :) !< face-normal solid velocity from the MPM nodal
                                                !! velocities alone [m/s]
    real(wp), allocatable :: rigid_face(:, :, :, :) !< 1 where the face velocity is prescribed
    logical :: explicit_drag = .false.          !< explicit (forward Euler) drag, for comparison
    !> face drag: each half cell of a face (its two sides of the face plane) with the solid
    !! fraction in that half (`half_low`, `half_high`) instead of its cell's fraction
    !! (`&coupling face_drag = 'face_plane'`)
    logical :: plane_drag = .false.
    real(wp), allocatable :: half_low(:, :, :, :)  !< solid fraction in the cell's low half
                                                   !! along direction d (i,j,k,d) [-]
    real(wp), allocatable :: half_high(:, :, :, :) !< the same in its high half [-]
    real(wp), allocatable :: heat_cap(:, :, :)  !< heat capacity per volume rho_bar_s c_s [J/m^3/K]
    real(wp), allocatable :: conductance(:, :, :) !< phi_s k_s of the grains [W/m/K]
    real(wp), allocatable :: temp(:, :, :)      !< solid cell temperature [K]: m c T / m c at the
                                                !! deposit, then the Lagrangian value
    real(wp) :: h_exchange = 0.0_wp             !< fluid-solid heat exchange H [W/m^3/K]: heat per
                                                !! volume H phi_f phi_s (T_s - T_f)
    ! Sliding contact with rigid bodies (`&mpm rigid_contact = 'friction'`): the deformable solids
    ! and the rigid bodies keep their own velocities; the fluids exchange momentum with the
    ! deformable solids where a cell holds any (their partner), with the rigid bodies elsewhere.
    ! Without sliding the fields below stay zero and `face_fraction` holds every solid.
    logical :: sliding = .false.                !< rigid bodies slide past the deformable solids
    real(wp), allocatable :: frac_def(:, :, :)  !< the deformable solids' fraction (particles) [-]
    real(wp), allocatable :: frac_rigid(:, :, :) !< the rigid bodies' fraction (particles) [-]
    real(wp), allocatable :: xfrac(:, :, :)     !< the fluids' exchange partner's fraction [-]
                                                !! (`drag` is per this fraction)
    real(wp), allocatable :: rigid_fraction(:, :, :, :)    !< rigid fraction on the low side of
                                                           !! the face plane [-]
    real(wp), allocatable :: rigid_fraction_hi(:, :, :, :) !< the same on its high side [-]
  contains
    procedure :: exchange_faces => solid_phase_exchange_faces
    procedure :: exchange_cells => solid_phase_exchange_cells
  end type solid_phase_t

  interface
    !> Implicit momentum exchange at the faces of the owned cells with the solid as one more
    !! material (eq. 34; `exchange_fluid_solid`).
    module subroutine solid_phase_exchange_faces(solid, state, grid, dt, k_exchange)
      class(solid_phase_t), intent(inout) :: solid  !< solid phase (uface, vface updated)
      type(ice_state_t), intent(inout) :: state     !< fluids (uface, vface updated)
      type(grid_t), intent(in) :: grid              !< block geometry
      real(wp), intent(in) :: dt                    !< exchange time [s]
      real(wp), intent(in) :: k_exchange            !< fluid-fluid K [kg/m^3/s]
    end subroutine solid_phase_exchange_faces

    !> Implicit momentum and heat exchange of the fluids with the solid in the owned cells
    !! (eqs. 50-55; `exchange_fluid_solid`).
    module subroutine solid_phase_exchange_cells(solid, state, grid, dt, k_exchange, h_exchange)
      class(solid_phase_t), intent(inout) :: solid  !< solid phase (temp updated)
      type(ice_state_t), intent(inout) :: state     !< fluids (lag updated)
      type(grid_t), intent(in) :: grid              !< block geometry
      real(wp), intent(in) :: dt                    !< time step [s]
      real(wp), intent(in) :: k_exchange            !< fluid-fluid K [kg/m^3/s]
      real(wp), intent(in) :: h_exchange            !< fluid-fluid H [W/m^3/K]
    end subroutine solid_phase_exchange_cells
  end interface

contains

  !> Allocate the solid-phase fields on `grid` for `nfluids` fluids (values zero).
  subroutine solid_phase_alloc(solid, grid, nfluids)
    type(solid_phase_t), intent(inout) :: solid  !< solid phase (freed first)
    type(grid_t), intent(in) :: grid             !< block geometry
    integer, intent(in) :: nfluids               !< number of fluids
    integer :: l(3), u(3), uf(3)
    l = grid%lbc
    u = grid%ubc
    uf = grid%ubc + 1
    call solid_phase_free(solid)
    associate (s => solid)
      ! every field zero: the cell fields take the zeros of vfrac, the face fields those of uface
      allocate(s%vfrac(l(1):u(1), l(2):u(2), l(3):u(3)), source=0.0_wp)
      allocate(s%source, s%rho, s%spvol, s%kappa, s%heat_cap, s%conductance, s%temp, &
        s%frac_def, s%xfrac, s%frac_rigid, source=s%vfrac)
      allocate(s%vel(l(1):u(1), l(2):u(2), l(3):u(3), 3), source=0.0_wp)
      allocate(s%half_low, s%half_high, source=s%vel)
      allocate(s%drag(l(1):u(1), l(2):u(2), l(3):u(3), max(nfluids, 1)), source=0.0_wp)
      allocate(s%uface(l(1):uf(1), l(2):uf(2), l(3):uf(3), 3), source=0.0_wp)
      allocate(s%uface0, s%vface, s%rigid_face, s%face_fraction, s%face_fraction_hi, &
        s%rigid_flux, s%rigid_fraction, s%rigid_fraction_hi, s%platen_coef, source=s%uface)
    end associate
  end subroutine solid_phase_alloc

  !> Release every field.
  subroutine solid_phase_free(solid)
    type(solid_phase_t), intent(inout) :: solid  !< solid phase
    if (allocated(solid%vfrac)) deallocate(solid%vfrac, solid%source, solid%rho, solid%spvol, &
      solid%kappa, solid%vel, solid%drag, solid%uface, solid%uface0, solid%vface, &
      solid%rigid_face, solid%face_fraction, solid%face_fraction_hi, solid%heat_cap, &
      solid%conductance, solid%temp, solid%rigid_flux, solid%rigid_fraction, &
      solid%rigid_fraction_hi, solid%frac_def, solid%xfrac, solid%frac_rigid, solid%platen_coef, &
      solid%half_low, solid%half_high)
  end subroutine solid_phase_free
end module exchange_solid_phase
