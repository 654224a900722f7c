!> The range checks of every namelist group that the namelist list declares (a `range`, `choices`
!! or `off` of a variable in modules/config/namelist/<group>.toml): `check_<group>_ranges(p, g,
!! err)` checks the parameters `p` of one group (label `g` in messages, `fluid(2)` for an
!! occurrence of a repeated group) in list order and records the first problem.
!!
!! The routines are generated (scripts/generate_namelists.py) into the included file. Checks that
!! involve another group, the number of ranks or a condition stay written by hand in
!! `config_validate` and `config_validate_phases`, which call these first.
module config_validate_ranges
  use mpmice_kinds, only: wp
  use config_types, only: run_params_t, grid_params_t, time_params_t, numerics_params_t, &
    solver_params_t, output_params_t, heat_params_t, physics_params_t, ice_params_t, &
    mpm_params_t, coupling_params_t, fluid_params_t, solid_params_t, region_params_t, &
    boundary_params_t, scene_names, shape_function_names, eos_names, solid_model_names, &
    solid_shape_names, drag_law_names, rigid_contact_names, contact_normal_names, drag_scheme_names, &
    local_damping_force_names, face_drag_names, boundary_fluid_names, boundary_thermal_names, &
    boundary_solid_names, balance_names, velocity_transfer_names
  use config_text, only: real_repr, ints_repr
  use config_check_tools, only: config_error_t, check_real, check_int, check_choice, check_finite, &
    check_nonblank
  implicit none
  private

  include 'config_nml_ranges_public.inc'

contains

  include 'config_nml_ranges.inc'
end module config_validate_ranges
