!> Top-level application: MPI start-up, command line, configuration, run, shutdown.
!!
!! Input errors (bad command line, unreadable or invalid namelist input) print one line on
!! standard error from rank 0 and end every rank with exit status 1 through `exit_cleanly`, before
!! anything is written. `--check` prints the resolved input on standard output and exits 0.
module mpmice_app
  use, intrinsic :: iso_fortran_env, only: output_unit, error_unit
  use mpi_f08, only: MPI_Init, MPI_Finalize, MPI_Comm, MPI_COMM_WORLD, MPI_Comm_dup, &
    MPI_Comm_free, MPI_Comm_rank, MPI_Bcast, MPI_INTEGER
  use mpmice_kinds, only: msg_len
  use mpmice_errors, only: exit_cleanly
  use mpmice_log, only: log_init, log_set_verbosity
  use mpmice_signals, only: signals_install
  use config_types, only: config_t
  use config_cli, only: cli_t, cli_from_command_line, cli_usage, mpmice_version, action_run, &
    action_check, action_help, action_version
  use config_parse, only: group_error_text
  use config_load, only: config_load_run
  use config_echo, only: config_to_text
  use driver_run_mod, only: driver_run
  use io_files, only: io_select_mpiio
  use driver_output, only: read_namelist_text
  implicit none
  private

  public :: app_run

contains

  !> Run MPMICE as the command line asks.
  subroutine app_run()
    type(MPI_Comm) :: comm
    type(cli_t) :: cli
    type(config_t) :: cfg
    character(len=:), allocatable :: errmsg, source, stored_text
    integer :: rank, stat
    logical :: root

    ! SIGTERM/SIGUSR1 from the first instant: a signal during start-up stops the run cleanly
    ! before its first step (docs/batch.md); installed again after MPI_Init in case the MPI
    ! library replaced it
    call signals_install()
    ! ROMIO for MPI-IO unless the user chose: Open MPI 4.1 OMPIO corrupted collective writes (docs/io.md)
    call io_select_mpiio()
    call MPI_Init()
    call signals_install()
    call MPI_Comm_dup(MPI_COMM_WORLD, comm)
    call MPI_Comm_rank(comm, rank)
    root = rank == 0
    call log_init(root)

    ! every rank sees the same arguments under mpirun
    call cli_from_command_line(cli, stat, errmsg)
    call stop_on_error(stat, errmsg, root)
    select case (cli%action)
    case (action_help)
      if (root) write(output_unit, '(a)', advance='no') cli_usage()
      call exit_cleanly(0)
    case (action_version)
      if (root) write(output_unit, '(a)') 'mpmice ' // mpmice_version
      call exit_cleanly(0)
    case default
      continue  ! run or check: below
    end select

    if (len_trim(cli%restart_file) > 0) then
      ! the configuration is the resolved input stored in the checkpoint, then the --set texts
      source = trim(cli%restart_file)
      call check_restart_file(source, comm, stat, errmsg)
      call stop_on_error(stat, errmsg, root)
      call read_namelist_text(source, comm, stored_text)
      call config_load_run(cfg, source, cli%sets(1:cli%nsets), comm, stat, errmsg, &
        base_text=stored_text)
    else
      source = trim(cli%case_file)
      call config_load_run(cfg, source, cli%sets(1:cli%nsets), comm, stat, errmsg)
    end if
    call stop_on_error(stat, errmsg, root)

    if (cli%action == action_check) then
      if (root) then
        write(output_unit, '(a)', advance='no') config_to_text(cfg)
        flush(output_unit)
      end if
      call exit_cleanly(0)
    end if

    call log_set_verbosity(cfg%run%verbosity)
    call MPI_Comm_free(comm)
    if (cli%action == action_run) call driver_run(cfg, source, trim(cli%restart_file))
    call MPI_Finalize()
  end subroutine app_run

  !> If `stat` /= 0: rank 0 prints `errmsg` on standard error, every rank exits with status 1.
  !! Every rank must call it with the same `stat`.
  subroutine stop_on_error(stat, errmsg, root)
    integer, intent(in) :: stat              !< 0 ok
    character(len=*), intent(in) :: errmsg   !< the one error line
    logical, intent(in) :: root              !< this rank prints
    if (stat == 0) return
    if (root) then
      write(error_unit, '(a)') trim(errmsg)
      flush(error_unit)
    end if
    call exit_cleanly(1)
  end subroutine stop_on_error

  !> Collective: rank 0 checks that the checkpoint `path` exists and is an HDF5 file.
  subroutine check_restart_file(path, comm, stat, errmsg)
    character(len=*), intent(in) :: path                  !< checkpoint file
    type(MPI_Comm), intent(in) :: comm                    !< communicator
    integer, intent(out) :: stat                          !< 0 ok, 1 input error (all ranks)
    character(len=:), allocatable, intent(out) :: errmsg  !< error line (rank 0)
    character(len=*), parameter :: hdf5_signature = char(137) // 'HDF' // achar(13) // &
      achar(10) // achar(26) // achar(10)
    character(len=8) :: head
    character(len=msg_len) :: iomsg
    integer :: rank, unit, ios
    logical :: exists
    call MPI_Comm_rank(comm, rank)
    stat = 0
    errmsg = ''
    if (rank == 0) then
      inquire(file=path, exist=exists)
      if (.not. exists) then
        stat = 1
        errmsg = group_error_text(path, '', 'cannot read the checkpoint: no such file')
      else
        open(newunit=unit, file=path, status='old', action='read', access='stream', &
          form='unformatted', iostat=ios, iomsg=iomsg)
        if (ios == 0) then
          read(unit, iostat=ios, iomsg=iomsg) head
          close(unit)
        end if
        if (ios /= 0) then
          stat = 1
          errmsg = group_error_text(path, '', 'cannot read the checkpoint: ' // trim(iomsg))
        else if (head /= hdf5_signature) then
          stat = 1
          errmsg = group_error_text(path, '', 'not an HDF5 checkpoint')
        end if
      end if
    end if
    call MPI_Bcast(stat, 1, MPI_INTEGER, 0, comm)
  end subroutine check_restart_file
end module mpmice_app
