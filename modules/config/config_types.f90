!> Run configuration: one parameter type per namelist group, every component defaulted.
!!
!! The components of each group's type, with their defaults (the documented defaults), come from the
!! namelist list (modules/config/namelist/<group>.toml) through the generated include files
!! (scripts/generate_namelists.py): the loader presets the namelist variables from a
!! default-initialised `config_t`, so changing a default in the list changes it everywhere,
!! docs/namelists.md included. Validation lives in `config_validate`, reading in `config_load`, the
!! echo in `config_echo`. The multiphase groups (`&physics`, `&ice`, `&mpm`, `&coupling`, and the
!! repeated `&fluid`, `&solid`, `&region`, `&boundary`) are defined in `config_materials` and
!! re-exported here.
module config_types
  use mpmice_kinds, only: wp, name_len, path_len
  use config_materials, only: physics_params_t, ice_params_t, mpm_params_t, coupling_params_t, &
    fluid_params_t, solid_params_t, region_params_t, boundary_params_t, max_fluids, max_solids, &
    max_regions, max_boundaries, max_polygon_points, eos_names, solid_model_names, &
    solid_shape_names, face_names, boundary_fluid_names, boundary_thermal_names, &
    boundary_solid_names, drag_law_names, drag_scheme_names, rigid_contact_names, &
    contact_normal_names, local_damping_force_names, face_drag_names, balance_names, &
    velocity_transfer_names, &
    particles_per_cell_used, max_history_points, history_unset, history_points_used, &
    max_blocks_per_dim, scene_names, shape_function_names
  implicit none
  private

  public :: config_t, run_params_t, grid_params_t, time_params_t, numerics_params_t
  public :: solver_params_t, output_params_t, heat_params_t
  public :: scene_names, shape_function_names, balance_names
  public :: physics_params_t, ice_params_t, mpm_params_t, coupling_params_t
  public :: fluid_params_t, solid_params_t, region_params_t, boundary_params_t
  public :: max_fluids, max_solids, max_regions, max_boundaries, max_polygon_points
  public :: eos_names, solid_model_names, solid_shape_names, face_names
  public :: boundary_fluid_names, boundary_thermal_names, boundary_solid_names
  public :: drag_law_names, drag_scheme_names, rigid_contact_names, contact_normal_names
  public :: local_damping_force_names, face_drag_names, velocity_transfer_names
  public :: particles_per_cell_used, boundary_for_face
  public :: max_history_points, history_unset, history_points_used
  public :: max_blocks_per_dim

  !> `&run`: what to run, where to write, when to stop.
  type :: run_params_t
    include 'config_nml_run_type.inc'
  end type run_params_t

  !> `&grid`: the uniform Cartesian grid and its decomposition.
  type :: grid_params_t
    include 'config_nml_grid_type.inc'
    !> cells of each block along x, y, z (`block_cells_x/y/z`; all zero: an even split)
    integer :: block_cells(max_blocks_per_dim, 3) = 0
  end type grid_params_t

  !> `&time`: time-step control.
  type :: time_params_t
    include 'config_nml_time_type.inc'
  end type time_params_t

  !> `&numerics`: discretisation choices.
  type :: numerics_params_t
    include 'config_nml_numerics_type.inc'
  end type numerics_params_t

  !> `&solver`: linear solver controls.
  type :: solver_params_t
    include 'config_nml_solver_type.inc'
  end type solver_params_t

  !> `&output`: what the dumps contain.
  type :: output_params_t
    include 'config_nml_output_type.inc'
  end type output_params_t

  !> `&heat`: heat conduction scene, dT/dt = div(k grad T) / (rho c).
  type :: heat_params_t
    include 'config_nml_heat_type.inc'
  end type heat_params_t

  !> The whole configuration of a run: one component per namelist group, a count and an array
  !! per repeated group (generated from modules/config/namelist/groups.toml).
  type :: config_t
    include 'config_nml_config_type.inc'
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
