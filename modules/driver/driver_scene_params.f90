!> The driver's side of `scene_params`: the parameter bundle of the scene `&run scene` names,
!! copied from the validated configuration (only the groups that scene reads), and the one place
!! that makes the scene of a bundle (`scene_create`).
module driver_scene_params
  use mpmice_errors, only: fatal
  use config_types, only: config_t, boundary_for_face, boundary_params_t
  use scene_params, only: scene_params_t, heat_scene_params_t, ice_scene_params_t, &
    mpm_scene_params_t, mpmice_scene_params_t
  use scene_interface, only: scene_t, scene_context_t
  use heat_scene, only: heat_scene_t, heat_scene_setup
  use ice_scene, only: ice_scene_t, ice_scene_setup
  use mpm_scene, only: mpm_scene_t, mpm_setup
  use mpmice_scene, only: mpmice_scene_t, mpmice_setup
  implicit none
  private

  public :: scene_params_from_config, scene_create

contains

  !> The bundle of `cfg%run%scene` (heat_conduction, ice, mpm or mpmice).
  subroutine scene_params_from_config(cfg, params)
    type(config_t), intent(in) :: cfg                          !< validated configuration
    class(scene_params_t), allocatable, intent(out) :: params  !< the scene's groups
    type(ice_scene_params_t) :: fluids
    type(mpm_scene_params_t) :: solids
    select case (trim(cfg%run%scene))
    case ('heat_conduction')
      params = heat_scene_params_t(numerics=cfg%numerics, solver=cfg%solver, heat=cfg%heat)
    case ('ice')
      call phase_groups(cfg, fluids, solids)
      params = fluids
    case ('mpm')
      call phase_groups(cfg, fluids, solids)
      params = solids
    case ('mpmice')
      call phase_groups(cfg, fluids, solids)
      params = mpmice_scene_params_t(ice=fluids, mpm=solids, coupling=cfg%coupling)
    case default
      ! the configuration accepts only scenes listed in config_types%scene_names
      call fatal('scene ''' // trim(cfg%run%scene) // ''' is not available in this build')
    end select
  end subroutine scene_params_from_config

  !> The fluids' groups (the ICE scene, and the fluids of the coupled one) and the solids'
  !! groups (the MPM scene, and the solids of the coupled one); both get the conditions of the
  !! six faces.
  subroutine phase_groups(cfg, fluids, solids)
    type(config_t), intent(in) :: cfg                   !< validated configuration
    type(ice_scene_params_t), intent(out) :: fluids     !< the fluids' bundle
    type(mpm_scene_params_t), intent(out) :: solids     !< the solids' bundle
    type(boundary_params_t) :: faces(6)
    integer :: face
    do face = 1, 6
      faces(face) = boundary_for_face(cfg, face)
    end do
    fluids = ice_scene_params_t(numerics=cfg%numerics, solver=cfg%solver, physics=cfg%physics, &
      ice=cfg%ice, nfluids=cfg%nfluids, nregions=cfg%nregions, fluids=cfg%fluids, &
      regions=cfg%regions, faces=faces)
    solids = mpm_scene_params_t(run=cfg%run, numerics=cfg%numerics, physics=cfg%physics, &
      mpm=cfg%mpm, nsolids=cfg%nsolids, solids=cfg%solids, faces=faces)
  end subroutine phase_groups

  !> The scene of the bundle `params` (its type names the scene), set up by its own typed setup
  !! in the run's context `ctx`, which the scene keeps.
  subroutine scene_create(params, ctx, scene)
    class(scene_params_t), intent(in) :: params        !< the scene's groups
    type(scene_context_t), intent(in) :: ctx           !< decomposition, grid and timers of the run
    class(scene_t), allocatable, intent(out) :: scene  !< the scene, in its initial state
    type(heat_scene_t), allocatable :: heat
    type(ice_scene_t), allocatable :: ice
    type(mpm_scene_t), allocatable :: mpm
    type(mpmice_scene_t), allocatable :: coupled
    select type (params)
    type is (heat_scene_params_t)
      allocate(heat)
      call heat_scene_setup(heat, params, ctx)
      call move_alloc(heat, scene)
    type is (ice_scene_params_t)
      allocate(ice)
      call ice_scene_setup(ice, params, ctx)
      call move_alloc(ice, scene)
    type is (mpm_scene_params_t)
      allocate(mpm)
      call mpm_setup(mpm, params, ctx)
      call move_alloc(mpm, scene)
    type is (mpmice_scene_params_t)
      allocate(coupled)
      call mpmice_setup(coupled, params, ctx)
      call move_alloc(coupled, scene)
    class default
      call fatal('scene_create: a parameter bundle of no known scene')
    end select
  end subroutine scene_create
end module driver_scene_params
