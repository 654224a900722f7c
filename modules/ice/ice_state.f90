!> State of the ICE fluids: structure-of-arrays cell fields per material, the shared cell
!! pressure fields and the face velocities.
!!
!! Cell fields use the grid's cell bounds `lbc..ubc` (ghosts included); face fields in direction
!! d hold at index i the LOW face of cell i (grid_layout convention) and are allocated
!! `lbc..ubc+1` in every dimension so that one allocation serves all three directions.
module ice_state
  use mpmice_kinds, only: wp, name_len
  use grid_layout, only: grid_t
  use ice_eos, only: eos_t
  implicit none
  private

  public :: ice_fluid_t, ice_solid_phase_t, ice_state_t, ice_state_alloc, ice_state_free
  public :: ice_solid_alloc

  !> One fluid material: parameters and cell/face fields.
  type :: ice_fluid_t
    character(len=name_len) :: name = ''        !< material name (dump group)
    type(eos_t) :: eos                          !< equation of state
    real(wp) :: viscosity = 0.0_wp              !< dynamic viscosity [Pa s]
    real(wp) :: conductivity = 0.0_wp           !< thermal conductivity [W/m/K]
    real(wp), allocatable :: rho(:, :, :)       !< bulk density rho_bar = m/V [kg/m^3]
    real(wp), allocatable :: vel(:, :, :, :)    !< velocity (i,j,k,component) [m/s]
    real(wp), allocatable :: temp(:, :, :)      !< temperature [K]
    real(wp), allocatable :: spvol(:, :, :)     !< intrinsic specific volume v = 1/rho_micro [m^3/kg]
    real(wp), allocatable :: vfrac(:, :, :)     !< volume fraction phi [-]
    real(wp), allocatable :: kappa(:, :, :)     !< compressibility v/c^2 [1/Pa]
    real(wp), allocatable :: c2(:, :, :)        !< squared sound speed [m^2/s^2]
    real(wp), allocatable :: uface(:, :, :, :)  !< face-normal velocity (i,j,k,direction) [m/s]
    real(wp), allocatable :: vface(:, :, :, :)  !< face specific volume (harmonic mean) [m^3/kg]
    real(wp), allocatable :: lag(:, :, :, :)    !< Lagrangian mass-specific u,v,w, cv T, v (i,j,k,5)
  end type ice_fluid_t

  !> The solid phase of a coupled (MPMICE) scene as the pressure equation and the exchange see it:
  !! all solid materials of a cell together (they share one MPM velocity field). Filled by the
  !! coupling (`mpmice_solid_cells`) each step; absent (`present = .false.`) in ICE-only runs.
  !! Face fields use the layout of `ice_fluid_t%uface`.
  type :: ice_solid_phase_t
    logical :: present = .false.                !< a solid phase takes part
    real(wp), allocatable :: vfrac(:, :, :)     !< solid volume fraction phi_s the fluids see [-]
    real(wp), allocatable :: source(:, :, :)    !< phi_s(particles) - phi_s this step [-]
    real(wp), allocatable :: rho(:, :, :)       !< solid bulk density m_s / V [kg/m^3]
    real(wp), allocatable :: spvol(:, :, :)     !< grain specific volume phi_s / rho_bar_s [m^3/kg]
    real(wp), allocatable :: kappa(:, :, :)     !< grain compressibility 1/K_s [1/Pa] (0: rigid grains)
    real(wp), allocatable :: vel(:, :, :, :)    !< cell velocity of the solid (i,j,k,component) [m/s]
    real(wp), allocatable :: drag(:, :, :, :)   !< reduced drag coefficient c per fluid (i,j,k,m):
                                                !! drag per volume phi_m phi_s c du [kg/m^3/s]
    real(wp), allocatable :: uface(:, :, :, :)  !< face-normal solid velocity [m/s]
    real(wp), allocatable :: uface0(:, :, :, :) !< the same from the MPM nodal velocities alone
    real(wp), allocatable :: vface(:, :, :, :)  !< exchange-modified face specific volume [m^3/kg]
    real(wp), allocatable :: rigid_face(:, :, :, :) !< 1 where the face velocity is prescribed
    real(wp), allocatable :: face_fraction(:, :, :, :) !< solid fraction on the low side of the
                                                       !! face plane [-]
    real(wp), allocatable :: face_fraction_hi(:, :, :, :) !< the same on its high side [-]
    logical :: explicit_drag = .false.          !< explicit (forward Euler) drag, for comparison
    !> loading platen per domain face: a closed face where the skeleton carries a surface load
    !! (`&boundary fluid = 'wall'` or 'free_slip' with `solid = 'traction'`); it is impermeable
    !! and moves with the skeleton (`ice_pressure`, platen_fluid_faces)
    logical :: platen(6) = .false.
    real(wp), allocatable :: platen_coef(:, :, :, :) !< on a platen face: face area over the
                                                     !! face nodes' mean solid mass [m^2/kg]
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
    real(wp), allocatable :: rigid_flux(:, :, :, :) !< rigid bodies' volume flux per face area
                                                    !! phi_r,f u_r,f [m/s] (prescribed)
    real(wp), allocatable :: rigid_fraction(:, :, :, :)    !< rigid fraction on the low side of
                                                           !! the face plane [-]
    real(wp), allocatable :: rigid_fraction_hi(:, :, :, :) !< the same on its high side [-]
  end type ice_solid_phase_t

  !> All fluids of a block and their shared fields.
  type :: ice_state_t
    integer :: nfluids = 0                          !< number of fluids
    type(ice_fluid_t), allocatable :: fluid(:)      !< fluids 1..nfluids
    real(wp), allocatable :: pressure(:, :, :)      !< cell pressure [Pa]
    real(wp), allocatable :: p_eq(:, :, :)          !< equilibration pressure of the step [Pa]
    real(wp), allocatable :: dp(:, :, :)            !< pressure correction of one outer pass [Pa]
    real(wp), allocatable :: dp_total(:, :, :)      !< p - p_eq (delta p of eq. 36) [Pa]
    real(wp), allocatable :: sum_kappa(:, :, :)     !< sum_m phi_m kappa_m [1/Pa]
    real(wp), allocatable :: rhs(:, :, :)           !< right-hand side of eq. 35 [m^3]
    real(wp), allocatable :: diag(:, :, :)          !< diagonal of eq. 35 [m^3/Pa]
    real(wp), allocatable :: coef(:, :, :, :)       !< low-face coefficients of eq. 35 [m^3/Pa]
    real(wp), allocatable :: pface(:, :, :, :)      !< face pressure, eq. 37 (i,j,k,direction) [Pa]
    real(wp), allocatable :: cons(:, :, :, :)       !< advection work: m, m u, m v, m w, m cv T, m v
    real(wp), allocatable :: lag_work(:, :, :, :)   !< Lagrangian-phase work (`ice_lagrangian`):
                                                    !! energy defect [J], cell mass [kg] (i,j,k,2)
    real(wp), allocatable :: eddy_viscosity(:, :, :) !< Smagorinsky eddy viscosity work of one
                                                    !! fluid (`ice_viscous`) [m^2/s]
    logical :: closed(6) = .true.                   !< domain face closed (wall) or open (pressure)
    real(wp) :: p_boundary(6) = 0.0_wp              !< pressure of an open face [Pa]
    integer :: inflow_fluid(6) = 0                  !< fluid filling a face's inflow (0: the
                                                    !< inner cell's composition)
    type(ice_solid_phase_t) :: solid                !< solid phase of a coupled scene
  end type ice_state_t

contains

  !> Allocate every field of `nfluids` fluids on `grid` (values zero).
  subroutine ice_state_alloc(state, grid, nfluids)
    type(ice_state_t), intent(inout) :: state  !< state (freed first)
    type(grid_t), intent(in) :: grid           !< block geometry
    integer, intent(in) :: nfluids             !< number of fluids
    integer :: m, l(3), u(3), uf(3)
    call ice_state_free(state)
    l = grid%lbc
    u = grid%ubc
    uf = grid%ubc + 1
    state%nfluids = nfluids
    allocate(state%fluid(nfluids))
    do m = 1, nfluids
      associate (f => state%fluid(m))
        allocate(f%rho(l(1):u(1), l(2):u(2), l(3):u(3)), source=0.0_wp)
        allocate(f%vel(l(1):u(1), l(2):u(2), l(3):u(3), 3), source=0.0_wp)
        allocate(f%temp(l(1):u(1), l(2):u(2), l(3):u(3)), source=0.0_wp)
        allocate(f%spvol(l(1):u(1), l(2):u(2), l(3):u(3)), source=0.0_wp)
        allocate(f%vfrac(l(1):u(1), l(2):u(2), l(3):u(3)), source=0.0_wp)
        allocate(f%kappa(l(1):u(1), l(2):u(2), l(3):u(3)), source=0.0_wp)
        allocate(f%c2(l(1):u(1), l(2):u(2), l(3):u(3)), source=0.0_wp)
        allocate(f%uface(l(1):uf(1), l(2):uf(2), l(3):uf(3), 3), source=0.0_wp)
        allocate(f%vface(l(1):uf(1), l(2):uf(2), l(3):uf(3), 3), source=0.0_wp)
        allocate(f%lag(l(1):u(1), l(2):u(2), l(3):u(3), 5), source=0.0_wp)
      end associate
    end do
    allocate(state%pressure(l(1):u(1), l(2):u(2), l(3):u(3)), source=0.0_wp)
    allocate(state%p_eq(l(1):u(1), l(2):u(2), l(3):u(3)), source=0.0_wp)
    allocate(state%dp(l(1):u(1), l(2):u(2), l(3):u(3)), source=0.0_wp)
    allocate(state%dp_total(l(1):u(1), l(2):u(2), l(3):u(3)), source=0.0_wp)
    allocate(state%sum_kappa(l(1):u(1), l(2):u(2), l(3):u(3)), source=0.0_wp)
    allocate(state%rhs(l(1):u(1), l(2):u(2), l(3):u(3)), source=0.0_wp)
    allocate(state%diag(l(1):u(1), l(2):u(2), l(3):u(3)), source=0.0_wp)
    allocate(state%coef(l(1):u(1), l(2):u(2), l(3):u(3), 3), source=0.0_wp)
    allocate(state%pface(l(1):uf(1), l(2):uf(2), l(3):uf(3), 3), source=0.0_wp)
    allocate(state%cons(l(1):u(1), l(2):u(2), l(3):u(3), 6), source=0.0_wp)
    allocate(state%lag_work(l(1):u(1), l(2):u(2), l(3):u(3), 2), source=0.0_wp)
    allocate(state%eddy_viscosity(l(1):u(1), l(2):u(2), l(3):u(3)), source=0.0_wp)
  end subroutine ice_state_alloc

  !> Allocate the solid-phase fields on `grid` (values zero) and mark the phase present.
  subroutine ice_solid_alloc(state, grid)
    type(ice_state_t), intent(inout) :: state  !< state (fluids allocated first)
    type(grid_t), intent(in) :: grid           !< block geometry
    integer :: l(3), u(3), uf(3)
    l = grid%lbc
    u = grid%ubc
    uf = grid%ubc + 1
    associate (s => state%solid)
      s%present = .true.
      allocate(s%vfrac(l(1):u(1), l(2):u(2), l(3):u(3)), source=0.0_wp)
      allocate(s%source, s%rho, s%spvol, s%kappa, s%heat_cap, s%conductance, s%temp, &
        mold=s%vfrac)
      s%heat_cap = 0.0_wp
      s%conductance = 0.0_wp
      s%temp = 0.0_wp
      s%source = 0.0_wp
      s%rho = 0.0_wp
      s%spvol = 0.0_wp
      s%kappa = 0.0_wp
      allocate(s%vel(l(1):u(1), l(2):u(2), l(3):u(3), 3), source=0.0_wp)
      allocate(s%drag(l(1):u(1), l(2):u(2), l(3):u(3), max(state%nfluids, 1)), source=0.0_wp)
      allocate(s%uface(l(1):uf(1), l(2):uf(2), l(3):uf(3), 3), source=0.0_wp)
      allocate(s%uface0, s%vface, s%rigid_face, s%face_fraction, s%face_fraction_hi, &
        mold=s%uface)
      s%face_fraction = 0.0_wp
      s%face_fraction_hi = 0.0_wp
      allocate(s%rigid_flux, s%rigid_fraction, s%rigid_fraction_hi, s%platen_coef, &
        mold=s%uface)
      s%platen_coef = 0.0_wp
      s%rigid_flux = 0.0_wp
      s%rigid_fraction = 0.0_wp
      s%rigid_fraction_hi = 0.0_wp
      allocate(s%frac_def, s%xfrac, s%frac_rigid, mold=s%vfrac)
      s%frac_def = 0.0_wp
      s%frac_rigid = 0.0_wp
      s%xfrac = 0.0_wp
      s%uface0 = 0.0_wp
      s%vface = 0.0_wp
      s%rigid_face = 0.0_wp
    end associate
  end subroutine ice_solid_alloc

  !> Release every field.
  subroutine ice_state_free(state)
    type(ice_state_t), intent(inout) :: state  !< state
    if (allocated(state%fluid)) deallocate(state%fluid)
    if (allocated(state%pressure)) deallocate(state%pressure)
    if (allocated(state%p_eq)) deallocate(state%p_eq)
    if (allocated(state%dp)) deallocate(state%dp)
    if (allocated(state%dp_total)) deallocate(state%dp_total)
    if (allocated(state%sum_kappa)) deallocate(state%sum_kappa)
    if (allocated(state%rhs)) deallocate(state%rhs)
    if (allocated(state%diag)) deallocate(state%diag)
    if (allocated(state%coef)) deallocate(state%coef)
    if (allocated(state%pface)) deallocate(state%pface)
    if (allocated(state%cons)) deallocate(state%cons)
    if (allocated(state%lag_work)) deallocate(state%lag_work)
    if (allocated(state%eddy_viscosity)) deallocate(state%eddy_viscosity)
    if (allocated(state%solid%vfrac)) deallocate(state%solid%vfrac, state%solid%source, &
      state%solid%rho, state%solid%spvol, state%solid%kappa, state%solid%vel, state%solid%drag, &
      state%solid%uface, state%solid%uface0, state%solid%vface, &
      state%solid%rigid_face, state%solid%face_fraction, state%solid%face_fraction_hi, &
      state%solid%heat_cap, state%solid%conductance, state%solid%temp, state%solid%rigid_flux, &
      state%solid%rigid_fraction, state%solid%rigid_fraction_hi, state%solid%frac_def, &
      state%solid%xfrac, state%solid%frac_rigid, state%solid%platen_coef)
    state%solid%present = .false.
    state%nfluids = 0
  end subroutine ice_state_free
end module ice_state
