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
end module driver_scene_params
