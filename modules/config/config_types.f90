!> Run configuration: one parameter type per namelist group, every component defaulted.
!!
!! The defaults written here are the documented defaults (docs/namelists.md): the loader presets
!! the namelist variables from a default-initialised `config_t`, so changing a default here changes
!! it everywhere. Validation lives in `config_validate`, reading in `config_load`, the echo in
!! `config_echo`. The multiphase groups (`&physics`, `&ice`, `&mpm`, `&coupling`, and the repeated
!! `&fluid`, `&solid`, `&region`, `&boundary`) are defined in `config_materials` and re-exported
!! here.
module config_types
  use mpmice_kinds, only: wp, name_len, path_len
  use config_materials, only: physics_params_t, ice_params_t, mpm_params_t, coupling_params_t, &
    fluid_params_t, solid_params_t, region_params_t, boundary_params_t, max_fluids, max_solids, &
    max_regions, max_boundaries, max_polygon_points, eos_names, solid_model_names, &
    solid_shape_names, face_names, boundary_fluid_names, boundary_thermal_names, &
    boundary_solid_names, drag_law_names, drag_scheme_names, rigid_contact_names, &
    particles_per_cell_used, max_history_points, history_unset, history_points_used
  implicit none
  private

  public :: config_t, run_params_t, grid_params_t, time_params_t, numerics_params_t
  public :: solver_params_t, output_params_t, heat_params_t
  public :: scene_names, shape_function_names
  public :: physics_params_t, ice_params_t, mpm_params_t, coupling_params_t
  public :: fluid_params_t, solid_params_t, region_params_t, boundary_params_t
  public :: max_fluids, max_solids, max_regions, max_boundaries, max_polygon_points
  public :: eos_names, solid_model_names, solid_shape_names, face_names
  public :: boundary_fluid_names, boundary_thermal_names, boundary_solid_names
  public :: drag_law_names, drag_scheme_names, rigid_contact_names
  public :: particles_per_cell_used, boundary_for_face
  public :: max_history_points, history_unset, history_points_used
  public :: max_blocks_per_dim

  !> Most blocks along one dimension that `&grid block_cells_x/y/z` can give.
  integer, parameter :: max_blocks_per_dim = 256

  !> Scenes the driver knows (the allowed values of `&run scene`). Later issues append to it.
  !! 'ice': fluids only (>= 1 `&fluid`, no `&solid`); 'mpm': solids only (>= 1 `&solid`, no
  !! `&fluid`); 'mpmice': fluids and solids coupled (>= 1 `&fluid` and >= 1 `&solid`). A scene
  !! may be listed before its solver exists: the driver then stops with "scene not available in
  !! this build".
  character(len=*), parameter :: scene_names(4) = [character(len=name_len) :: &
    'heat_conduction', 'ice', 'mpm', 'mpmice']
  !> Allowed values of `&numerics shape_function`.
  character(len=*), parameter :: shape_function_names(2) = [character(len=name_len) :: &
    'linear', 'gimp']

  !> `&run`: what to run, where to write, when to stop.
  type :: run_params_t
    character(len=name_len) :: name = 'mpmice'             !< case name (prefix of output files)
    character(len=name_len) :: scene = 'heat_conduction'   !< scene to set up (one of scene_names)
    character(len=path_len) :: output_dir = 'output'       !< directory for dumps, echo and log
    real(wp) :: end_time = 1.0_wp                          !< simulated end time [s]
    real(wp) :: output_interval = 0.0_wp                   !< dump interval [s] (0: first and last)
    real(wp) :: checkpoint_interval = 0.0_wp               !< checkpoint interval [s] (0: none)
    integer :: max_steps = 0                               !< step limit (0: unlimited)
    real(wp) :: wall_time_limit = 0.0_wp                   !< wall-clock budget [s] (0: none)
    real(wp) :: max_energy_growth = 0.0_wp                 !< solid energy / reference stop (0: off)
    real(wp) :: max_particle_loss_fraction = 1.0_wp        !< lost particles share stop (1: off)
    real(wp) :: min_dt_ratio = 0.0_wp                      !< step-collapse stop (0: off)
    real(wp) :: progress_interval = 10.0_wp                !< progress line interval [s wall time]
    integer :: verbosity = 1                               !< 0 quiet, 1 normal, 2 debug
    logical :: overwrite = .false.                         !< may replace another run's output
  end type run_params_t

  !> `&grid`: the uniform Cartesian grid and its decomposition.
  type :: grid_params_t
    integer :: ncells(3) = [10, 1, 1]                      !< cells per dimension (1: inactive)
    real(wp) :: lower(3) = [0.0_wp, 0.0_wp, 0.0_wp]        !< low corner of the domain [m]
    real(wp) :: upper(3) = [1.0_wp, 1.0_wp, 1.0_wp]        !< high corner of the domain [m]
    logical :: periodic(3) = [.false., .false., .false.]   !< periodic dimensions
    integer :: ghost_width = 2                             !< ghost layers in active dimensions
    integer :: dims(3) = [0, 0, 0]                         !< ranks per dimension (0: automatic)
    !> cells of each block along x, y, z (`block_cells_x/y/z`; all zero: an even split)
    integer :: block_cells(max_blocks_per_dim, 3) = 0
  end type grid_params_t

  !> `&time`: time-step control.
  type :: time_params_t
    real(wp) :: cfl = 0.5_wp                               !< Courant number (safety factor)
    real(wp) :: dt_init = 1.0e-3_wp                        !< first time step [s]
    real(wp) :: dt_max = 1.0e-3_wp                         !< largest time step [s]
    real(wp) :: dt_min = 1.0e-12_wp                        !< smallest time step [s] (below: stop)
    real(wp) :: dt_growth = 1.1_wp                         !< largest ratio of successive steps
  end type time_params_t

  !> `&numerics`: discretisation choices.
  type :: numerics_params_t
    integer :: advection_order = 2                         !< 1 first order, 2 limited second order
    character(len=name_len) :: shape_function = 'gimp'     !< MPM shape functions: linear or gimp
    real(wp) :: time_theta = 1.0_wp                        !< implicit weight (1 BE, 0.5 CN)
  end type numerics_params_t

  !> `&solver`: linear solver controls.
  type :: solver_params_t
    real(wp) :: tolerance = 1.0e-10_wp                     !< relative residual tolerance
    integer :: max_iterations = 200                        !< iteration limit
    integer :: print_level = 0                             !< solver diagnostics 0..3
  end type solver_params_t

  !> `&output`: what the dumps contain.
  type :: output_params_t
    logical :: xdmf = .true.                               !< write XDMF files next to the dumps
    character(len=path_len) :: fields = 'all'              !< fields to dump ('all' or a list)
  end type output_params_t

  !> `&heat`: heat conduction scene, dT/dt = div(k grad T) / (rho c).
  type :: heat_params_t
    real(wp) :: conductivity = 1.0_wp                      !< thermal conductivity k [W/m/K]
    real(wp) :: density = 1.0_wp                           !< density rho [kg/m^3]
    real(wp) :: heat_capacity = 1.0_wp                     !< specific heat capacity c [J/kg/K]
    real(wp) :: base_temperature = 300.0_wp                !< base and wall temperature [K]
    real(wp) :: amplitude = 1.0_wp                         !< initial perturbation amplitude [K]
    integer :: modes(3) = [1, 1, 1]                        !< initial mode numbers per dimension
  end type heat_params_t

  !> The whole configuration of a run: one component per namelist group.
  type :: config_t
    type(run_params_t) :: run            !< `&run`
    type(grid_params_t) :: grid          !< `&grid`
    type(time_params_t) :: time          !< `&time`
    type(numerics_params_t) :: numerics  !< `&numerics`
    type(solver_params_t) :: solver      !< `&solver`
    type(output_params_t) :: output      !< `&output`
    type(heat_params_t) :: heat          !< `&heat`
    type(physics_params_t) :: physics    !< `&physics`
    type(ice_params_t) :: ice            !< `&ice`
    type(mpm_params_t) :: mpm            !< `&mpm`
    type(coupling_params_t) :: coupling  !< `&coupling`
    integer :: nfluids = 0               !< number of `&fluid` groups
    integer :: nsolids = 0               !< number of `&solid` groups
    integer :: nregions = 0              !< number of `&region` groups
    integer :: nboundaries = 0           !< number of `&boundary` groups
    type(fluid_params_t) :: fluids(max_fluids)              !< `&fluid` occurrences 1..nfluids
    type(solid_params_t) :: solids(max_solids)              !< `&solid` occurrences 1..nsolids
    type(region_params_t) :: regions(max_regions)           !< `&region` occurrences, in order
    type(boundary_params_t) :: boundaries(max_boundaries)   !< `&boundary` occurrences
  end type config_t

contains

  !> The conditions on face `face_index` (1..6 = x-, x+, y-, y+, z-, z+): the `&boundary` group
  !! of that face, or the defaults (fluid 'wall', thermal 'adiabatic', solid 'fixed') with `face`
  !! set when the input has none. Periodic and inactive faces also get the defaults (no group
  !! is allowed there); the solvers do not apply them.
  pure function boundary_for_face(cfg, face_index) result(b)
    type(config_t), intent(in) :: cfg      !< configuration
    integer, intent(in) :: face_index      !< 1..6
    type(boundary_params_t) :: b
    integer :: i
    b%face = face_names(face_index)
    do i = 1, cfg%nboundaries
      if (cfg%boundaries(i)%face == face_names(face_index)) then
        b = cfg%boundaries(i)
        return
      end if
    end do
  end function boundary_for_face
end module config_types
