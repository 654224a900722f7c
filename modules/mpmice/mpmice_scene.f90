!> The coupled scene `mpmice`: porous or impermeable MPM solids in ICE fluids (paper eqs. 1-75,
!! design §5). The fluids are an `ice_scene_t`, the solids an `mpm_scene_t`; this scene owns the
!! solid phase on the grid (`mpmice_solid_cells`) and runs ICE's stage sequence (`ice_stages`)
!! with the solid's stages between them:
!!
!!  P2G (26-27, effective stress, surface loads) -> nodal v^{L-} (40-41) -> solid cell variables
!!  (28) -> [ICE] equilibration with the pores (10-11, sum phi_f = n) -> [ICE] face velocities
!!  of the fluids (31) -> porous fluid predictor and solid face velocities (33) -> [ICE] face
!!  exchange with drag (34, E8) -> [ICE] implicit pressure with the solid's volume flux (35-36)
!!  -> [ICE] face pressure (37), fluid Lagrangian values (42-46) -> solid face increments to the
!!  nodes (52, 66-69, E5) -> solid cell velocity and conduction (48, 38-39) -> [ICE] cell
!!  exchange of the fluids with the solid and the implicit heat exchange (50-55) -> face blend,
!!  heat increments to the particles (68, 73) -> [ICE] fluid advection (58-65) -> tracked solid
!!  fraction -> G2P + constitutive update (70-75) -> pore pressure on the particles ->
!!  migration.
!!
!! The face velocities of fluids and solid are those at the end of the step (`face_time` 1):
!! the solid's carry the stress of the whole step, so its pressure force must act for the whole
!! step too; with `&numerics time_theta` < 1 the pressure change is weighted by theta
!! (docs/mpmice.md, "theta and Smagorinsky").
!!
!! The skeleton's constitutive models see the effective stress only (eq. 3); the fluid pressure
!! acts on it through the face pressure gradient. A fluid 'wall' where the skeleton carries a
!! surface load (`solid = 'traction'`) is a loading platen: impermeable, moving with the
!! skeleton, the load shared with the pore fluid (`ice_pressure` platen_fluid_faces). A fluid's
!! `&fluid volume_fraction` is its share of the pore space. See docs/mpmice.md.
module mpmice_scene
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use mpmice_geostatic, only: buoyant_geostatic_stress
  use mpmice_kinds, only: wp, name_len
  use mpmice_errors, only: fatal, int_text, real_short_text
  use mpmice_log, only: log_info
  use mpmice_timers, only: timer_register, timer_start, timer_stop
  use config_types, only: boundary_params_t
  use scene_params, only: mpmice_scene_params_t
  use parallel_domain, only: domain_t
  use parallel_halo, only: halo_t, halo_init, halo_free, halo_reverse_cell_vec, &
    halo_exchange_cell
  use parallel_reduce, only: global_sum, global_min
  use grid_layout, only: grid_t
  use io_hdf5, only: h5_file_t
  use io_xdmf, only: xdmf_particles_t
  use io_files, only: io_join_path
  use scene_interface, only: scene_t, scene_health_t, scene_context_t
  use exchange_solid_phase, only: solid_phase_t, solid_phase_alloc, solid_phase_free
  use ice_scene, only: ice_scene_t, ice_scene_setup, ice_fluids_stable_dt, &
    ice_pressure_average_step
  use ice_stages, only: exchange_primitives, ice_step_begin, ice_step_reject, &
    ice_stage_equilibrate, ice_stage_face_velocities, ice_stage_face_exchange, &
    ice_stage_pressure, ice_stage_lagrangian, ice_stage_cell_exchange, ice_stage_advect
  use ice_equilibration, only: ice_equilibrate
  use ice_bc, only: ice_bc_fill, bc_scalar, bc_temperature, bc_wall, bc_free_slip
  use mpm_scene, only: mpm_scene_t, mpm_setup, mpm_gravity, mpm_damping, mpm_stage_g2p, &
    mpm_migrate_all, p2g_solids
  use mpm_constitutive, only: model_rigid
  use mpm_p2g, only: p2g_complete
  use mpm_nodal, only: nodal_solve, nodal_finish, nodal_bc_at_time, bc_traction, nodal_damp
  use mpm_loads, only: surface_load_t, surface_load_init, surface_load_scatter, &
    surface_load_power
  use exchange_drag, only: drag_law_from_name
  use mpmice_solid_coupling, only: solid_coupling_t
  use mpmice_deposit_layout, only: deposit_size
  use mpmice_solid_cells, only: solid_deposit, solid_cell_fields, solid_face_predictor, &
    solid_face_to_nodes, solid_track_fraction, solid_cell_velocity, solid_pore_pressure, &
    fluid_face_blend, fluid_face_predictor_porous
  use mpmice_rigid_contact, only: wall_fraction, contact_pressure_accel
  use mpmice_solid_state, only: open_face_reservoirs, solid_state_write, solid_state_restore
  use mpmice_contact_force, only: contact_force_t, contact_force_init, contact_force_write, &
    contact_force_free
  use mpmice_solid_heat, only: solid_conduction, solid_conduction_dt, solid_heat_to_particles
  use mpmice_suspension, only: suspension_packing, suspension_settling
  implicit none
  private

  public :: mpmice_scene_t, mpmice_setup

  !> The parts whose stability limit can set the step (`mpmice_stable_dt`), as the summary
  !! names them.
  character(len=*), parameter :: limit_names(3) = [character(len=40) :: &
    'the fluids (flow, viscosity, conduction)', 'the solids (wave speed)', 'solid conduction']

  !> A tracked solid fraction below this in a cell where the particles hold no grains is a
  !! residual of the relaxation (which only decays it geometrically, 0.9 per step): it is removed
  !! in one step.
  real(wp), parameter :: residual_fraction = 1.0e-10_wp

  !> Fluids and porous solids with implicit pressure and exchange.
  type, extends(scene_t) :: mpmice_scene_t
    type(ice_scene_t) :: fl                               !< the fluids (ICE)
    type(mpm_scene_t) :: so                               !< the solids (MPM)
    !> the solid phase on the fluid grid, handed to ICE's stages (`ice_stages`)
    type(solid_phase_t) :: solid
    type(solid_coupling_t), allocatable :: coupling(:)    !< coupling parameters per solid
    type(surface_load_t), allocatable :: loads(:)         !< surface load per solid
    type(halo_t) :: halo                                  !< buffers for the cell deposits
    real(wp), allocatable :: dep(:, :, :, :)              !< particle deposits (comp, cells)
    real(wp), allocatable :: static_dep(:, :, :, :)       !< the static rigid solids' share of
                                                          !! dep, kept (`mpm_scene_t%static`)
    logical :: static_dep_ready = .false.                 !< static_dep holds that share
    real(wp), allocatable :: phi_p(:, :, :)               !< particles' solid fraction
    real(wp), allocatable :: du(:, :, :, :)               !< face increments, rigid-face flags
                                                          !! (6, nodes)
    real(wp), allocatable :: contact_dv(:, :, :, :)       !< velocity the contact's first pass
                                                          !! removed (3, nodes; sliding only)
    real(wp), allocatable :: contact_acc(:, :, :, :)      !< expected pressure acceleration at
                                                          !! contact nodes (3, nodes)
    real(wp), allocatable :: contact_f(:, :, :, :)        !< contact force on the rigid bodies
                                                          !! per node (3, nodes) [N]
    type(contact_force_t) :: forces                       !< the rigid bodies' force series
    real(wp) :: max_fraction = 0.999_wp                   !< cap of the solid fraction
    real(wp) :: relaxation = 0.1_wp                       !< solid-fraction relaxation per step
    real(wp), allocatable :: uprev(:, :, :, :, :)          !< last final face velocities
    real(wp), allocatable :: nbuf(:, :, :)                 !< node-shaped scratch (checkpoints)
    real(wp), allocatable :: temp_old(:, :, :)             !< solid cell temperature at time n [K]
    real(wp), allocatable :: dtemp(:, :, :)                !< its increment over the step [K]
    integer :: t_cells = 0, t_nodes = 0                   !< timer ids
    !> steps of this run whose stability limit each part set (`limit_names`)
    integer :: limit_steps(size(limit_names)) = 0
  contains
    procedure :: stable_dt => mpmice_stable_dt
    procedure :: step => mpmice_step
    procedure :: write_state => mpmice_write_state
    procedure :: restore => mpmice_restore
    procedure :: output_layout => mpmice_output_layout
    procedure :: all_finite => mpmice_all_finite
    procedure :: summary => mpmice_summary
    procedure :: free => mpmice_free
    procedure :: health => mpmice_health
  end type mpmice_scene_t

contains

  !> Fluids, solids, the solid phase on the grid; the fluids are scaled into the pore space and
  !! equilibrated with it. The fluids, the solids and the scene keep `ctx`.
  subroutine mpmice_setup(self, par, ctx)
    class(mpmice_scene_t), intent(inout) :: self    !< scene
    type(mpmice_scene_params_t), intent(in) :: par  !< the scene's groups
    type(scene_context_t), intent(in) :: ctx        !< decomposition, grid and timers of the run
    integer :: s, m, ns, its, failed, face, d, ndep
    type(boundary_params_t) :: b
    self%ctx = ctx
    associate (dom => ctx%dom, grid => ctx%grid, timers => ctx%timers)
      if (par%ice%nfluids < 1 .or. par%mpm%nsolids < 1) call fatal('mpmice scene: needs at ' // &
        'least one &fluid and one &solid group')
      if (any(grid%active .and. grid%ng < 2)) call fatal('mpmice scene: &grid ghost_width must ' // &
        'be >= 2')
      call ice_scene_setup(self%fl, par%ice, ctx)
      call mpm_setup(self%so, par%mpm, ctx)
      self%t_cells = timer_register(timers, 'MPMICE solid cells')
      self%t_nodes = timer_register(timers, 'MPMICE faces to nodes')
      ns = par%mpm%nsolids
      self%max_fraction = par%coupling%max_solid_fraction
      self%relaxation = par%coupling%solid_fraction_relaxation
      allocate(self%coupling(ns), self%loads(ns))
      do s = 1, ns
        associate (c => par%mpm%solids(s))
          self%coupling(s)%drag_law = drag_law_from_name(c%drag_law)
          self%coupling(s)%grain_size = c%grain_size
          self%coupling(s)%drag_coefficient = c%drag_coefficient
          self%coupling(s)%forchheimer_a = c%forchheimer_a
          self%coupling(s)%forchheimer_b = c%forchheimer_b
          self%coupling(s)%surface_drag_parallel = c%surface_drag_parallel
          self%coupling(s)%suspension_cell_bound = c%suspension_cell_bound
          self%coupling(s)%suspension_settling = c%suspension_settling
          if (c%grain_bulk_modulus > 0.0_wp) self%coupling(s)%grain_kappa = 1.0_wp / &
            c%grain_bulk_modulus
          self%coupling(s)%grain_density = c%density
          self%coupling(s)%heat_capacity = c%heat_capacity
          self%coupling(s)%conductivity = c%conductivity
          self%coupling(s)%rigid = trim(c%model) == 'rigid'
          self%loads(s) = surface_load_init(c%traction, c%traction_lower, c%traction_upper, &
            c%traction_ramp_time, grid)
        end associate
      end do
      call solid_phase_alloc(self%solid, grid, self%fl%state%nfluids)
      self%fl%label = 'MPMICE'
      ! end-of-step face velocities for fluids and solid (docs/mpmice.md, "theta and Smagorinsky")
      self%fl%face_time = 1.0_wp
      ! frictional contact with rigid bodies: they keep their own velocity (docs/mpmice.md)
      self%solid%sliding = self%so%bc%friction_contact .and. &
        any(self%so%mats(:)%model == model_rigid)
      self%solid%explicit_drag = trim(par%coupling%drag_scheme) == 'explicit'
      self%solid%plane_drag = trim(par%coupling%face_drag) == 'face_plane'
      ! a wall where the skeleton carries a surface load is a loading platen: impermeable, moving
      ! with the skeleton; the load beyond the face's `pressure` is shared with the pore fluid
      do face = 1, 6
        d = (face + 1) / 2
        if (.not. grid%active(d) .or. grid%periodic(d)) cycle
        if (self%so%bc%kind(face) /= bc_traction) cycle
        if (self%fl%bc%fluid(face) /= bc_wall .and. self%fl%bc%fluid(face) /= bc_free_slip) cycle
        b = par%mpm%faces(face)
        self%solid%platen(face) = .true.
        self%fl%state%p_boundary(face) = b%pressure
      end do
      self%solid%h_exchange = par%coupling%heat_exchange_coefficient
      ! only the components the scene uses (the zero fill, the reverse halo and the reads move
      ! 15 of the 24 components of one solid without sliding bodies or face-plane drag)
      ndep = deposit_size(ns, self%solid%sliding, self%solid%plane_drag)
      allocate(self%dep(ndep, grid%lbc(1):grid%ubc(1), grid%lbc(2):grid%ubc(2), &
        grid%lbc(3):grid%ubc(3)), source=0.0_wp)
      if (any(self%so%static)) allocate(self%static_dep, mold=self%dep)
      allocate(self%du(6, grid%lbn(1):grid%ubn(1), grid%lbn(2):grid%ubn(2), &
        grid%lbn(3):grid%ubn(3)), source=0.0_wp)
      allocate(self%contact_dv(3, grid%lbn(1):grid%ubn(1), grid%lbn(2):grid%ubn(2), &
        grid%lbn(3):grid%ubn(3)), source=0.0_wp)
      allocate(self%contact_acc, self%contact_f, mold=self%contact_dv)
      self%contact_acc = 0.0_wp
      self%contact_f = 0.0_wp
      if (self%solid%sliding) call contact_force_init(self%forces, self%so, grid, &
        io_join_path(trim(par%mpm%run%output_dir), trim(par%mpm%run%name) // '_contact_force.csv'))
      allocate(self%phi_p(grid%lbc(1):grid%ubc(1), grid%lbc(2):grid%ubc(2), &
        grid%lbc(3):grid%ubc(3)), source=0.0_wp)
      call halo_init(self%halo, dom, grid, max(ndep, size(self%du, 1)))
      allocate(self%uprev(3, grid%lbc(1):grid%ubc(1), grid%lbc(2):grid%ubc(2), &
        grid%lbc(3):grid%ubc(3), par%ice%nfluids), source=0.0_wp)
      allocate(self%nbuf(grid%lbn(1):grid%ubn(1), grid%lbn(2):grid%ubn(2), &
        grid%lbn(3):grid%ubn(3)), source=0.0_wp)
      allocate(self%temp_old, self%dtemp, mold=self%phi_p)
      self%temp_old = 0.0_wp
      self%dtemp = 0.0_wp

      ! the initial solid fraction; the fluids fill the pores (their fractions scaled by n); with
      ! sliding rigid bodies a second deposit knows their wall cells (solid_deposit)
      call deposit_solids(self, dom, grid)
      if (self%solid%sliding) call deposit_solids(self, dom, grid)
      self%solid%vfrac = self%phi_p
      ! ghosts beyond a domain face mirror the inner cell, like the fluids' bulk densities
      call ice_bc_fill(grid, self%fl%bc, self%solid%vfrac, bc_scalar)
      self%phi_p = self%solid%vfrac
      self%solid%source = 0.0_wp
      do m = 1, self%fl%state%nfluids
        associate (f => self%fl%state%fluid(m))
          f%rho = f%rho * (1.0_wp - self%phi_p)
        end associate
      end do
      call exchange_primitives(self%fl)
      call open_face_reservoirs(self%fl%state, self%solid, grid)
      call ice_equilibrate(self%fl%state, grid, self%fl%eq_tolerance, self%fl%eq_max, its, failed, &
        solid=self%solid)
      if (global_sum(dom, failed) > 0) call fatal('mpmice scene: initial pressure equilibration ' &
        // 'with the solid failed')
      ! geostatic stress: the skeleton carries the grains' submerged weight (a restart has it)
      if (.not. self%so%restored) then
        do s = 1, ns
          if (par%mpm%solids(s)%geostatic .and. .not. self%coupling(s)%rigid) then
            call buoyant_geostatic_stress(self%so%parts(s), self%fl%state, grid, &
            par%mpm%solids(s)%density)
          end if
        end do
      end if
      call log_info('mpmice: ' // int_text(ns) // ' solids, ' // int_text(par%ice%nfluids) // &
        ' fluids, drag ' // trim(par%coupling%drag_scheme))
    end associate
  end subroutine mpmice_setup

  !> Deposit every solid's particles into the cells, sum the halo, and set the cell fields of the
  !! solid phase; `phi_p` gets the particles' solid fraction.
  subroutine deposit_solids(self, dom, grid, dt)
    class(mpmice_scene_t), intent(inout) :: self  !< scene
    type(domain_t), intent(in) :: dom             !< decomposition
    type(grid_t), intent(in) :: grid              !< block geometry
    real(wp), intent(in), optional :: dt          !< step [s]: face-plane fractions swept over it
    integer :: s, ns
    ns = size(self%coupling)
    ! a static rigid solid deposits the same every step (no motion, no sweep; its heat only
    ! when the solid's conduction changed its temperature): kept in static_dep
    if (allocated(self%static_dep)) then
      if (.not. self%static_dep_ready) then
        self%static_dep = 0.0_wp
        do s = 1, ns
          if (self%so%static(s)) call solid_deposit(self%so%parts(s), s, ns, &
            self%coupling(s), grid, self%static_dep, self%solid%sliding, &
            halves=self%solid%plane_drag)
        end do
        self%static_dep_ready = .true.
      end if
      self%dep = self%static_dep
    else
      self%dep = 0.0_wp
    end if
    do s = 1, ns
      if (self%so%static(s)) cycle
      call solid_deposit(self%so%parts(s), s, ns, self%coupling(s), grid, self%dep, &
        self%solid%sliding, self%solid%frac_rigid, dt, self%solid%plane_drag)
    end do
    ! a particle's domain reaches one cell beyond its own; with sliding rigid bodies its
    ! deposit over a wall cell goes on to that cell's neighbours (`wall_neighbours`), one more
    call halo_reverse_cell_vec(self%halo, dom, grid, self%dep, width=merge(2, 1, &
      self%solid%sliding))
    call solid_cell_fields(self%fl%state, self%solid, grid, self%dep, self%coupling, &
      self%max_fraction, self%phi_p)
    ! the solid's conduction sees the fluid's thermal conditions at the domain faces
    call ice_bc_fill(grid, self%fl%bc, self%solid%conductance, bc_scalar)
    call ice_bc_fill(grid, self%fl%bc, self%solid%temp, bc_temperature)
  end subroutine deposit_solids

  !> The smallest of the fluid (advective CFL, viscosity, conduction), solid (wave speed) and
  !! solid conduction (cfl times `solid_conduction_dt`) limits; counts which one set it
  !! (`limit_steps`, reported by the summary).
  function mpmice_stable_dt(self, cfl) result(dt)
    class(mpmice_scene_t), intent(inout) :: self  !< scene
    real(wp), intent(in) :: cfl                   !< Courant number
    real(wp) :: dt
    real(wp) :: limits(size(limit_names))
    integer :: which
    limits = [ice_fluids_stable_dt(self%fl, cfl, self%solid), self%so%stable_dt(cfl), &
      cfl * global_min(self%ctx%dom, solid_conduction_dt(self%solid, self%ctx%grid))]
    which = minloc(limits, dim=1)
    dt = limits(which)
    self%limit_steps(which) = self%limit_steps(which) + 1
  end function mpmice_stable_dt

  !> One coupled step (module header); rejected when the pressure iteration or the
  !! equilibration fails, with the state it had changed by then (the cell pressure, the fluids'
  !! final face velocities) put back, so the retry starts from the accepted state.
  subroutine mpmice_step(self, time, dt, accepted)
    class(mpmice_scene_t), intent(inout) :: self  !< scene
    real(wp), intent(in) :: time                  !< time at the start of the step [s]
    real(wp), intent(in) :: dt                    !< step [s]
    logical, intent(out) :: accepted              !< the step was taken
    integer :: s, m, d
    real(wp) :: g(3), alpha

    accepted = .false.
    call ice_step_begin(self%fl)
    associate (fl => self%fl, so => self%so, st => self%fl%state, dom => self%ctx%dom, &
      grid => self%ctx%grid, timers => self%ctx%timers)
      ! MPM: P2G with the effective stress and the loads, nodal v^{L-}
      call timer_start(timers, so%t_p2g)
      call p2g_solids(so, grid)
      do s = 1, so%nsolids
        if (so%mats(s)%model == model_rigid) cycle
        call surface_load_scatter(self%loads(s), so%parts(s), so%nodes%q, so%shape_kind, &
          grid, time + dt)
      end do
      call p2g_complete(so%nodes, dom, grid, so%halo)
      call timer_stop(timers, so%t_p2g)
      call timer_start(timers, so%t_nodal)
      g = mpm_gravity(so, time + dt)
      ! the damping of the solid's own force here, or of the whole increment after the fluids'
      alpha = merge(0.0_wp, mpm_damping(so, time), so%damp_total)
      call nodal_bc_at_time(so%bc, time + dt)
      if (self%solid%sliding) then
        call contact_pressure_accel(st, self%solid, grid, so%nodes, so%min_mass, self%contact_acc)
        call nodal_solve(so%nodes, grid, g, alpha, dt, so%bc, so%min_mass, &
          self%contact_dv, self%contact_acc)
      else
        call nodal_solve(so%nodes, grid, g, alpha, dt, so%bc, so%min_mass)
      end if
      call timer_stop(timers, so%t_nodal)

      ! solid phase on the grid; the particles' fraction beyond the tracked one is a source
      call timer_start(timers, self%t_cells)
      call deposit_solids(self, dom, grid, dt)
      do s = 1, so%nsolids
        if (self%coupling(s)%suspension_settling) then
          call suspension_settling(so%parts(s), so%mats(s), grid, self%solid, st, &
            self%coupling(s)%grain_density, fl%gravity, dt)
        end if
        if (self%coupling(s)%suspension_cell_bound) then
          call suspension_packing(so%parts(s), so%mats(s), s, grid, self%dep)
        end if
      end do
      self%solid%source = self%relaxation * (self%phi_p - self%solid%vfrac)
      ! a residual where the particles have left goes at once (docs/mpmice.md departure 18)
      where (self%phi_p <= 0.0_wp .and. self%solid%vfrac < residual_fraction) &
        self%solid%source = -self%solid%vfrac
      ! sliding rigid bodies: the wall cells keep their tracked fraction (a soil's overlap with
      ! them is not seen, mpmice_rigid_contact%partner_fields)
      if (self%solid%sliding) where (self%solid%frac_rigid >= wall_fraction) &
        self%solid%source = 0.0_wp
      call timer_stop(timers, self%t_cells)

      if (.not. ice_stage_equilibrate(fl, time, self%solid)) return

      ! face velocities of the fluids and of the solid, face exchange with drag
      call timer_start(timers, fl%t_face)
      do m = 1, st%nfluids
        do s = 1, 3
          self%uprev(s, :, :, :, m) = st%fluid(m)%uface(grid%lbc(1):grid%ubc(1), &
            grid%lbc(2):grid%ubc(2), grid%lbc(3):grid%ubc(3), s)
        end do
      end do
      call timer_stop(timers, fl%t_face)
      call ice_stage_face_velocities(fl, dt)
      call timer_start(timers, fl%t_face)
      call fluid_face_predictor_porous(st, self%solid, grid, self%uprev)
      call solid_face_predictor(st, self%solid, grid, so%nodes, dt, so%min_mass)
      call timer_stop(timers, fl%t_face)
      call ice_stage_face_exchange(fl, dt, self%solid)

      ! eq. 35 with the solid's volume flux and coefficient (ice_pressure)
      if (.not. ice_stage_pressure(fl, time, dt, self%solid)) then
        ! non-finite: taken as it is, so the run loop's check fails the run and dumps the state
        if (fl%nonfinite) then
          accepted = .true.
          return
        end if
        ! the retry's porous predictor reads the last accepted final face velocities
        do m = 1, st%nfluids
          do s = 1, 3
            st%fluid(m)%uface(grid%lbc(1):grid%ubc(1), grid%lbc(2):grid%ubc(2), &
              grid%lbc(3):grid%ubc(3), s) = self%uprev(s, :, :, :, m)
          end do
        end do
        call ice_step_reject(fl)
        return
      end if

      call ice_stage_lagrangian(fl, dt, self%solid)

      ! the solid's pressure force and drag, from the faces back to the nodes
      call timer_start(timers, self%t_nodes)
      call solid_face_to_nodes(self%solid, grid, dom, self%halo, so%nodes, self%du, so%min_mass)
      if (so%damp_total) then
        alpha = mpm_damping(so, time)
        if (alpha > 0.0_wp) call nodal_damp(so%nodes, grid, alpha, so%min_mass)
      end if
      if (self%solid%sliding) then
        call nodal_finish(so%nodes, grid, dt, so%bc, so%min_mass, self%contact_dv, &
          self%contact_f)
      else
        call nodal_finish(so%nodes, grid, dt, so%bc, so%min_mass)
      end if
      call timer_stop(timers, self%t_nodes)

      ! the fluids' drag toward the solid's final velocity (eqs. 50-51)
      call timer_start(timers, fl%t_lagrange)
      call solid_cell_velocity(self%solid, grid, so%nodes, so%min_mass)
      ! the ghosts too: the next step's drag in the ghost cells takes its slip from them
      ! (`solid_cell_fields`), and the faces of the block's edge take that drag
      do d = 1, 3
        call halo_exchange_cell(self%halo, dom, grid, self%solid%vel(:, :, :, d))
      end do
      ! the solid's heat: conduction (38-39), then the exchange with the fluids (52-55) in
      ! the cell exchange, the increments back to the particles (68, 73)
      self%temp_old = self%solid%temp
      call solid_conduction(self%solid, grid, dt, self%dtemp)
      call timer_stop(timers, fl%t_lagrange)
      call ice_stage_cell_exchange(fl, dt, self%solid)
      call timer_start(timers, fl%t_lagrange)
      call fluid_face_blend(st, self%solid, grid)
      self%dtemp = self%solid%temp - self%temp_old
      call halo_exchange_cell(fl%halo, dom, grid, self%dtemp)
      ! isothermal scenes: nothing to add, skip the per-particle overlap weights
      if (any(self%dtemp /= 0.0_wp)) then
        do s = 1, so%nsolids
          call solid_heat_to_particles(so%parts(s), grid, self%dtemp)
        end do
        self%static_dep_ready = .false.  ! the static solids' heat deposit changed
      end if
      call timer_stop(timers, fl%t_lagrange)

      ! fluid advection; traces of a fluid in the pores take the cell's mixture values
      call ice_stage_advect(fl, time, dt, traces=.true., solid=self%solid)

      call timer_start(timers, self%t_cells)
      call solid_track_fraction(st, self%solid, grid, dt, self%max_fraction)
      call halo_exchange_cell(fl%halo, dom, grid, self%solid%vfrac)
      call ice_bc_fill(grid, fl%bc, self%solid%vfrac, bc_scalar)
      call open_face_reservoirs(st, self%solid, grid)
      call timer_stop(timers, self%t_cells)

      call mpm_stage_g2p(so, time, dt)
      call timer_start(timers, so%t_g2p)
      do s = 1, so%nsolids
        call solid_pore_pressure(so%parts(s), grid, st%pressure)
      end do
      call timer_stop(timers, so%t_g2p)
      call mpm_migrate_all(so, time + dt)
      call ice_pressure_average_step(fl, dt)
      fl%steps = fl%steps + 1
      if (self%solid%sliding) call contact_force_write(self%forces, so, st, self%solid, fl%halo, &
        dom, grid, time + dt, self%dep, self%contact_f, fl%gravity)
    end associate
    accepted = .true.
  end subroutine mpmice_step

  !> The solids' health (`mpm_health`) with the power of their surface loads added; the fluids'
  !! forces on the solids (pressure gradient, drag) are not counted as loads.
  subroutine mpmice_health(self, time, health)
    class(mpmice_scene_t), intent(inout) :: self     !< scene
    real(wp), intent(in) :: time                     !< time of the state [s]
    type(scene_health_t), intent(out) :: health      !< energy, load power, particle counts
    real(wp) :: power
    integer :: s
    call self%so%health(time, health)
    power = 0.0_wp
    do s = 1, self%so%nsolids
      if (self%so%mats(s)%model == model_rigid) cycle
      power = power + surface_load_power(self%loads(s), self%so%parts(s), time)
    end do
    health%load_power = health%load_power + global_sum(self%ctx%dom, power)
  end subroutine mpmice_health


  !> Fluid and solid datasets, plus `cell/solid_volume_fraction` (the tracked phi_s) and
  !! `cell/porosity`; a checkpoint adds the tracked fraction and the solid cell velocity.
  subroutine mpmice_write_state(self, file, checkpoint)
    class(mpmice_scene_t), intent(inout) :: self  !< scene
    type(h5_file_t), intent(in) :: file           !< open file
    logical, intent(in) :: checkpoint             !< full restart state
    call self%fl%write_state(file, checkpoint)
    call self%so%write_state(file, checkpoint)
    call solid_state_write(file, self%ctx%grid, self%fl%state, self%solid, self%nbuf, self%phi_p, checkpoint)
  end subroutine mpmice_write_state

  !> Fluids, particles and the tracked solid fraction of a checkpoint.
  subroutine mpmice_restore(self, file)
    class(mpmice_scene_t), intent(inout) :: self  !< scene
    type(h5_file_t), intent(in) :: file           !< open checkpoint
    call self%fl%restore(file)
    call self%so%restore(file)
    self%static_dep_ready = .false.  ! from the restored particles, as the continuing run had it
    call solid_state_restore(file, self%ctx%dom, self%ctx%grid, self%fl, self%solid, self%halo, self%nbuf)
  end subroutine mpmice_restore

  !> Datasets of both parts and of the solid phase.
  subroutine mpmice_output_layout(self, cell_paths, particle_sets)
    class(mpmice_scene_t), intent(in) :: self                            !< scene
    character(len=name_len), allocatable, intent(out) :: cell_paths(:)   !< cell dataset paths
    type(xdmf_particles_t), allocatable, intent(out) :: particle_sets(:) !< particle sets
    character(len=name_len), allocatable :: fluid_paths(:), solid_paths(:)
    type(xdmf_particles_t), allocatable :: none(:)
    call self%fl%output_layout(fluid_paths, none)
    call self%so%output_layout(solid_paths, particle_sets)
    allocate(cell_paths(size(fluid_paths) + size(solid_paths) + 2))
    cell_paths(1:size(fluid_paths)) = fluid_paths
    cell_paths(size(fluid_paths) + 1:size(fluid_paths) + size(solid_paths)) = solid_paths
    cell_paths(size(cell_paths) - 1) = 'cell/solid_volume_fraction'
    cell_paths(size(cell_paths)) = 'cell/porosity'
  end subroutine mpmice_output_layout

  !> Both parts finite.
  function mpmice_all_finite(self) result(finite)
    class(mpmice_scene_t), intent(in) :: self  !< scene
    logical :: finite, solids_finite
    ! both parts evaluated (a function call inside .and. may be skipped)
    finite = self%fl%all_finite()
    solids_finite = self%so%all_finite()
    finite = finite .and. solids_finite
    associate (lo => self%ctx%grid%lo, hi => self%ctx%grid%hi)
      finite = finite .and. all(ieee_is_finite(self%solid%vfrac(lo(1):hi(1), &
        lo(2):hi(2), lo(3):hi(3))))
    end associate
  end function mpmice_all_finite

  !> Statistics of both parts.
  subroutine mpmice_summary(self)
    class(mpmice_scene_t), intent(inout) :: self  !< scene
    integer :: m, total
    character(len=:), allocatable :: line
    call self%fl%summary()
    call self%so%summary()
    total = sum(self%limit_steps)
    if (total == 0) return
    line = 'mpmice: step limit set by'
    do m = 1, size(limit_names)
      line = line // ' ' // trim(limit_names(m)) // ' in ' // int_text(self%limit_steps(m)) // &
        ' steps (' // real_short_text(100.0_wp * real(self%limit_steps(m), wp) / real(total, wp)) // &
        ' %)' // trim(merge(',', ' ', m < size(limit_names)))
    end do
    call log_info(trim(line) // ' of ' // int_text(total))
  end subroutine mpmice_summary

  !> Release everything.
  subroutine mpmice_free(self)
    class(mpmice_scene_t), intent(inout) :: self  !< scene
    call self%fl%free()
    call self%so%free()
    call solid_phase_free(self%solid)
    call halo_free(self%halo)
    if (allocated(self%dep)) deallocate(self%dep, self%du, self%phi_p, self%uprev, self%nbuf, &
      self%temp_old, self%dtemp, self%contact_dv, self%contact_acc, self%contact_f)
    call contact_force_free(self%forces)
    if (allocated(self%static_dep)) deallocate(self%static_dep)
    self%static_dep_ready = .false.
    if (allocated(self%coupling)) deallocate(self%coupling, self%loads)
  end subroutine mpmice_free
end module mpmice_scene
