!> The solid-only MPM scene `mpm` (explicit update-stress-last MPM, paper eqs. 26-27, 40-41,
!! 69-75): all solids share one set of node fields (single velocity field, no contact algorithm),
!! each solid keeps its own particles and constitutive model.
!!
!! Step: P2G (mass, momentum, internal force) -> reverse halo -> nodal solve with gravity
!! (ramped over `&mpm gravity_ramp_time`), local damping and the `&boundary solid` conditions ->
!! G2P (FLIP/PIC blend, position, F, volume, stress) -> migration. dt = `&time cfl` dx/(c + |v|).
!! Rank 0 appends one line per step to `<output_dir>/<name>_mpm_series.csv`: time, kinetic
!! energy, elastic strain energy, largest particle coordinate per dimension, smallest ditto.
module mpm_scene
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use mpmice_kinds, only: wp, i8, name_len, path_len
  use mpmice_errors, only: int_text, real_short_text, fatal
  use mpmice_log, only: log_info, log_warning
  use mpmice_timers, only: timer_register, timer_start, timer_stop
  use config_types, only: history_points_used, solid_params_t, mpm_params_t
  use scene_params, only: mpm_scene_params_t
  use parallel_domain, only: domain_t
  use parallel_halo, only: halo_t, halo_init, halo_free
  use parallel_reduce, only: global_sum, global_max, global_min
  use grid_layout, only: grid_t
  use io_hdf5, only: h5_file_t, h5_write_attribute, h5_read_attribute
  use io_files, only: io_join_path, io_open_series
  use io_xdmf, only: xdmf_particles_t
  use scene_interface, only: scene_t, scene_health_t, scene_context_t
  use particles_store, only: particles_t, particles_free, particles_select_state
  use particles_seeding, only: seed_solid
  use mpm_shape, only: shape_kind_from_name
  use mpm_nodes, only: mpm_nodes_t, nodes_init, nodes_free, nq, node_rigid_mass
  use mpm_p2g, only: p2g_accumulate, p2g_accumulate_rigid, p2g_complete
  use mpm_nodal, only: nodal_bc_t, nodal_solve, bc_kind_from_name, face_load_power, bc_fixed, &
    bc_roller, nodal_bc_at_time
  use mpm_g2p, only: g2p_update
  use mpm_constitutive, only: material_t, material_init, material_at, model_from_name, &
    wave_speed, model_rigid, model_state
  use mpm_rigid, only: rigid_motion_t, rigid_velocity, rigid_displacement, rigid_is_static
  use particles_migration, only: migration_t, migration_init, migrate_particles, &
    keep_inside_walls
  use mpm_output, only: write_particle_dump, write_particle_checkpoint, &
    read_particle_checkpoint, particle_xdmf_set, write_cell_dump, cell_dump_paths
  implicit none
  private

  public :: mpm_scene_t, mpm_setup, mpm_gravity, mpm_damping, mpm_stage_g2p, move_rigid
  public :: mpm_migrate_all, solid_energies, p2g_solids

  !> Solid bodies on a background grid.
  type, extends(scene_t) :: mpm_scene_t
    integer :: nsolids = 0                                  !< solids
    character(len=name_len), allocatable :: names(:)        !< solid names
    type(particles_t), allocatable :: parts(:)              !< particles per solid
    type(material_t), allocatable :: mats(:)                !< constitutive model per solid
    type(rigid_motion_t), allocatable :: motions(:)         !< prescribed motion (rigid solids)
    logical, allocatable :: static(:)                       !< rigid solid that never moves, its
                                                            !! grid share kept (&mpm
                                                            !! cache_static_rigid)
    real(wp), allocatable :: static_q(:, :, :, :)           !< the static rigid solids' share of
                                                            !! the node fields (8-14), kept
    integer(i8), allocatable :: global_np(:)                !< particles per solid, all ranks
    type(mpm_nodes_t) :: nodes                              !< shared node fields
    type(halo_t) :: halo                                    !< halo buffers
    type(migration_t) :: mig                                !< migration tables
    type(nodal_bc_t) :: bc                                  !< solid boundary conditions
    integer :: shape_kind = 2                               !< shape functions
    real(wp) :: gravity(3) = 0.0_wp                         !< gravity [m/s^2]
    real(wp) :: ramp_time = 0.0_wp                          !< gravity ramp [s]
    real(wp) :: damping = 0.0_wp                            !< local damping factor
    real(wp) :: damping_end = 0.0_wp                        !< damped steps begin before this
                                                            !! time [s] (0: the whole run)
    logical :: damp_total = .false.                         !< damp the whole nodal increment
                                                            !! (coupled scene, nodal_damp)
    real(wp) :: flip = 0.99_wp                              !< FLIP fraction
    real(wp) :: min_mass = 0.0_wp                           !< empty-node threshold [kg]
    integer(i8) :: removed = 0_i8                           !< particles that left the domain
    integer(i8) :: walled = 0_i8                            !< particles put back inside a wall
                                                            !! (this rank's, `keep_inside_walls`)
    character(len=path_len) :: series_path = ''             !< time-series file
    logical :: restored = .false.                           !< state came from a checkpoint
    logical :: series_started = .false.                     !< series file opened this run
    integer :: t_p2g = 0, t_nodal = 0, t_g2p = 0, t_migrate = 0  !< timer ids
  contains
    procedure :: stable_dt => mpm_stable_dt
    procedure :: step => mpm_step
    procedure :: write_state => mpm_write_state
    procedure :: restore => mpm_restore
    procedure :: output_layout => mpm_output_layout
    procedure :: all_finite => mpm_all_finite
    procedure :: summary => mpm_summary
    procedure :: free => mpm_free
    procedure :: health => mpm_health
  end type mpm_scene_t

contains

  !> Materials, particles, node fields, boundary conditions; keeps `ctx`.
  subroutine mpm_setup(self, par, ctx)
    class(mpm_scene_t), intent(inout) :: self    !< scene
    type(mpm_scene_params_t), intent(in) :: par  !< the scene's groups
    type(scene_context_t), intent(in) :: ctx     !< decomposition, grid and timers of the run
    integer :: s, face, n
    real(wp) :: mmin
    logical :: keep_hardening, keep_cyclic, keep_gap, keep_affine
    type(mpm_params_t) :: default_mpm  ! the documented defaults of &mpm
    self%ctx = ctx
    associate (dom => ctx%dom, grid => ctx%grid, timers => ctx%timers)
      if (any(grid%active .and. grid%ng < 1)) call fatal('mpm scene: &grid ghost_width must be >= 1')
      self%t_p2g = timer_register(timers, 'MPM particle to grid')
      self%t_nodal = timer_register(timers, 'MPM nodal solve')
      self%t_g2p = timer_register(timers, 'MPM grid to particle + stress')
      self%t_migrate = timer_register(timers, 'MPM migration')
      self%nsolids = par%nsolids
      allocate(self%names(self%nsolids), self%parts(self%nsolids), self%mats(self%nsolids), &
        self%global_np(self%nsolids), self%motions(self%nsolids), self%static(self%nsolids))
      self%shape_kind = shape_kind_from_name(par%numerics%shape_function)
      self%gravity = par%physics%gravity
      self%ramp_time = par%mpm%gravity_ramp_time
      self%damping = par%mpm%local_damping
      self%damping_end = par%mpm%local_damping_end
      self%damp_total = par%mpm%local_damping_force == 'total'
      self%flip = par%mpm%flip_fraction
      ! APIC takes the PIC velocity: a FLIP fraction other than the default has no effect
      if (par%mpm%velocity_transfer == 'apic' .and. &
        par%mpm%flip_fraction /= default_mpm%flip_fraction) then
        call log_warning('mpm: &mpm flip_fraction = ' // real_short_text(par%mpm%flip_fraction) &
          // ' is not used with velocity_transfer = ''apic''')
      end if
      mmin = huge(1.0_wp)
      do s = 1, self%nsolids
        associate (sp => par%solids(s))
          self%names(s) = sp%name
          self%mats(s) = material_init(model_from_name(sp%model), (1.0_wp - sp%porosity) * &
            sp%density, sp%youngs_modulus, sp%poisson_ratio, sp%cohesion, sp%friction_angle, &
            sp%dilation_angle, sp%tension_cutoff, sp%tensile_strength)
          if (sp%max_porosity < 1.0_wp) self%mats(s)%j_loose = (1.0_wp - sp%porosity) / &
            (1.0_wp - sp%max_porosity)
          if (sp%min_porosity > 0.0_wp) self%mats(s)%j_dense = (1.0_wp - sp%porosity) / &
            (1.0_wp - sp%min_porosity)
          call set_soil_params(self%mats(s), sp)
          self%motions(s) = rigid_motion_t(sp%prescribed_velocity, sp%acceleration_amplitude, &
            sp%acceleration_frequency, sp%acceleration_duration, sp%acceleration_start)
          call model_state(self%mats(s)%model, self%mats(s)%css%c1, self%mats(s)%css%lambda_c, &
            self%mats(s)%css%tension_gap, par%mpm%velocity_transfer, keep_hardening, &
            keep_cyclic, keep_gap, keep_affine)
          call particles_select_state(self%parts(s), keep_hardening, keep_cyclic, keep_gap, &
            keep_affine)
          call seed_solid(self%parts(s), sp, grid, self%gravity)
          if (self%mats(s)%model == model_rigid) call move_rigid(self, s, grid, 0.0_wp, 0.0_wp)
          self%static(s) = par%mpm%cache_static_rigid .and. &
            self%mats(s)%model == model_rigid .and. rigid_is_static(self%motions(s))
          if (self%parts(s)%np > 0) mmin = min(mmin, minval(self%parts(s)%mass(1:self%parts(s)%np)))
          self%global_np(s) = global_sum(dom, int(self%parts(s)%np, i8))
          call log_info('mpm: solid ' // trim(sp%name) // ' (' // trim(sp%model) // '): ' // &
            int_text(int(self%global_np(s))) // ' particles')
        end associate
      end do
      self%min_mass = 1.0e-12_wp * global_min(dom, mmin)
      do face = 1, 6
        associate (b => par%faces(face))
          self%bc%kind(face) = bc_kind_from_name(b%solid)
          self%bc%velocity(:, face) = b%solid_velocity
          n = history_points_used(b%solid_velocity_times)
          if (n > size(self%bc%times, 1)) call fatal('mpm scene: velocity history longer ' // &
            'than the nodal table')
          self%bc%npoints(face) = n
          self%bc%times(1:n, face) = b%solid_velocity_times(1:n)
          self%bc%history(:, 1:n, face) = b%solid_velocity_history(:, 1:n)
          self%bc%traction(:, face) = b%solid_traction
        end associate
      end do
      self%bc%friction_contact = trim(par%mpm%rigid_contact) == 'friction'
      self%bc%friction = par%mpm%contact_friction
      self%bc%smoothed_normal = trim(par%mpm%contact_normal) == 'smoothed'
      call nodes_init(self%nodes, grid)
      call keep_static_share(self, grid)
      call halo_init(self%halo, dom, grid, nq)
      call migration_init(self%mig, dom, grid)
      self%series_path = io_join_path(trim(par%run%output_dir), trim(par%run%name) // &
        '_mpm_series.csv')
    end associate
  end subroutine mpm_setup

  !> The `&solid` parameters of the soil models (docs/soil_models.md): Modified Cam-Clay M
  !! (from `friction_angle` phi when 0: M = 6 sin phi / (3 - sin phi), triaxial compression),
  !! lambda, kappa, v0 = 1 / (1 - porosity), p_c0, OCR, G or nu, p'_min; the critical-state
  !! sand's rheology and the packing phi0 = 1 - porosity.
  pure subroutine set_soil_params(mat, sp)
    type(material_t), intent(inout) :: mat   !< material (model and elasticity set)
    type(solid_params_t), intent(in) :: sp   !< its `&solid`
    real(wp) :: sphi
    sphi = sin(sp%friction_angle * acos(-1.0_wp) / 180.0_wp)
    mat%mcc%m = sp%critical_state_ratio
    if (mat%mcc%m <= 0.0_wp) mat%mcc%m = 6.0_wp * sphi / (3.0_wp - sphi)
    mat%mcc%lambda = sp%compression_index
    mat%mcc%kappa = sp%swelling_index
    mat%mcc%v0 = 1.0_wp / (1.0_wp - sp%porosity)
    mat%mcc%pc0 = sp%preconsolidation_pressure
    mat%mcc%ocr = sp%ocr
    mat%mcc%shear_modulus = sp%shear_modulus
    mat%mcc%poisson = sp%poisson_ratio
    mat%mcc%min_pressure = sp%min_pressure
    mat%css%mu1 = sp%friction_mu1
    mat%css%mu2 = sp%friction_mu2
    mat%css%j0 = sp%viscous_j0
    mat%css%phi_m = sp%critical_solid_fraction
    mat%css%k_dil = sp%dilatancy_constant
    mat%css%eta_f = sp%fluid_viscosity
    mat%css%lambda_c = sp%compaction_index
    mat%css%p_a = sp%compaction_pressure
    mat%css%c1 = sp%densification_c1
    mat%css%c2 = sp%densification_c2
    mat%css%gamma_t = sp%densification_threshold
    mat%css%evd_max = sp%densification_max
    mat%css%elastic_amp = sp%densification_elastic
    mat%css%t_min = sp%densification_min_half_cycle
    mat%css%t_start = sp%densification_start
    mat%css%tension_gap = sp%tension_gap
    mat%plastic_start = sp%plastic_start
    mat%modulus_exponent = sp%modulus_exponent
    mat%modulus_p_ref = sp%modulus_reference_pressure
    mat%solid_fraction0 = 1.0_wp - sp%porosity
  end subroutine set_soil_params

  !> dt = cfl min_p dx_min / (c_p + |v_p|) over all particles (global), c_p the wave speed of
  !! the particle's current deformation F (`wave_speed`: a dilated particle of a rate model is
  !! faster, c_p^2 = (lambda + 2 mu) J / rho0).
  function mpm_stable_dt(self, cfl) result(dt)
    class(mpm_scene_t), intent(inout) :: self  !< scene
    real(wp), intent(in) :: cfl                !< Courant number
    real(wp) :: dt
    real(wp) :: h, speed, f(3, 3)
    integer :: s, ip
    h = minval(self%ctx%grid%dx, mask=self%ctx%grid%active)
    dt = huge(1.0_wp)
    do s = 1, self%nsolids
      if (self%static(s)) cycle  ! no wave, no velocity: no limit
      associate (p => self%parts(s))
        speed = 0.0_wp
        do ip = 1, p%np
          f(:, 1) = p%f(1:3, ip)
          f(:, 2) = p%f(4:6, ip)
          f(:, 3) = p%f(7:9, ip)
          speed = max(speed, wave_speed(self%mats(s), f, p%stress(:, ip)) + norm2(p%v(:, ip)))
        end do
        if (speed > 0.0_wp) dt = min(dt, cfl * h / speed)
      end associate
    end do
    dt = global_min(self%ctx%dom, dt)
  end function mpm_stable_dt

  !> One explicit MPM step.
  subroutine mpm_step(self, time, dt, accepted)
    class(mpm_scene_t), intent(inout) :: self    !< scene
    real(wp), intent(in) :: time                 !< time at the start of the step [s]
    real(wp), intent(in) :: dt                   !< step [s]
    logical, intent(out) :: accepted             !< always true
    associate (dom => self%ctx%dom, grid => self%ctx%grid, timers => self%ctx%timers)
      call timer_start(timers, self%t_p2g)
      call p2g_solids(self, grid)
      call p2g_complete(self%nodes, dom, grid, self%halo)
      call timer_stop(timers, self%t_p2g)
      call timer_start(timers, self%t_nodal)
      call nodal_bc_at_time(self%bc, time + dt)
      call nodal_solve(self%nodes, grid, mpm_gravity(self, time + dt), mpm_damping(self, time), &
        dt, self%bc, self%min_mass)
      call timer_stop(timers, self%t_nodal)
      call mpm_stage_g2p(self, time, dt)
      call mpm_migrate_all(self, time + dt)
      call write_series(self, dom, time + dt)
    end associate
    accepted = .true.
  end subroutine mpm_step

  !> Gravity at `time` [m/s^2]: `&physics gravity` ramped linearly from 0 over `&mpm
  !! gravity_ramp_time` (none when 0).
  pure function mpm_gravity(self, time) result(g)
    class(mpm_scene_t), intent(in) :: self  !< scene
    real(wp), intent(in) :: time            !< time [s]
    real(wp) :: g(3)
    real(wp) :: ramp
    ramp = 1.0_wp
    if (self%ramp_time > 0.0_wp) ramp = min(1.0_wp, time / self%ramp_time)
    g = ramp * self%gravity
  end function mpm_gravity

  !> Local damping factor of the step that begins at `time`: `&mpm local_damping` before `&mpm
  !! local_damping_end` (over the whole run when that is 0), 0 from then on.
  pure function mpm_damping(self, time) result(alpha)
    class(mpm_scene_t), intent(in) :: self  !< scene
    real(wp), intent(in) :: time            !< time at the start of the step [s]
    real(wp) :: alpha
    alpha = self%damping
    if (self%damping_end > 0.0_wp .and. time >= self%damping_end) alpha = 0.0_wp
  end function mpm_damping

  !> G2P of the deformable solids (velocity, position, F, volume, stress; eqs. 70-75) and the
  !! prescribed motion of the rigid ones, over the step `dt` from `time`.
  subroutine mpm_stage_g2p(self, time, dt)
    class(mpm_scene_t), intent(inout) :: self  !< scene
    real(wp), intent(in) :: time               !< time at the start of the step [s]
    real(wp), intent(in) :: dt                 !< step [s]
    integer :: s
    call timer_start(self%ctx%timers, self%t_g2p)
    do s = 1, self%nsolids
      if (self%mats(s)%model == model_rigid) then
        if (.not. self%static(s)) call move_rigid(self, s, self%ctx%grid, time, dt)
      else
        ! the material of this step: elastic before `&solid plastic_start`, no densification
        ! before `densification_start` (`material_at`)
        call g2p_update(self%parts(s), self%nodes, material_at(self%mats(s), time), &
          self%shape_kind, self%ctx%grid, dt, self%flip)
      end if
    end do
    call timer_stop(self%ctx%timers, self%t_g2p)
  end subroutine mpm_stage_g2p

  !> Migrate the particles of every solid to their owners; particles that left the domain are
  !! removed, counted and logged (collective). A deformable solid's particles that passed a
  !! wall face (`solid = 'fixed'` or `'roller'`) are first put back on it (`keep_inside_walls`).
  subroutine mpm_migrate_all(self, time)
    class(mpm_scene_t), intent(inout) :: self  !< scene
    real(wp), intent(in) :: time               !< time after the step [s]
    integer :: s, removed, moved, face
    logical :: walls(6)
    call timer_start(self%ctx%timers, self%t_migrate)
    walls = [(self%bc%kind(face) == bc_fixed .or. self%bc%kind(face) == bc_roller, face = 1, 6)]
    associate (dom => self%ctx%dom)
      do s = 1, self%nsolids
        if (self%static(s)) cycle  ! never moves: stays on its rank and in the domain
        if (self%mats(s)%model /= model_rigid) then
          call keep_inside_walls(self%parts(s), self%ctx%grid, walls, moved)
          self%walled = self%walled + int(moved, i8)
        end if
        call migrate_particles(self%mig, self%parts(s), dom, self%ctx%grid, removed)
        removed = global_sum(dom, removed)
        if (removed > 0) then
          self%removed = self%removed + int(removed, i8)
          call log_warning('mpm: ' // int_text(removed) // ' particles of ' // &
            trim(self%names(s)) // ' left the domain at t = ' // real_short_text(time) // ' s')
          self%global_np(s) = global_sum(dom, int(self%parts(s)%np, i8))
        end if
      end do
    end associate
    call timer_stop(self%ctx%timers, self%t_migrate)
  end subroutine mpm_migrate_all

  !> Move the particles of rigid solid `s` from `time` to `time + dt` along the prescribed
  !! motion and set their velocity to v(time + dt) (inactive dimensions stay at rest).
  subroutine move_rigid(self, s, grid, time, dt)
    class(mpm_scene_t), intent(inout) :: self  !< scene
    integer, intent(in) :: s                   !< rigid solid
    type(grid_t), intent(in) :: grid           !< block geometry
    real(wp), intent(in) :: time               !< start of the step [s]
    real(wp), intent(in) :: dt                 !< step [s]
    real(wp) :: dx(3), v(3)
    integer :: ip
    dx = merge(rigid_displacement(self%motions(s), time, dt), 0.0_wp, grid%active)
    v = merge(rigid_velocity(self%motions(s), time + dt), 0.0_wp, grid%active)
    do ip = 1, self%parts(s)%np
      self%parts(s)%x(:, ip) = self%parts(s)%x(:, ip) + dx
      self%parts(s)%v(:, ip) = v
    end do
  end subroutine move_rigid

  !> P2G of every solid into the zeroed node fields (before the halo sum): the deformable ones'
  !! mass, momentum and internal force (components 1-7), the rigid ones' mass, momentum and mass
  !! gradient (8-14). A static rigid solid (`static`: no velocity, no shaking) cannot change its
  !! share, so it comes from `static_q` (`keep_static_share`; the bed of the debris flow: 92 % of
  !! its particles).
  subroutine p2g_solids(self, grid)
    class(mpm_scene_t), intent(inout) :: self  !< scene
    type(grid_t), intent(in) :: grid           !< block geometry
    integer :: s
    self%nodes%q(:, :, :, :) = 0.0_wp
    if (allocated(self%static_q)) self%nodes%q(node_rigid_mass:nq, :, :, :) = &
      self%static_q(node_rigid_mass:nq, :, :, :)
    do s = 1, self%nsolids
      if (self%static(s)) cycle
      if (self%mats(s)%model == model_rigid) then
        call p2g_accumulate_rigid(self%parts(s), self%nodes%q, self%shape_kind, grid)
      else
        call p2g_accumulate(self%parts(s), self%nodes%q, self%shape_kind, grid)
      end if
    end do
  end subroutine p2g_solids

  !> `static_q`: the static rigid solids' node share from their particles, at the start and
  !! after a restart (allocated when there is any such solid).
  subroutine keep_static_share(self, grid)
    class(mpm_scene_t), intent(inout) :: self  !< scene (particles seeded or restored)
    type(grid_t), intent(in) :: grid           !< block geometry
    integer :: s
    if (.not. any(self%static)) return
    if (.not. allocated(self%static_q)) allocate(self%static_q, mold=self%nodes%q)
    self%static_q = 0.0_wp
    do s = 1, self%nsolids
      if (self%static(s)) call p2g_accumulate_rigid(self%parts(s), self%static_q, &
        self%shape_kind, grid)
    end do
  end subroutine keep_static_share

  !> This rank's kinetic energy and elastic strain energy of the solids [J] (the strain energy
  !! from the stress with the solid's elastic constants: sigma : C^-1 : sigma / 2 per volume).
  function solid_energies(self, deformable_only) result(e)
    class(mpm_scene_t), intent(in) :: self             !< scene
    logical, intent(in), optional :: deformable_only   !< leave rigid solids out
    real(wp) :: e(2)
    real(wp) :: sig(6), en, nu, tr, ss
    integer :: s, ip
    logical :: skip_rigid
    skip_rigid = .false.
    if (present(deformable_only)) skip_rigid = deformable_only
    e = 0.0_wp
    do s = 1, self%nsolids
      if (skip_rigid .and. self%mats(s)%model == model_rigid) cycle
      associate (p => self%parts(s), mat => self%mats(s))
        en = mat%mu * (3.0_wp * mat%lambda + 2.0_wp * mat%mu) / max(mat%lambda + mat%mu, &
          tiny(1.0_wp))
        nu = mat%lambda / max(2.0_wp * (mat%lambda + mat%mu), tiny(1.0_wp))
        do ip = 1, p%np
          e(1) = e(1) + 0.5_wp * p%mass(ip) * sum(p%v(:, ip)**2)
          sig = p%stress(:, ip)
          tr = sig(1) + sig(2) + sig(3)
          ss = sum(sig(1:3)**2) + 2.0_wp * sum(sig(4:6)**2)
          if (en > 0.0_wp) e(2) = e(2) + p%volume(ip) * ((1.0_wp + nu) * ss - nu * tr * tr) &
            / (2.0_wp * en)
        end do
      end associate
    end do
  end function solid_energies

  !> Energy (kinetic + strain) of the deformable solids, the power of gravity (ramped) and of the
  !! domain-face tractions on them, the particle count and the particles lost (collective).
  subroutine mpm_health(self, time, health)
    class(mpm_scene_t), intent(inout) :: self        !< scene
    real(wp), intent(in) :: time                     !< time of the state [s]
    type(scene_health_t), intent(out) :: health      !< energy, load power, particle counts
    real(wp) :: e(3), g(3)
    integer :: s, ip
    g = merge(mpm_gravity(self, time), 0.0_wp, self%ctx%grid%active)
    e = 0.0_wp
    do s = 1, self%nsolids
      if (self%mats(s)%model == model_rigid) cycle
      associate (p => self%parts(s))
        do ip = 1, p%np
          e(3) = e(3) + p%mass(ip) * dot_product(g, p%v(:, ip))
        end do
      end associate
    end do
    e(1:2) = solid_energies(self, deformable_only=.true.)
    e(3) = e(3) + face_load_power(self%nodes, self%ctx%grid, self%bc, self%min_mass)
    e = global_sum(self%ctx%dom, e)
    health%has_solids = .true.
    health%energy = e(1) + e(2)
    health%load_power = e(3)
    health%particles = sum(self%global_np)
    health%lost = self%removed
  end subroutine mpm_health

  !> Append the energies and extents at `time` to the series file (rank 0 writes).
  subroutine write_series(self, dom, time)
    class(mpm_scene_t), intent(inout) :: self  !< scene
    type(domain_t), intent(in) :: dom          !< decomposition
    real(wp), intent(in) :: time               !< time [s]
    real(wp) :: e(2), xmax(3), xmin(3)
    integer :: s, ip, d, unit
    logical :: fresh
    e = solid_energies(self)
    xmax = -huge(1.0_wp)
    xmin = huge(1.0_wp)
    do s = 1, self%nsolids
      associate (p => self%parts(s))
        do ip = 1, p%np
          do d = 1, 3
            xmax(d) = max(xmax(d), p%x(d, ip))
            xmin(d) = min(xmin(d), p%x(d, ip))
          end do
        end do
      end associate
    end do
    e = global_sum(dom, e)
    do d = 1, 3
      xmax(d) = global_max(dom, xmax(d))
      xmin(d) = global_min(dom, xmin(d))
    end do
    if (dom%rank /= 0) return
    call io_open_series(trim(self%series_path), self%restored, self%series_started, unit, fresh)
    if (fresh) write(unit, '(a)') 'time,kinetic_energy,strain_energy,xmax,ymax,zmax,xmin,ymin,zmin'
    write(unit, '(es24.16e3, 8(",", es24.16e3))') time, e, xmax, xmin
    close(unit)
  end subroutine write_series

  !> Particle datasets of every solid (dump) or the full state (checkpoint).
  subroutine mpm_write_state(self, file, checkpoint)
    class(mpm_scene_t), intent(inout) :: self  !< scene
    type(h5_file_t), intent(in) :: file        !< open file
    logical, intent(in) :: checkpoint          !< full restart state
    integer :: s
    do s = 1, self%nsolids
      if (checkpoint) then
        call write_particle_checkpoint(file, self%names(s), self%parts(s))
      else
        call write_particle_dump(file, self%names(s), self%parts(s))
        call write_cell_dump(file, self%names(s), self%parts(s), self%ctx%grid)
      end if
    end do
    if (checkpoint) call h5_write_attribute(file, 'mpm_removed_particles', self%removed)
  end subroutine mpm_write_state

  !> Particles of a checkpoint, migrated to their owners (any rank count).
  subroutine mpm_restore(self, file)
    class(mpm_scene_t), intent(inout) :: self  !< scene
    type(h5_file_t), intent(in) :: file        !< open checkpoint
    integer :: s, removed
    real(wp) :: lp(3)
    associate (dom => self%ctx%dom, grid => self%ctx%grid)
      do s = 1, self%nsolids
        lp = self%parts(s)%half_width
        call read_particle_checkpoint(file, self%names(s), self%parts(s))
        self%parts(s)%half_width = lp
        call migrate_particles(self%mig, self%parts(s), dom, grid, removed)
        self%global_np(s) = global_sum(dom, int(self%parts(s)%np, i8))
      end do
    end associate
    call h5_read_attribute(file, 'mpm_removed_particles', self%removed)
    self%restored = .true.
    call keep_static_share(self, self%ctx%grid)  ! from the restored particles, as the continuing run
  end subroutine mpm_restore

  !> Cell averages and one particle set per solid.
  subroutine mpm_output_layout(self, cell_paths, particle_sets)
    class(mpm_scene_t), intent(in) :: self                               !< scene
    character(len=name_len), allocatable, intent(out) :: cell_paths(:)   !< cell dataset paths
    type(xdmf_particles_t), allocatable, intent(out) :: particle_sets(:) !< particle sets
    integer :: s
    allocate(cell_paths(5 * self%nsolids))
    allocate(particle_sets(self%nsolids))
    do s = 1, self%nsolids
      cell_paths(5 * s - 4:5 * s) = cell_dump_paths(self%names(s))
      particle_sets(s) = particle_xdmf_set(self%names(s), self%global_np(s))
    end do
  end subroutine mpm_output_layout

  !> True when every particle position, velocity and stress is finite (static rigid solids, whose
  !! particles never change, are not looked at).
  function mpm_all_finite(self) result(finite)
    class(mpm_scene_t), intent(in) :: self  !< scene
    logical :: finite
    integer :: s, n
    finite = .true.
    do s = 1, self%nsolids
      if (self%static(s)) cycle  ! never moves and carries no stress: its seeded values stay
      n = self%parts(s)%np
      finite = finite .and. all(ieee_is_finite(self%parts(s)%x(:, 1:n))) .and. &
        all(ieee_is_finite(self%parts(s)%v(:, 1:n))) .and. &
        all(ieee_is_finite(self%parts(s)%stress(:, 1:n)))
    end do
  end function mpm_all_finite

  !> Particle counts and removals.
  subroutine mpm_summary(self)
    class(mpm_scene_t), intent(inout) :: self  !< scene
    integer :: s
    do s = 1, self%nsolids
      call log_info('mpm: solid ' // trim(self%names(s)) // ': ' // &
        int_text(int(self%global_np(s))) // ' particles at the end')
    end do
    call log_info('mpm: particles removed (left the domain): ' // int_text(int(self%removed)))
    call log_info('mpm: particle positions put back inside a wall face: ' // &
      int_text(int(global_sum(self%ctx%dom, self%walled))))
  end subroutine mpm_summary

  !> Release everything.
  subroutine mpm_free(self)
    class(mpm_scene_t), intent(inout) :: self  !< scene
    integer :: s
    if (allocated(self%parts)) then
      do s = 1, size(self%parts)
        call particles_free(self%parts(s))
      end do
      deallocate(self%parts, self%mats, self%names, self%global_np, self%motions, self%static)
    end if
    if (allocated(self%static_q)) deallocate(self%static_q)
    call nodes_free(self%nodes)
    call halo_free(self%halo)
    self%nsolids = 0
  end subroutine mpm_free
end module mpm_scene
