!> The resolved configuration as namelist text: printed by `--check`, written to
!! `<output_dir>/<name>.used.nml` and stored in checkpoints.
!!
!! Every variable of every group is written, defaults included, with reals in the shortest form
!! that reads back bitwise identical, so reading the text with `config_load_text` reproduces the
!! configuration exactly. The text has one `variable = value` per line and no comments after
!! values (postproc/namelist.py reads it). Repeated groups (`&fluid`, `&solid`, `&region`,
!! `&boundary`) follow the singletons, one group per occurrence in order; reading the text
!! appends them again in the same order. The unused tail of a `&boundary` velocity history is
!! written as one repeat count (`192*-1.7976931348623157e308`).
module config_echo
  use mpmice_kinds, only: wp, msg_len
  use config_types, only: config_t, fluid_params_t, solid_params_t, region_params_t, &
    boundary_params_t, history_unset
  use config_text, only: real_repr, reals_repr, ints_repr, logicals_repr, quoted
  use parallel_domain, only: blocks_given
  use io_write_failure, only: io_check_size, io_remove_file
  implicit none
  private

  public :: config_to_text, config_write_used, config_used_path

  character(len=*), parameter :: nl = achar(10)  !< line end

contains

  !> All groups of `cfg` as namelist text (lines end with a line feed).
  function config_to_text(cfg) result(text)
    type(config_t), intent(in) :: cfg  !< configuration
    character(len=:), allocatable :: text
    integer :: k

    text = '! MPMICE resolved input: every variable, defaults included' // nl
    text = text // '&run' // nl
    call add('name', quoted(cfg%run%name))
    call add('scene', quoted(cfg%run%scene))
    call add('output_dir', quoted(cfg%run%output_dir))
    call add('end_time', real_repr(cfg%run%end_time))
    call add('output_interval', real_repr(cfg%run%output_interval))
    call add('checkpoint_interval', real_repr(cfg%run%checkpoint_interval))
    call add('max_steps', ints_repr([cfg%run%max_steps]))
    call add('wall_time_limit', real_repr(cfg%run%wall_time_limit))
    call add('max_energy_growth', real_repr(cfg%run%max_energy_growth))
    call add('max_particle_loss_fraction', real_repr(cfg%run%max_particle_loss_fraction))
    call add('min_dt_ratio', real_repr(cfg%run%min_dt_ratio))
    call add('progress_interval', real_repr(cfg%run%progress_interval))
    call add('verbosity', ints_repr([cfg%run%verbosity]))
    call add('overwrite', logicals_repr([cfg%run%overwrite]))
    text = text // '/' // nl // '&grid' // nl
    call add('ncells', ints_repr(cfg%grid%ncells))
    call add('lower', reals_repr(cfg%grid%lower))
    call add('upper', reals_repr(cfg%grid%upper))
    call add('periodic', logicals_repr(cfg%grid%periodic))
    call add('ghost_width', ints_repr([cfg%grid%ghost_width]))
    call add('dims', ints_repr(cfg%grid%dims))
    call add('block_cells_x', blocks_repr(cfg%grid%block_cells(:, 1)))
    call add('block_cells_y', blocks_repr(cfg%grid%block_cells(:, 2)))
    call add('block_cells_z', blocks_repr(cfg%grid%block_cells(:, 3)))
    text = text // '/' // nl // '&time' // nl
    call add('cfl', real_repr(cfg%time%cfl))
    call add('dt_init', real_repr(cfg%time%dt_init))
    call add('dt_max', real_repr(cfg%time%dt_max))
    call add('dt_min', real_repr(cfg%time%dt_min))
    call add('dt_growth', real_repr(cfg%time%dt_growth))
    text = text // '/' // nl // '&numerics' // nl
    call add('advection_order', ints_repr([cfg%numerics%advection_order]))
    call add('shape_function', quoted(cfg%numerics%shape_function))
    call add('time_theta', real_repr(cfg%numerics%time_theta))
    text = text // '/' // nl // '&solver' // nl
    call add('tolerance', real_repr(cfg%solver%tolerance))
    call add('max_iterations', ints_repr([cfg%solver%max_iterations]))
    call add('print_level', ints_repr([cfg%solver%print_level]))
    text = text // '/' // nl // '&output' // nl
    call add('xdmf', logicals_repr([cfg%output%xdmf]))
    call add('fields', quoted(cfg%output%fields))
    text = text // '/' // nl // '&heat' // nl
    call add('conductivity', real_repr(cfg%heat%conductivity))
    call add('density', real_repr(cfg%heat%density))
    call add('heat_capacity', real_repr(cfg%heat%heat_capacity))
    call add('base_temperature', real_repr(cfg%heat%base_temperature))
    call add('amplitude', real_repr(cfg%heat%amplitude))
    call add('modes', ints_repr(cfg%heat%modes))
    text = text // '/' // nl // '&physics' // nl
    call add('gravity', reals_repr(cfg%physics%gravity))
    call add('reference_pressure', real_repr(cfg%physics%reference_pressure))
    call add('hydrostatic_init', logicals_repr([cfg%physics%hydrostatic_init]))
    text = text // '/' // nl // '&ice' // nl
    call add('outer_tolerance', real_repr(cfg%ice%outer_tolerance))
    call add('max_outer_iterations', ints_repr([cfg%ice%max_outer_iterations]))
    call add('exchange_coefficient', real_repr(cfg%ice%exchange_coefficient))
    call add('heat_exchange_coefficient', real_repr(cfg%ice%heat_exchange_coefficient))
    call add('smagorinsky', logicals_repr([cfg%ice%smagorinsky]))
    call add('smagorinsky_constant', real_repr(cfg%ice%smagorinsky_constant))
    call add('equilibration_tolerance', real_repr(cfg%ice%equilibration_tolerance))
    call add('max_equilibration_iterations', ints_repr([cfg%ice%max_equilibration_iterations]))
    call add('sound_speed_factor', real_repr(cfg%ice%sound_speed_factor))
    call add('interface_compression', real_repr(cfg%ice%interface_compression))
    text = text // '/' // nl // '&mpm' // nl
    call add('flip_fraction', real_repr(cfg%mpm%flip_fraction))
    call add('gravity_ramp_time', real_repr(cfg%mpm%gravity_ramp_time))
    call add('local_damping', real_repr(cfg%mpm%local_damping))
    call add('rigid_contact', quoted(cfg%mpm%rigid_contact))
    call add('contact_friction', real_repr(cfg%mpm%contact_friction))
    call add('cache_static_rigid', logicals_repr([cfg%mpm%cache_static_rigid]))
    text = text // '/' // nl // '&coupling' // nl
    call add('drag_scheme', quoted(cfg%coupling%drag_scheme))
    call add('heat_exchange_coefficient', real_repr(cfg%coupling%heat_exchange_coefficient))
    call add('max_solid_fraction', real_repr(cfg%coupling%max_solid_fraction))
    call add('solid_fraction_relaxation', real_repr(cfg%coupling%solid_fraction_relaxation))
    text = text // '/' // nl
    do k = 1, cfg%nfluids
      call add_fluid(cfg%fluids(k))
    end do
    do k = 1, cfg%nsolids
      call add_solid(cfg%solids(k))
    end do
    do k = 1, cfg%nregions
      call add_region(cfg%regions(k))
    end do
    do k = 1, cfg%nboundaries
      call add_boundary(cfg%boundaries(k))
    end do

  contains

    subroutine add(name, value)
      character(len=*), intent(in) :: name
      character(len=*), intent(in) :: value
      text = text // '  ' // name // ' = ' // value // nl
    end subroutine add

    !> A table: its entries in use, or a comment saying that none is set (reading the echo
    !! back leaves the table unset either way).
    subroutine add_table(name, value)
      character(len=*), intent(in) :: name
      character(len=*), intent(in) :: value
      if (len(value) > 0) then
        call add(name, value)
      else
        text = text // '  ! ' // name // ' = unset' // nl
      end if
    end subroutine add_table

    subroutine add_fluid(p)
      type(fluid_params_t), intent(in) :: p
      text = text // '&fluid' // nl
      call add('name', quoted(p%name))
      call add('eos', quoted(p%eos))
      call add('gamma', real_repr(p%gamma))
      call add('heat_capacity_cv', real_repr(p%heat_capacity_cv))
      call add('reference_density', real_repr(p%reference_density))
      call add('reference_pressure', real_repr(p%reference_pressure))
      call add('reference_temperature', real_repr(p%reference_temperature))
      call add('bulk_modulus', real_repr(p%bulk_modulus))
      call add('thermal_expansion', real_repr(p%thermal_expansion))
      call add('stiffened_pressure', real_repr(p%stiffened_pressure))
      call add('viscosity', real_repr(p%viscosity))
      call add('conductivity', real_repr(p%conductivity))
      call add('volume_fraction', real_repr(p%volume_fraction))
      call add('velocity', reals_repr(p%velocity))
      call add('temperature', real_repr(p%temperature))
      call add('pressure', real_repr(p%pressure))
      text = text // '/' // nl
    end subroutine add_fluid

    subroutine add_solid(p)
      type(solid_params_t), intent(in) :: p
      text = text // '&solid' // nl
      call add('name', quoted(p%name))
      call add('model', quoted(p%model))
      call add('density', real_repr(p%density))
      call add('youngs_modulus', real_repr(p%youngs_modulus))
      call add('poisson_ratio', real_repr(p%poisson_ratio))
      call add('cohesion', real_repr(p%cohesion))
      call add('friction_angle', real_repr(p%friction_angle))
      call add('dilation_angle', real_repr(p%dilation_angle))
      call add('tension_cutoff', logicals_repr([p%tension_cutoff]))
      call add('tensile_strength', real_repr(p%tensile_strength))
      call add('k0', real_repr(p%k0))
      call add('geostatic', logicals_repr([p%geostatic]))
      call add('shape', quoted(p%shape))
      call add('lower', reals_repr(p%lower))
      call add('upper', reals_repr(p%upper))
      call add('npoints', ints_repr([p%npoints]))
      call add('polygon_x', reals_repr(p%polygon_x))
      call add('polygon_y', reals_repr(p%polygon_y))
      call add('plane_point', reals_repr(p%plane_point))
      call add('plane_normal', reals_repr(p%plane_normal))
      call add('rotation_deg', real_repr(p%rotation_deg))
      call add('particles_per_cell', ints_repr(p%particles_per_cell))
      call add('velocity', reals_repr(p%velocity))
      call add('temperature', real_repr(p%temperature))
      call add('heat_capacity', real_repr(p%heat_capacity))
      call add('conductivity', real_repr(p%conductivity))
      call add('porosity', real_repr(p%porosity))
      call add('max_porosity', real_repr(p%max_porosity))
      call add('min_porosity', real_repr(p%min_porosity))
      call add('grain_size', real_repr(p%grain_size))
      call add('prescribed_velocity', reals_repr(p%prescribed_velocity))
      call add('acceleration_amplitude', reals_repr(p%acceleration_amplitude))
      call add('acceleration_frequency', real_repr(p%acceleration_frequency))
      call add('acceleration_duration', real_repr(p%acceleration_duration))
      call add('velocity_wavenumber', reals_repr(p%velocity_wavenumber))
      call add('drag_law', quoted(p%drag_law))
      call add('drag_coefficient', real_repr(p%drag_coefficient))
      call add('forchheimer_a', real_repr(p%forchheimer_a))
      call add('forchheimer_b', real_repr(p%forchheimer_b))
      call add('grain_bulk_modulus', real_repr(p%grain_bulk_modulus))
      call add('traction', reals_repr(p%traction))
      call add('traction_lower', reals_repr(p%traction_lower))
      call add('traction_upper', reals_repr(p%traction_upper))
      call add('traction_ramp_time', real_repr(p%traction_ramp_time))
      call add('critical_state_ratio', real_repr(p%critical_state_ratio))
      call add('compression_index', real_repr(p%compression_index))
      call add('swelling_index', real_repr(p%swelling_index))
      call add('preconsolidation_pressure', real_repr(p%preconsolidation_pressure))
      call add('ocr', real_repr(p%ocr))
      call add('shear_modulus', real_repr(p%shear_modulus))
      call add('min_pressure', real_repr(p%min_pressure))
      call add('friction_mu1', real_repr(p%friction_mu1))
      call add('friction_mu2', real_repr(p%friction_mu2))
      call add('viscous_j0', real_repr(p%viscous_j0))
      call add('critical_solid_fraction', real_repr(p%critical_solid_fraction))
      call add('dilatancy_constant', real_repr(p%dilatancy_constant))
      call add('fluid_viscosity', real_repr(p%fluid_viscosity))
      call add('polygon_file', quoted(p%polygon_file))
      call add('profile_file', quoted(p%profile_file))
      call add('profile_lower_file', quoted(p%profile_lower_file))
      call add('layer_thickness', real_repr(p%layer_thickness))
      call add_table('profile_lower_level', table_repr([p%profile_lower_level]))
      text = text // '/' // nl
    end subroutine add_solid

    subroutine add_region(p)
      type(region_params_t), intent(in) :: p
      text = text // '&region' // nl
      call add('material', quoted(p%material))
      call add('lower', reals_repr(p%lower))
      call add('upper', reals_repr(p%upper))
      call add('volume_fraction', real_repr(p%volume_fraction))
      call add('velocity', reals_repr(p%velocity))
      call add('temperature', real_repr(p%temperature))
      call add('pressure', real_repr(p%pressure))
      call add('shape', quoted(p%shape))
      call add('polygon_file', quoted(p%polygon_file))
      call add('profile_file', quoted(p%profile_file))
      call add('profile_lower_file', quoted(p%profile_lower_file))
      call add('layer_thickness', real_repr(p%layer_thickness))
      call add_table('profile_lower_level', table_repr([p%profile_lower_level]))
      text = text // '/' // nl
    end subroutine add_region

    subroutine add_boundary(p)
      type(boundary_params_t), intent(in) :: p
      text = text // '&boundary' // nl
      call add('face', quoted(p%face))
      call add('fluid', quoted(p%fluid))
      call add('pressure', real_repr(p%pressure))
      call add('velocity', reals_repr(p%velocity))
      call add('inflow_fluid', quoted(p%inflow_fluid))
      call add('thermal', quoted(p%thermal))
      call add('temperature', real_repr(p%temperature))
      call add('solid', quoted(p%solid))
      call add('solid_velocity', reals_repr(p%solid_velocity))
      call add('solid_traction', reals_repr(p%solid_traction))
      call add_table('solid_velocity_times', table_repr(p%solid_velocity_times))
      call add_table('solid_velocity_history', table_repr(reshape(p%solid_velocity_history, &
        [size(p%solid_velocity_history)])))
      text = text // '/' // nl
    end subroutine add_boundary
  end function config_to_text

  !> A table with trailing unused entries (`history_unset`): the entries up to the last one in
  !! use (an empty text when none is); the unused tail keeps its default when read back.
  function table_repr(x) result(text)
    real(wp), intent(in) :: x(:)  !< table
    character(len=:), allocatable :: text
    integer :: n
    n = size(x)
    do while (n > 0)
      if (x(n) /= history_unset) exit
      n = n - 1
    end do
    text = ''
    if (n > 0) text = reals_repr(x(1:n))
  end function table_repr

  !> Path of the echo file: `<output_dir>/<name>.used.nml`.
  function config_used_path(cfg) result(path)
    type(config_t), intent(in) :: cfg  !< configuration
    character(len=:), allocatable :: path
    path = trim(cfg%run%output_dir) // '/' // trim(cfg%run%name) // '.used.nml'
  end function config_used_path

  !> Write `config_to_text(cfg)` to `path` (replacing it). Call on one rank; the directory must
  !! exist. Without `stat` a failure is fatal; with it, `stat` /= 0 and `errmsg` say why.
  subroutine config_write_used(cfg, path, stat, errmsg)
    use mpmice_errors, only: fatal
    type(config_t), intent(in) :: cfg                      !< configuration
    character(len=*), intent(in) :: path                   !< file to write
    integer, intent(out), optional :: stat                 !< 0 on success
    character(len=*), intent(out), optional :: errmsg      !< reason on failure
    character(len=msg_len) :: iomsg
    character(len=:), allocatable :: text, reason
    integer :: unit, ios
    text = config_to_text(cfg)
    open(newunit=unit, file=path, status='replace', action='write', access='stream', &
      form='unformatted', iostat=ios, iomsg=iomsg)
    if (ios == 0) then
      write(unit, iostat=ios, iomsg=iomsg) text
      close(unit)
      ! a full disk: gfortran reports nothing, the size on disk tells; no partial file stays
      if (ios == 0) call io_check_size(path, len(text), ios, reason)
      if (ios /= 0) then
        if (allocated(reason)) iomsg = reason
        call io_remove_file(path)
      end if
    end if
    if (present(stat)) stat = ios
    if (present(errmsg)) errmsg = ''
    if (ios /= 0) then
      if (present(errmsg)) errmsg = 'cannot write ' // trim(path) // ': ' // trim(iomsg)
      if (.not. present(stat)) call fatal('cannot write ' // trim(path) // ': ' // trim(iomsg))
    end if
  end subroutine config_write_used

  !> The entries of a `block_cells` column up to its last non-zero one ('0' when all are zero).
  function blocks_repr(cells) result(text)
    integer, intent(in) :: cells(:)  !< cells per block, zero-padded
    character(len=:), allocatable :: text
    integer :: n
    n = blocks_given(cells)
    if (n == 0) then
      text = '0'
    else
      text = ints_repr(cells(1:n))
    end if
  end function blocks_repr
end module config_echo
