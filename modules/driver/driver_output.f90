!> Dumps, checkpoints and failure dumps of a run, written through the HDF5/XDMF layer.
!!
!! Every file carries the design's root attributes (`time`, `step`, `dt`, `ndim`, `ncells`, `lower`,
!! `dx`, ...), the resolved input as the string attribute `namelist` and the program version as
!! `mpmice_version` (module mpmice_build_info), so a dump is
!! self-describing and a checkpoint restarts the run on its own. A checkpoint also stores the clock
!! (`dt_next`, `output_index`, `checkpoint_index`) and the scene's full state under `/checkpoint/`;
!! it is written to a temporary name and renamed, so an interrupted write never leaves a
!! half-written file under a checkpoint's name.
module driver_output
  use parallel_comm, only: MPI_Comm, barrier
  use mpmice_kinds, only: path_len, name_len
  use mpmice_errors, only: fatal
  use mpmice_build_info, only: mpmice_version
  use parallel_domain, only: domain_t
  use grid_layout, only: grid_t
  use io_files, only: io_rename, io_join_path, io_dump_stem, io_file_exists
  use io_hdf5, only: h5_file_t, h5_create, h5_open, h5_close, h5_write_attribute, &
    h5_read_attribute, h5_write_dump_header, h5_attribute_exists
  use io_xdmf, only: xdmf_write_dump, xdmf_update_series, xdmf_particles_t
  use io_write_failure, only: io_write_failed, enospc
  use mpmice_faults, only: fault_step
  use driver_clock, only: clock_t
  use scene_interface, only: scene_t
  implicit none
  private

  public :: write_state_file, read_checkpoint, read_namelist_text
  public :: checkpoint_version

  integer, parameter :: checkpoint_version = 1  !< layout version of checkpoints

contains

  !> Write the state at `clock` into `output_dir` (collective), by `kind`:
  !! * 'dump': `<name>_<step>.h5` with its XDMF file (`xdmf`), added to the time series
  !!   `<name>.xmf`;
  !! * 'failed': the failure dump `<name>_failed_<step>.h5` with its XDMF file (`xdmf`);
  !! * 'checkpoint': `<name>_checkpoint_<step>.h5` with the clock and the scene's full state.
  !! Each is written under a temporary name and renamed: a kill or a full disk never leaves a
  !! partial file under its final name (a failed write ends the run, io_write_failure).
  subroutine write_state_file(scene, dom, grid, clock, output_dir, name, namelist_text, xdmf, &
    kind, path)
    class(scene_t), intent(inout) :: scene            !< scene whose state is written
    type(domain_t), intent(in) :: dom                 !< decomposition
    type(grid_t), intent(in) :: grid                  !< block geometry
    type(clock_t), intent(in) :: clock                !< run clock
    character(len=*), intent(in) :: output_dir        !< output directory
    character(len=*), intent(in) :: name              !< case name
    character(len=*), intent(in) :: namelist_text     !< resolved input
    logical, intent(in) :: xdmf                       !< write XDMF files (dumps)
    character(len=*), intent(in) :: kind              !< 'dump', 'failed' or 'checkpoint'
    character(len=path_len), intent(out), optional :: path !< file written
    type(h5_file_t) :: file
    character(len=:), allocatable :: stem, h5_path
    character(len=name_len), allocatable :: cell_paths(:)
    type(xdmf_particles_t), allocatable :: particle_sets(:)
    integer :: fault_dump_step
    logical :: checkpoint

    checkpoint = kind == 'checkpoint'
    select case (kind)
    case ('failed')
      stem = io_dump_stem(trim(name) // '_failed', clock%step)
    case ('checkpoint')
      stem = io_dump_stem(trim(name) // '_checkpoint', clock%step)
    case default
      stem = io_dump_stem(name, clock%step)
    end select
    h5_path = io_join_path(output_dir, stem // '.h5')
    call h5_create(file, h5_path // '.tmp', dom%comm, final_path=h5_path)
    call write_header(file, grid, clock, namelist_text)
    if (checkpoint) then
      call write_clock(file, clock)
    else
      fault_dump_step = fault_step('enospc_dump_step')   ! testing aid, docs/testing.md
      if (fault_dump_step >= 0 .and. clock%step == fault_dump_step .and. dom%rank == 0) then
        call io_write_failed(h5_path // '.tmp', h5_path, 'MPMICE_FAULT', enospc)
      end if
    end if
    call scene%write_state(file, checkpoint)
    call h5_close(file)
    if (checkpoint) call barrier(dom%comm)
    if (dom%rank == 0) call io_rename(h5_path // '.tmp', h5_path)
    call barrier(dom%comm)
    if (xdmf .and. .not. checkpoint .and. dom%rank == 0) then
      call scene%output_layout(cell_paths, particle_sets)
      call xdmf_write_dump(io_join_path(output_dir, stem // '.xmf.tmp'), stem // '.h5', grid, &
        clock%time, cell_paths, particle_sets)
      call io_rename(io_join_path(output_dir, stem // '.xmf.tmp'), &
        io_join_path(output_dir, stem // '.xmf'))
      if (kind /= 'failed') then
        call xdmf_update_series(io_join_path(output_dir, trim(name) // '.xmf'), &
          io_join_path(output_dir, stem // '.xmf'), clock%time)
      end if
    end if
    if (present(path)) path = h5_path
  end subroutine write_state_file

  !> The clock of a checkpoint: what the root attributes of `write_header` leave out.
  subroutine write_clock(file, clock)
    type(h5_file_t), intent(in) :: file   !< open checkpoint
    type(clock_t), intent(in) :: clock    !< run clock
    call h5_write_attribute(file, 'checkpoint_version', checkpoint_version)
    call h5_write_attribute(file, 'dt_next', clock%dt_next)
    call h5_write_attribute(file, 'output_index', clock%output_index)
    call h5_write_attribute(file, 'checkpoint_index', clock%checkpoint_index)
    call h5_write_attribute(file, 'stop_energy_reference', clock%energy_reference)
    call h5_write_attribute(file, 'stop_load_work', clock%load_work)
    call h5_write_attribute(file, 'stop_dt_reference', clock%dt_reference)
  end subroutine write_clock

  !> Read the clock and the scene's state from a checkpoint. The clock's limits (end time,
  !! intervals, dt limits) come from the configuration and are set by the caller before.
  !! Collective.
  subroutine read_checkpoint(scene, dom, grid, path, clock)
    class(scene_t), intent(inout) :: scene   !< scene to restore
    type(domain_t), intent(in) :: dom        !< decomposition
    type(grid_t), intent(in) :: grid         !< block geometry
    character(len=*), intent(in) :: path     !< checkpoint file
    type(clock_t), intent(inout) :: clock    !< clock to restore
    type(h5_file_t) :: file
    integer :: version, ncells(3)

    call h5_open(file, path, dom%comm)
    call h5_read_attribute(file, 'checkpoint_version', version)
    if (version /= checkpoint_version) call fatal('read_checkpoint: ' // trim(path) // &
      ' has an unsupported checkpoint layout version')
    call h5_read_attribute(file, 'ncells', ncells)
    if (any(ncells /= grid%ncells)) call fatal('read_checkpoint: ' // trim(path) // &
      ' was written for another grid (&grid ncells cannot change on restart)')
    call h5_read_attribute(file, 'time', clock%time)
    call h5_read_attribute(file, 'step', clock%step)
    clock%first_step = clock%step
    call h5_read_attribute(file, 'dt', clock%dt)
    call h5_read_attribute(file, 'dt_next', clock%dt_next)
    call h5_read_attribute(file, 'output_index', clock%output_index)
    call h5_read_attribute(file, 'checkpoint_index', clock%checkpoint_index)
    ! references of the run-loop stops (checkpoints written before they existed: set anew)
    if (h5_attribute_exists(file, 'stop_energy_reference')) then
      call h5_read_attribute(file, 'stop_energy_reference', clock%energy_reference)
      call h5_read_attribute(file, 'stop_load_work', clock%load_work)
      call h5_read_attribute(file, 'stop_dt_reference', clock%dt_reference)
    end if
    call scene%restore(file)
    call h5_close(file)
  end subroutine read_checkpoint

  !> The resolved input stored in a dump or checkpoint (attribute `namelist`). Collective.
  subroutine read_namelist_text(path, comm, text)
    character(len=*), intent(in) :: path              !< file to read
    type(MPI_Comm), intent(in) :: comm                !< communicator of the readers
    character(len=:), allocatable, intent(out) :: text !< the namelist text
    type(h5_file_t) :: file
    if (.not. io_file_exists(path)) call fatal('read_namelist_text: no such file ' // trim(path))
    call h5_open(file, path, comm)
    call h5_read_attribute(file, 'namelist', text)
    call h5_close(file)
  end subroutine read_namelist_text

  !> Root attributes shared by dumps and checkpoints.
  subroutine write_header(file, grid, clock, namelist_text)
    type(h5_file_t), intent(in) :: file           !< open file
    type(grid_t), intent(in) :: grid              !< block geometry
    type(clock_t), intent(in) :: clock            !< run clock
    character(len=*), intent(in) :: namelist_text !< resolved input
    call h5_write_dump_header(file, clock%time, clock%step, clock%dt, grid)
    call h5_write_attribute(file, 'namelist', namelist_text)
    call h5_write_attribute(file, 'mpmice_version', mpmice_version)
  end subroutine write_header
end module driver_output
