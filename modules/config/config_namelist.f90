!> The namelist groups of the configuration: the table of groups and variables, and the reads that
!! apply namelist text to a `config_t`.
!!
!! Each group has one routine that presets its namelist variables from the `config_t` (so absent
!! variables keep their value, defaults included), reads and copies back on success. The table
!! `variables` lists every variable with its type; the parser uses it to reject unknown names and
!! to describe the expected value in error messages. Adding a variable means adding it to its
!! `*_params_t` type, to its group's read routine, to this table and to `config_echo`.
module config_namelist
  use, intrinsic :: ieee_exceptions, only: ieee_get_halting_mode, ieee_set_halting_mode, &
    ieee_get_flag, ieee_set_flag, ieee_overflow, ieee_underflow, ieee_invalid, ieee_flag_type
  use mpmice_kinds, only: wp, name_len, path_len, msg_len
  use config_types, only: config_t, run_params_t, grid_params_t, time_params_t, &
    numerics_params_t, solver_params_t, output_params_t, heat_params_t, max_polygon_points, &
    max_history_points, max_blocks_per_dim
  use config_occurrences, only: is_repeated_group, occurrence_count
  use config_read_phases, only: read_physics, read_ice, read_mpm, read_coupling, read_fluid, &
    read_solid, read_region, read_boundary
  implicit none
  private

  public :: variable_info_t, group_names, variables, find_variable, group_variable_names
  public :: describe_value, namelist_assign

  !> Known singleton groups, in echo order.
  character(len=*), parameter :: group_names(11) = [character(len=8) :: &
    'run', 'grid', 'time', 'numerics', 'solver', 'output', 'heat', 'physics', 'ice', 'mpm', &
    'coupling']

  !> One namelist variable.
  type :: variable_info_t
    character(len=8) :: group = ''    !< group name without `&`
    character(len=32) :: name = ''    !< variable name
    character :: kind = 'r'           !< `i` integer, `r` real, `l` logical, `c` character
    integer :: size = 1               !< number of entries (1 scalar, 3 per-dimension array)
    integer :: length = 0             !< declared length of a character variable
  end type variable_info_t

  !> Every variable of every group.
  type(variable_info_t), parameter :: variables(*) = [ &
    variable_info_t('run', 'name', 'c', 1, name_len), &
    variable_info_t('run', 'scene', 'c', 1, name_len), &
    variable_info_t('run', 'output_dir', 'c', 1, path_len), &
    variable_info_t('run', 'end_time', 'r', 1, 0), &
    variable_info_t('run', 'output_interval', 'r', 1, 0), &
    variable_info_t('run', 'checkpoint_interval', 'r', 1, 0), &
    variable_info_t('run', 'max_steps', 'i', 1, 0), &
    variable_info_t('run', 'wall_time_limit', 'r', 1, 0), &
    variable_info_t('run', 'max_energy_growth', 'r', 1, 0), &
    variable_info_t('run', 'max_particle_loss_fraction', 'r', 1, 0), &
    variable_info_t('run', 'min_dt_ratio', 'r', 1, 0), &
    variable_info_t('run', 'progress_interval', 'r', 1, 0), &
    variable_info_t('run', 'verbosity', 'i', 1, 0), &
    variable_info_t('run', 'overwrite', 'l', 1, 0), &
    variable_info_t('grid', 'ncells', 'i', 3, 0), &
    variable_info_t('grid', 'lower', 'r', 3, 0), &
    variable_info_t('grid', 'upper', 'r', 3, 0), &
    variable_info_t('grid', 'periodic', 'l', 3, 0), &
    variable_info_t('grid', 'ghost_width', 'i', 1, 0), &
    variable_info_t('grid', 'dims', 'i', 3, 0), &
    variable_info_t('grid', 'block_cells_x', 'i', max_blocks_per_dim, 0), &
    variable_info_t('grid', 'block_cells_y', 'i', max_blocks_per_dim, 0), &
    variable_info_t('grid', 'block_cells_z', 'i', max_blocks_per_dim, 0), &
    variable_info_t('time', 'cfl', 'r', 1, 0), &
    variable_info_t('time', 'dt_init', 'r', 1, 0), &
    variable_info_t('time', 'dt_max', 'r', 1, 0), &
    variable_info_t('time', 'dt_min', 'r', 1, 0), &
    variable_info_t('time', 'dt_growth', 'r', 1, 0), &
    variable_info_t('numerics', 'advection_order', 'i', 1, 0), &
    variable_info_t('numerics', 'shape_function', 'c', 1, name_len), &
    variable_info_t('numerics', 'time_theta', 'r', 1, 0), &
    variable_info_t('solver', 'tolerance', 'r', 1, 0), &
    variable_info_t('solver', 'max_iterations', 'i', 1, 0), &
    variable_info_t('solver', 'print_level', 'i', 1, 0), &
    variable_info_t('output', 'xdmf', 'l', 1, 0), &
    variable_info_t('output', 'fields', 'c', 1, path_len), &
    variable_info_t('heat', 'conductivity', 'r', 1, 0), &
    variable_info_t('heat', 'density', 'r', 1, 0), &
    variable_info_t('heat', 'heat_capacity', 'r', 1, 0), &
    variable_info_t('heat', 'base_temperature', 'r', 1, 0), &
    variable_info_t('heat', 'amplitude', 'r', 1, 0), &
    variable_info_t('heat', 'modes', 'i', 3, 0), &
    variable_info_t('physics', 'gravity', 'r', 3, 0), &
    variable_info_t('physics', 'reference_pressure', 'r', 1, 0), &
    variable_info_t('physics', 'hydrostatic_init', 'l', 1, 0), &
    variable_info_t('ice', 'outer_tolerance', 'r', 1, 0), &
    variable_info_t('ice', 'max_outer_iterations', 'i', 1, 0), &
    variable_info_t('ice', 'exchange_coefficient', 'r', 1, 0), &
    variable_info_t('ice', 'heat_exchange_coefficient', 'r', 1, 0), &
    variable_info_t('ice', 'smagorinsky', 'l', 1, 0), &
    variable_info_t('ice', 'smagorinsky_constant', 'r', 1, 0), &
    variable_info_t('ice', 'equilibration_tolerance', 'r', 1, 0), &
    variable_info_t('ice', 'max_equilibration_iterations', 'i', 1, 0), &
    variable_info_t('ice', 'sound_speed_factor', 'r', 1, 0), &
    variable_info_t('ice', 'interface_compression', 'r', 1, 0), &
    variable_info_t('mpm', 'flip_fraction', 'r', 1, 0), &
    variable_info_t('mpm', 'gravity_ramp_time', 'r', 1, 0), &
    variable_info_t('mpm', 'local_damping', 'r', 1, 0), &
    variable_info_t('mpm', 'rigid_contact', 'c', 1, name_len), &
    variable_info_t('mpm', 'contact_friction', 'r', 1, 0), &
    variable_info_t('mpm', 'cache_static_rigid', 'l', 1, 0), &
    variable_info_t('coupling', 'drag_scheme', 'c', 1, name_len), &
    variable_info_t('coupling', 'heat_exchange_coefficient', 'r', 1, 0), &
    variable_info_t('coupling', 'max_solid_fraction', 'r', 1, 0), &
    variable_info_t('coupling', 'solid_fraction_relaxation', 'r', 1, 0), &
    variable_info_t('fluid', 'name', 'c', 1, name_len), &
    variable_info_t('fluid', 'eos', 'c', 1, name_len), &
    variable_info_t('fluid', 'gamma', 'r', 1, 0), &
    variable_info_t('fluid', 'heat_capacity_cv', 'r', 1, 0), &
    variable_info_t('fluid', 'reference_density', 'r', 1, 0), &
    variable_info_t('fluid', 'reference_pressure', 'r', 1, 0), &
    variable_info_t('fluid', 'reference_temperature', 'r', 1, 0), &
    variable_info_t('fluid', 'bulk_modulus', 'r', 1, 0), &
    variable_info_t('fluid', 'thermal_expansion', 'r', 1, 0), &
    variable_info_t('fluid', 'stiffened_pressure', 'r', 1, 0), &
    variable_info_t('fluid', 'viscosity', 'r', 1, 0), &
    variable_info_t('fluid', 'conductivity', 'r', 1, 0), &
    variable_info_t('fluid', 'volume_fraction', 'r', 1, 0), &
    variable_info_t('fluid', 'velocity', 'r', 3, 0), &
    variable_info_t('fluid', 'temperature', 'r', 1, 0), &
    variable_info_t('fluid', 'pressure', 'r', 1, 0), &
    variable_info_t('solid', 'name', 'c', 1, name_len), &
    variable_info_t('solid', 'model', 'c', 1, name_len), &
    variable_info_t('solid', 'density', 'r', 1, 0), &
    variable_info_t('solid', 'youngs_modulus', 'r', 1, 0), &
    variable_info_t('solid', 'poisson_ratio', 'r', 1, 0), &
    variable_info_t('solid', 'cohesion', 'r', 1, 0), &
    variable_info_t('solid', 'friction_angle', 'r', 1, 0), &
    variable_info_t('solid', 'dilation_angle', 'r', 1, 0), &
    variable_info_t('solid', 'tension_cutoff', 'l', 1, 0), &
    variable_info_t('solid', 'tensile_strength', 'r', 1, 0), &
    variable_info_t('solid', 'k0', 'r', 1, 0), &
    variable_info_t('solid', 'geostatic', 'l', 1, 0), &
    variable_info_t('solid', 'shape', 'c', 1, name_len), &
    variable_info_t('solid', 'lower', 'r', 3, 0), &
    variable_info_t('solid', 'upper', 'r', 3, 0), &
    variable_info_t('solid', 'npoints', 'i', 1, 0), &
    variable_info_t('solid', 'polygon_x', 'r', max_polygon_points, 0), &
    variable_info_t('solid', 'polygon_y', 'r', max_polygon_points, 0), &
    variable_info_t('solid', 'plane_point', 'r', 3, 0), &
    variable_info_t('solid', 'plane_normal', 'r', 3, 0), &
    variable_info_t('solid', 'rotation_deg', 'r', 1, 0), &
    variable_info_t('solid', 'particles_per_cell', 'i', 3, 0), &
    variable_info_t('solid', 'velocity', 'r', 3, 0), &
    variable_info_t('solid', 'temperature', 'r', 1, 0), &
    variable_info_t('solid', 'heat_capacity', 'r', 1, 0), &
    variable_info_t('solid', 'conductivity', 'r', 1, 0), &
    variable_info_t('solid', 'porosity', 'r', 1, 0), &
    variable_info_t('solid', 'max_porosity', 'r', 1, 0), &
    variable_info_t('solid', 'min_porosity', 'r', 1, 0), &
    variable_info_t('solid', 'grain_size', 'r', 1, 0), &
    variable_info_t('solid', 'prescribed_velocity', 'r', 3, 0), &
    variable_info_t('solid', 'acceleration_amplitude', 'r', 3, 0), &
    variable_info_t('solid', 'acceleration_frequency', 'r', 1, 0), &
    variable_info_t('solid', 'acceleration_duration', 'r', 1, 0), &
    variable_info_t('solid', 'velocity_wavenumber', 'r', 3, 0), &
    variable_info_t('solid', 'drag_law', 'c', 1, name_len), &
    variable_info_t('solid', 'drag_coefficient', 'r', 1, 0), &
    variable_info_t('solid', 'forchheimer_a', 'r', 1, 0), &
    variable_info_t('solid', 'forchheimer_b', 'r', 1, 0), &
    variable_info_t('solid', 'grain_bulk_modulus', 'r', 1, 0), &
    variable_info_t('solid', 'traction', 'r', 3, 0), &
    variable_info_t('solid', 'traction_lower', 'r', 3, 0), &
    variable_info_t('solid', 'traction_upper', 'r', 3, 0), &
    variable_info_t('solid', 'traction_ramp_time', 'r', 1, 0), &
    variable_info_t('solid', 'critical_state_ratio', 'r', 1, 0), &
    variable_info_t('solid', 'compression_index', 'r', 1, 0), &
    variable_info_t('solid', 'swelling_index', 'r', 1, 0), &
    variable_info_t('solid', 'preconsolidation_pressure', 'r', 1, 0), &
    variable_info_t('solid', 'ocr', 'r', 1, 0), &
    variable_info_t('solid', 'shear_modulus', 'r', 1, 0), &
    variable_info_t('solid', 'min_pressure', 'r', 1, 0), &
    variable_info_t('solid', 'friction_mu1', 'r', 1, 0), &
    variable_info_t('solid', 'friction_mu2', 'r', 1, 0), &
    variable_info_t('solid', 'viscous_j0', 'r', 1, 0), &
    variable_info_t('solid', 'critical_solid_fraction', 'r', 1, 0), &
    variable_info_t('solid', 'dilatancy_constant', 'r', 1, 0), &
    variable_info_t('solid', 'fluid_viscosity', 'r', 1, 0), &
    variable_info_t('solid', 'polygon_file', 'c', 1, path_len), &
    variable_info_t('solid', 'profile_file', 'c', 1, path_len), &
    variable_info_t('solid', 'profile_lower_file', 'c', 1, path_len), &
    variable_info_t('solid', 'layer_thickness', 'r', 1, 0), &
    variable_info_t('solid', 'profile_lower_level', 'r', 1, 0), &
    variable_info_t('region', 'material', 'c', 1, name_len), &
    variable_info_t('region', 'lower', 'r', 3, 0), &
    variable_info_t('region', 'upper', 'r', 3, 0), &
    variable_info_t('region', 'volume_fraction', 'r', 1, 0), &
    variable_info_t('region', 'velocity', 'r', 3, 0), &
    variable_info_t('region', 'temperature', 'r', 1, 0), &
    variable_info_t('region', 'pressure', 'r', 1, 0), &
    variable_info_t('region', 'shape', 'c', 1, name_len), &
    variable_info_t('region', 'polygon_file', 'c', 1, path_len), &
    variable_info_t('region', 'profile_file', 'c', 1, path_len), &
    variable_info_t('region', 'profile_lower_file', 'c', 1, path_len), &
    variable_info_t('region', 'layer_thickness', 'r', 1, 0), &
    variable_info_t('region', 'profile_lower_level', 'r', 1, 0), &
    variable_info_t('boundary', 'face', 'c', 1, name_len), &
    variable_info_t('boundary', 'fluid', 'c', 1, name_len), &
    variable_info_t('boundary', 'pressure', 'r', 1, 0), &
    variable_info_t('boundary', 'velocity', 'r', 3, 0), &
    variable_info_t('boundary', 'inflow_fluid', 'c', 1, name_len), &
    variable_info_t('boundary', 'thermal', 'c', 1, name_len), &
    variable_info_t('boundary', 'temperature', 'r', 1, 0), &
    variable_info_t('boundary', 'solid', 'c', 1, name_len), &
    variable_info_t('boundary', 'solid_velocity', 'r', 3, 0), &
    variable_info_t('boundary', 'solid_traction', 'r', 3, 0), &
    variable_info_t('boundary', 'solid_velocity_times', 'r', max_history_points, 0), &
    variable_info_t('boundary', 'solid_velocity_history', 'r', 3 * max_history_points, 0)]

contains

  !> Index of `name` (lower case, no subscript) of `group` in `variables`, 0 if unknown.
  pure integer function find_variable(group, name)
    character(len=*), intent(in) :: group  !< group name without `&`
    character(len=*), intent(in) :: name   !< variable name
    integer :: i
    find_variable = 0
    if (len_trim(name) == 0) return
    do i = 1, size(variables)
      if (variables(i)%group == group .and. variables(i)%name == name) then
        find_variable = i
        return
      end if
    end do
  end function find_variable

  !> Names of the variables of `group`, comma separated.
  function group_variable_names(group) result(text)
    character(len=*), intent(in) :: group  !< group name without `&`
    character(len=:), allocatable :: text
    integer :: i
    text = ''
    do i = 1, size(variables)
      if (variables(i)%group /= group .or. len_trim(group) == 0) cycle
      if (len(text) > 0) text = text // ', '
      text = text // trim(variables(i)%name)
    end do
  end function group_variable_names

  !> What a value of variable `info` must look like (for error messages).
  function describe_value(info) result(text)
    type(variable_info_t), intent(in) :: info  !< variable
    character(len=:), allocatable :: text
    character(len=16) :: n
    write(n, '(i0)') info%size
    select case (info%kind)
    case ('i')
      text = 'an integer'
      if (info%size > 1) text = 'up to ' // trim(n) // ' integers'
    case ('r')
      text = 'a real number'
      if (info%size > 1) text = 'up to ' // trim(n) // ' real numbers'
    case ('l')
      text = '.true. or .false.'
      if (info%size > 1) text = 'up to ' // trim(n) // ' of .true./.false.'
    case default
      write(n, '(i0)') info%length
      text = 'a quoted string of at most ' // trim(n) // ' characters'
    end select
  end function describe_value

  !> Read namelist text `text` (one complete `&group ... /`) into `cfg`. On failure `cfg` is
  !! unchanged and `ios`/`iomsg` hold the compiler's status and message. Floating-point traps
  !! (debug builds) are off during the read: a value such as `1e400` reads as infinity, which
  !! validation then rejects, instead of stopping the program.
  !! A repeated group updates its occurrence `occurrence` (1..count; required for those groups).
  subroutine namelist_assign(cfg, group, text, ios, iomsg, occurrence)
    type(config_t), intent(inout) :: cfg     !< configuration to update
    character(len=*), intent(in) :: group    !< group name (lower case, no `&`)
    character(len=*), intent(in) :: text     !< namelist text of that group
    integer, intent(out) :: ios              !< 0 on success
    character(len=msg_len), intent(out) :: iomsg !< compiler message on failure
    integer, intent(in), optional :: occurrence  !< element of a repeated group
    type(ieee_flag_type), parameter :: traps(3) = [ieee_overflow, ieee_underflow, ieee_invalid]
    logical :: halting(3), flags(3)
    integer :: k
    k = 0
    if (present(occurrence)) k = occurrence
    call ieee_get_halting_mode(traps, halting)
    call ieee_get_flag(traps, flags)
    call ieee_set_halting_mode(traps, .false.)
    call assign_group(cfg, group, text, k, ios, iomsg)
    call ieee_set_flag(traps, flags)
    call ieee_set_halting_mode(traps, halting)
  end subroutine namelist_assign

  !> `namelist_assign` without the floating-point trap handling.
  subroutine assign_group(cfg, group, text, k, ios, iomsg)
    type(config_t), intent(inout) :: cfg     !< configuration to update
    character(len=*), intent(in) :: group    !< group name (lower case, no `&`)
    character(len=*), intent(in) :: text     !< namelist text of that group
    integer, intent(in) :: k                 !< occurrence of a repeated group
    integer, intent(out) :: ios              !< 0 on success
    character(len=msg_len), intent(out) :: iomsg !< compiler message on failure
    iomsg = ''
    if (is_repeated_group(group)) then
      if (k < 1 .or. k > occurrence_count(cfg, group)) then
        ios = -1
        iomsg = 'no such occurrence of &' // trim(group)
        return
      end if
    end if
    select case (group)
    case ('run')
      call read_run(cfg%run, text, ios, iomsg)
    case ('grid')
      call read_grid(cfg%grid, text, ios, iomsg)
    case ('time')
      call read_time(cfg%time, text, ios, iomsg)
    case ('numerics')
      call read_numerics(cfg%numerics, text, ios, iomsg)
    case ('solver')
      call read_solver(cfg%solver, text, ios, iomsg)
    case ('output')
      call read_output(cfg%output, text, ios, iomsg)
    case ('heat')
      call read_heat(cfg%heat, text, ios, iomsg)
    case ('physics')
      call read_physics(cfg%physics, text, ios, iomsg)
    case ('ice')
      call read_ice(cfg%ice, text, ios, iomsg)
    case ('mpm')
      call read_mpm(cfg%mpm, text, ios, iomsg)
    case ('coupling')
      call read_coupling(cfg%coupling, text, ios, iomsg)
    case ('fluid')
      call read_fluid(cfg%fluids(k), text, ios, iomsg)
    case ('solid')
      call read_solid(cfg%solids(k), text, ios, iomsg)
    case ('region')
      call read_region(cfg%regions(k), text, ios, iomsg)
    case ('boundary')
      call read_boundary(cfg%boundaries(k), text, ios, iomsg)
    case default
      ios = -1
      iomsg = 'unknown namelist group &' // trim(group)
    end select
  end subroutine assign_group

  !> `&run`.
  subroutine read_run(p, text, ios, iomsg)
    type(run_params_t), intent(inout) :: p  !< parameters to update
    character(len=*), intent(in) :: text    !< namelist text
    integer, intent(out) :: ios             !< iostat
    character(len=*), intent(inout) :: iomsg !< iomsg
    character(len=name_len) :: name, scene
    character(len=path_len) :: output_dir
    real(wp) :: end_time, output_interval, checkpoint_interval, wall_time_limit, progress_interval
    real(wp) :: max_energy_growth, max_particle_loss_fraction, min_dt_ratio
    integer :: max_steps, verbosity
    logical :: overwrite
    namelist /run/ name, scene, output_dir, end_time, output_interval, checkpoint_interval, &
      max_steps, wall_time_limit, progress_interval, verbosity, max_energy_growth, &
      max_particle_loss_fraction, min_dt_ratio, overwrite
    name = p%name
    scene = p%scene
    output_dir = p%output_dir
    end_time = p%end_time
    output_interval = p%output_interval
    checkpoint_interval = p%checkpoint_interval
    max_steps = p%max_steps
    wall_time_limit = p%wall_time_limit
    max_energy_growth = p%max_energy_growth
    max_particle_loss_fraction = p%max_particle_loss_fraction
    min_dt_ratio = p%min_dt_ratio
    progress_interval = p%progress_interval
    verbosity = p%verbosity
    overwrite = p%overwrite
    read(text, nml=run, iostat=ios, iomsg=iomsg)
    if (ios /= 0) return
    p%name = name
    p%scene = scene
    p%output_dir = output_dir
    p%end_time = end_time
    p%output_interval = output_interval
    p%checkpoint_interval = checkpoint_interval
    p%max_steps = max_steps
    p%wall_time_limit = wall_time_limit
    p%max_energy_growth = max_energy_growth
    p%max_particle_loss_fraction = max_particle_loss_fraction
    p%min_dt_ratio = min_dt_ratio
    p%progress_interval = progress_interval
    p%verbosity = verbosity
    p%overwrite = overwrite
  end subroutine read_run

  !> `&grid`.
  subroutine read_grid(p, text, ios, iomsg)
    type(grid_params_t), intent(inout) :: p !< parameters to update
    character(len=*), intent(in) :: text    !< namelist text
    integer, intent(out) :: ios             !< iostat
    character(len=*), intent(inout) :: iomsg !< iomsg
    integer :: ncells(3), ghost_width, dims(3)
    integer :: block_cells_x(max_blocks_per_dim), block_cells_y(max_blocks_per_dim), &
      block_cells_z(max_blocks_per_dim)
    real(wp) :: lower(3), upper(3)
    logical :: periodic(3)
    namelist /grid/ ncells, lower, upper, periodic, ghost_width, dims, block_cells_x, &
      block_cells_y, block_cells_z
    ncells = p%ncells
    lower = p%lower
    upper = p%upper
    periodic = p%periodic
    ghost_width = p%ghost_width
    dims = p%dims
    block_cells_x = p%block_cells(:, 1)
    block_cells_y = p%block_cells(:, 2)
    block_cells_z = p%block_cells(:, 3)
    read(text, nml=grid, iostat=ios, iomsg=iomsg)
    if (ios /= 0) return
    p%ncells = ncells
    p%lower = lower
    p%upper = upper
    p%periodic = periodic
    p%ghost_width = ghost_width
    p%dims = dims
    p%block_cells(:, 1) = block_cells_x
    p%block_cells(:, 2) = block_cells_y
    p%block_cells(:, 3) = block_cells_z
  end subroutine read_grid

  !> `&time`.
  subroutine read_time(p, text, ios, iomsg)
    type(time_params_t), intent(inout) :: p !< parameters to update
    character(len=*), intent(in) :: text    !< namelist text
    integer, intent(out) :: ios             !< iostat
    character(len=*), intent(inout) :: iomsg !< iomsg
    real(wp) :: cfl, dt_init, dt_max, dt_min, dt_growth
    namelist /time/ cfl, dt_init, dt_max, dt_min, dt_growth
    cfl = p%cfl
    dt_init = p%dt_init
    dt_max = p%dt_max
    dt_min = p%dt_min
    dt_growth = p%dt_growth
    read(text, nml=time, iostat=ios, iomsg=iomsg)
    if (ios /= 0) return
    p%cfl = cfl
    p%dt_init = dt_init
    p%dt_max = dt_max
    p%dt_min = dt_min
    p%dt_growth = dt_growth
  end subroutine read_time

  !> `&numerics`.
  subroutine read_numerics(p, text, ios, iomsg)
    type(numerics_params_t), intent(inout) :: p !< parameters to update
    character(len=*), intent(in) :: text        !< namelist text
    integer, intent(out) :: ios                 !< iostat
    character(len=*), intent(inout) :: iomsg    !< iomsg
    integer :: advection_order
    character(len=name_len) :: shape_function
    real(wp) :: time_theta
    namelist /numerics/ advection_order, shape_function, time_theta
    advection_order = p%advection_order
    shape_function = p%shape_function
    time_theta = p%time_theta
    read(text, nml=numerics, iostat=ios, iomsg=iomsg)
    if (ios /= 0) return
    p%advection_order = advection_order
    p%shape_function = shape_function
    p%time_theta = time_theta
  end subroutine read_numerics

  !> `&solver`.
  subroutine read_solver(p, text, ios, iomsg)
    type(solver_params_t), intent(inout) :: p !< parameters to update
    character(len=*), intent(in) :: text      !< namelist text
    integer, intent(out) :: ios               !< iostat
    character(len=*), intent(inout) :: iomsg  !< iomsg
    real(wp) :: tolerance
    integer :: max_iterations, print_level
    namelist /solver/ tolerance, max_iterations, print_level
    tolerance = p%tolerance
    max_iterations = p%max_iterations
    print_level = p%print_level
    read(text, nml=solver, iostat=ios, iomsg=iomsg)
    if (ios /= 0) return
    p%tolerance = tolerance
    p%max_iterations = max_iterations
    p%print_level = print_level
  end subroutine read_solver

  !> `&output`.
  subroutine read_output(p, text, ios, iomsg)
    type(output_params_t), intent(inout) :: p !< parameters to update
    character(len=*), intent(in) :: text      !< namelist text
    integer, intent(out) :: ios               !< iostat
    character(len=*), intent(inout) :: iomsg  !< iomsg
    logical :: xdmf
    character(len=path_len) :: fields
    namelist /output/ xdmf, fields
    xdmf = p%xdmf
    fields = p%fields
    read(text, nml=output, iostat=ios, iomsg=iomsg)
    if (ios /= 0) return
    p%xdmf = xdmf
    p%fields = fields
  end subroutine read_output

  !> `&heat`.
  subroutine read_heat(p, text, ios, iomsg)
    type(heat_params_t), intent(inout) :: p !< parameters to update
    character(len=*), intent(in) :: text    !< namelist text
    integer, intent(out) :: ios             !< iostat
    character(len=*), intent(inout) :: iomsg !< iomsg
    real(wp) :: conductivity, density, heat_capacity, base_temperature, amplitude
    integer :: modes(3)
    namelist /heat/ conductivity, density, heat_capacity, base_temperature, amplitude, modes
    conductivity = p%conductivity
    density = p%density
    heat_capacity = p%heat_capacity
    base_temperature = p%base_temperature
    amplitude = p%amplitude
    modes = p%modes
    read(text, nml=heat, iostat=ios, iomsg=iomsg)
    if (ios /= 0) return
    p%conductivity = conductivity
    p%density = density
    p%heat_capacity = heat_capacity
    p%base_temperature = base_temperature
    p%amplitude = amplitude
    p%modes = modes
  end subroutine read_heat
end module config_namelist
