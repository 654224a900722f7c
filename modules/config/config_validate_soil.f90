!> Validation of the `&solid` parameters of the soil models (Modified Cam-Clay,
!! critical-state sand; docs/soil_models.md). Ranges are checked whatever the model, so a
!! default never fails; the model-specific requirements only for that model.
module config_validate_soil
  use mpmice_kinds, only: wp
  use config_types, only: solid_params_t
  use config_text, only: real_repr
  use config_check_tools, only: config_error_t, check_real
  implicit none
  private

  public :: check_soil

contains

  !> Check the soil parameters of one `&solid` (group label `g`).
  subroutine check_soil(p, g, err)
    type(solid_params_t), intent(in) :: p       !< solid
    character(len=*), intent(in) :: g           !< group label
    type(config_error_t), intent(inout) :: err  !< problem record
    if (err%found) return
    call check_real(err, g, 'critical_state_ratio', p%critical_state_ratio, &
      '0 (from friction_angle) or 0 < M < 3', min_value=0.0_wp, max_value=3.0_wp, &
      max_open=.true.)
    call check_real(err, g, 'compression_index', p%compression_index, '> 0', &
      min_value=0.0_wp, min_open=.true.)
    if (err%found) return
    call check_real(err, g, 'swelling_index', p%swelling_index, '0 < kappa < ' // &
      'compression_index (' // real_repr(p%compression_index) // ')', min_value=0.0_wp, &
      max_value=p%compression_index, min_open=.true., max_open=.true.)
    call check_real(err, g, 'preconsolidation_pressure', p%preconsolidation_pressure, &
      '>= 0 [Pa] (0: from ocr)', min_value=0.0_wp)
    call check_real(err, g, 'ocr', p%ocr, '>= 1', min_value=1.0_wp)
    call check_real(err, g, 'shear_modulus', p%shear_modulus, &
      '>= 0 [Pa] (0: from poisson_ratio)', min_value=0.0_wp)
    call check_real(err, g, 'min_pressure', p%min_pressure, '> 0 [Pa]', min_value=0.0_wp, &
      min_open=.true.)
    call check_real(err, g, 'friction_mu1', p%friction_mu1, '>= 0', min_value=0.0_wp)
    if (err%found) return
    call check_real(err, g, 'friction_mu2', p%friction_mu2, '>= friction_mu1 (' // &
      real_repr(p%friction_mu1) // ')', min_value=p%friction_mu1)
    call check_real(err, g, 'viscous_j0', p%viscous_j0, '> 0', min_value=0.0_wp, &
      min_open=.true.)
    call check_real(err, g, 'critical_solid_fraction', p%critical_solid_fraction, &
      '0 < phi_m < 1', min_value=0.0_wp, max_value=1.0_wp, min_open=.true., max_open=.true.)
    call check_real(err, g, 'dilatancy_constant', p%dilatancy_constant, '>= 0', &
      min_value=0.0_wp)
    call check_real(err, g, 'fluid_viscosity', p%fluid_viscosity, '>= 0 [Pa s]', &
      min_value=0.0_wp)
    if (err%found) return
    select case (trim(p%model))
    case ('cam_clay', 'modified_cam_clay', 'critical_state_sand')
      ! the specific volume 1 / (1 - porosity) and the packing 1 - porosity need a porosity
      call check_real(err, g, 'porosity', p%porosity, '0 < n < 1 for model ' // &
        trim(p%model), min_value=0.0_wp, max_value=1.0_wp, min_open=.true., max_open=.true.)
    case default
      ! the other models take the porosity as it is
    end select
  end subroutine check_soil
end module config_validate_soil
