!> The parameters each scene receives: one bundle type per scene, holding only the namelist
!! groups that scene reads (`config_scene_groups` lists them), assembled by the driver from the
!! whole configuration (`driver_scene_params`). A scene's setup takes only its own bundle type,
!! so it cannot read another scene's groups; `driver_scene_params%scene_create` picks the scene
!! from the bundle's type.
!!
!! The `&boundary` groups arrive resolved per face (`faces(1:6)`, x-, x+, y-, y+, z-, z+: the
!! face's group, or the defaults when the input has none; `config_types%boundary_for_face`).
!! `&run`, `&grid`, `&time` and `&output` belong to the driver (decomposition, clock, dumps);
!! only the MPM bundle carries `&run` (its series file is named after the run).
module scene_params
  use config_types, only: run_params_t, numerics_params_t, solver_params_t, physics_params_t, &
    heat_params_t, ice_params_t, mpm_params_t, coupling_params_t, fluid_params_t, &
    solid_params_t, region_params_t, boundary_params_t, max_fluids, max_solids, max_regions
  implicit none
  private

  public :: scene_params_t, heat_scene_params_t, ice_scene_params_t, mpm_scene_params_t, &
    mpmice_scene_params_t

  !> Parameters of a scene (abstract: each scene extends it with its groups).
  type, abstract :: scene_params_t
  end type scene_params_t

  !> `scene = 'heat_conduction'`: `&numerics`, `&solver`, `&heat`.
  type, extends(scene_params_t) :: heat_scene_params_t
    type(numerics_params_t) :: numerics  !< `&numerics`
    type(solver_params_t) :: solver      !< `&solver`
    type(heat_params_t) :: heat          !< `&heat`
  end type heat_scene_params_t

  !> `scene = 'ice'`: `&numerics`, `&solver`, `&physics`, `&ice`, `&fluid`, `&region`,
  !! `&boundary`.
  type, extends(scene_params_t) :: ice_scene_params_t
    type(numerics_params_t) :: numerics  !< `&numerics`
    type(solver_params_t) :: solver      !< `&solver`
    type(physics_params_t) :: physics    !< `&physics`
    type(ice_params_t) :: ice            !< `&ice`
    integer :: nfluids = 0               !< number of `&fluid` groups
    type(fluid_params_t) :: fluids(max_fluids)     !< `&fluid` occurrences 1..nfluids
    integer :: nregions = 0              !< number of `&region` groups
    type(region_params_t) :: regions(max_regions)  !< `&region` occurrences, in order
    type(boundary_params_t) :: faces(6)            !< conditions on each face
  end type ice_scene_params_t

  !> `scene = 'mpm'`: `&run` (names), `&numerics`, `&physics`, `&mpm`, `&solid`, `&boundary`.
  type, extends(scene_params_t) :: mpm_scene_params_t
    type(run_params_t) :: run            !< `&run` (output directory and run name)
    type(numerics_params_t) :: numerics  !< `&numerics`
    type(physics_params_t) :: physics    !< `&physics`
    type(mpm_params_t) :: mpm            !< `&mpm`
    integer :: nsolids = 0               !< number of `&solid` groups
    type(solid_params_t) :: solids(max_solids)  !< `&solid` occurrences 1..nsolids
    type(boundary_params_t) :: faces(6)         !< conditions on each face
  end type mpm_scene_params_t

  !> `scene = 'mpmice'`: the fluids' and the solids' bundles, and `&coupling`.
  type, extends(scene_params_t) :: mpmice_scene_params_t
    type(ice_scene_params_t) :: ice        !< groups of the fluids (ICE)
    type(mpm_scene_params_t) :: mpm        !< groups of the solids (MPM)
    type(coupling_params_t) :: coupling    !< `&coupling`
  end type mpmice_scene_params_t
end module scene_params
