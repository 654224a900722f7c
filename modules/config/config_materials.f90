!> Parameter types of the multiphase scenes (`ice`, `mpm`, `mpmice`): the singleton groups
!! `&physics`, `&ice`, `&mpm`, `&coupling` and the repeated groups `&fluid`, `&solid`, `&region`,
!! `&boundary`.
!!
!! As in `config_types`, the default initialisers are the documented defaults (docs/namelists.md).
!! A repeated group may appear several times; each occurrence is one element of an array of
!! `config_t` (at most `max_fluids`, ... elements), and every occurrence starts from the type's
!! defaults. `config_types` re-exports everything public here.
module config_materials
  use mpmice_kinds, only: wp, name_len, path_len
  use geometry_shapes, only: file_shape_t, level_unset
  implicit none
  private

  public :: physics_params_t, ice_params_t, mpm_params_t, coupling_params_t
  public :: fluid_params_t, solid_params_t, region_params_t, boundary_params_t
  public :: max_fluids, max_solids, max_regions, max_boundaries, max_polygon_points
  public :: eos_names, solid_model_names, solid_shape_names, face_names
  public :: boundary_fluid_names, boundary_thermal_names, boundary_solid_names
  public :: drag_law_names, drag_scheme_names, rigid_contact_names
  public :: particles_per_cell_used
  public :: max_history_points, history_unset, history_points_used

  integer, parameter :: max_fluids = 8        !< most `&fluid` groups in one input
  integer, parameter :: max_solids = 8        !< most `&solid` groups in one input
  integer, parameter :: max_regions = 32      !< most `&region` groups in one input
  integer, parameter :: max_boundaries = 6    !< most `&boundary` groups (one per face)
  integer, parameter :: max_polygon_points = 32  !< most vertices of a `&solid` polygon
  integer, parameter :: max_history_points = 64  !< most points of a `&boundary` velocity history
  !> Value of the unused entries of `solid_velocity_times` and `solid_velocity_history`.
  real(wp), parameter :: history_unset = -huge(1.0_wp)

  !> Allowed values of `&fluid eos`.
  character(len=*), parameter :: eos_names(3) = [character(len=name_len) :: &
    'ideal_gas', 'linear_water', 'stiffened_gas']
  !> Allowed values of `&solid model`.
  character(len=*), parameter :: solid_model_names(7) = [character(len=name_len) :: &
    'linear_elastic', 'neo_hookean', 'mohr_coulomb', 'rigid', 'cam_clay', &
    'modified_cam_clay', 'critical_state_sand']
  !> Allowed values of `&solid shape`.
  character(len=*), parameter :: solid_shape_names(4) = [character(len=name_len) :: &
    'box', 'polygon', 'half_space', 'profile']
  !> Allowed values of `&solid drag_law` (fluid-solid drag of scene 'mpmice').
  character(len=*), parameter :: drag_law_names(5) = [character(len=name_len) :: &
    'kozeny_carman', 'beetstra', 'constant', 'impermeable', 'forchheimer']
  !> Allowed values of `&mpm rigid_contact` (deformable solids against rigid ones).
  character(len=*), parameter :: rigid_contact_names(2) = [character(len=name_len) :: &
    'no_slip', 'friction']
  !> Allowed values of `&coupling drag_scheme`.
  character(len=*), parameter :: drag_scheme_names(2) = [character(len=name_len) :: &
    'implicit', 'explicit']
  !> Faces of the domain, in `face_index` order 1..6.
  character(len=*), parameter :: face_names(6) = [character(len=2) :: &
    'x-', 'x+', 'y-', 'y+', 'z-', 'z+']
  !> Allowed values of `&boundary fluid`.
  character(len=*), parameter :: boundary_fluid_names(5) = [character(len=name_len) :: &
    'wall', 'free_slip', 'pressure', 'inflow', 'outflow']
  !> Allowed values of `&boundary thermal`.
  character(len=*), parameter :: boundary_thermal_names(2) = [character(len=name_len) :: &
    'adiabatic', 'fixed']
  !> Allowed values of `&boundary solid`.
  character(len=*), parameter :: boundary_solid_names(5) = [character(len=name_len) :: &
    'fixed', 'roller', 'free', 'velocity', 'traction']

  !> `&physics`: body force and reference state shared by all materials.
  type :: physics_params_t
    real(wp) :: gravity(3) = [0.0_wp, 0.0_wp, 0.0_wp]  !< gravitational acceleration [m/s^2]
    real(wp) :: reference_pressure = 101325.0_wp       !< reference (top) pressure [Pa]
    logical :: hydrostatic_init = .false.              !< initial p, rho in hydrostatic balance
  end type physics_params_t

  !> `&ice`: controls of the ICE multi-fluid solver.
  type :: ice_params_t
    real(wp) :: outer_tolerance = 1.0e-7_wp          !< outer-iteration tolerance (volume fractions)
    integer :: max_outer_iterations = 20             !< outer-iteration limit
    real(wp) :: exchange_coefficient = 1.0e15_wp     !< momentum exchange K [kg/m^3/s]
    real(wp) :: heat_exchange_coefficient = 0.0_wp   !< heat exchange H [W/m^3/K]
    logical :: smagorinsky = .false.                 !< Smagorinsky turbulence model on
    real(wp) :: smagorinsky_constant = 0.17_wp       !< Smagorinsky constant C_s
    real(wp) :: equilibration_tolerance = 1.0e-10_wp !< pressure equilibration tolerance
    integer :: max_equilibration_iterations = 100    !< pressure equilibration iteration limit
    real(wp) :: sound_speed_factor = 0.0_wp          !< weight of c in the CFL limit (0: advective)
    real(wp) :: interface_compression = 0.0_wp       !< C of the two fluids' interface compression
  end type ice_params_t

  !> `&mpm`: controls of the MPM solid solver.
  type :: mpm_params_t
    real(wp) :: flip_fraction = 0.99_wp              !< 1 pure FLIP, 0 pure PIC
    real(wp) :: gravity_ramp_time = 0.0_wp           !< gravity grows linearly over this time [s]
    real(wp) :: local_damping = 0.0_wp               !< local (Cundall) damping factor 0..1
    character(len=name_len) :: rigid_contact = 'no_slip' !< one of rigid_contact_names
    real(wp) :: contact_friction = 0.0_wp            !< Coulomb coefficient of 'friction' [-]
    logical :: cache_static_rigid = .true.           !< keep the grid share of static rigid
                                                     !! solids (.false.: recompute every step)
  end type mpm_params_t

  !> `&coupling`: fluid-solid coupling of scene 'mpmice'.
  type :: coupling_params_t
    character(len=name_len) :: drag_scheme = 'implicit'  !< one of drag_scheme_names
    real(wp) :: heat_exchange_coefficient = 0.0_wp       !< fluid-solid heat exchange [W/m^3/K]
    real(wp) :: max_solid_fraction = 0.999_wp            !< cap of the cell solid volume fraction
    real(wp) :: solid_fraction_relaxation = 0.1_wp       !< share of the particle/grid solid
                                                         !! fraction difference corrected per step
  end type coupling_params_t

  !> `&fluid` (repeated): one fluid material, its equation of state and initial state.
  type :: fluid_params_t
    character(len=name_len) :: name = ''                 !< unique identifier (required)
    character(len=name_len) :: eos = 'ideal_gas'        !< one of eos_names
    real(wp) :: gamma = 1.4_wp                           !< ratio of specific heats
    real(wp) :: heat_capacity_cv = 717.5_wp              !< c_v [J/kg/K]
    real(wp) :: reference_density = 999.8_wp             !< rho_ref [kg/m^3]
    real(wp) :: reference_pressure = 101325.0_wp         !< p_ref [Pa]
    real(wp) :: reference_temperature = 283.15_wp        !< T_ref [K]
    real(wp) :: bulk_modulus = 2.0e9_wp                  !< K [Pa]
    real(wp) :: thermal_expansion = 0.18_wp              !< alpha [kg/m^3/K] (linear water EOS)
    real(wp) :: stiffened_pressure = 0.0_wp              !< p_inf [Pa] (stiffened gas)
    real(wp) :: viscosity = 0.0_wp                       !< dynamic viscosity [Pa s]
    real(wp) :: conductivity = 0.0_wp                    !< thermal conductivity [W/m/K]
    real(wp) :: volume_fraction = 0.0_wp                 !< initial volume fraction everywhere
    real(wp) :: velocity(3) = [0.0_wp, 0.0_wp, 0.0_wp]   !< initial velocity [m/s]
    real(wp) :: temperature = 300.0_wp                   !< initial temperature [K]
    real(wp) :: pressure = 101325.0_wp                   !< initial pressure [Pa]
  end type fluid_params_t

  !> `&region` (repeated): initial state of one material inside a box (later regions win).
  type :: region_params_t
    character(len=name_len) :: material = ''             !< name of a &fluid or &solid
    real(wp) :: lower(3) = [0.0_wp, 0.0_wp, 0.0_wp]      !< low corner [m]
    real(wp) :: upper(3) = [0.0_wp, 0.0_wp, 0.0_wp]      !< high corner [m]
    real(wp) :: volume_fraction = 1.0_wp                 !< volume fraction inside
    real(wp) :: velocity(3) = [0.0_wp, 0.0_wp, 0.0_wp]   !< velocity inside [m/s]
    real(wp) :: temperature = 300.0_wp                   !< temperature inside [K]
    real(wp) :: pressure = 101325.0_wp                   !< pressure inside [Pa]
    !> 'box' (the box alone), 'polygon' or 'profile': the box and the file shape (docs/geometry.md)
    character(len=name_len) :: shape = 'box'
    character(len=path_len) :: polygon_file = ''         !< CSV polygon (shape 'polygon')
    character(len=path_len) :: profile_file = ''         !< CSV upper profile (shape 'profile')
    character(len=path_len) :: profile_lower_file = ''   !< CSV lower profile (shape 'profile')
    real(wp) :: layer_thickness = 0.0_wp                 !< > 0: layer of it on one profile [m]
    real(wp) :: profile_lower_level = level_unset        !< constant lower bound [m]
    type(file_shape_t) :: geometry                       !< shape read from the files
  end type region_params_t

  !> `&solid` (repeated): one solid body: constitutive model, geometry, particles, initial state.
  type :: solid_params_t
    character(len=name_len) :: name = ''                 !< unique identifier (required)
    character(len=name_len) :: model = 'linear_elastic'  !< one of solid_model_names
    real(wp) :: density = 2650.0_wp                      !< grain/solid density [kg/m^3]
    real(wp) :: youngs_modulus = 1.0e7_wp                !< E [Pa]
    real(wp) :: poisson_ratio = 0.3_wp                   !< nu
    real(wp) :: cohesion = 0.0_wp                        !< c [Pa]
    real(wp) :: friction_angle = 30.0_wp                 !< phi [deg]
    real(wp) :: dilation_angle = 0.0_wp                  !< psi [deg]
    logical :: tension_cutoff = .true.                   !< tension cut-off on
    real(wp) :: tensile_strength = 0.0_wp                !< tensile strength [Pa]
    real(wp) :: k0 = -1.0_wp                             !< lateral stress ratio (-1: nu/(1-nu))
    logical :: geostatic = .false.                       !< geostatic initial stress
    character(len=name_len) :: shape = 'box'             !< one of solid_shape_names
    real(wp) :: lower(3) = [0.0_wp, 0.0_wp, 0.0_wp]      !< box low corner [m]
    real(wp) :: upper(3) = [0.0_wp, 0.0_wp, 0.0_wp]      !< box high corner [m]
    integer :: npoints = 0                               !< polygon vertices in use
    real(wp) :: polygon_x(max_polygon_points) = 0.0_wp   !< polygon vertex x [m]
    real(wp) :: polygon_y(max_polygon_points) = 0.0_wp   !< polygon vertex y [m]
    real(wp) :: plane_point(3) = [0.0_wp, 0.0_wp, 0.0_wp]   !< half-space plane point [m]
    real(wp) :: plane_normal(3) = [0.0_wp, 0.0_wp, 1.0_wp]  !< half-space outward normal
    real(wp) :: rotation_deg = 0.0_wp                    !< box rotation about z [deg]
    integer :: particles_per_cell(3) = [2, 2, 2]         !< particles per cell per dimension
    real(wp) :: velocity(3) = [0.0_wp, 0.0_wp, 0.0_wp]   !< initial velocity [m/s]
    !> initial velocity profile: velocity * prod over k_d /= 0 of sin(k_d (x_d - lower_d)) [rad/m]
    real(wp) :: velocity_wavenumber(3) = [0.0_wp, 0.0_wp, 0.0_wp]
    real(wp) :: temperature = 300.0_wp                   !< initial temperature [K]
    real(wp) :: heat_capacity = 800.0_wp                 !< specific heat [J/kg/K]
    real(wp) :: conductivity = 0.4_wp                    !< thermal conductivity [W/m/K]
    real(wp) :: porosity = 0.0_wp                        !< porosity n
    real(wp) :: max_porosity = 1.0_wp                    !< loosest packing (1: never loose)
    real(wp) :: min_porosity = 0.0_wp                    !< densest packing: a contractant sand
                                                         !< (dilation_angle < 0) stops compacting
    real(wp) :: grain_size = 1.0e-3_wp                   !< grain diameter [m]
    real(wp) :: prescribed_velocity(3) = [0.0_wp, 0.0_wp, 0.0_wp]    !< rigid velocity [m/s]
    real(wp) :: acceleration_amplitude(3) = [0.0_wp, 0.0_wp, 0.0_wp] !< rigid A [m/s^2]
    real(wp) :: acceleration_frequency = 0.0_wp          !< rigid f [Hz]
    real(wp) :: acceleration_duration = 0.0_wp           !< rigid: a = 0 after it [s] (0: never)
    character(len=name_len) :: drag_law = 'kozeny_carman' !< one of drag_law_names (mpmice)
    real(wp) :: drag_coefficient = 0.0_wp                !< K of drag_law 'constant' [kg/m^3/s]
    real(wp) :: forchheimer_a = 150.0_wp                 !< linear (Ergun) a of 'forchheimer' [-]
    real(wp) :: forchheimer_b = 1.75_wp                  !< quadratic (Ergun) b of 'forchheimer' [-]
    real(wp) :: grain_bulk_modulus = 0.0_wp              !< K_s [Pa] (0: incompressible grains)
    real(wp) :: traction(3) = [0.0_wp, 0.0_wp, 0.0_wp]   !< surface load on the skeleton [Pa]
    real(wp) :: traction_lower(3) = [0.0_wp, 0.0_wp, 0.0_wp] !< loaded box low corner [m]
    real(wp) :: traction_upper(3) = [0.0_wp, 0.0_wp, 0.0_wp] !< loaded box high corner [m]
    real(wp) :: traction_ramp_time = 0.0_wp              !< traction grows linearly over it [s]
    ! soil models (docs/soil_models.md): Modified Cam-Clay ('cam_clay')
    real(wp) :: critical_state_ratio = 0.0_wp   !< M = q/p' at critical state (0: from
                                                !< friction_angle)
    real(wp) :: compression_index = 0.2_wp      !< lambda, v-ln p' slope of the NCL
    real(wp) :: swelling_index = 0.04_wp        !< kappa, v-ln p' slope of the swelling lines
    real(wp) :: preconsolidation_pressure = 0.0_wp  !< p_c0 [Pa] (0: from ocr)
    real(wp) :: ocr = 1.0_wp                    !< overconsolidation ratio on the initial stress
    real(wp) :: shear_modulus = 0.0_wp          !< constant G [Pa] (0: from poisson_ratio)
    real(wp) :: min_pressure = 1.0e3_wp         !< p'_min of the bulk modulus v p'/kappa [Pa]
    ! critical-state sand ('critical_state_sand')
    real(wp) :: friction_mu1 = 0.32_wp          !< mu_1, quasi-static critical friction
    real(wp) :: friction_mu2 = 0.7_wp           !< mu_2, friction at large J
    real(wp) :: viscous_j0 = 0.005_wp           !< J_0 of mu_eq(J)
    real(wp) :: critical_solid_fraction = 0.585_wp  !< phi_m, quasi-static critical packing
    real(wp) :: dilatancy_constant = 4.09_wp    !< K of tan(psi) = K (phi - phi_eq)
    real(wp) :: fluid_viscosity = 0.0_wp        !< eta_f of J [Pa s] (0: quasi-static)
    character(len=path_len) :: polygon_file = ''         !< CSV polygon (shape 'polygon')
    character(len=path_len) :: profile_file = ''         !< CSV upper profile (shape 'profile')
    character(len=path_len) :: profile_lower_file = ''   !< CSV lower profile (shape 'profile')
    real(wp) :: layer_thickness = 0.0_wp                 !< > 0: layer of it on one profile [m]
    real(wp) :: profile_lower_level = level_unset        !< constant lower bound [m]
    type(file_shape_t) :: geometry                       !< shape read from the files
  end type solid_params_t

  !> `&boundary` (repeated, at most one per face): conditions on one face of the domain.
  type :: boundary_params_t
    character(len=name_len) :: face = ''                 !< one of face_names (required)
    character(len=name_len) :: fluid = 'wall'            !< one of boundary_fluid_names
    real(wp) :: pressure = 101325.0_wp                   !< for fluid = 'pressure' [Pa]
    real(wp) :: velocity(3) = [0.0_wp, 0.0_wp, 0.0_wp]   !< for fluid = 'inflow' [m/s]
    !> name of the &fluid that enters through this face ('': the composition of the cell
    !! next to the face); fluid = 'pressure', 'inflow' or 'outflow' only
    character(len=name_len) :: inflow_fluid = ''
    character(len=name_len) :: thermal = 'adiabatic'     !< one of boundary_thermal_names
    real(wp) :: temperature = 300.0_wp                   !< for thermal = 'fixed' [K]
    character(len=name_len) :: solid = 'fixed'           !< one of boundary_solid_names
    real(wp) :: solid_velocity(3) = [0.0_wp, 0.0_wp, 0.0_wp] !< for solid = 'velocity' [m/s]
    real(wp) :: solid_traction(3) = [0.0_wp, 0.0_wp, 0.0_wp] !< for solid = 'traction' [Pa]
    !> times of the piecewise-linear velocity history of solid = 'velocity' [s] (leading
    !! entries in use, the rest `history_unset`; none in use: `solid_velocity` throughout)
    real(wp) :: solid_velocity_times(max_history_points) = history_unset
    !> velocity at each of those times [m/s]
    real(wp) :: solid_velocity_history(3, max_history_points) = history_unset
  end type boundary_params_t

contains

  !> Particles per cell the solver uses for solid `s` on a grid of `ncells` cells: the
  !! configured numbers along active dimensions, 1 along inactive ones (enforced silently).
  pure function particles_per_cell_used(s, ncells) result(ppc)
    type(solid_params_t), intent(in) :: s  !< solid
    integer, intent(in) :: ncells(3)       !< `&grid ncells`
    integer :: ppc(3)
    ppc = merge(s%particles_per_cell, 1, ncells > 1)
  end function particles_per_cell_used

  !> Number of leading entries of a `&boundary solid_velocity_times` table in use (those
  !! before the first `history_unset`).
  pure integer function history_points_used(times) result(n)
    real(wp), intent(in) :: times(:)  !< table [s]
    n = 0
    do while (n < size(times))
      if (times(n + 1) == history_unset) exit
      n = n + 1
    end do
  end function history_points_used
end module config_materials
