!> What ICE's stages see of a second phase that shares the fluids' cells: its volume fraction,
!! its compressibility and its face volume flux (the solid's terms of the pressure equation,
!! paper eq. 35, and of the equilibration, eqs. 1 and 10-11), and the implicit exchange with it
!! (eqs. 34 and 50-55) as two deferred procedures. ICE's stages and kernels take it as an
!! optional argument and, without it, solve the fluids alone; the exchange layer's
!! `solid_phase_t` (module `exchange_solid_phase`) extends it with the drag, heat and contact
!! fields of a coupled scene and implements the exchange. Face fields use the layout of
!! `ice_fluid_t%uface` (cells lbc..ubc, faces up to ubc + 1); the owner allocates every field.
module ice_solid_view
  use mpmice_kinds, only: wp
  use grid_layout, only: grid_t
  use ice_state, only: ice_state_t
  implicit none
  private

  public :: ice_solid_view_t

  !> The solid phase as the fluids' pressure equation, equilibration and advection see it.
  type, abstract :: ice_solid_view_t
    real(wp), allocatable :: vfrac(:, :, :)     !< solid volume fraction phi_s the fluids see [-]
    real(wp), allocatable :: source(:, :, :)    !< phi_s(particles) - phi_s this step [-]
    real(wp), allocatable :: kappa(:, :, :)     !< grain compressibility 1/K_s [1/Pa] (0: rigid
                                                !! grains)
    real(wp), allocatable :: uface(:, :, :, :)  !< face-normal solid velocity [m/s]
    real(wp), allocatable :: vface(:, :, :, :)  !< exchange-modified face specific volume [m^3/kg]
    real(wp), allocatable :: face_fraction(:, :, :, :) !< solid fraction on the low side of the
                                                       !! face plane [-]
    real(wp), allocatable :: face_fraction_hi(:, :, :, :) !< the same on its high side [-]
    real(wp), allocatable :: rigid_flux(:, :, :, :) !< rigid bodies' volume flux per face area
                                                    !! phi_r,f u_r,f [m/s] (prescribed)
    !> loading platen per domain face: a closed face where the skeleton carries a surface load
    !! (`&boundary fluid = 'wall'` or 'free_slip' with `solid = 'traction'`); it is impermeable
    !! and moves with the skeleton (`ice_pressure`, platen_fluid_faces)
    logical :: platen(6) = .false.
    real(wp), allocatable :: platen_coef(:, :, :, :) !< on a platen face: face area over the
                                                     !! face nodes' mean solid mass [m^2/kg]
  contains
    !> implicit momentum exchange at the faces with the solid as one more material (eq. 34)
    procedure(exchange_faces_interface), deferred :: exchange_faces
    !> implicit momentum and heat exchange in the cells with the solid (eqs. 50-55)
    procedure(exchange_cells_interface), deferred :: exchange_cells
  end type ice_solid_view_t

  abstract interface
    !> Face exchange of the fluids and the solid over dt: the fluids' uface and vface and the
    !! solid's uface and vface updated on the faces of the owned cells.
    subroutine exchange_faces_interface(solid, state, grid, dt, k_exchange)
      import :: ice_solid_view_t, ice_state_t, grid_t, wp
      class(ice_solid_view_t), intent(inout) :: solid  !< solid phase
      type(ice_state_t), intent(inout) :: state        !< fluids
      type(grid_t), intent(in) :: grid                 !< block geometry
      real(wp), intent(in) :: dt                       !< exchange time [s]
      real(wp), intent(in) :: k_exchange               !< fluid-fluid K [kg/m^3/s]
    end subroutine exchange_faces_interface

    !> Cell exchange of the fluids with the solid over dt: the fluids' Lagrangian velocities and
    !! energies and the solid's temperature updated in the owned cells.
    subroutine exchange_cells_interface(solid, state, grid, dt, k_exchange, h_exchange)
      import :: ice_solid_view_t, ice_state_t, grid_t, wp
      class(ice_solid_view_t), intent(inout) :: solid  !< solid phase
      type(ice_state_t), intent(inout) :: state        !< fluids
      type(grid_t), intent(in) :: grid                 !< block geometry
      real(wp), intent(in) :: dt                       !< time step [s]
      real(wp), intent(in) :: k_exchange               !< fluid-fluid K [kg/m^3/s]
      real(wp), intent(in) :: h_exchange               !< fluid-fluid H [W/m^3/K]
    end subroutine exchange_cells_interface
  end interface
end module ice_solid_view
