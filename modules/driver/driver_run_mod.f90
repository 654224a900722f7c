!> Run driver: decomposition, output directory and input echo, scene dispatch, final status;
!! with `&grid rebalance`, the run's continuation on new blocks from the checkpoint where the
!! time loop found them (`driver_loop%run_segment_t`).
module driver_run_mod
  use, intrinsic :: iso_fortran_env, only: error_unit
  use parallel_comm, only: MPI_Comm, bcast
  use mpmice_kinds, only: msg_len
  use mpmice_errors, only: exit_cleanly, int_text
  use mpmice_log, only: log_info, log_is_root, log_warning, log_open_file, log_close_file
  use mpmice_build_info, only: mpmice_version
  use config_types, only: config_t, max_blocks_per_dim
  use config_echo, only: config_to_text, config_write_used, config_used_path
  use parallel_domain, only: grid_init, domain_t, domain_init, domain_free
  use grid_layout, only: grid_t
  use driver_preflight, only: preflight_output_dir
  use driver_balance, only: run_block_cells
  use driver_loop, only: run_scene, run_status_t, run_segment_t
  use scene_params, only: scene_params_t
  use driver_scene_params, only: scene_params_from_config
  implicit none
  private

  public :: driver_run

contains

  !> Run the scene described by `cfg` (read from `source_file`), or continue it from
  !! `restart_file` ('' when not restarting) on the ranks of `comm` (the program's duplicate of
  !! the world communicator). Ends the process with status 3 if the run failed.
  subroutine driver_run(cfg, source_file, restart_file, comm)
    type(config_t), intent(in) :: cfg                  !< validated configuration
    character(len=*), intent(in) :: source_file        !< case file the configuration came from
    character(len=*), intent(in) :: restart_file       !< checkpoint to continue, '' if none
    type(MPI_Comm), intent(in) :: comm                 !< the program's communicator
    type(domain_t), target :: dom
    type(grid_t), target :: grid
    type(run_status_t) :: status
    type(run_segment_t) :: segment
    class(scene_params_t), allocatable :: params
    character(len=:), allocatable :: text
    character(len=msg_len) :: errmsg
    character(len=:), allocatable :: log_msg, dir_errmsg
    character(len=msg_len) :: balance_report
    character(len=:), allocatable :: report_text
    integer :: stat, block_cells(max_blocks_per_dim, 3)

    block_cells = run_block_cells(cfg, comm, restart_file, balance_report)
    call domain_init(dom, comm, cfg%grid%ncells, cfg%grid%periodic, cfg%grid%ghost_width, &
      cfg%grid%dims, block_cells)
    call grid_init(grid, dom, cfg%grid%lower, cfg%grid%upper)
    text = config_to_text(cfg)

    ! Output directory (refused when unusable or holding another run's output) and the echo of
    ! the resolved input (rank 0); a failure is one line on standard error, exit status 1.
    stat = 0
    errmsg = ''
    if (dom%rank == 0) then
      call preflight_output_dir(cfg, restart_file, stat, dir_errmsg)
      if (stat /= 0) then
        errmsg = dir_errmsg
      else
        call config_write_used(cfg, config_used_path(cfg), stat, errmsg)
        if (stat /= 0) errmsg = 'mpmice: error: cannot write to &run output_dir = ''' // &
          trim(cfg%run%output_dir) // ''' ' // trim(errmsg)
      end if
      if (stat /= 0) then
        write(error_unit, '(a)') trim(errmsg)
        flush(error_unit)
      end if
    end if
    call bcast(dom%comm, stat, 0)
    if (stat /= 0) call exit_cleanly(1)

    ! The log file: every line printed from here on (progress, warnings, the timer table).
    call log_open_file(log_path(cfg), len(restart_file) > 0, stat, log_msg)
    if (stat /= 0) call log_warning('no log file ' // log_path(cfg) // ': ' // log_msg)

    call log_info('mpmice: scene ' // trim(cfg%run%scene) // ' from ' // trim(source_file) // &
      ' on ' // int_text(dom%nranks) // ' ranks, blocks ' // int_text(dom%dims(1)) // ' x ' // &
      int_text(dom%dims(2)) // ' x ' // int_text(dom%dims(3)) // ', cells ' // &
      int_text(grid%ncells(1)) // ' x ' // int_text(grid%ncells(2)) // ' x ' // &
      int_text(grid%ncells(3)))
    if (trim(cfg%grid%balance) == 'cost') then
      report_text = trim(balance_report)
      if (len(report_text) > 0) report_text = '; ' // report_text
      if (len(restart_file) > 0) report_text = ' (particles counted in the checkpoint)' // &
        report_text
      call log_info('mpmice: blocks balanced by cost: ' // block_text(dom) // report_text)
    end if
    call log_info('mpmice: output in ' // trim(cfg%run%output_dir) // ', resolved input ' // &
      config_used_path(cfg))
    call log_info('mpmice: version ' // mpmice_version)

    call scene_params_from_config(cfg, params)
    call run_scene(params, cfg, text, dom, grid, restart_file, status, segment)
    do while (len_trim(segment%rebalance_from) > 0)
      call domain_free(dom)
      call domain_init(dom, comm, cfg%grid%ncells, cfg%grid%periodic, cfg%grid%ghost_width, &
        cfg%grid%dims, segment%block_cells)
      call grid_init(grid, dom, cfg%grid%lower, cfg%grid%upper)
      call log_info('mpmice: blocks rebalanced at ' // trim(segment%rebalance_from) // ': ' // &
        block_text(dom) // '; ' // trim(segment%blocks_report))
      call run_scene(params, cfg, text, dom, grid, trim(segment%rebalance_from), status, &
        segment)
    end do

    call domain_free(dom)
    if (status%exit_code /= 0) then
      if (log_is_root()) call log_info('mpmice: run failed: ' // trim(status%reason))
      call exit_cleanly(status%exit_code)
    end if
    call log_info('mpmice: ' // trim(status%reason))
    call log_close_file()
  end subroutine driver_run

  !> The cells of each block along the split dimensions, e.g. 'x 190, 310'.
  function block_text(dom) result(text)
    type(domain_t), intent(in) :: dom  !< decomposition
    character(len=:), allocatable :: text
    character(len=*), parameter :: axes = 'xyz'
    integer :: d, c
    text = ''
    do d = 1, 3
      if (dom%dims(d) < 2) cycle
      if (len(text) > 0) text = text // '; '
      text = text // axes(d:d)
      do c = 1, dom%dims(d)
        text = text // merge(' ', ',', c == 1) // int_text(dom%first_cell(c, d) - &
          dom%first_cell(c - 1, d))
      end do
    end do
    if (len(text) == 0) text = 'one block'
  end function block_text

  !> Path of the run's log file: `<output_dir>/<name>.log`.
  function log_path(cfg) result(path)
    type(config_t), intent(in) :: cfg  !< configuration
    character(len=:), allocatable :: path
    path = trim(cfg%run%output_dir) // '/' // trim(cfg%run%name) // '.log'
  end function log_path
end module driver_run_mod
