!> Top-level application: MPI start-up, command line, configuration, run, shutdown.
!!
!! Input errors (bad command line, unreadable or invalid namelist input) print one line on
!! standard error from rank 0 and end every rank with exit status 1 through `exit_cleanly`, before
!! anything is written. `--check` prints the resolved input on standard output and exits 0.
module mpmice_app
  use, intrinsic :: iso_fortran_env, only: output_unit, error_unit
  use mpi_f08, only: MPI_Init, MPI_Finalize, MPI_Comm, MPI_COMM_WORLD, MPI_Comm_dup, &
    MPI_Comm_free, MPI_Comm_rank, MPI_Bcast, MPI_INTEGER
  use mpmice_errors, only: exit_cleanly
  use mpmice_log, only: log_init, log_set_verbosity
  use config_types, only: config_t
  use config_cli, only: cli_t, cli_from_command_line, cli_usage, mpmice_version, action_run, &
    action_check, action_help, action_version
  use config_parse, only: group_error_text
  use config_load, only: config_load_run
  use config_echo, only: config_to_text
  use driver_run_mod, only: driver_run
  implicit none
  private

  public :: app_run

contains

  !> Run MPMICE as the command line asks.
  subroutine app_run()
    type(MPI_Comm) :: comm
    type(cli_t) :: cli
    type(config_t) :: cfg
    character(len=:), allocatable :: errmsg
    integer :: rank, stat
    logical :: root

    call MPI_Init()
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
    end select

    if (len_trim(cli%restart_file) > 0) then
      call check_restart_file(cli%restart_file, comm, stat, errmsg)
      call stop_on_error(stat, errmsg, root)
      ! reading the configuration stored in a checkpoint (and continuing the run) is done by the
      ! checkpoint reader, which this build does not have yet
      call stop_on_error(1, group_error_text(cli%restart_file, '', &
        'restarting from a checkpoint is not available in this build'), root)
    end if

    call config_load_run(cfg, trim(cli%case_file), cli%sets(1:cli%nsets), comm, stat, errmsg)
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
    if (cli%action == action_run) call driver_run(cfg, trim(cli%case_file), '')
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

  !> Collective: rank 0 checks that the checkpoint `path` exists and can be opened.
  subroutine check_restart_file(path, comm, stat, errmsg)
    character(len=*), intent(in) :: path                  !< checkpoint file
    type(MPI_Comm), intent(in) :: comm                    !< communicator
    integer, intent(out) :: stat                          !< 0 ok, 1 input error (all ranks)
    character(len=:), allocatable, intent(out) :: errmsg  !< error line (rank 0)
    integer :: rank, unit, ios
    logical :: exists
    call MPI_Comm_rank(comm, rank)
    stat = 0
    errmsg = ''
    if (rank == 0) then
      inquire(file=trim(path), exist=exists)
      if (.not. exists) then
        stat = 1
        errmsg = group_error_text(path, '', 'cannot read the checkpoint: no such file')
      else
        open(newunit=unit, file=trim(path), status='old', action='read', access='stream', &
          form='unformatted', iostat=ios)
        if (ios /= 0) then
          stat = 1
          errmsg = group_error_text(path, '', 'cannot read the checkpoint')
        else
          close(unit)
        end if
      end if
    end if
    call MPI_Bcast(stat, 1, MPI_INTEGER, 0, comm)
  end subroutine check_restart_file
end module mpmice_app
