!> Load a run's configuration: case file, then `--set` overrides, then validation; rank 0 does the
!! work and every rank ends with the identical configuration or the identical failure status.
module config_load
  use parallel_comm, only: MPI_Comm, comm_rank, comm_size, bcast, bcast_text
  use mpmice_kinds, only: msg_len
  use mpmice_errors, only: input_error_text, fatal
  use config_types, only: config_t
  use config_parse, only: config_load_text, config_origin_t, origin_source, group_error_text
  use config_validate, only: config_error_t, config_check
  use config_echo, only: config_to_text
  use config_geometry_files, only: geometry_paths_resolve, geometry_check_variables, &
    geometry_files_load, geometry_files_bcast
  use config_scene_groups, only: is_echo_text, check_run_group, check_scene_groups
  implicit none
  private

  public :: config_load_file, config_read_text_file, config_resolve, config_load_run
  public :: config_bcast, open_stream

contains

  !> The whole content of the file `path`. `stat` /= 0 and `errmsg` (one input-error line) when
  !! it cannot be read.
  subroutine config_read_text_file(path, text, stat, errmsg)
    character(len=*), intent(in) :: path                   !< file to read
    character(len=:), allocatable, intent(out) :: text     !< its content
    integer, intent(out) :: stat                           !< 0 ok, 1 error
    character(len=:), allocatable, intent(out) :: errmsg   !< error line
    character(len=msg_len) :: iomsg
    integer :: unit, ios, nbytes

    stat = 1
    text = ''
    errmsg = ''
    call open_stream(path, 'file', unit, errmsg)
    if (len(errmsg) > 0) return
    inquire(unit=unit, size=nbytes)
    if (nbytes < 0) then
      close(unit)
      errmsg = group_error_text(path, '', 'cannot read the file: not a regular file')
      return
    end if
    deallocate(text)
    allocate(character(len=nbytes) :: text)
    if (nbytes > 0) read(unit, iostat=ios, iomsg=iomsg) text
    close(unit)
    if (ios /= 0) then
      errmsg = group_error_text(path, '', 'cannot read the file: ' // trim(iomsg))
      return
    end if
    stat = 0
  end subroutine config_read_text_file

  !> Open the existing file `path` for reading as a byte stream on a new `unit`; otherwise
  !! `errmsg` is the input-error line `cannot read the <what>: <reason>` (else empty).
  subroutine open_stream(path, what, unit, errmsg)
    character(len=*), intent(in) :: path                    !< file to open
    character(len=*), intent(in) :: what                    !< what it is, for the message
    integer, intent(out) :: unit                            !< the open unit
    character(len=:), allocatable, intent(inout) :: errmsg  !< error line, '' when open
    character(len=msg_len) :: iomsg
    integer :: ios
    logical :: exists
    errmsg = ''
    unit = -1
    inquire(file=path, exist=exists)
    if (.not. exists) then
      errmsg = group_error_text(path, '', 'cannot read the ' // what // ': no such file')
      return
    end if
    open(newunit=unit, file=path, status='old', action='read', access='stream', &
      form='unformatted', iostat=ios, iomsg=iomsg)
    if (ios /= 0) errmsg = group_error_text(path, '', 'cannot read the ' // what // ': ' // &
      trim(iomsg))
  end subroutine open_stream

  !> Apply the namelist file `path` to `cfg` (variables it does not set keep their values).
  subroutine config_load_file(cfg, path, stat, errmsg, origin)
    type(config_t), intent(inout) :: cfg                    !< configuration to update
    character(len=*), intent(in) :: path                    !< namelist file
    integer, intent(out) :: stat                            !< 0 ok, 1 input error
    character(len=:), allocatable, intent(out) :: errmsg    !< error line
    type(config_origin_t), intent(inout), optional :: origin !< provenance of each variable
    character(len=:), allocatable :: text
    call config_read_text_file(path, text, stat, errmsg)
    if (stat /= 0) return
    call config_load_text(cfg, text, path, stat, errmsg, origin)
  end subroutine config_load_file

  !> Resolve a configuration on one rank: defaults, then the case file `source`, then each
  !! `sets(i)` in order (as overrides: a repeated group modifies the occurrence its selector
  !! names), then validation for a run on `nranks` ranks. With `base_text` that text
  !! replaces the file's content (a restart passes the text stored in the checkpoint, with the
  !! checkpoint's path as `source`). Error lines name the input that set the bad variable.
  !! Geometry file names are made absolute (relative to the folder of `source`) and the files
  !! read and checked (`config_geometry_files`).
  subroutine config_resolve(cfg, source, sets, nranks, stat, errmsg, base_text)
    type(config_t), intent(out) :: cfg                     !< resolved configuration
    character(len=*), intent(in) :: source                 !< case file (or checkpoint) name
    character(len=*), intent(in) :: sets(:)                !< `--set` texts, applied in order
    integer, intent(in) :: nranks                          !< ranks of the run
    integer, intent(out) :: stat                           !< 0 ok, 1 input error
    character(len=:), allocatable, intent(out) :: errmsg   !< error line
    character(len=*), intent(in), optional :: base_text    !< configuration text to use instead
    type(config_origin_t) :: origin
    type(config_error_t) :: err
    character(len=:), allocatable :: text, groups, set_groups, all_set_groups
    logical :: echo
    integer :: i

    if (present(base_text)) then
      text = base_text
    else
      call config_read_text_file(source, text, stat, errmsg)
      if (stat /= 0) return
    end if
    call config_load_text(cfg, text, source, stat, errmsg, origin, groups=groups)
    if (stat /= 0) return
    echo = is_echo_text(text)
    if (.not. present(base_text)) then
      ! a case file (a checkpoint's text always holds &run)
      call check_run_group(groups, source, stat, errmsg)
      if (stat /= 0) return
    end if
    all_set_groups = ''
    do i = 1, size(sets)
      call config_load_text(cfg, sets(i), '--set', stat, errmsg, origin, overrides=.true., &
        groups=set_groups)
      if (stat /= 0) return
      all_set_groups = all_set_groups // set_groups
    end do
    call geometry_paths_resolve(cfg, source)
    call config_check(cfg, nranks, err)
    if (.not. err%found) call geometry_check_variables(cfg, err)
    if (err%found) then
      stat = 1
      errmsg = input_error_text(origin_source(origin, err%group, err%variable, source), &
        err%group, err%variable, err%value, err%allowed)
      return
    end if
    ! a valid input's groups must be those of its scene (an echo holds every singleton group)
    call check_scene_groups(cfg%run%scene, groups, source, echo, stat, errmsg)
    if (stat /= 0) return
    call check_scene_groups(cfg%run%scene, all_set_groups, '--set', .false., stat, errmsg)
    if (stat /= 0) return
    call geometry_files_load(cfg, stat, errmsg)
  end subroutine config_resolve

  !> Collective over `comm`: rank 0 resolves the configuration (`config_resolve`) for a run on
  !! the ranks of `comm` and broadcasts the outcome; every rank returns the same `stat` and
  !! `errmsg` and, on success, the same configuration (broadcast as its resolved namelist text).
  !! Nothing is printed: the caller reports `errmsg` from rank 0 and exits.
  subroutine config_load_run(cfg, source, sets, comm, stat, errmsg, base_text)
    type(config_t), intent(out) :: cfg                     !< resolved configuration
    character(len=*), intent(in) :: source                 !< case file (or checkpoint) name
    character(len=*), intent(in) :: sets(:)                !< `--set` texts, applied in order
    type(MPI_Comm), intent(in) :: comm                     !< communicator of the run
    integer, intent(out) :: stat                           !< 0 ok, 1 input error
    character(len=:), allocatable, intent(out) :: errmsg   !< error line (all ranks)
    character(len=*), intent(in), optional :: base_text    !< text to use instead of the file
    errmsg = ''
    if (comm_rank(comm) == 0) call config_resolve(cfg, source, sets, comm_size(comm), stat, &
      errmsg, base_text)
    call bcast(comm, stat, 0)
    call bcast_text(comm, errmsg, 0)
    if (stat == 0) call config_bcast(cfg, comm)
  end subroutine config_load_run

  !> Give every rank of `comm` rank 0's configuration (sent as its namelist text, which reads
  !! back bitwise identical). Collective.
  subroutine config_bcast(cfg, comm)
    type(config_t), intent(inout) :: cfg  !< configuration (significant on rank 0)
    type(MPI_Comm), intent(in) :: comm    !< communicator
    character(len=:), allocatable :: text, errmsg
    type(config_t) :: fresh
    integer :: stat
    if (comm_rank(comm) == 0) text = config_to_text(cfg)
    call bcast_text(comm, text, 0)
    if (comm_rank(comm) /= 0) then
      call config_load_text(fresh, text, 'broadcast configuration', stat, errmsg)
      if (stat /= 0) call fatal('config_bcast: ' // errmsg)
      cfg = fresh
    end if
    call geometry_files_bcast(cfg, comm)
  end subroutine config_bcast
end module config_load
