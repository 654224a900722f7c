!> Range and consistency checks of a configuration.
!!
!! `config_check` finds the first invalid variable (groups in echo order; in each group the range
!! checks the namelist list declares, `config_validate_ranges`, in list order, and the checks
!! written here) and describes it in a `config_error_t`: group, variable, value as text and the
!! allowed range. Checks that depend on the number of ranks (cells per block, `dims`) use the same
!! `choose_dims` as the decomposition, so a configuration that passes can be decomposed. The
!! multiphase groups and the scene-dependent checks are in `config_validate_phases`; an error in
!! occurrence k of a repeated group names the group `fluid(k)`.
module config_validate
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use mpmice_kinds, only: wp, i8
  use parallel_domain, only: choose_dims, blocks_given
  use parallel_balance, only: block_layouts
  use config_types, only: config_t, max_blocks_per_dim
  use config_text, only: real_repr, reals_repr, ints_repr, quoted
  use config_check_tools, only: config_error_t, set_error
  use config_validate_ranges, only: check_run_ranges, check_grid_ranges, check_time_ranges, &
    check_numerics_ranges, check_solver_ranges, check_output_ranges, check_heat_ranges
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
    call check_time_ranges(cfg%time, 'time', err)
    if (err%found) return
    call check_numerics_ranges(cfg%numerics, 'numerics', err)
    if (err%found) return
    call check_solver_ranges(cfg%solver, 'solver', err)
    if (err%found) return
    call check_output_ranges(cfg%output, 'output', err)
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
      call check_run_ranges(p, 'run', err)
      if (err%found) return
      if (len_trim(p%output_dir) == 0) then
        call set_error(err, 'run', 'output_dir', quoted(p%output_dir), 'a non-empty path')
        return
      end if
      if (trim(p%scene) /= 'mpm' .and. trim(p%scene) /= 'mpmice') then
        if (p%max_energy_growth > 0.0_wp) then
          call set_error(err, 'run', 'max_energy_growth', real_repr(p%max_energy_growth), &
            '0 for scene ''' // trim(p%scene) // ''' (the stop watches solids: mpm, mpmice)')
        else if (p%max_particle_loss_fraction < 1.0_wp) then
          call set_error(err, 'run', 'max_particle_loss_fraction', &
            real_repr(p%max_particle_loss_fraction), '1 for scene ''' // trim(p%scene) // &
            ''' (the stop counts particles: mpm, mpmice)')
        end if
      end if
    end associate
  end subroutine check_run

  !> `&grid`, including the checks that depend on the number of ranks.
  subroutine check_grid(cfg, nranks, err)
    type(config_t), intent(in) :: cfg           !< configuration
    integer, intent(in) :: nranks               !< number of ranks
    type(config_error_t), intent(inout) :: err  !< problem record
    logical :: active(3)
    integer :: dims(3), d, requested, need, request(3), given(3), nlayouts
    integer, allocatable :: layouts(:, :)
    logical :: ok
    character(len=:), allocatable :: ranks_text, rank_variable, rank_value, rank_rule

    ok = .false.
    call check_grid_ranges(cfg%grid, 'grid', err)
    if (err%found) return
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
      if (p%rebalance .and. trim(p%balance) /= 'cost') then
        call set_error(err, 'grid', 'rebalance', '.true.', &
          ".false., or balance = 'cost' (balance = " // quoted(p%balance) // ')')
        return
      end if
      if (p%rebalance .and. .not. cfg%run%checkpoint_interval > 0.0_wp) then
        call set_error(err, 'grid', 'rebalance', '.true.', &
          '.false., or &run checkpoint_interval > 0 (the blocks move at checkpoints; ' // &
          'checkpoint_interval = ' // real_repr(cfg%run%checkpoint_interval) // ')')
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
      nlayouts = 0
      if (nranks > 1) then
        ! 'cost' takes the layout from those that fit (`block_layouts`), not only this one
        call block_layouts(nranks, active, request, p%ncells, max(p%ghost_width, 1), &
          max_blocks_per_dim, dims, layouts, nlayouts)
        if (nlayouts > 0 .and. trim(p%balance) == 'cost') dims = layouts(:, 1)
      end if
      do d = 1, 3
        ! given blocks were checked against the ghost width by check_block_cells
        if (.not. active(d) .or. given(d) > 0) cycle
        if (p%ncells(d) / dims(d) < p%ghost_width) then
          call set_error(err, 'grid', 'ncells', ints_repr(p%ncells), &
            'at least ghost_width (' // ints_repr([p%ghost_width]) // &
            ') cells per block along each active dimension (' // ranks_text // ' split ' // &
            ints_repr(dims(1:1)) // ' x ' // ints_repr(dims(2:2)) // ' x ' // &
            ints_repr(dims(3:3)) // '; ' // fitting_layout(layouts, nlayouts) // ')')
          return
        end if
      end do
    end associate
  end subroutine check_grid

  !> The advice of the ghost-width error: a layout that fits (`block_layouts`), or fewer ranks.
  function fitting_layout(layouts, nlayouts) result(text)
    integer, intent(in) :: layouts(:, :)   !< (3, nlayouts) layouts that fit
    integer, intent(in) :: nlayouts        !< their number
    character(len=:), allocatable :: text
    if (nlayouts > 0) then
      text = 'the layout ' // ints_repr(layouts(:, 1)) // ' fits: set &grid dims = ' // &
        ints_repr(layouts(:, 1)) // ", or balance = 'cost'"
    else
      text = 'use fewer ranks'
    end if
  end function fitting_layout

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

  !> `&heat`.
  subroutine check_heat(cfg, err)
    type(config_t), intent(in) :: cfg           !< configuration
    type(config_error_t), intent(inout) :: err  !< problem record
    call check_heat_ranges(cfg%heat, 'heat', err)
    if (err%found) return
    if (any(cfg%grid%ncells > 1 .and. cfg%heat%modes < 1)) then
      call set_error(err, 'heat', 'modes', ints_repr(cfg%heat%modes), &
        'each entry >= 1 along active dimensions')
    end if
  end subroutine check_heat
end module config_validate
