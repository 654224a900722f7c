!> Validation of the multiphase groups (`&physics`, `&ice`, `&mpm`, `&coupling`, `&fluid`,
!! `&solid`, `&region`, `&boundary`) and of the scene-dependent group counts.
!!
!! Called by `config_check` after the other groups. Problems in occurrence k of a repeated group
!! are reported against the group `fluid(k)` (and so on). Where regions and solids lie against
!! the domain, and whether the initial volume fractions sum to one in every cell, is checked by
!! `config_validate_extent` (called last).
module config_validate_phases
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use mpmice_kinds, only: wp
  use config_types, only: config_t, solid_params_t, eos_names, &
    solid_model_names, solid_shape_names, face_names, boundary_fluid_names, &
    boundary_thermal_names, boundary_solid_names, max_polygon_points, drag_law_names, &
    drag_scheme_names, rigid_contact_names, boundary_params_t, max_history_points, history_unset, &
    history_points_used
  use config_text, only: real_repr, reals_repr, ints_repr, quoted, join_names
  use config_check_tools, only: config_error_t, set_error, check_real, check_int, check_choice, &
    occurrence_label
  use config_validate_extent, only: check_extents
  use config_validate_soil, only: check_soil
  implicit none
  private

  public :: check_phases

  real(wp), parameter :: pi = 3.14159265358979323846_wp  !< pi

contains

  !> Check the multiphase groups of `cfg`; `err` records the first problem.
  subroutine check_phases(cfg, err)
    type(config_t), intent(in) :: cfg           !< configuration
    type(config_error_t), intent(inout) :: err  !< problem record
    integer :: k
    call check_singletons(cfg, err)
    do k = 1, cfg%nfluids
      call check_fluid(cfg, k, err)
    end do
    do k = 1, cfg%nsolids
      call check_solid(cfg, k, err)
    end do
    do k = 1, cfg%nregions
      call check_region(cfg, k, err)
    end do
    do k = 1, cfg%nboundaries
      call check_boundary(cfg, k, err)
    end do
    call check_scene(cfg, err)
    call check_extents(cfg, err)
  end subroutine check_phases

  !> Every entry of `x` finite.
  subroutine check_finite(err, group, variable, x, unit)
    type(config_error_t), intent(inout) :: err  !< problem record
    character(len=*), intent(in) :: group       !< group label
    character(len=*), intent(in) :: variable    !< variable name
    real(wp), intent(in) :: x(:)                !< values
    character(len=*), intent(in) :: unit        !< unit text, e.g. ' [m]'
    if (err%found) return
    if (.not. all(ieee_is_finite(x))) then
      call set_error(err, group, variable, reals_repr(x), 'finite numbers' // unit)
    end if
  end subroutine check_finite

  !> `&physics`, `&ice`, `&mpm`, `&coupling`.
  subroutine check_singletons(cfg, err)
    type(config_t), intent(in) :: cfg           !< configuration
    type(config_error_t), intent(inout) :: err  !< problem record
    call check_finite(err, 'physics', 'gravity', cfg%physics%gravity, ' [m/s^2]')
    call check_real(err, 'physics', 'reference_pressure', cfg%physics%reference_pressure, &
      '> 0 [Pa]', min_value=0.0_wp, min_open=.true.)
    associate (p => cfg%ice)
      call check_real(err, 'ice', 'outer_tolerance', p%outer_tolerance, '> 0', &
        min_value=0.0_wp, min_open=.true.)
      call check_int(err, 'ice', 'max_outer_iterations', p%max_outer_iterations, '>= 1', &
        min_value=1)
      call check_real(err, 'ice', 'exchange_coefficient', p%exchange_coefficient, &
        '>= 0 [kg/m^3/s]', min_value=0.0_wp)
      call check_real(err, 'ice', 'heat_exchange_coefficient', p%heat_exchange_coefficient, &
        '>= 0 [W/m^3/K]', min_value=0.0_wp)
      call check_real(err, 'ice', 'smagorinsky_constant', p%smagorinsky_constant, '> 0', &
        min_value=0.0_wp, min_open=.true.)
      call check_real(err, 'ice', 'equilibration_tolerance', p%equilibration_tolerance, '> 0', &
        min_value=0.0_wp, min_open=.true.)
      call check_int(err, 'ice', 'max_equilibration_iterations', &
        p%max_equilibration_iterations, '>= 1', min_value=1)
      call check_real(err, 'ice', 'sound_speed_factor', p%sound_speed_factor, '0..10', &
        min_value=0.0_wp, max_value=10.0_wp)
      call check_real(err, 'ice', 'interface_compression', p%interface_compression, &
        '0..4 (0: off; > 0 needs exactly two &fluid groups)', min_value=0.0_wp, max_value=4.0_wp)
      if (.not. err%found .and. p%interface_compression > 0.0_wp .and. cfg%nfluids /= 2) then
        call set_error(err, 'ice', 'interface_compression', real_repr(p%interface_compression), &
        '0 with ' // ints_repr([cfg%nfluids]) // ' &fluid groups (compression acts between ' // &
        'exactly two)')
      end if
    end associate
    associate (p => cfg%mpm)
      call check_real(err, 'mpm', 'flip_fraction', p%flip_fraction, &
        '0..1 (1: pure FLIP, 0: PIC)', min_value=0.0_wp, max_value=1.0_wp)
      call check_real(err, 'mpm', 'gravity_ramp_time', p%gravity_ramp_time, '>= 0 [s]', &
        min_value=0.0_wp)
      call check_real(err, 'mpm', 'local_damping', p%local_damping, '0..1', min_value=0.0_wp, &
        max_value=1.0_wp)
      call check_choice(err, 'mpm', 'rigid_contact', p%rigid_contact, rigid_contact_names)
      call check_real(err, 'mpm', 'contact_friction', p%contact_friction, '>= 0', &
        min_value=0.0_wp)
    end associate
    associate (p => cfg%coupling)
      call check_choice(err, 'coupling', 'drag_scheme', p%drag_scheme, drag_scheme_names)
      call check_real(err, 'coupling', 'heat_exchange_coefficient', &
        p%heat_exchange_coefficient, '>= 0 [W/m^3/K]', min_value=0.0_wp)
      call check_real(err, 'coupling', 'max_solid_fraction', p%max_solid_fraction, &
        '0 < max_solid_fraction <= 1', min_value=0.0_wp, max_value=1.0_wp, min_open=.true.)
      call check_real(err, 'coupling', 'solid_fraction_relaxation', &
        p%solid_fraction_relaxation, '0 <= solid_fraction_relaxation <= 1', min_value=0.0_wp, &
        max_value=1.0_wp)
    end associate
  end subroutine check_singletons

  !> `name` of occurrence `k` of `group` ('fluid' or 'solid'): an identifier, unique among the
  !! names of all fluids and solids.
  subroutine check_material_name(cfg, group, k, name, err)
    type(config_t), intent(in) :: cfg           !< configuration
    character(len=*), intent(in) :: group       !< 'fluid' or 'solid'
    integer, intent(in) :: k                    !< occurrence
    character(len=*), intent(in) :: name        !< its name
    type(config_error_t), intent(inout) :: err  !< problem record
    character(len=*), parameter :: letters = 'abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ'
    character(len=*), parameter :: name_chars = letters // '0123456789_'
    integer :: j
    if (err%found) return
    if (len_trim(name) == 0) then
      call set_error(err, occurrence_label(group, k), 'name', quoted(name), &
        'required: a unique name (letter first, then letters, digits, ''_'')')
      return
    end if
    if (verify(name(1:1), letters) > 0 .or. verify(trim(name), name_chars) > 0) then
      call set_error(err, occurrence_label(group, k), 'name', quoted(name), &
        'an identifier: letter first, then letters, digits, ''_''')
      return
    end if
    do j = 1, cfg%nfluids
      if (group == 'fluid' .and. j >= k) exit
      if (cfg%fluids(j)%name == name) then
        call set_error(err, occurrence_label(group, k), 'name', quoted(name), &
          'unique among &fluid and &solid names (already used by ' // &
          '&' // occurrence_label('fluid', j) // ')')
        return
      end if
    end do
    if (group == 'fluid') return
    do j = 1, k - 1
      if (cfg%solids(j)%name == name) then
        call set_error(err, occurrence_label(group, k), 'name', quoted(name), &
          'unique among &fluid and &solid names (already used by ' // &
          '&' // occurrence_label('solid', j) // ')')
        return
      end if
    end do
  end subroutine check_material_name

  !> `&fluid(k)`.
  subroutine check_fluid(cfg, k, err)
    type(config_t), intent(in) :: cfg           !< configuration
    integer, intent(in) :: k                    !< occurrence
    type(config_error_t), intent(inout) :: err  !< problem record
    character(len=:), allocatable :: g
    if (err%found) return
    g = occurrence_label('fluid', k)
    associate (p => cfg%fluids(k))
      call check_material_name(cfg, 'fluid', k, p%name, err)
      call check_choice(err, g, 'eos', p%eos, eos_names)
      call check_real(err, g, 'gamma', p%gamma, '> 1', min_value=1.0_wp, min_open=.true.)
      call positive(g, 'heat_capacity_cv', p%heat_capacity_cv, ' [J/kg/K]')
      call positive(g, 'reference_density', p%reference_density, ' [kg/m^3]')
      call positive(g, 'reference_pressure', p%reference_pressure, ' [Pa]')
      call positive(g, 'reference_temperature', p%reference_temperature, ' [K]')
      call positive(g, 'bulk_modulus', p%bulk_modulus, ' [Pa]')
      call non_negative(err, g, 'thermal_expansion', p%thermal_expansion, ' [kg/m^3/K]')
      call non_negative(err, g, 'stiffened_pressure', p%stiffened_pressure, ' [Pa]')
      call non_negative(err, g, 'viscosity', p%viscosity, ' [Pa s]')
      call non_negative(err, g, 'conductivity', p%conductivity, ' [W/m/K]')
      call check_real(err, g, 'volume_fraction', p%volume_fraction, '0..1', min_value=0.0_wp, &
        max_value=1.0_wp)
      call check_finite(err, g, 'velocity', p%velocity, ' [m/s]')
      call positive(g, 'temperature', p%temperature, ' [K]')
      call positive(g, 'pressure', p%pressure, ' [Pa]')
    end associate

  contains

    subroutine positive(group, variable, x, unit)
      character(len=*), intent(in) :: group, variable, unit
      real(wp), intent(in) :: x
      call check_real(err, group, variable, x, '> 0' // unit, min_value=0.0_wp, min_open=.true.)
    end subroutine positive
  end subroutine check_fluid

  !> A real >= 0.
  subroutine non_negative(err, group, variable, x, unit)
    type(config_error_t), intent(inout) :: err  !< problem record
    character(len=*), intent(in) :: group       !< group label
    character(len=*), intent(in) :: variable    !< variable name
    real(wp), intent(in) :: x                   !< value
    character(len=*), intent(in) :: unit        !< unit text
    call check_real(err, group, variable, x, '>= 0' // unit, min_value=0.0_wp)
  end subroutine non_negative

  !> A real > 0.
  subroutine positive_real(err, group, variable, x, unit)
    type(config_error_t), intent(inout) :: err  !< problem record
    character(len=*), intent(in) :: group       !< group label
    character(len=*), intent(in) :: variable    !< variable name
    real(wp), intent(in) :: x                   !< value
    character(len=*), intent(in) :: unit        !< unit text
    call check_real(err, group, variable, x, '> 0' // unit, min_value=0.0_wp, min_open=.true.)
  end subroutine positive_real

  !> `&solid(k)`: material, then geometry and particles, then state and rigid motion.
  subroutine check_solid(cfg, k, err)
    type(config_t), intent(in) :: cfg           !< configuration
    integer, intent(in) :: k                    !< occurrence
    type(config_error_t), intent(inout) :: err  !< problem record
    character(len=:), allocatable :: g
    real(wp) :: limit
    if (err%found) return
    g = occurrence_label('solid', k)
    associate (p => cfg%solids(k))
      call check_material_name(cfg, 'solid', k, p%name, err)
      call check_choice(err, g, 'model', p%model, solid_model_names)
      call positive_real(err, g, 'density', p%density, ' [kg/m^3]')
      call positive_real(err, g, 'youngs_modulus', p%youngs_modulus, ' [Pa]')
      call check_real(err, g, 'poisson_ratio', p%poisson_ratio, '-1 < nu < 0.5', &
        min_value=-1.0_wp, max_value=0.5_wp, min_open=.true., max_open=.true.)
      call non_negative(err, g, 'cohesion', p%cohesion, ' [Pa]')
      call check_real(err, g, 'friction_angle', p%friction_angle, '0..89 [deg]', &
        min_value=0.0_wp, max_value=89.0_wp)
      if (err%found) return
      call check_real(err, g, 'dilation_angle', p%dilation_angle, '-friction_angle..' // &
        'friction_angle (' // real_repr(p%friction_angle) // ') [deg]', &
        min_value=-p%friction_angle, max_value=p%friction_angle)
      call non_negative(err, g, 'tensile_strength', p%tensile_strength, ' [Pa]')
      if (err%found) return
      if (p%friction_angle > 0.0_wp) then
        limit = p%cohesion / tan(p%friction_angle * pi / 180.0_wp)
        call check_real(err, g, 'tensile_strength', p%tensile_strength, &
          '<= cohesion / tan(friction_angle) (' // real_repr(limit) // ') [Pa]', &
          max_value=limit)
      end if
      if (.not. err%found .and. p%k0 /= -1.0_wp) then
        call check_real(err, g, 'k0', p%k0, '-1 (use nu/(1-nu)) or 0..5', min_value=0.0_wp, &
          max_value=5.0_wp)
      end if
      call check_geometry(cfg, k, g, err)
      call check_finite(err, g, 'velocity', p%velocity, ' [m/s]')
      call check_finite(err, g, 'velocity_wavenumber', p%velocity_wavenumber, ' [rad/m]')
      call positive_real(err, g, 'temperature', p%temperature, ' [K]')
      call positive_real(err, g, 'heat_capacity', p%heat_capacity, ' [J/kg/K]')
      call non_negative(err, g, 'conductivity', p%conductivity, ' [W/m/K]')
      call check_real(err, g, 'porosity', p%porosity, '0 <= n < 1', min_value=0.0_wp, &
        max_value=1.0_wp, max_open=.true.)
      if (.not. err%found .and. p%max_porosity /= 1.0_wp) then
        if (trim(p%model) /= 'mohr_coulomb' .and. trim(p%model) /= 'critical_state_sand') then
          call check_real(err, g, 'max_porosity', p%max_porosity, &
            '1 (only a mohr_coulomb solid or a critical_state_sand solid loses its grain ' // &
            'contacts)', min_value=1.0_wp, &
            max_value=1.0_wp)
        else
          call check_real(err, g, 'max_porosity', p%max_porosity, 'porosity (' // &
            real_repr(p%porosity) // ') < value <= 1', min_value=p%porosity, &
            max_value=1.0_wp, min_open=.true.)
        end if
      end if
      call check_min_porosity(p, g, err)
      call positive_real(err, g, 'grain_size', p%grain_size, ' [m]')
      call check_finite(err, g, 'prescribed_velocity', p%prescribed_velocity, ' [m/s]')
      call check_finite(err, g, 'acceleration_amplitude', p%acceleration_amplitude, ' [m/s^2]')
      call non_negative(err, g, 'acceleration_frequency', p%acceleration_frequency, ' [Hz]')
      call non_negative(err, g, 'acceleration_duration', p%acceleration_duration, &
        ' [s] (0: no end)')
      call check_choice(err, g, 'drag_law', p%drag_law, drag_law_names)
      call non_negative(err, g, 'drag_coefficient', p%drag_coefficient, ' [kg/m^3/s]')
      call non_negative(err, g, 'forchheimer_a', p%forchheimer_a, ' [-] (Ergun: 150)')
      call non_negative(err, g, 'forchheimer_b', p%forchheimer_b, ' [-] (Ergun: 1.75)')
      call check_real(err, g, 'grain_bulk_modulus', p%grain_bulk_modulus, &
        '>= 0 [Pa] (0: incompressible grains)', min_value=0.0_wp)
      call check_traction(p, g, err)
      call check_soil(p, g, err)
    end associate
  end subroutine check_solid

  !> The surface load of a solid: finite values, a box with upper > lower along every axis
  !! where the traction is non-zero, a ramp time >= 0.
  subroutine check_traction(p, g, err)
    type(solid_params_t), intent(in) :: p       !< solid
    character(len=*), intent(in) :: g           !< group label
    type(config_error_t), intent(inout) :: err  !< problem record
    call check_finite(err, g, 'traction', p%traction, ' [Pa]')
    call check_finite(err, g, 'traction_lower', p%traction_lower, ' [m]')
    call check_finite(err, g, 'traction_upper', p%traction_upper, ' [m]')
    if (err%found) return
    if (any(p%traction /= 0.0_wp .and. p%traction_upper <= p%traction_lower)) then
      call set_error(err, g, 'traction_upper', reals_repr(p%traction_upper), &
        'each entry > traction_lower (' // reals_repr(p%traction_lower) // &
        ') along the axes where traction (' // reals_repr(p%traction) // ') is non-zero [m]')
      return
    end if
    call non_negative(err, g, 'traction_ramp_time', p%traction_ramp_time, &
      ' [s] (0: applied at t = 0)')
  end subroutine check_traction

  !> Shape, geometry and particles of `&solid(k)`.
  subroutine check_geometry(cfg, k, g, err)
    type(config_t), intent(in) :: cfg           !< configuration
    integer, intent(in) :: k                    !< occurrence
    character(len=*), intent(in) :: g           !< group label
    type(config_error_t), intent(inout) :: err  !< problem record
    logical :: active(3)
    integer :: n
    real(wp) :: area
    if (err%found) return
    active = cfg%grid%ncells > 1
    associate (p => cfg%solids(k))
      call check_choice(err, g, 'shape', p%shape, solid_shape_names)
      if (err%found) return
      select case (p%shape)
      case ('box')
        call check_finite(err, g, 'lower', p%lower, ' [m]')
        call check_finite(err, g, 'upper', p%upper, ' [m]')
        if (.not. err%found .and. any(active .and. p%upper <= p%lower)) then
          call set_error(err, g, 'upper', reals_repr(p%upper), 'each entry > lower (' // &
            reals_repr(p%lower) // ') along active dimensions [m]')
        end if
      case ('polygon')
        if (len_trim(p%polygon_file) > 0) return  ! vertices from the file: config_geometry_files
        call check_int(err, g, 'npoints', p%npoints, '3..' // ints_repr([max_polygon_points]) &
          // ' for shape = ''polygon''', min_value=3, max_value=max_polygon_points)
        if (err%found) return
        n = p%npoints
        call check_finite(err, g, 'polygon_x', p%polygon_x(1:n), ' [m]')
        call check_finite(err, g, 'polygon_y', p%polygon_y(1:n), ' [m]')
        if (err%found) return
        area = 0.5_wp * sum(p%polygon_x(1:n) * cshift(p%polygon_y(1:n), 1) &
          - cshift(p%polygon_x(1:n), 1) * p%polygon_y(1:n))
        if (.not. (abs(area) > 0.0_wp)) then
          call set_error(err, g, 'polygon_y', reals_repr(p%polygon_y(1:n)), &
            'vertices (polygon_x, polygon_y)(1:npoints) enclosing a non-zero area [m]')
        end if
      case ('half_space')
        call check_finite(err, g, 'plane_point', p%plane_point, ' [m]')
        call check_finite(err, g, 'plane_normal', p%plane_normal, '')
        if (.not. err%found .and. all(p%plane_normal == 0.0_wp)) then
          call set_error(err, g, 'plane_normal', reals_repr(p%plane_normal), 'a non-zero vector')
        end if
      case default
        ! unreachable: check_choice accepted the shape
      end select
      if (p%shape == 'box') then
        call check_real(err, g, 'rotation_deg', p%rotation_deg, 'finite [deg]')
      else
        call check_real(err, g, 'rotation_deg', p%rotation_deg, &
          '0 unless shape = ''box'' [deg]', min_value=0.0_wp, max_value=0.0_wp)
      end if
      if (.not. err%found .and. any(active .and. p%particles_per_cell < 1)) then
        call set_error(err, g, 'particles_per_cell', ints_repr(p%particles_per_cell), &
          'each entry >= 1 along active dimensions (inactive: ignored, 1 is used)')
      end if
    end associate
  end subroutine check_geometry

  !> `&region(k)`.
  subroutine check_region(cfg, k, err)
    type(config_t), intent(in) :: cfg           !< configuration
    integer, intent(in) :: k                    !< occurrence
    type(config_error_t), intent(inout) :: err  !< problem record
    character(len=:), allocatable :: g
    if (err%found) return
    g = occurrence_label('region', k)
    associate (p => cfg%regions(k))
      if (.not. (any(cfg%fluids(1:cfg%nfluids)%name == p%material) .or. &
        any(cfg%solids(1:cfg%nsolids)%name == p%material)) .or. len_trim(p%material) == 0) then
        call set_error(err, g, 'material', quoted(p%material), 'the name of a &fluid or ' // &
          '&solid (' // material_list(cfg) // ')')
        return
      end if
      call check_finite(err, g, 'lower', p%lower, ' [m]')
      call check_finite(err, g, 'upper', p%upper, ' [m]')
      if (.not. err%found .and. any(p%upper < p%lower)) then
        call set_error(err, g, 'upper', reals_repr(p%upper), 'each entry >= lower (' // &
          reals_repr(p%lower) // ') [m]')
      end if
      call check_real(err, g, 'volume_fraction', p%volume_fraction, '0..1', min_value=0.0_wp, &
        max_value=1.0_wp)
      call check_finite(err, g, 'velocity', p%velocity, ' [m/s]')
      call positive_real(err, g, 'temperature', p%temperature, ' [K]')
      call positive_real(err, g, 'pressure', p%pressure, ' [Pa]')
    end associate
  end subroutine check_region

  !> Names of all fluids and solids, quoted, or `none defined`.
  function material_list(cfg, fluids_only) result(text)
    type(config_t), intent(in) :: cfg  !< configuration
    logical, intent(in), optional :: fluids_only !< list the `&fluid` names alone
    character(len=:), allocatable :: text
    integer :: j, nsolids
    text = ''
    do j = 1, cfg%nfluids
      if (len(text) > 0) text = text // ', '
      text = text // quoted(cfg%fluids(j)%name)
    end do
    nsolids = cfg%nsolids
    if (present(fluids_only)) then
      if (fluids_only) nsolids = 0
    end if
    do j = 1, nsolids
      if (len(text) > 0) text = text // ', '
      text = text // quoted(cfg%solids(j)%name)
    end do
    if (len(text) == 0) text = 'none defined'
  end function material_list

  !> `&boundary(k)`: a known face of an active, non-periodic dimension, given once.
  subroutine check_boundary(cfg, k, err)
    type(config_t), intent(in) :: cfg           !< configuration
    integer, intent(in) :: k                    !< occurrence
    type(config_error_t), intent(inout) :: err  !< problem record
    character(len=:), allocatable :: g
    integer :: f, d, j
    if (err%found) return
    g = occurrence_label('boundary', k)
    associate (p => cfg%boundaries(k))
      if (len_trim(p%face) == 0) then
        call set_error(err, g, 'face', quoted(p%face), 'required: one of ' // &
          join_names(face_names, ', ', ''))
        return
      end if
      call check_choice(err, g, 'face', p%face, face_names)
      if (err%found) return
      f = findloc(face_names, p%face(1:2), dim=1)
      d = (f + 1) / 2
      do j = 1, k - 1
        if (cfg%boundaries(j)%face == p%face) then
          call set_error(err, g, 'face', quoted(p%face), 'at most one &boundary per face ' // &
            '(already given by &' // occurrence_label('boundary', j) // ')')
          return
        end if
      end do
      if (cfg%grid%ncells(d) == 1) then
        call set_error(err, g, 'face', quoted(p%face), 'a face of an active dimension ' // &
          '(&grid ncells = ' // ints_repr(cfg%grid%ncells) // ')')
        return
      end if
      if (cfg%grid%periodic(d)) then
        call set_error(err, g, 'face', quoted(p%face), 'a face of a non-periodic dimension ' // &
          '(&grid periodic = ' // periodic_text(cfg%grid%periodic) // ')')
        return
      end if
      call check_choice(err, g, 'fluid', p%fluid, boundary_fluid_names)
      call positive_real(err, g, 'pressure', p%pressure, ' [Pa]')
      call check_finite(err, g, 'velocity', p%velocity, ' [m/s]')
      call check_inflow_fluid(cfg, p, g, err)
      call check_choice(err, g, 'thermal', p%thermal, boundary_thermal_names)
      call positive_real(err, g, 'temperature', p%temperature, ' [K]')
      call check_choice(err, g, 'solid', p%solid, boundary_solid_names)
      call check_finite(err, g, 'solid_velocity', p%solid_velocity, ' [m/s]')
      call check_finite(err, g, 'solid_traction', p%solid_traction, ' [Pa]')
      call check_velocity_history(p, g, err)
    end associate
  end subroutine check_boundary

  !> `min_porosity` of one `&solid` (label `g`): 0 (off), or for a contractant Mohr-Coulomb
  !! solid (dilation_angle < 0, which then needs it) 0 < value < porosity.
  subroutine check_min_porosity(p, g, err)
    type(solid_params_t), intent(in) :: p       !< the group
    character(len=*), intent(in) :: g           !< group label
    type(config_error_t), intent(inout) :: err  !< problem record
    if (err%found) return
    if (trim(p%model) == 'mohr_coulomb' .and. p%dilation_angle < 0.0_wp) then
      call check_real(err, g, 'min_porosity', p%min_porosity, '0 < value < porosity (' // &
        real_repr(p%porosity) // '): a contractant sand (dilation_angle < 0) needs its ' // &
        'densest packing', min_value=0.0_wp, max_value=p%porosity, min_open=.true., &
        max_open=.true.)
    else if (p%min_porosity /= 0.0_wp) then
      call check_real(err, g, 'min_porosity', p%min_porosity, '0 (only a mohr_coulomb ' // &
        'solid with dilation_angle < 0 compacts plastically)', min_value=0.0_wp, &
        max_value=0.0_wp)
    end if
  end subroutine check_min_porosity

  !> `inflow_fluid` of one `&boundary` (label `g`): empty, or the name of a `&fluid` on a face
  !! that fluid can enter (fluid = 'pressure', 'inflow' or 'outflow').
  subroutine check_inflow_fluid(cfg, p, g, err)
    type(config_t), intent(in) :: cfg           !< configuration
    type(boundary_params_t), intent(in) :: p    !< the group
    character(len=*), intent(in) :: g           !< group label
    type(config_error_t), intent(inout) :: err  !< problem record
    if (err%found .or. len_trim(p%inflow_fluid) == 0) return
    if (.not. any(cfg%fluids(1:cfg%nfluids)%name == p%inflow_fluid)) then
      call set_error(err, g, 'inflow_fluid', quoted(p%inflow_fluid), '''''' // &
        ' or the name of a &fluid (' // material_list(cfg, fluids_only=.true.) // ')')
    else if (p%fluid /= 'pressure' .and. p%fluid /= 'inflow' .and. p%fluid /= 'outflow') then
      call set_error(err, g, 'inflow_fluid', quoted(p%inflow_fluid), '''''' // &
        ' on a face with fluid = ''' // trim(p%fluid) // ''' (a name only with fluid = ' // &
        '''pressure'', ''inflow'' or ''outflow'')')
    end if
  end subroutine check_inflow_fluid

  !> `solid_velocity_times` / `solid_velocity_history` of one `&boundary` (label `g`): the
  !! times consecutive from entry 1 (the rest unset), finite and strictly increasing; one
  !! finite velocity column per time and none beyond; a table only with solid = 'velocity' and
  !! `solid_velocity` left at 0.
  subroutine check_velocity_history(p, g, err)
    type(boundary_params_t), intent(in) :: p    !< the group
    character(len=*), intent(in) :: g           !< group label
    type(config_error_t), intent(inout) :: err  !< problem record
    integer :: n, m, j
    character(len=:), allocatable :: count_text
    if (err%found) return
    n = history_points_used(p%solid_velocity_times)
    count_text = ints_repr([n])
    if (any(p%solid_velocity_times(n + 1:) /= history_unset)) then
      call set_error(err, g, 'solid_velocity_times', reals_repr(pack(p%solid_velocity_times, &
        p%solid_velocity_times /= history_unset)), 'consecutive entries from ' // &
        'solid_velocity_times(1), at most ' // ints_repr([max_history_points]) // ' [s]')
      return
    end if
    call check_finite(err, g, 'solid_velocity_times', p%solid_velocity_times(1:n), ' [s]')
    if (err%found) return
    if (n > 1) then
      if (any(p%solid_velocity_times(2:n) <= p%solid_velocity_times(1:n - 1))) then
        call set_error(err, g, 'solid_velocity_times', reals_repr(p%solid_velocity_times(1:n)), &
          'strictly increasing times [s]')
        return
      end if
    end if
    m = 0
    do j = 1, max_history_points
      if (any(p%solid_velocity_history(:, j) /= history_unset)) m = j
    end do
    if (m /= n .or. any(p%solid_velocity_history(:, 1:n) == history_unset)) then
      call set_error(err, g, 'solid_velocity_history', reals_repr(pack(p%solid_velocity_history, &
        p%solid_velocity_history /= history_unset)), '3 components for each of the ' // &
        count_text // ' solid_velocity_times, as (:, 1:' // count_text // ') [m/s]')
      return
    end if
    call check_finite(err, g, 'solid_velocity_history', &
      reshape(p%solid_velocity_history(:, 1:n), [3 * n]), ' [m/s]')
    if (err%found .or. n == 0) return
    if (trim(p%solid) /= 'velocity') then
      call set_error(err, g, 'solid_velocity_times', reals_repr(p%solid_velocity_times(1:n)), &
        'a velocity history only with solid = ''velocity'' (here ' // quoted(p%solid) // ')')
    else if (any(p%solid_velocity /= 0.0_wp)) then
      call set_error(err, g, 'solid_velocity', reals_repr(p%solid_velocity), '0, 0, 0 ' // &
        'when solid_velocity_times is given (the history prescribes the velocity) [m/s]')
    end if
  end subroutine check_velocity_history

  !> `&grid periodic` as namelist text.
  pure function periodic_text(periodic) result(text)
    logical, intent(in) :: periodic(3)  !< periodic flags
    character(len=:), allocatable :: text
    integer :: d
    text = ''
    do d = 1, 3
      if (d > 1) text = text // ', '
      text = text // trim(merge('.true. ', '.false.', periodic(d)))
    end do
  end function periodic_text

  !> The groups a scene needs: 'ice' at least one `&fluid` and no `&solid`, 'mpm' at least one
  !! `&solid` and no `&fluid`, 'mpmice' at least one of each. The range checks of `&solid` and
  !! `&fluid` apply in every scene (so 'mpmice' gets those of 'ice' and 'mpm'); in particular
  !! `grain_size` > 0, which the drag laws 'kozeny_carman' and 'beetstra' need, and
  !! 0 <= `porosity` < 1 are checked for every solid, rigid ones included.
  subroutine check_scene(cfg, err)
    type(config_t), intent(in) :: cfg           !< configuration
    type(config_error_t), intent(inout) :: err  !< problem record
    character(len=:), allocatable :: counts
    if (err%found) return
    counts = ' (the input has ' // ints_repr([cfg%nfluids]) // ' &fluid, ' // &
      ints_repr([cfg%nsolids]) // ' &solid)'
    select case (cfg%run%scene)
    case ('ice')
      if (cfg%nfluids < 1 .or. cfg%nsolids > 0) then
        call set_error(err, 'run', 'scene', quoted(cfg%run%scene), 'scene ''ice'' needs ' // &
          'at least one &fluid group and no &solid group' // counts)
      end if
    case ('mpm')
      if (cfg%nsolids < 1 .or. cfg%nfluids > 0) then
        call set_error(err, 'run', 'scene', quoted(cfg%run%scene), 'scene ''mpm'' needs ' // &
          'at least one &solid group and no &fluid group' // counts)
      end if
    case ('mpmice')
      if (cfg%nfluids < 1 .or. cfg%nsolids < 1) then
        call set_error(err, 'run', 'scene', quoted(cfg%run%scene), 'scene ''mpmice'' needs ' &
          // 'at least one &fluid group and at least one &solid group' // counts)
      end if
    case default
      ! other scenes take no &fluid or &solid groups into account
    end select
  end subroutine check_scene
end module config_validate_phases
