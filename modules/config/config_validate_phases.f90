!> Validation of the multiphase groups (`&physics`, `&ice`, `&mpm`, `&coupling`, `&fluid`, `&solid`,
!! `&region`, `&boundary`) and of the scene-dependent group counts.
!!
!! Called by `config_check` after the other groups. Each group is checked against the ranges its
!! namelist list declares (`config_validate_ranges`) after the variable that names an occurrence
!! (`name`, `material`, `face`) and before the checks written here (conditions, other groups).
!! Problems in occurrence k of a repeated group are reported against the group `fluid(k)` (and so
!! on). Where regions and solids lie against the domain, and whether the initial volume fractions
!! sum to one in every cell, is checked by `config_validate_extent` (called last).
module config_validate_phases
  use mpmice_kinds, only: wp, name_len
  use config_types, only: config_t, solid_params_t, face_names, max_polygon_points, &
    boundary_params_t, max_history_points, history_unset, history_points_used
  use config_text, only: real_repr, reals_repr, ints_repr, quoted, join_names
  use config_check_tools, only: config_error_t, set_error, check_real, check_int, check_choice, &
    check_finite, occurrence_label
  use config_validate_ranges, only: check_physics_ranges, check_ice_ranges, check_mpm_ranges, &
    check_coupling_ranges, check_fluid_ranges, check_solid_ranges, check_region_ranges, &
    check_boundary_ranges
  use config_validate_extent, only: check_extents
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
      call check_material_name(cfg, 'fluid', k, cfg%fluids(k)%name, err)
      call check_fluid_ranges(cfg%fluids(k), occurrence_label('fluid', k), err)
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

  !> `&physics`, `&ice`, `&mpm`, `&coupling`.
  subroutine check_singletons(cfg, err)
    type(config_t), intent(in) :: cfg           !< configuration
    type(config_error_t), intent(inout) :: err  !< problem record
    call check_physics_ranges(cfg%physics, 'physics', err)
    call check_ice_ranges(cfg%ice, 'ice', err)
    associate (p => cfg%ice)
      if (.not. err%found .and. p%interface_compression > 0.0_wp .and. cfg%nfluids /= 2) then
        call set_error(err, 'ice', 'interface_compression', real_repr(p%interface_compression), &
        '0 with ' // ints_repr([cfg%nfluids]) // ' &fluid groups (compression acts between ' // &
        'exactly two)')
      end if
    end associate
    call check_mpm_ranges(cfg%mpm, 'mpm', err)
    call check_coupling_ranges(cfg%coupling, 'coupling', err)
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
    character(len=name_len) :: other
    character(len=:), allocatable :: other_label
    integer :: j, position
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
    ! the materials before this one: the fluids in order, then the solids
    position = k
    if (group == 'solid') position = cfg%nfluids + k
    do j = 1, position - 1
      if (j <= cfg%nfluids) then
        other = cfg%fluids(j)%name
        other_label = occurrence_label('fluid', j)
      else
        other = cfg%solids(j - cfg%nfluids)%name
        other_label = occurrence_label('solid', j - cfg%nfluids)
      end if
      if (other == name) then
        call set_error(err, occurrence_label(group, k), 'name', quoted(name), &
          'unique among &fluid and &solid names (already used by &' // other_label // ')')
        return
      end if
    end do
  end subroutine check_material_name

  !> `&solid(k)`: the name, the ranges, then the conditions between its variables: tensile
  !! strength, geometry and particles, packing limits, the loaded box, the porosity the soil
  !! models need.
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
      call check_solid_ranges(p, g, err)
      if (err%found) return
      if (p%friction_angle > 0.0_wp) then
        limit = p%cohesion / tan(p%friction_angle * pi / 180.0_wp)
        call check_real(err, g, 'tensile_strength', p%tensile_strength, &
          '<= cohesion / tan(friction_angle) (' // real_repr(limit) // ') [Pa]', &
          max_value=limit)
      end if
      call check_geometry(cfg, k, g, err)
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
      call check_suspension_option(err, g, 'suspension_cell_bound', p%suspension_cell_bound, &
        p%max_porosity)
      call check_suspension_option(err, g, 'suspension_settling', p%suspension_settling, &
        p%max_porosity)
      call check_zero_unless(err, g, 'compaction_index', p%compaction_index, &
        trim(p%model) == 'critical_state_sand', &
        'only a critical_state_sand solid compacts at low effective stress')
      if (.not. err%found .and. p%tension_gap .and. trim(p%model) /= 'critical_state_sand') then
        call set_error(err, g, 'tension_gap', '.true.', '.false. unless model = ' // &
          "'critical_state_sand' (only its no-tension rule keeps a gap)")
      end if
      call check_min_porosity(p, g, err)
      call check_zero_unless(err, g, 'modulus_exponent', p%modulus_exponent, &
        trim(p%model) == 'mohr_coulomb' .or. trim(p%model) == 'critical_state_sand', &
        'only a mohr_coulomb solid or a critical_state_sand solid has a pressure-dependent modulus')
      if (.not. err%found .and. any(p%traction /= 0.0_wp .and. &
        p%traction_upper <= p%traction_lower)) then
        call set_error(err, g, 'traction_upper', reals_repr(p%traction_upper), &
          'each entry > traction_lower (' // reals_repr(p%traction_lower) // &
          ') along the axes where traction (' // reals_repr(p%traction) // ') is non-zero [m]')
      end if
      select case (trim(p%model))
      case ('cam_clay', 'modified_cam_clay', 'critical_state_sand')
        ! the specific volume 1 / (1 - porosity) and the packing 1 - porosity need a porosity
        call check_real(err, g, 'porosity', p%porosity, '0 < n < 1 for model ' // &
          trim(p%model), min_value=0.0_wp, max_value=1.0_wp, min_open=.true., max_open=.true.)
      case default
        ! the other models take the porosity as it is
      end select
    end associate
  end subroutine check_solid

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
      call check_region_ranges(p, g, err)
      if (err%found) return
      if (any(p%upper < p%lower)) then
        call set_error(err, g, 'upper', reals_repr(p%upper), 'each entry >= lower (' // &
          reals_repr(p%lower) // ') [m]')
      end if
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
      call check_boundary_ranges(p, g, err)
      call check_inflow_fluid(cfg, p, g, err)
      call check_velocity_history(p, g, err)
    end associate
  end subroutine check_boundary

  !> An option of the suspended particles (`name`, `.true.` when `on`) of the `&solid` labelled
  !! `g`: only with a loosest packing (`max_porosity` < 1).
  subroutine check_suspension_option(err, g, name, on, max_porosity)
    type(config_error_t), intent(inout) :: err  !< problem record
    character(len=*), intent(in) :: g           !< group label
    character(len=*), intent(in) :: name        !< the option's variable
    logical, intent(in) :: on                   !< its value
    real(wp), intent(in) :: max_porosity        !< the group's `max_porosity`
    if (err%found .or. .not. on .or. max_porosity < 1.0_wp) return
    call set_error(err, g, name, '.true.', '.false. unless max_porosity < 1 (only a solid ' // &
      'that loses its grain contacts is suspended)')
  end subroutine check_suspension_option

  !> A model's own variable `name` of the `&solid` labelled `g`: 0 unless the group's model uses
  !! it (`applies`); `why` says which model does.
  subroutine check_zero_unless(err, g, name, value, applies, why)
    type(config_error_t), intent(inout) :: err  !< problem record
    character(len=*), intent(in) :: g           !< group label
    character(len=*), intent(in) :: name        !< the variable
    real(wp), intent(in) :: value               !< its value
    logical, intent(in) :: applies              !< the group's model uses it
    character(len=*), intent(in) :: why         !< the model that uses it, for the message
    if (err%found .or. applies .or. value == 0.0_wp) return
    call check_real(err, g, name, value, '0 (' // why // ')', min_value=0.0_wp, max_value=0.0_wp)
  end subroutine check_zero_unless

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
  !! 0 <= `porosity` < 1 are checked for every solid, rigid ones included. In 'mpmice' the
  !! face-plane drag (`&coupling face_drag`) excludes frictional contact of rigid bodies.
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
      ! the face-plane drag splits one solid phase's deposit; with frictional contact of rigid
      ! bodies the faces take each solid's own fraction instead (`solid_face_partner`)
      if (.not. err%found .and. trim(cfg%coupling%face_drag) == 'face_plane' .and. &
        trim(cfg%mpm%rigid_contact) == 'friction' .and. &
        any(cfg%solids(1:cfg%nsolids)%model == 'rigid')) then
        call set_error(err, 'coupling', 'face_drag', quoted(cfg%coupling%face_drag), &
          '''cell'' with &mpm rigid_contact = ''friction'' and a rigid &solid (the face-plane ' &
          // 'drag does not apply to sliding rigid bodies)')
      end if
    case default
      ! other scenes take no &fluid or &solid groups into account
    end select
    ! APIC with the tent functions: the bar of docs/mpm.md "Velocity transfer" crossing cells
    ! gains energy without bound (45 times its own in 10 periods)
    if (.not. err%found .and. cfg%nsolids > 0 .and. trim(cfg%mpm%velocity_transfer) == 'apic' &
      .and. trim(cfg%numerics%shape_function) == 'linear') then
      call set_error(err, 'mpm', 'velocity_transfer', quoted(cfg%mpm%velocity_transfer), &
        '''flip'' with &numerics shape_function = ''linear'' (APIC needs ''gimp'')')
    end if
  end subroutine check_scene
end module config_validate_phases
