!> Top-level application: MPI start-up, command line, configuration, run, shutdown.
!!
!! Input errors (bad command line, unreadable or invalid namelist input) print one line on
!! standard error from rank 0 and end every rank with exit status 1 through `exit_cleanly`, before
!! anything is written. `--check` prints the resolved input on standard output and exits 0.
module mpmice_app
  use, intrinsic :: iso_fortran_env, only: output_unit, error_unit
  use parallel_comm, only: MPI_Comm, mpi_start, mpi_stop, comm_rank
  use mpmice_errors, only: exit_cleanly
  use mpmice_log, only: log_init, log_set_verbosity
  use mpmice_signals, only: signals_install
  use config_types, only: config_t
  use config_cli, only: cli_t, cli_from_command_line, cli_usage, mpmice_version, action_run, &
    action_check, action_help, action_version
  use config_load, only: config_load_run
  use config_echo, only: config_to_text
  use driver_run_mod, only: driver_run
  use io_files, only: io_select_mpiio
  use driver_restart, only: restart_load
  use driver_preflight, only: preflight_memory
  implicit none
  private

  public :: app_run

contains

  !> Run MPMICE as the command line asks.
  subroutine app_run()
    type(MPI_Comm) :: comm
    type(cli_t) :: cli
    type(config_t) :: cfg
    character(len=:), allocatable :: errmsg, source
    integer :: rank, stat
    logical :: root

    ! SIGTERM/SIGUSR1 from the first instant: a signal during start-up stops the run cleanly
    ! before its first step (docs/batch.md); installed again after MPI_Init in case the MPI
    ! library replaced it
    call signals_install()
    ! ROMIO for MPI-IO unless the user chose: Open MPI 4.1 OMPIO corrupted collective writes (docs/io.md)
    call io_select_mpiio()
    call mpi_start(comm)
    call signals_install()
    rank = comm_rank(comm)
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
      ! the resolved input stored in the checkpoint, then the --set texts; changes the
      ! checkpoint cannot honour are refused, the output folder is the checkpoint's
      source = trim(cli%restart_file)
      call restart_load(source, cli%sets(1:cli%nsets), comm, cfg, stat, errmsg)
    else
      source = trim(cli%case_file)
      call config_load_run(cfg, source, cli%sets(1:cli%nsets), comm, stat, errmsg)
    end if
    call stop_on_error(stat, errmsg, root)
    ! a run that cannot fit in the memory of its nodes is refused, also by --check
    call preflight_memory(cfg, comm, stat, errmsg)
    call stop_on_error(stat, errmsg, root)

    if (cli%action == action_check) then
      if (root) then
        write(output_unit, '(a)', advance='no') config_to_text(cfg)
        flush(output_unit)
      end if
      call exit_cleanly(0)
    end if

    call log_set_verbosity(cfg%run%verbosity)
    if (cli%action == action_run) call driver_run(cfg, source, trim(cli%restart_file), comm)
    call mpi_stop(comm)
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

end module mpmice_app
