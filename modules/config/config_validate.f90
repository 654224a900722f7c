!> Range and consistency checks of a configuration.
!!
!! `config_check` finds the first invalid variable (groups in echo order, variables in table
!! order) and describes it in a `config_error_t`: group, variable, value as text and the allowed
!! range. Checks that depend on the number of ranks (cells per block, `dims`) use the same
!! `choose_dims` as the decomposition, so a configuration that passes can be decomposed. The
!! multiphase groups and the scene-dependent checks are in `config_validate_phases`; an error in
!! occurrence k of a repeated group names the group `fluid(k)`.
module config_validate
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use mpmice_kinds, only: wp, i8
  use parallel_domain, only: choose_dims, blocks_given
  use config_types, only: config_t, scene_names, shape_function_names
  use config_text, only: real_repr, reals_repr, ints_repr, quoted
  use config_check_tools, only: config_error_t, set_error, check_real, check_int, check_choice
  use config_validate_phases, only: check_phases
  implicit none
  private

  public :: config_error_t, config_check, ghost_width_needed

  !> Axis letters of the per-dimension variables (`block_cells_x`, ...).
  character(len=3), parameter :: axis_names = 'xyz'

contains

  !> Check every variable of `cfg` for a run on `nranks` ranks; `err%found` tells if one is bad.
  !! Calls `MPI_Dims_create` (through `choose_dims`) when `nranks > 1`: MPI must be initialised.
  subroutine config_check(cfg, nranks, err)
    type(config_t), intent(in) :: cfg          !< configuration to check
    integer, intent(in) :: nranks              !< number of ranks of the run
    type(config_error_t), intent(out) :: err   !< first problem, if any
    call check_run(cfg, err)
    if (err%found) return
    call check_grid(cfg, nranks, err)
    if (err%found) return
    call check_time(cfg, err)
    if (err%found) return
    call check_numerics(cfg, err)
    if (err%found) return
    call check_solver(cfg, err)
    if (err%found) return
    call check_output(cfg, err)
    if (err%found) return
    call check_heat(cfg, err)
    if (err%found) return
    call check_phases(cfg, err)
  end subroutine config_check

  !> Ghost layers the numerics need: `advection_order` cells for advection, 2 for GIMP and 1 for
  !! linear shape functions, 2 for the Smagorinsky model (the strain rate of the ghost cells).
  pure integer function ghost_width_needed(cfg)
    type(config_t), intent(in) :: cfg  !< configuration
    ghost_width_needed = max(cfg%numerics%advection_order, 1)
    if (cfg%numerics%shape_function == 'gimp') ghost_width_needed = max(ghost_width_needed, 2)
    if (cfg%ice%smagorinsky) ghost_width_needed = max(ghost_width_needed, 2)
  end function ghost_width_needed

  !> `&run`.
  subroutine check_run(cfg, err)
    type(config_t), intent(in) :: cfg           !< configuration
    type(config_error_t), intent(inout) :: err  !< problem record
    character(len=*), parameter :: name_chars = 'abcdefghijklmnopqrstuvwxyz' // &
      'ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-.'
    associate (p => cfg%run)
      if (len_trim(p%name) == 0 .or. verify(trim(p%name), name_chars) > 0) then
        call set_error(err, 'run', 'name', quoted(p%name), &
          'non-empty, letters, digits, ''_'', ''-'' and ''.'' only (a file name prefix)')
        return
      end if
      call check_choice(err, 'run', 'scene', p%scene, scene_names)
      if (err%found) return
      if (len_trim(p%output_dir) == 0) then
        call set_error(err, 'run', 'output_dir', quoted(p%output_dir), 'a non-empty path')
        return
      end if
      call check_real(err, 'run', 'end_time', p%end_time, '>= 0 [s]', min_value=0.0_wp)
      call check_real(err, 'run', 'output_interval', p%output_interval, &
        '>= 0 [s] (0: first and last state only)', min_value=0.0_wp)
      call check_real(err, 'run', 'checkpoint_interval', p%checkpoint_interval, &
        '>= 0 [s] (0: no checkpoints)', min_value=0.0_wp)
      call check_int(err, 'run', 'max_steps', p%max_steps, '>= 0 (0: unlimited)', min_value=0)
      call check_real(err, 'run', 'wall_time_limit', p%wall_time_limit, &
        '>= 0 [s] (0: no limit)', min_value=0.0_wp)
      if (p%max_energy_growth /= 0.0_wp) call check_real(err, 'run', 'max_energy_growth', &
        p%max_energy_growth, '0 (off) or > 1', min_value=1.0_wp, min_open=.true.)
      call check_real(err, 'run', 'max_particle_loss_fraction', p%max_particle_loss_fraction, &
        '0 <= f <= 1 (1: off)', min_value=0.0_wp, max_value=1.0_wp)
      call check_real(err, 'run', 'min_dt_ratio', p%min_dt_ratio, '0 <= r < 1 (0: off)', &
        min_value=0.0_wp, max_value=1.0_wp, max_open=.true.)
      if (.not. err%found .and. trim(p%scene) /= 'mpm' .and. trim(p%scene) /= 'mpmice') then
        if (p%max_energy_growth > 0.0_wp) then
          call set_error(err, 'run', 'max_energy_growth', real_repr(p%max_energy_growth), &
            '0 for scene ''' // trim(p%scene) // ''' (the stop watches solids: mpm, mpmice)')
        else if (p%max_particle_loss_fraction < 1.0_wp) then
          call set_error(err, 'run', 'max_particle_loss_fraction', &
            real_repr(p%max_particle_loss_fraction), '1 for scene ''' // trim(p%scene) // &
            ''' (the stop counts particles: mpm, mpmice)')
        end if
      end if
      call check_real(err, 'run', 'progress_interval', p%progress_interval, &
        '>= 0 [s of wall time]', min_value=0.0_wp)
      call check_int(err, 'run', 'verbosity', p%verbosity, '0, 1 or 2', min_value=0, max_value=2)
    end associate
  end subroutine check_run

  !> `&grid`, including the checks that depend on the number of ranks.
  subroutine check_grid(cfg, nranks, err)
    type(config_t), intent(in) :: cfg           !< configuration
    integer, intent(in) :: nranks               !< number of ranks
    type(config_error_t), intent(inout) :: err  !< problem record
    logical :: active(3)
    integer :: dims(3), d, requested, need, request(3), given(3)
    logical :: ok
    character(len=:), allocatable :: ranks_text, rank_variable, rank_value, rank_rule

    ok = .false.
    associate (p => cfg%grid)
      if (any(p%ncells < 1)) then
        call set_error(err, 'grid', 'ncells', ints_repr(p%ncells), 'each entry >= 1')
        return
      end if
      if (.not. all(ieee_is_finite(p%lower))) then
        call set_error(err, 'grid', 'lower', reals_repr(p%lower), 'finite numbers [m]')
        return
      end if
      if (all(ieee_is_finite(p%upper))) then
        if (all(p%upper > p%lower)) ok = .true.
      end if
      if (.not. ok) then
        call set_error(err, 'grid', 'upper', reals_repr(p%upper), &
          'each entry > lower (' // reals_repr(p%lower) // ') [m]')
        return
      end if
      need = ghost_width_needed(cfg)
      if (p%ghost_width < need .or. p%ghost_width > 4) then
        call set_error(err, 'grid', 'ghost_width', ints_repr([p%ghost_width]), &
          ints_repr([need]) // '..4 (advection_order = ' // &
          ints_repr([cfg%numerics%advection_order]) // ', shape_function = ' // &
          quoted(cfg%numerics%shape_function) // ', &ice smagorinsky = ' // &
          trim(merge('.true. ', '.false.', cfg%ice%smagorinsky)) // ')')
        return
      end if

      active = p%ncells > 1
      ranks_text = ints_repr([nranks]) // ' ranks'
      if (any(p%dims < 0) .or. any(.not. active .and. p%dims > 1)) then
        call set_error(err, 'grid', 'dims', ints_repr(p%dims), &
          'each entry >= 0 (0: automatic), 0 or 1 where ncells is 1')
        return
      end if
      call check_block_cells(p%ncells, p%ghost_width, p%dims, p%block_cells, err, given)
      if (err%found) return
      request = merge(given, p%dims, given > 0)
      ! a rank-count mismatch is blamed on dims, or on the first given block list
      rank_variable = 'dims'
      rank_value = ints_repr(p%dims)
      rank_rule = 'product of the non-zero entries'
      do d = 3, 1, -1
        if (given(d) > 0) then
          rank_variable = 'block_cells_' // axis_names(d:d)
          rank_value = ints_repr(p%block_cells(1:given(d), d))
          rank_rule = 'number of entries (blocks) times the given blocks of the other dimensions'
        end if
      end do
      requested = product(merge(request, 1, active .and. request > 0))
      if (all(.not. active .or. request > 0) .and. requested /= nranks .and. any(active)) then
        call set_error(err, 'grid', rank_variable, rank_value, rank_rule // &
          ' = number of ranks (' // ranks_text // ')')
        return
      end if
      if (mod(nranks, requested) /= 0) then
        call set_error(err, 'grid', rank_variable, rank_value, rank_rule // &
          ' divides the number of ranks (' // ranks_text // ')')
        return
      end if
      if (.not. any(active) .and. nranks > 1) then
        call set_error(err, 'grid', 'ncells', ints_repr(p%ncells), &
          'a single-cell grid runs on 1 rank, not ' // ranks_text)
        return
      end if
      if (product(int(p%ncells, i8)) < int(nranks, i8)) then
        call set_error(err, 'grid', 'ncells', ints_repr(p%ncells), &
          'at least one cell per rank (' // ranks_text // ')')
        return
      end if
      dims = 1
      if (nranks > 1) dims = choose_dims(nranks, active, request)
      do d = 1, 3
        ! given blocks were checked against the ghost width by check_block_cells
        if (.not. active(d) .or. given(d) > 0) cycle
        if (p%ncells(d) / dims(d) < p%ghost_width) then
          call set_error(err, 'grid', 'ncells', ints_repr(p%ncells), &
            'at least ghost_width (' // ints_repr([p%ghost_width]) // &
            ') cells per block along each active dimension (' // ranks_text // ' split ' // &
            ints_repr(dims(1:1)) // ' x ' // ints_repr(dims(2:2)) // ' x ' // &
            ints_repr(dims(3:3)) // '; use fewer ranks or set &grid dims)')
          return
        end if
      end do
    end associate
  end subroutine check_grid

  !> `&grid block_cells_x/y/z`: each given list (up to its last non-zero entry) only along an
  !! active dimension, every entry >= ghost_width, the sum = ncells, its length = dims where
  !! dims is given. `given`: the number of blocks each list gives (0: none, an even split).
  subroutine check_block_cells(ncells, ghost_width, dims, block_cells, err, given)
    integer, intent(in) :: ncells(3)                    !< cells per dimension
    integer, intent(in) :: ghost_width                  !< ghost layers
    integer, intent(in) :: dims(3)                      !< requested blocks (0: automatic)
    integer, intent(in) :: block_cells(:, :)            !< cells per block, zero-padded
    type(config_error_t), intent(inout) :: err          !< problem record
    integer, intent(out) :: given(3)                    !< blocks each list gives (0: none)
    integer :: d, n
    character(len=:), allocatable :: variable, value
    given = 0
    do d = 1, 3
      n = blocks_given(block_cells(:, d))
      if (n == 0) cycle
      variable = 'block_cells_' // axis_names(d:d)
      value = ints_repr(block_cells(1:n, d))
      if (ncells(d) == 1) then
        call set_error(err, 'grid', variable, value, 'only along a dimension with ncells > 1 ' // &
          '(ncells = ' // ints_repr(ncells) // ')')
      else if (any(block_cells(1:n, d) < ghost_width)) then
        call set_error(err, 'grid', variable, value, 'each entry >= ghost_width (' // &
          ints_repr([ghost_width]) // ') up to the last block, 0 after it')
      else if (sum(block_cells(1:n, d)) /= ncells(d)) then
        call set_error(err, 'grid', variable, value, 'entries summing to ncells(' // &
          ints_repr([d]) // ') = ' // ints_repr([ncells(d)]))
      else if (dims(d) > 0 .and. dims(d) /= n) then
        call set_error(err, 'grid', variable, value, ints_repr([dims(d)]) // &
          ' entries (&grid dims = ' // ints_repr(dims) // '), or dims(' // ints_repr([d]) // &
          ') = 0')
      end if
      if (err%found) return
      given(d) = n
    end do
  end subroutine check_block_cells

  !> `&time`.
  subroutine check_time(cfg, err)
    type(config_t), intent(in) :: cfg           !< configuration
    type(config_error_t), intent(inout) :: err  !< problem record
    associate (p => cfg%time)
      call check_real(err, 'time', 'cfl', p%cfl, '0 < cfl <= 1', min_value=0.0_wp, &
        max_value=1.0_wp, min_open=.true.)
      call check_real(err, 'time', 'dt_init', p%dt_init, '> 0 [s]', min_value=0.0_wp, &
        min_open=.true.)
      if (err%found) return
      call check_real(err, 'time', 'dt_max', p%dt_max, '>= dt_init (' // real_repr(p%dt_init) &
        // ') [s]', min_value=p%dt_init)
      call check_real(err, 'time', 'dt_min', p%dt_min, '0 < dt_min <= dt_init (' // &
        real_repr(p%dt_init) // ') [s]', min_value=0.0_wp, max_value=p%dt_init, min_open=.true.)
      call check_real(err, 'time', 'dt_growth', p%dt_growth, '>= 1', min_value=1.0_wp)
    end associate
  end subroutine check_time

  !> `&numerics`.
  subroutine check_numerics(cfg, err)
    type(config_t), intent(in) :: cfg           !< configuration
    type(config_error_t), intent(inout) :: err  !< problem record
    associate (p => cfg%numerics)
      call check_int(err, 'numerics', 'advection_order', p%advection_order, '1 or 2', &
        min_value=1, max_value=2)
      call check_choice(err, 'numerics', 'shape_function', p%shape_function, &
        shape_function_names)
      call check_real(err, 'numerics', 'time_theta', p%time_theta, &
        '0.5 <= time_theta <= 1 (1: backward Euler, 0.5: Crank-Nicolson)', min_value=0.5_wp, &
        max_value=1.0_wp)
    end associate
  end subroutine check_numerics

  !> `&solver`.
  subroutine check_solver(cfg, err)
    type(config_t), intent(in) :: cfg           !< configuration
    type(config_error_t), intent(inout) :: err  !< problem record
    associate (p => cfg%solver)
      call check_real(err, 'solver', 'tolerance', p%tolerance, '0 < tolerance < 1 (relative)', &
        min_value=0.0_wp, max_value=1.0_wp, min_open=.true., max_open=.true.)
      call check_int(err, 'solver', 'max_iterations', p%max_iterations, '>= 1', min_value=1)
      call check_int(err, 'solver', 'print_level', p%print_level, '0..3', min_value=0, &
        max_value=3)
    end associate
  end subroutine check_solver

  !> `&output`.
  subroutine check_output(cfg, err)
    type(config_t), intent(in) :: cfg           !< configuration
    type(config_error_t), intent(inout) :: err  !< problem record
    if (len_trim(cfg%output%fields) == 0) then
      call set_error(err, 'output', 'fields', quoted(cfg%output%fields), &
        '''all'' or a list of field names')
    end if
  end subroutine check_output

  !> `&heat`.
  subroutine check_heat(cfg, err)
    type(config_t), intent(in) :: cfg           !< configuration
    type(config_error_t), intent(inout) :: err  !< problem record
    associate (p => cfg%heat)
      call check_real(err, 'heat', 'conductivity', p%conductivity, '> 0 [W/m/K]', &
        min_value=0.0_wp, min_open=.true.)
      call check_real(err, 'heat', 'density', p%density, '> 0 [kg/m^3]', min_value=0.0_wp, &
        min_open=.true.)
      call check_real(err, 'heat', 'heat_capacity', p%heat_capacity, '> 0 [J/kg/K]', &
        min_value=0.0_wp, min_open=.true.)
      call check_real(err, 'heat', 'base_temperature', p%base_temperature, '> 0 [K]', &
        min_value=0.0_wp, min_open=.true.)
      if (err%found) return
      call check_real(err, 'heat', 'amplitude', p%amplitude, '|amplitude| < base_temperature (' &
        // real_repr(p%base_temperature) // ') [K]', min_value=-p%base_temperature, &
        max_value=p%base_temperature, min_open=.true., max_open=.true.)
      if (err%found) return
      if (any(cfg%grid%ncells > 1 .and. p%modes < 1)) then
        call set_error(err, 'heat', 'modes', ints_repr(p%modes), &
          'each entry >= 1 along active dimensions')
      end if
    end associate
  end subroutine check_heat
end module config_validate
