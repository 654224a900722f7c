!> The driver's side of `scene_params`: the parameter bundle of the scene `&run scene` names,
!! copied from the validated configuration (only the groups that scene reads).
module driver_scene_params
  use mpmice_errors, only: fatal
  use config_types, only: config_t, boundary_for_face
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
      allocate(ice_scene_params_t :: params)
      select type (params)
      type is (ice_scene_params_t)
        call fill_ice(cfg, params)
      end select
    case ('mpm')
      allocate(mpm_scene_params_t :: params)
      select type (params)
      type is (mpm_scene_params_t)
        call fill_mpm(cfg, params)
      end select
    case ('mpmice')
      allocate(mpmice_scene_params_t :: params)
      select type (params)
      type is (mpmice_scene_params_t)
        call fill_ice(cfg, params%ice)
        call fill_mpm(cfg, params%mpm)
        params%coupling = cfg%coupling
      end select
    case default
      ! the configuration accepts only scenes listed in config_types%scene_names
      call fatal('scene ''' // trim(cfg%run%scene) // ''' is not available in this build')
    end select
  end subroutine scene_params_from_config

  !> The fluids' groups (the ICE scene, and the fluids of the coupled one).
  subroutine fill_ice(cfg, p)
    type(config_t), intent(in) :: cfg              !< validated configuration
    type(ice_scene_params_t), intent(inout) :: p   !< bundle to fill
    integer :: face
    p%numerics = cfg%numerics
    p%solver = cfg%solver
    p%physics = cfg%physics
    p%ice = cfg%ice
    p%nfluids = cfg%nfluids
    p%nregions = cfg%nregions
    p%fluids = cfg%fluids
    p%regions = cfg%regions
    do face = 1, 6
      p%faces(face) = boundary_for_face(cfg, face)
    end do
  end subroutine fill_ice

  !> The solids' groups (the MPM scene, and the solids of the coupled one).
  subroutine fill_mpm(cfg, p)
    type(config_t), intent(in) :: cfg              !< validated configuration
    type(mpm_scene_params_t), intent(inout) :: p   !< bundle to fill
    integer :: face
    p%run = cfg%run
    p%numerics = cfg%numerics
    p%physics = cfg%physics
    p%mpm = cfg%mpm
    p%nsolids = cfg%nsolids
    p%solids = cfg%solids
    do face = 1, 6
      p%faces(face) = boundary_for_face(cfg, face)
    end do
  end subroutine fill_mpm
end module driver_scene_params
