!> The driver's side of `scene_params`: the parameter bundle of the scene `&run scene` names,
!! copied from the validated configuration (only the groups that scene reads).
module driver_scene_params
  use mpmice_errors, only: fatal
  use config_types, only: config_t, boundary_for_face, boundary_params_t
  use scene_params, only: scene_params_t, heat_scene_params_t, ice_scene_params_t, &
    mpm_scene_params_t, mpmice_scene_params_t
  implicit none
  private

  public :: scene_params_from_config

contains

  !> The bundle of `cfg%run%scene` (heat_conduction, ice, mpm or mpmice).
  subroutine scene_params_from_config(cfg, params)
    type(config_t), intent(in) :: cfg                          !< validated configuration
    class(scene_params_t), allocatable, intent(out) :: params  !< the scene's groups
    select case (trim(cfg%run%scene))
    case ('heat_conduction')
      params = heat_scene_params_t(numerics=cfg%numerics, solver=cfg%solver, heat=cfg%heat)
    case ('ice')
      params = ice_bundle(cfg)
    case ('mpm')
      params = mpm_bundle(cfg)
    case ('mpmice')
      params = mpmice_scene_params_t(ice=ice_bundle(cfg), mpm=mpm_bundle(cfg), &
        coupling=cfg%coupling)
    case default
      ! the configuration accepts only scenes listed in config_types%scene_names
      call fatal('scene ''' // trim(cfg%run%scene) // ''' is not available in this build')
    end select
  end subroutine scene_params_from_config

  !> The fluids' groups (the ICE scene, and the fluids of the coupled one).
  function ice_bundle(cfg) result(p)
    type(config_t), intent(in) :: cfg  !< validated configuration
    type(ice_scene_params_t) :: p
    p = ice_scene_params_t(numerics=cfg%numerics, solver=cfg%solver, physics=cfg%physics, &
      ice=cfg%ice, nfluids=cfg%nfluids, nregions=cfg%nregions, fluids=cfg%fluids, &
      regions=cfg%regions, faces=faces_of(cfg))
  end function ice_bundle

  !> The solids' groups (the MPM scene, and the solids of the coupled one).
  function mpm_bundle(cfg) result(p)
    type(config_t), intent(in) :: cfg  !< validated configuration
    type(mpm_scene_params_t) :: p
    p = mpm_scene_params_t(run=cfg%run, numerics=cfg%numerics, physics=cfg%physics, &
      mpm=cfg%mpm, nsolids=cfg%nsolids, solids=cfg%solids, faces=faces_of(cfg))
  end function mpm_bundle

  !> The `&boundary` conditions of the six faces (x-, x+, y-, y+, z-, z+).
  function faces_of(cfg) result(faces)
    type(config_t), intent(in) :: cfg  !< validated configuration
    type(boundary_params_t) :: faces(6)
    integer :: face
    do face = 1, 6
      faces(face) = boundary_for_face(cfg, face)
    end do
  end function faces_of
end module driver_scene_params
