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

  public :: ice_fluid_t, ice_state_t, ice_work_t, ice_state_alloc, ice_state_free

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

  !> Work storage of the stages, allocated with the state so that no stage allocates in the
  !! time loop: rows along x (cells and faces lbc(1)..ubc(1) + 1; face i of a row is the low face
  !! of cell i) for the sweeps of `ice_viscous`, `ice_lagrangian`, `ice_advection` and
  !! `ice_pressure`, a cell field of `ice_face_pressures` and one of `ice_lagrangian` (a
  !! fluid's pressure work through the faces) and the per-fluid flags of
  !! `ice_equilibration`. A stage passes them to its worker as explicit-shape
  !! arguments of the extent it needs (at most the allocated one).
  type :: ice_work_t
    real(wp), allocatable :: tau_lo(:, :)   !< viscous stress of the low faces (i, component) [Pa]
    real(wp), allocatable :: tau_hi(:, :)   !< viscous stress of the high faces (i, component) [Pa]
    !> `row_stress` work per face: coefficient, normal derivatives (3), transverse (3), divergence
    real(wp), allocatable :: stress(:, :)
    real(wp), allocatable :: flux_lo(:)     !< face fluxes p_f u_f phi_f of the low faces
    real(wp), allocatable :: flux_hi(:)     !< face fluxes p_f u_f phi_f of the high faces
    logical, allocatable :: pos(:)          !< advection: upwind cell is the low one (u > 0)
    real(wp), allocatable :: urow(:)        !< advection: face velocities [m/s]
    real(wp), allocatable :: dist(:)        !< advection: centroid offset of the swept volume [m]
    real(wp), allocatable :: mflux(:)       !< advection: mass flux [kg]
    real(wp), allocatable :: qf(:)          !< advection: reconstructed face value
    real(wp), allocatable :: vf(:, :)       !< advection: reconstructed face velocities [m/s]
    real(wp), allocatable :: xc(:)          !< cell-centre coordinates along x [m]
    real(wp), allocatable :: yc(:)          !< cell-centre coordinates along y [m]
    real(wp), allocatable :: zc(:)          !< cell-centre coordinates along z [m]
    real(wp), allocatable :: cell_weight(:, :, :) !< face pressures: the cells' weights [kg/m^3]
    real(wp), allocatable :: pressure_work(:, :, :) !< Lagrangian values: pressure work [J]
    logical, allocatable :: active(:)       !< equilibration: fluids in the volume sum
    logical, allocatable :: trace_active(:) !< equilibration: the same without the traces
  end type ice_work_t

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
    type(ice_work_t) :: work                        !< work storage of the stages
    logical :: closed(6) = .true.                   !< domain face closed (wall) or open (pressure)
    real(wp) :: p_boundary(6) = 0.0_wp              !< pressure of an open face [Pa]
    integer :: inflow_fluid(6) = 0                  !< fluid filling a face's inflow (0: the
                                                    !< inner cell's composition)
  end type ice_state_t

contains

  !> Allocate every field of `nfluids` fluids on `grid` (values zero).
  subroutine ice_state_alloc(state, grid, nfluids)
    type(ice_state_t), intent(inout) :: state  !< state (freed first)
    type(grid_t), intent(in) :: grid           !< block geometry
    integer, intent(in) :: nfluids             !< number of fluids
    integer :: m, l(3), u(3), uf(3)
    ! zero templates: a cell field and the faces of the three directions
    real(wp), allocatable :: cells(:, :, :), faces(:, :, :, :)
    call ice_state_free(state)
    l = grid%lbc
    u = grid%ubc
    uf = grid%ubc + 1
    allocate(cells(l(1):u(1), l(2):u(2), l(3):u(3)), source=0.0_wp)
    allocate(faces(l(1):uf(1), l(2):uf(2), l(3):uf(3), 3), source=0.0_wp)
    state%nfluids = nfluids
    allocate(state%fluid(nfluids))
    do m = 1, nfluids
      associate (f => state%fluid(m))
        allocate(f%rho, f%temp, f%spvol, f%vfrac, f%kappa, f%c2, source=cells)
        allocate(f%uface, f%vface, source=faces)
        allocate(f%vel(l(1):u(1), l(2):u(2), l(3):u(3), 3), source=0.0_wp)
        allocate(f%lag(l(1):u(1), l(2):u(2), l(3):u(3), 5), source=0.0_wp)
      end associate
    end do
    allocate(state%pressure, state%p_eq, state%dp, state%dp_total, state%sum_kappa, state%rhs, &
      state%diag, state%eddy_viscosity, source=cells)
    allocate(state%pface, source=faces)
    allocate(state%coef(l(1):u(1), l(2):u(2), l(3):u(3), 3), source=0.0_wp)
    allocate(state%cons(l(1):u(1), l(2):u(2), l(3):u(3), 6), source=0.0_wp)
    allocate(state%lag_work(l(1):u(1), l(2):u(2), l(3):u(3), 2), source=0.0_wp)
    call work_alloc(state%work, l, u, nfluids)
  end subroutine ice_state_alloc

  !> Allocate the work storage (values zero) of `nfluids` fluids on a block with cell bounds l..u.
  subroutine work_alloc(work, l, u, nfluids)
    type(ice_work_t), intent(out) :: work  !< work storage (freed by intent(out))
    integer, intent(in) :: l(3)            !< lower cell bounds (ghosts included)
    integer, intent(in) :: u(3)            !< upper cell bounds (ghosts included)
    integer, intent(in) :: nfluids         !< number of fluids
    real(wp), allocatable :: row(:)
    allocate(row(l(1):u(1) + 1), source=0.0_wp)
    allocate(work%flux_lo, work%flux_hi, work%urow, work%dist, &
      work%mflux, work%qf, source=row)
    allocate(work%pos(l(1):u(1) + 1), source=.false.)
    allocate(work%tau_lo(l(1):u(1) + 1, 3), work%tau_hi(l(1):u(1) + 1, 3), &
      work%vf(l(1):u(1) + 1, 3), work%stress(l(1):u(1) + 1, 8), source=0.0_wp)
    allocate(work%xc(l(1):u(1)), work%yc(l(2):u(2)), work%zc(l(3):u(3)), source=0.0_wp)
    allocate(work%cell_weight(l(1):u(1), l(2):u(2), l(3):u(3)), work%pressure_work(l(1):u(1), &
      l(2):u(2), l(3):u(3)), source=0.0_wp)
    allocate(work%active(nfluids), work%trace_active(nfluids), source=.false.)
  end subroutine work_alloc

  !> Release every field.
  subroutine ice_state_free(state)
    type(ice_state_t), intent(inout) :: state  !< state
    if (allocated(state%fluid)) deallocate(state%fluid)
    ! the fields are allocated together (`ice_state_alloc`)
    if (allocated(state%pressure)) deallocate(state%pressure, state%p_eq, state%dp, &
      state%dp_total, state%sum_kappa, state%rhs, state%diag, state%coef, state%pface, &
      state%cons, state%lag_work, state%eddy_viscosity)
    state%work = ice_work_t()
    state%nfluids = 0
  end subroutine ice_state_free
end module ice_state
