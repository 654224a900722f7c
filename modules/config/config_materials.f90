!> Parameter types of the multiphase scenes (`ice`, `mpm`, `mpmice`): the singleton groups
!! `&physics`, `&ice`, `&mpm`, `&coupling` and the repeated groups `&fluid`, `&solid`, `&region`,
!! `&boundary`.
!!
!! The components of each type, their defaults and doc comments, the size limits and the allowed
!! values of the string variables (`eos_names`, ...) are generated from the namelist list
!! (modules/config/namelist/*.toml, scripts/generate_namelists.py) into the included files;
!! docs/namelists.md's tables come from the same list.
!! A repeated group may appear several times; each occurrence is one element of an array of
!! `config_t` (at most `max_fluids`, ... elements), and every occurrence starts from the type's
!! defaults. `config_types` re-exports everything public here.
module config_materials
  use mpmice_kinds, only: wp, name_len, path_len
  use geometry_shapes, only: file_shape_t, level_unset
  implicit none
  private

  public :: physics_params_t, ice_params_t, mpm_params_t, coupling_params_t, fluid_params_t, &
    solid_params_t, region_params_t, boundary_params_t
  public :: face_names, particles_per_cell_used, history_unset, history_points_used
  ! the size limits and the arrays of allowed values (`eos_names`, ...), from the list
  include 'config_nml_public.inc'

  include 'config_nml_limits.inc'
  !> Value of the unused entries of `solid_velocity_times` and `solid_velocity_history`.
  real(wp), parameter :: history_unset = -huge(1.0_wp)

  !> Faces of the domain, in `face_index` order 1..6.
  character(len=*), parameter :: face_names(6) = [character(len=2) :: &
    'x-', 'x+', 'y-', 'y+', 'z-', 'z+']
  ! the allowed values of the string variables (`scene_names`, `eos_names`, ...), from the list
  include 'config_nml_choices.inc'

  !> `&physics`: body force and reference state shared by all materials.
  type :: physics_params_t
    include 'config_nml_physics_type.inc'
  end type physics_params_t

  !> `&ice`: controls of the ICE multi-fluid solver.
  type :: ice_params_t
    include 'config_nml_ice_type.inc'
  end type ice_params_t

  !> `&mpm`: controls of the MPM solid solver.
  type :: mpm_params_t
    include 'config_nml_mpm_type.inc'
  end type mpm_params_t

  !> `&coupling`: fluid-solid coupling of scene 'mpmice'.
  type :: coupling_params_t
    include 'config_nml_coupling_type.inc'
  end type coupling_params_t

  !> `&fluid` (repeated): one fluid material, its equation of state and initial state.
  type :: fluid_params_t
    include 'config_nml_fluid_type.inc'
  end type fluid_params_t

  !> `&region` (repeated): initial state of one material inside a box (later regions win).
  type :: region_params_t
    include 'config_nml_region_type.inc'
    type(file_shape_t) :: geometry                       !< shape read from the files
  end type region_params_t

  !> `&solid` (repeated): one solid body: constitutive model, geometry, particles, initial state.
  type :: solid_params_t
    include 'config_nml_solid_type.inc'
    type(file_shape_t) :: geometry                       !< shape read from the files
  end type solid_params_t

  !> `&boundary` (repeated, at most one per face): conditions on one face of the domain.
  type :: boundary_params_t
    include 'config_nml_boundary_type.inc'
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
