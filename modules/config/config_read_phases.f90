!> Namelist reads of the multiphase groups (`&physics`, `&ice`, `&mpm`, `&coupling`, `&fluid`,
!! `&solid`, `&region`, `&boundary`), used by `config_namelist`.
!!
!! As for the other groups, each routine presets the namelist variables from the parameters (so
!! absent variables keep their value), reads `text` and copies back on success only.
module config_read_phases
  use mpmice_kinds, only: wp, name_len, path_len
  use config_materials, only: physics_params_t, ice_params_t, mpm_params_t, coupling_params_t, &
    fluid_params_t, solid_params_t, region_params_t, boundary_params_t, max_polygon_points, &
    max_history_points
  implicit none
  private

  public :: read_physics, read_ice, read_mpm, read_coupling, read_fluid, read_solid, read_region
  public :: read_boundary

contains

  !> `&physics`.
  subroutine read_physics(p, text, ios, iomsg)
    type(physics_params_t), intent(inout) :: p !< parameters to update
    character(len=*), intent(in) :: text       !< namelist text
    integer, intent(out) :: ios                !< iostat
    character(len=*), intent(inout) :: iomsg   !< iomsg
    real(wp) :: gravity(3), reference_pressure
    logical :: hydrostatic_init
    namelist /physics/ gravity, reference_pressure, hydrostatic_init
    gravity = p%gravity
    reference_pressure = p%reference_pressure
    hydrostatic_init = p%hydrostatic_init
    read(text, nml=physics, iostat=ios, iomsg=iomsg)
    if (ios /= 0) return
    p%gravity = gravity
    p%reference_pressure = reference_pressure
    p%hydrostatic_init = hydrostatic_init
  end subroutine read_physics

  !> `&ice`.
  subroutine read_ice(p, text, ios, iomsg)
    type(ice_params_t), intent(inout) :: p   !< parameters to update
    character(len=*), intent(in) :: text     !< namelist text
    integer, intent(out) :: ios              !< iostat
    character(len=*), intent(inout) :: iomsg !< iomsg
    real(wp) :: outer_tolerance, exchange_coefficient, heat_exchange_coefficient
    real(wp) :: smagorinsky_constant, equilibration_tolerance, sound_speed_factor
    real(wp) :: interface_compression
    integer :: max_outer_iterations, max_equilibration_iterations
    logical :: smagorinsky
    namelist /ice/ outer_tolerance, max_outer_iterations, exchange_coefficient, &
      heat_exchange_coefficient, smagorinsky, smagorinsky_constant, equilibration_tolerance, &
      max_equilibration_iterations, sound_speed_factor, interface_compression
    outer_tolerance = p%outer_tolerance
    max_outer_iterations = p%max_outer_iterations
    exchange_coefficient = p%exchange_coefficient
    heat_exchange_coefficient = p%heat_exchange_coefficient
    smagorinsky = p%smagorinsky
    smagorinsky_constant = p%smagorinsky_constant
    equilibration_tolerance = p%equilibration_tolerance
    max_equilibration_iterations = p%max_equilibration_iterations
    sound_speed_factor = p%sound_speed_factor
    interface_compression = p%interface_compression
    read(text, nml=ice, iostat=ios, iomsg=iomsg)
    if (ios /= 0) return
    p%outer_tolerance = outer_tolerance
    p%max_outer_iterations = max_outer_iterations
    p%exchange_coefficient = exchange_coefficient
    p%heat_exchange_coefficient = heat_exchange_coefficient
    p%smagorinsky = smagorinsky
    p%smagorinsky_constant = smagorinsky_constant
    p%equilibration_tolerance = equilibration_tolerance
    p%max_equilibration_iterations = max_equilibration_iterations
    p%sound_speed_factor = sound_speed_factor
    p%interface_compression = interface_compression
  end subroutine read_ice

  !> `&mpm`.
  subroutine read_mpm(p, text, ios, iomsg)
    type(mpm_params_t), intent(inout) :: p   !< parameters to update
    character(len=*), intent(in) :: text     !< namelist text
    integer, intent(out) :: ios              !< iostat
    character(len=*), intent(inout) :: iomsg !< iomsg
    real(wp) :: flip_fraction, gravity_ramp_time, local_damping, contact_friction
    character(len=name_len) :: rigid_contact
    logical :: cache_static_rigid
    namelist /mpm/ flip_fraction, gravity_ramp_time, local_damping, rigid_contact, &
      contact_friction, cache_static_rigid
    flip_fraction = p%flip_fraction
    cache_static_rigid = p%cache_static_rigid
    rigid_contact = p%rigid_contact
    contact_friction = p%contact_friction
    gravity_ramp_time = p%gravity_ramp_time
    local_damping = p%local_damping
    read(text, nml=mpm, iostat=ios, iomsg=iomsg)
    if (ios /= 0) return
    p%flip_fraction = flip_fraction
    p%gravity_ramp_time = gravity_ramp_time
    p%local_damping = local_damping
    p%rigid_contact = rigid_contact
    p%contact_friction = contact_friction
    p%cache_static_rigid = cache_static_rigid
  end subroutine read_mpm

  !> `&coupling`.
  subroutine read_coupling(p, text, ios, iomsg)
    type(coupling_params_t), intent(inout) :: p !< parameters to update
    character(len=*), intent(in) :: text        !< namelist text
    integer, intent(out) :: ios                 !< iostat
    character(len=*), intent(inout) :: iomsg    !< iomsg
    character(len=name_len) :: drag_scheme
    real(wp) :: heat_exchange_coefficient, max_solid_fraction, solid_fraction_relaxation
    namelist /coupling/ drag_scheme, heat_exchange_coefficient, max_solid_fraction, &
      solid_fraction_relaxation
    solid_fraction_relaxation = p%solid_fraction_relaxation
    drag_scheme = p%drag_scheme
    heat_exchange_coefficient = p%heat_exchange_coefficient
    max_solid_fraction = p%max_solid_fraction
    read(text, nml=coupling, iostat=ios, iomsg=iomsg)
    if (ios /= 0) return
    p%drag_scheme = drag_scheme
    p%heat_exchange_coefficient = heat_exchange_coefficient
    p%max_solid_fraction = max_solid_fraction
    p%solid_fraction_relaxation = solid_fraction_relaxation
  end subroutine read_coupling

  !> `&fluid` (one occurrence).
  subroutine read_fluid(p, text, ios, iomsg)
    type(fluid_params_t), intent(inout) :: p !< parameters to update
    character(len=*), intent(in) :: text     !< namelist text
    integer, intent(out) :: ios              !< iostat
    character(len=*), intent(inout) :: iomsg !< iomsg
    character(len=name_len) :: name, eos
    real(wp) :: gamma, heat_capacity_cv, reference_density, reference_pressure
    real(wp) :: reference_temperature, bulk_modulus, thermal_expansion, stiffened_pressure
    real(wp) :: viscosity, conductivity, volume_fraction, velocity(3), temperature, pressure
    namelist /fluid/ name, eos, gamma, heat_capacity_cv, reference_density, reference_pressure, &
      reference_temperature, bulk_modulus, thermal_expansion, stiffened_pressure, viscosity, &
      conductivity, volume_fraction, velocity, temperature, pressure
    name = p%name
    eos = p%eos
    gamma = p%gamma
    heat_capacity_cv = p%heat_capacity_cv
    reference_density = p%reference_density
    reference_pressure = p%reference_pressure
    reference_temperature = p%reference_temperature
    bulk_modulus = p%bulk_modulus
    thermal_expansion = p%thermal_expansion
    stiffened_pressure = p%stiffened_pressure
    viscosity = p%viscosity
    conductivity = p%conductivity
    volume_fraction = p%volume_fraction
    velocity = p%velocity
    temperature = p%temperature
    pressure = p%pressure
    read(text, nml=fluid, iostat=ios, iomsg=iomsg)
    if (ios /= 0) return
    p%name = name
    p%eos = eos
    p%gamma = gamma
    p%heat_capacity_cv = heat_capacity_cv
    p%reference_density = reference_density
    p%reference_pressure = reference_pressure
    p%reference_temperature = reference_temperature
    p%bulk_modulus = bulk_modulus
    p%thermal_expansion = thermal_expansion
    p%stiffened_pressure = stiffened_pressure
    p%viscosity = viscosity
    p%conductivity = conductivity
    p%volume_fraction = volume_fraction
    p%velocity = velocity
    p%temperature = temperature
    p%pressure = pressure
  end subroutine read_fluid

  !> `&region` (one occurrence).
  subroutine read_region(p, text, ios, iomsg)
    type(region_params_t), intent(inout) :: p !< parameters to update
    character(len=*), intent(in) :: text      !< namelist text
    integer, intent(out) :: ios               !< iostat
    character(len=*), intent(inout) :: iomsg  !< iomsg
    character(len=name_len) :: material, shape
    real(wp) :: lower(3), upper(3), volume_fraction, velocity(3), temperature, pressure
    character(len=path_len) :: polygon_file, profile_file, profile_lower_file
    real(wp) :: layer_thickness, profile_lower_level
    namelist /region/ material, lower, upper, volume_fraction, velocity, temperature, pressure, &
      shape, polygon_file, profile_file, profile_lower_file, layer_thickness, profile_lower_level
    shape = p%shape
    polygon_file = p%polygon_file
    profile_file = p%profile_file
    profile_lower_file = p%profile_lower_file
    layer_thickness = p%layer_thickness
    profile_lower_level = p%profile_lower_level
    material = p%material
    lower = p%lower
    upper = p%upper
    volume_fraction = p%volume_fraction
    velocity = p%velocity
    temperature = p%temperature
    pressure = p%pressure
    read(text, nml=region, iostat=ios, iomsg=iomsg)
    if (ios /= 0) return
    p%material = material
    p%lower = lower
    p%upper = upper
    p%volume_fraction = volume_fraction
    p%velocity = velocity
    p%temperature = temperature
    p%pressure = pressure
    p%shape = shape
    p%polygon_file = polygon_file
    p%profile_file = profile_file
    p%profile_lower_file = profile_lower_file
    p%layer_thickness = layer_thickness
    p%profile_lower_level = profile_lower_level
  end subroutine read_region

  !> `&solid` (one occurrence).
  subroutine read_solid(p, text, ios, iomsg)
    type(solid_params_t), intent(inout) :: p !< parameters to update
    character(len=*), intent(in) :: text     !< namelist text
    integer, intent(out) :: ios              !< iostat
    character(len=*), intent(inout) :: iomsg !< iomsg
    character(len=name_len) :: name, model, shape, drag_law
    real(wp) :: drag_coefficient, grain_bulk_modulus, traction(3), traction_lower(3)
    real(wp) :: traction_upper(3), traction_ramp_time
    real(wp) :: density, youngs_modulus, poisson_ratio, cohesion, friction_angle
    real(wp) :: dilation_angle, tensile_strength, k0, lower(3), upper(3)
    real(wp) :: polygon_x(max_polygon_points), polygon_y(max_polygon_points)
    real(wp) :: plane_point(3), plane_normal(3), rotation_deg, velocity(3), temperature
    real(wp) :: heat_capacity, conductivity, porosity, grain_size, prescribed_velocity(3)
    real(wp) :: acceleration_amplitude(3), acceleration_frequency, velocity_wavenumber(3)
    real(wp) :: acceleration_duration, max_porosity, min_porosity
    real(wp) :: forchheimer_a, forchheimer_b
    real(wp) :: critical_state_ratio, compression_index, swelling_index
    real(wp) :: preconsolidation_pressure, ocr, shear_modulus, min_pressure, friction_mu1
    real(wp) :: friction_mu2, viscous_j0, critical_solid_fraction, dilatancy_constant
    real(wp) :: fluid_viscosity
    integer :: npoints, particles_per_cell(3)
    logical :: tension_cutoff, geostatic
    character(len=path_len) :: polygon_file, profile_file, profile_lower_file
    real(wp) :: layer_thickness, profile_lower_level
    namelist /solid/ name, model, density, youngs_modulus, poisson_ratio, cohesion, &
      friction_angle, dilation_angle, tension_cutoff, tensile_strength, k0, geostatic, shape, &
      lower, upper, npoints, polygon_x, polygon_y, plane_point, plane_normal, rotation_deg, &
      particles_per_cell, velocity, temperature, heat_capacity, conductivity, porosity, &
      max_porosity, min_porosity, grain_size, prescribed_velocity, acceleration_amplitude, &
      acceleration_frequency, acceleration_duration, velocity_wavenumber, drag_law, &
      drag_coefficient, grain_bulk_modulus, traction, traction_lower, traction_upper, &
      traction_ramp_time, forchheimer_a, forchheimer_b, critical_state_ratio, &
      compression_index, swelling_index, preconsolidation_pressure, ocr, shear_modulus, &
      min_pressure, friction_mu1, friction_mu2, viscous_j0, critical_solid_fraction, &
      dilatancy_constant, fluid_viscosity, polygon_file, profile_file, profile_lower_file, &
      layer_thickness, profile_lower_level
    polygon_file = p%polygon_file
    profile_file = p%profile_file
    profile_lower_file = p%profile_lower_file
    layer_thickness = p%layer_thickness
    profile_lower_level = p%profile_lower_level
    name = p%name
    model = p%model
    density = p%density
    youngs_modulus = p%youngs_modulus
    poisson_ratio = p%poisson_ratio
    cohesion = p%cohesion
    friction_angle = p%friction_angle
    dilation_angle = p%dilation_angle
    tension_cutoff = p%tension_cutoff
    tensile_strength = p%tensile_strength
    k0 = p%k0
    geostatic = p%geostatic
    shape = p%shape
    lower = p%lower
    upper = p%upper
    npoints = p%npoints
    polygon_x = p%polygon_x
    polygon_y = p%polygon_y
    plane_point = p%plane_point
    plane_normal = p%plane_normal
    rotation_deg = p%rotation_deg
    particles_per_cell = p%particles_per_cell
    velocity = p%velocity
    temperature = p%temperature
    heat_capacity = p%heat_capacity
    conductivity = p%conductivity
    porosity = p%porosity
    max_porosity = p%max_porosity
    min_porosity = p%min_porosity
    grain_size = p%grain_size
    prescribed_velocity = p%prescribed_velocity
    acceleration_amplitude = p%acceleration_amplitude
    acceleration_frequency = p%acceleration_frequency
    acceleration_duration = p%acceleration_duration
    velocity_wavenumber = p%velocity_wavenumber
    drag_law = p%drag_law
    drag_coefficient = p%drag_coefficient
    forchheimer_a = p%forchheimer_a
    forchheimer_b = p%forchheimer_b
    grain_bulk_modulus = p%grain_bulk_modulus
    traction = p%traction
    traction_lower = p%traction_lower
    traction_upper = p%traction_upper
    traction_ramp_time = p%traction_ramp_time
    critical_state_ratio = p%critical_state_ratio
    compression_index = p%compression_index
    swelling_index = p%swelling_index
    preconsolidation_pressure = p%preconsolidation_pressure
    ocr = p%ocr
    shear_modulus = p%shear_modulus
    min_pressure = p%min_pressure
    friction_mu1 = p%friction_mu1
    friction_mu2 = p%friction_mu2
    viscous_j0 = p%viscous_j0
    critical_solid_fraction = p%critical_solid_fraction
    dilatancy_constant = p%dilatancy_constant
    fluid_viscosity = p%fluid_viscosity
    read(text, nml=solid, iostat=ios, iomsg=iomsg)
    if (ios /= 0) return
    p%name = name
    p%model = model
    p%density = density
    p%youngs_modulus = youngs_modulus
    p%poisson_ratio = poisson_ratio
    p%cohesion = cohesion
    p%friction_angle = friction_angle
    p%dilation_angle = dilation_angle
    p%tension_cutoff = tension_cutoff
    p%tensile_strength = tensile_strength
    p%k0 = k0
    p%geostatic = geostatic
    p%shape = shape
    p%lower = lower
    p%upper = upper
    p%npoints = npoints
    p%polygon_x = polygon_x
    p%polygon_y = polygon_y
    p%plane_point = plane_point
    p%plane_normal = plane_normal
    p%rotation_deg = rotation_deg
    p%particles_per_cell = particles_per_cell
    p%velocity = velocity
    p%temperature = temperature
    p%heat_capacity = heat_capacity
    p%conductivity = conductivity
    p%porosity = porosity
    p%max_porosity = max_porosity
    p%min_porosity = min_porosity
    p%grain_size = grain_size
    p%prescribed_velocity = prescribed_velocity
    p%acceleration_amplitude = acceleration_amplitude
    p%acceleration_frequency = acceleration_frequency
    p%acceleration_duration = acceleration_duration
    p%velocity_wavenumber = velocity_wavenumber
    p%drag_law = drag_law
    p%drag_coefficient = drag_coefficient
    p%forchheimer_a = forchheimer_a
    p%forchheimer_b = forchheimer_b
    p%grain_bulk_modulus = grain_bulk_modulus
    p%traction = traction
    p%traction_lower = traction_lower
    p%traction_upper = traction_upper
    p%traction_ramp_time = traction_ramp_time
    p%critical_state_ratio = critical_state_ratio
    p%compression_index = compression_index
    p%swelling_index = swelling_index
    p%preconsolidation_pressure = preconsolidation_pressure
    p%ocr = ocr
    p%shear_modulus = shear_modulus
    p%min_pressure = min_pressure
    p%friction_mu1 = friction_mu1
    p%friction_mu2 = friction_mu2
    p%viscous_j0 = viscous_j0
    p%critical_solid_fraction = critical_solid_fraction
    p%dilatancy_constant = dilatancy_constant
    p%fluid_viscosity = fluid_viscosity
    p%polygon_file = polygon_file
    p%profile_file = profile_file
    p%profile_lower_file = profile_lower_file
    p%layer_thickness = layer_thickness
    p%profile_lower_level = profile_lower_level
  end subroutine read_solid

  !> `&boundary` (one occurrence).
  subroutine read_boundary(p, text, ios, iomsg)
    type(boundary_params_t), intent(inout) :: p !< parameters to update
    character(len=*), intent(in) :: text        !< namelist text
    integer, intent(out) :: ios                 !< iostat
    character(len=*), intent(inout) :: iomsg    !< iomsg
    character(len=name_len) :: face, fluid, thermal, solid, inflow_fluid
    real(wp) :: pressure, velocity(3), temperature, solid_velocity(3), solid_traction(3)
    real(wp) :: solid_velocity_times(max_history_points)
    real(wp) :: solid_velocity_history(3, max_history_points)
    namelist /boundary/ face, fluid, pressure, velocity, inflow_fluid, thermal, temperature, &
      solid, solid_velocity, solid_traction, solid_velocity_times, solid_velocity_history
    face = p%face
    fluid = p%fluid
    pressure = p%pressure
    velocity = p%velocity
    inflow_fluid = p%inflow_fluid
    thermal = p%thermal
    temperature = p%temperature
    solid = p%solid
    solid_velocity = p%solid_velocity
    solid_traction = p%solid_traction
    solid_velocity_times = p%solid_velocity_times
    solid_velocity_history = p%solid_velocity_history
    read(text, nml=boundary, iostat=ios, iomsg=iomsg)
    if (ios /= 0) return
    p%face = face
    p%fluid = fluid
    p%pressure = pressure
    p%velocity = velocity
    p%inflow_fluid = inflow_fluid
    p%thermal = thermal
    p%temperature = temperature
    p%solid = solid
    p%solid_velocity = solid_velocity
    p%solid_traction = solid_traction
    p%solid_velocity_times = solid_velocity_times
    p%solid_velocity_history = solid_velocity_history
  end subroutine read_boundary
end module config_read_phases
