!> The configuration of `mpmice --restart CHECKPOINT [--set ...]`, checked before anything is
!! written (docs/batch.md "What a restart accepts").
!!
!! A restart is refused with one input-error line (exit status 1) when
!! * the checkpoint is missing, unreadable, not HDF5, truncated or corrupt, or is a dump or
!!   another HDF5 file rather than a checkpoint, or has a layout version this build cannot read
!!   (`io_hdf5_probe` opens it with HDF5's error printing off);
!! * a `--set` changes a variable that the checkpoint cannot honour: anything except the
!!   variables of `restart_changeable` (run control, decomposition, time-step limits, solver
!!   and outer-iteration tolerances, output selection). The grid, the scene, the materials,
!!   the boundaries and the initial conditions are those of the stored state;
!! * a solid needs per-particle state that the checkpoint lacks (`model_state`: Cam-Clay's
!!   `hardening`, the densifying sand's `cyclic` and `cyclic_half_time`, the sand's `gap` with
!!   `tension_gap`; a deformable solid's `affine` with `&mpm velocity_transfer = 'apic'`).
!!
!! A restart continues its own run in the checkpoint's folder: unless a `--set` gives another
!! `&run output_dir`, the output folder is the folder that holds the checkpoint (as named on the
!! command line), not the stored `output_dir` read relative to the current working directory.
module driver_restart
  use parallel_comm, only: MPI_Comm, comm_rank, comm_size, bcast, bcast_text
  use mpmice_kinds, only: msg_len
  use mpmice_errors, only: input_error_text, int_text
  use config_types, only: config_t
  use config_parse, only: group_error_text
  use config_load, only: config_load_run, config_resolve, open_stream
  use config_echo, only: config_to_text
  use io_files, only: io_dirname
  use io_hdf5_probe, only: checkpoint_probe_t, h5_probe_checkpoint
  use mpm_constitutive, only: model_state, model_from_name
  use driver_output, only: checkpoint_version
  implicit none
  private

  public :: restart_load, restart_changeable

  !> `group variable` pairs a restart may change with `--set`; every other variable must keep
  !! the value stored in the checkpoint.
  character(len=*), parameter :: restart_changeable(*) = [character(len=40) :: &
    'run output_dir', 'run end_time', 'run output_interval', 'run checkpoint_interval', &
    'run max_steps', 'run wall_time_limit', 'run max_energy_growth', &
    'run max_particle_loss_fraction', 'run min_dt_ratio', 'run progress_interval', &
    'run verbosity', 'run overwrite', 'grid dims', 'grid block_cells_x', 'grid block_cells_y', &
    'grid block_cells_z', 'grid balance', 'grid particle_weight', 'grid rebalance', &
    'time cfl', 'time dt_init', &
    'time dt_max', 'time dt_min', 'time dt_growth', 'solver tolerance', 'solver max_iterations', &
    'solver print_level', 'ice outer_tolerance', 'ice max_outer_iterations', 'output xdmf', &
    'output fields']

  character(len=*), parameter :: nl = achar(10)  !< line end

contains

  !> Collective over `comm`: check the checkpoint `path`, resolve its stored input with the
  !! `--set` texts `sets` and refuse changes it cannot honour; on success `cfg` is the run's
  !! configuration, with `&run output_dir` set to the checkpoint's folder unless a `--set`
  !! changed it. `stat` = 1 and `errmsg` (one input-error line, every rank) otherwise.
  subroutine restart_load(path, sets, comm, cfg, stat, errmsg)
    character(len=*), intent(in) :: path                  !< checkpoint file
    character(len=*), intent(in) :: sets(:)               !< `--set` texts in order
    type(MPI_Comm), intent(in) :: comm                    !< communicator of the run
    type(config_t), intent(out) :: cfg                    !< configuration of the restart
    integer, intent(out) :: stat                          !< 0 ok, 1 input error
    character(len=:), allocatable, intent(out) :: errmsg  !< error line
    type(checkpoint_probe_t) :: info
    type(config_t) :: stored
    character(len=:), allocatable :: text, reason
    integer :: rank, nranks
    logical :: same_dir

    rank = comm_rank(comm)
    nranks = comm_size(comm)
    errmsg = ''
    text = ''
    stat = 0
    if (rank == 0) then
      call check_file_head(path, stat, errmsg)
      if (stat == 0) then
        call h5_probe_checkpoint(path, info, stat, reason)
        if (stat /= 0) then
          errmsg = cannot_restart(path, reason)
        else if (info%version /= checkpoint_version) then
          stat = 1
          errmsg = cannot_restart(path, 'checkpoint layout version ' // int_text(info%version) &
            // ', this build reads version ' // int_text(checkpoint_version))
        else
          text = info%namelist
        end if
      end if
    end if
    call bcast_status(stat, errmsg, comm)
    if (stat /= 0) return
    call bcast_text(comm, text, 0)

    call config_load_run(cfg, path, sets, comm, stat, errmsg, base_text=text)
    if (stat /= 0) return

    same_dir = .false.
    if (rank == 0) then
      ! the stored input alone, to see what the --set texts changed
      call config_resolve(stored, path, [character(len=1) ::], nranks, stat, errmsg, &
        base_text=text)
      if (stat /= 0) then
        errmsg = cannot_restart(path, 'its stored input is invalid: ' // errmsg)
      else if (any(stored%grid%ncells /= info%ncells) .or. any(stored%grid%lower /= info%lower) &
        .or. any(stored%grid%upper /= info%upper)) then
        stat = 1
        errmsg = cannot_restart(path, 'its grid attributes disagree with its stored input ' // &
          '(corrupt checkpoint)')
      else
        call refuse_changes(config_to_text(stored), config_to_text(cfg), stat, errmsg)
      end if
      if (stat == 0) call check_model_state(path, stored, info%datasets, stat, errmsg)
      same_dir = cfg%run%output_dir == stored%run%output_dir
    end if
    call bcast_status(stat, errmsg, comm)
    if (stat /= 0) return
    call bcast(comm, same_dir, 0)
    if (same_dir) cfg%run%output_dir = io_dirname(path)
  end subroutine restart_load

  !> `stat` = 1 and the error line when a solid of `stored` needs model-specific particle state
  !! (`mpm_constitutive%model_state`) that the checkpoint `path` lacks.
  subroutine check_model_state(path, stored, datasets, stat, errmsg)
    character(len=*), intent(in) :: path                   !< checkpoint
    type(config_t), intent(in) :: stored                   !< its stored input
    character(len=*), intent(in) :: datasets(:)            !< its datasets (`h5_probe_checkpoint`)
    integer, intent(inout) :: stat                         !< 1 on refusal
    character(len=:), allocatable, intent(inout) :: errmsg !< error line
    character(len=:), allocatable :: g, missing
    logical :: hardening, cyclic, gap, affine
    integer :: k
    do k = 1, stored%nsolids
      associate (sp => stored%solids(k))
        call model_state(model_from_name(sp%model), sp%densification_c1, &
          sp%compaction_index, sp%tension_gap, stored%mpm%velocity_transfer, hardening, &
          cyclic, gap, affine)
        g = 'checkpoint/particles/' // trim(sp%name) // '/'
        missing = ''
        if (cyclic) then
          if (.not. any(datasets == g // 'cyclic_half_time')) missing = g // 'cyclic_half_time'
          if (.not. any(datasets == g // 'cyclic')) missing = g // 'cyclic'
        end if
        if (hardening .and. .not. any(datasets == g // 'hardening')) missing = g // 'hardening'
        if (gap .and. .not. any(datasets == g // 'gap')) missing = g // 'gap'
        if (affine .and. .not. any(datasets == g // 'affine')) missing = g // 'affine'
        if (len(missing) > 0) then
          stat = 1
          errmsg = cannot_restart(path, 'it lacks /' // missing // ', which &solid ' // &
            trim(sp%name) // ' (model ' // trim(sp%model) // ') needs')
          return
        end if
      end associate
    end do
  end subroutine check_model_state

  !> `stat` = 1 and the error line when the first `--set` change between the echo texts
  !! `old_text` (stored input) and `new_text` (with the `--set` texts) is not in
  !! `restart_changeable`. Both texts come from `config_to_text`, so equal values read equal.
  subroutine refuse_changes(old_text, new_text, stat, errmsg)
    character(len=*), intent(in) :: old_text               !< echo of the stored input
    character(len=*), intent(in) :: new_text               !< echo of the restart's input
    integer, intent(out) :: stat                           !< 0 ok, 1 refused
    character(len=:), allocatable, intent(inout) :: errmsg !< error line
    character(len=:), allocatable :: old_line, new_line, group, variable
    integer :: old_pos, new_pos, eq

    stat = 0
    old_pos = 1
    new_pos = 1
    group = ''
    do while (old_pos <= len(old_text) .and. new_pos <= len(new_text))
      old_line = next_line(old_text, old_pos)
      new_line = next_line(new_text, new_pos)
      if (len(new_line) > 0) then
        if (new_line(1:1) == '&') group = new_line(2:)
      end if
      if (old_line == new_line) cycle
      eq = index(new_line, ' = ')
      if (eq == 0 .or. index(old_line, ' = ') /= eq) then
        stat = 1
        errmsg = group_error_text('--set', '', 'a restart cannot add or remove &fluid, ' // &
          '&solid, &region or &boundary groups (the checkpoint holds the state of its own ' // &
          'materials and boundaries)')
        return
      end if
      variable = adjustl(new_line(1:eq - 1))
      if (any(restart_changeable == group // ' ' // trim(variable))) cycle
      stat = 1
      errmsg = input_error_text('--set', group, trim(variable), new_line(eq + 3:), &
        'a restart cannot change it (the checkpoint was written with ' // old_line(eq + 3:) &
        // '); a restart accepts changes only to ' // changeable_text() // ' (docs/batch.md)')
      return
    end do
    if (old_pos <= len(old_text) .or. new_pos <= len(new_text)) then
      stat = 1
      errmsg = group_error_text('--set', '', 'a restart cannot add or remove &fluid, &solid, ' &
        // '&region or &boundary groups (the checkpoint holds the state of its own materials ' &
        // 'and boundaries)')
    end if
  end subroutine refuse_changes

  !> `restart_changeable` as one text, grouped: `&run end_time, ...; &grid dims, ...`.
  function changeable_text() result(text)
    character(len=:), allocatable :: text
    character(len=:), allocatable :: group, last
    integer :: n, sp
    text = ''
    last = ''
    do n = 1, size(restart_changeable)
      sp = index(restart_changeable(n), ' ')
      group = restart_changeable(n)(1:sp - 1)
      if (group /= last) then
        if (n > 1) text = text // '; '
        text = text // '&' // group // ' '
        last = group
      else
        text = text // ', '
      end if
      text = text // trim(restart_changeable(n)(sp + 1:))
    end do
  end function changeable_text

  !> The line of `text` that starts at `pos` (without its line feed); `pos` moves past it.
  function next_line(text, pos) result(line)
    character(len=*), intent(in) :: text  !< text of lines ending with a line feed
    integer, intent(inout) :: pos         !< start of the line; on return the next one
    character(len=:), allocatable :: line
    integer :: end
    end = index(text(pos:), nl)
    if (end == 0) then
      line = text(pos:)
      pos = len(text) + 1
    else
      line = text(pos:pos + end - 2)
      pos = pos + end
    end if
  end function next_line

  !> Rank 0's check that `path` exists, can be read and starts with the HDF5 signature.
  subroutine check_file_head(path, stat, errmsg)
    character(len=*), intent(in) :: path                  !< checkpoint file
    integer, intent(out) :: stat                          !< 0 ok, 1 input error
    character(len=:), allocatable, intent(inout) :: errmsg !< error line
    character(len=*), parameter :: hdf5_signature = char(137) // 'HDF' // achar(13) // &
      achar(10) // achar(26) // achar(10)
    character(len=8) :: head
    character(len=msg_len) :: iomsg
    integer :: unit, ios
    stat = 1
    call open_stream(path, 'checkpoint', unit, errmsg)
    if (len(errmsg) > 0) return
    read(unit, iostat=ios, iomsg=iomsg) head
    close(unit)
    if (ios /= 0) then
      errmsg = group_error_text(path, '', 'cannot read the checkpoint: ' // trim(iomsg))
    else if (head /= hdf5_signature) then
      errmsg = group_error_text(path, '', 'not an HDF5 checkpoint')
    else
      stat = 0
    end if
  end subroutine check_file_head

  !> The error line of a checkpoint that cannot be continued.
  function cannot_restart(path, reason) result(text)
    character(len=*), intent(in) :: path    !< checkpoint
    character(len=*), intent(in) :: reason  !< why
    character(len=:), allocatable :: text
    text = group_error_text(path, '', 'cannot restart from it: ' // reason)
  end function cannot_restart

  !> Broadcast rank 0's `stat` and `errmsg`.
  subroutine bcast_status(stat, errmsg, comm)
    integer, intent(inout) :: stat                         !< status (significant on rank 0)
    character(len=:), allocatable, intent(inout) :: errmsg !< error line (rank 0)
    type(MPI_Comm), intent(in) :: comm                     !< communicator
    call bcast(comm, stat, 0)
    if (stat /= 0) call bcast_text(comm, errmsg, 0)
  end subroutine bcast_status
end module driver_restart
