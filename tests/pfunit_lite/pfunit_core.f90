!> Core of pfunit-lite, MPMICE's small stand-in for pFUnit: the test object handed to MPI tests,
!! failure recording, and the runner used by the drivers that `pf2f90.py` generates.
!!
!! A failing assertion prints `file:line`, the test, the rank, expected and actual values and the
!! message, and is recorded; the generated code then returns from the test (as pFUnit does) and the
!! runner goes on with the next test. After each test the failure flags are reduced over all ranks.
module pfunit_core
  use, intrinsic :: iso_fortran_env, only: output_unit, real64, int64
  use mpi_f08, only: MPI_Comm, MPI_COMM_WORLD, MPI_COMM_NULL, MPI_UNDEFINED, MPI_INTEGER, MPI_MAX, &
    MPI_DOUBLE_PRECISION, MPI_Init, MPI_Initialized, MPI_Finalize, MPI_Comm_rank, MPI_Comm_size, &
    MPI_Comm_split, MPI_Comm_free, MPI_Allreduce, MPI_Barrier, MPI_Wtime, operator(/=)
  implicit none
  private

  public :: SourceLocation, MpiTestMethod, anyExceptions, pf_fail
  public :: pf_runner_t, pf_runner_init, pf_test_start, pf_test_end, pf_runner_finish
  public :: pf_real_text, pf_int_text, pf_logical_text, pf_index_text

  integer, parameter :: dp = real64
  integer, parameter :: text_len = 256

  !> Where an assertion sits in the `.pf` file (pFUnit's `SourceLocation`).
  type :: SourceLocation
    character(len=text_len) :: fileName = '<unknown>'  !< base name of the .pf file
    integer :: lineNumber = 0                          !< line of the assertion
  end type SourceLocation

  !> Test object of an MPI test (pFUnit's `MpiTestMethod`): a communicator of exactly the
  !! requested number of ranks.
  type :: MpiTestMethod
    type(MPI_Comm) :: comm = MPI_COMM_NULL  !< communicator of the ranks running the test
    integer :: rank = 0                     !< rank in `comm`
    integer :: npes = 0                     !< size of `comm`
  contains
    procedure :: getMpiCommunicator => mpi_test_method_communicator
    procedure :: getProcessRank => mpi_test_method_rank
    procedure :: getNumProcesses => mpi_test_method_npes
  end type MpiTestMethod

  !> State of one run of a generated driver (one executable run under mpiexec).
  type :: pf_runner_t
    character(len=text_len) :: source = ''    !< .pf file of the tests
    character(len=text_len) :: filter = ''    !< run only tests whose name contains this
    logical :: all_npes = .false.             !< run every npes <= world size (pFUnit style)
    integer :: world_rank = 0                 !< rank in MPI_COMM_WORLD
    integer :: world_size = 1                 !< size of MPI_COMM_WORLD
    integer :: passed = 0                     !< tests passed so far
    integer :: failed = 0                     !< tests failed so far
    integer :: skipped = 0                    !< tests not run at this world size or filtered out
    logical :: active = .false.               !< the current test runs in this execution
    integer :: npes = 0                       !< ranks of the current test (0: serial)
    real(dp) :: start_time = 0.0_dp           !< MPI_Wtime at the start of the current test [s]
  end type pf_runner_t

  !> Module state (allowed exception: the test framework's global context, as pFUnit's): failures
  !! recorded in the current test on this rank, and the test's name, rank and size for messages.
  integer, save :: failures_in_test = 0
  character(len=text_len), save :: current_test = '<no test>'
  integer, save :: current_rank = 0
  integer, save :: current_npes = 1

contains

  !> Communicator of the ranks running this MPI test.
  function mpi_test_method_communicator(this) result(comm)
    class(MpiTestMethod), intent(in) :: this  !< test object
    type(MPI_Comm) :: comm
    comm = this%comm
  end function mpi_test_method_communicator

  !> Rank of the calling process in the test communicator.
  integer function mpi_test_method_rank(this)
    class(MpiTestMethod), intent(in) :: this  !< test object
    mpi_test_method_rank = this%rank
  end function mpi_test_method_rank

  !> Number of processes in the test communicator.
  integer function mpi_test_method_npes(this)
    class(MpiTestMethod), intent(in) :: this  !< test object
    mpi_test_method_npes = this%npes
  end function mpi_test_method_npes

  !> True when the current test has recorded a failure on this rank.
  logical function anyExceptions()
    anyExceptions = failures_in_test > 0
  end function anyExceptions

  !> Record a failed assertion and print it (one write, so ranks do not interleave lines).
  subroutine pf_fail(assertion, detail, message, location)
    character(len=*), intent(in) :: assertion                !< e.g. 'assertEqual'
    character(len=*), intent(in) :: detail                   !< expected/actual description
    character(len=*), intent(in), optional :: message        !< user message
    type(SourceLocation), intent(in), optional :: location   !< where the assertion is
    character(len=:), allocatable :: text
    character(len=32) :: buf
    failures_in_test = failures_in_test + 1
    if (present(location)) then
      write(buf, '(i0)') location%lineNumber
      text = trim(location%fileName) // ':' // trim(buf) // ': '
    else
      text = '<unknown location>: '
    end if
    write(buf, '(a,i0,a,i0)') 'rank ', current_rank, ' of ', current_npes
    text = text // 'FAILED ' // assertion // ' in ' // trim(current_test) // ' (' // trim(buf) &
      // ')' // new_line('a') // '    ' // detail
    if (present(message)) then
      if (len_trim(message) > 0) text = text // new_line('a') // '    message: ' // trim(message)
    end if
    write(output_unit, '(a)') text
    flush(output_unit)
  end subroutine pf_fail

  !> Full-precision text of a real.
  function pf_real_text(x) result(text)
    real(dp), intent(in) :: x  !< value
    character(len=:), allocatable :: text
    character(len=40) :: buf
    write(buf, '(es24.16e3)') x
    text = trim(adjustl(buf))
  end function pf_real_text

  !> Text of an integer.
  function pf_int_text(i) result(text)
    integer(int64), intent(in) :: i  !< value
    character(len=:), allocatable :: text
    character(len=24) :: buf
    write(buf, '(i0)') i
    text = trim(buf)
  end function pf_int_text

  !> Text of a logical.
  function pf_logical_text(l) result(text)
    logical, intent(in) :: l  !< value
    character(len=:), allocatable :: text
    if (l) then
      text = '.true.'
    else
      text = '.false.'
    end if
  end function pf_logical_text

  !> Subscripts `(i,j,k)` (from 1) of element `flat` (from 1) of an array of shape `shp`.
  function pf_index_text(flat, shp) result(text)
    integer, intent(in) :: flat    !< position in array element order
    integer, intent(in) :: shp(:)  !< shape of the array
    character(len=:), allocatable :: text
    integer :: d, rest
    rest = flat - 1
    text = '('
    do d = 1, size(shp)
      text = text // pf_int_text(int(mod(rest, shp(d)) + 1, int64))
      if (d < size(shp)) text = text // ','
      rest = rest / shp(d)
    end do
    text = text // ')'
  end function pf_index_text

  !> Start MPI (if needed) and read the driver's options: `--all-npes`, `--filter SUBSTRING`.
  subroutine pf_runner_init(runner, source)
    type(pf_runner_t), intent(out) :: runner  !< runner to set up
    character(len=*), intent(in) :: source    !< .pf file of the tests
    logical :: initialized
    integer :: i, nargs
    character(len=text_len) :: arg
    call MPI_Initialized(initialized)
    if (.not. initialized) call MPI_Init()
    call MPI_Comm_rank(MPI_COMM_WORLD, runner%world_rank)
    call MPI_Comm_size(MPI_COMM_WORLD, runner%world_size)
    runner%source = source
    nargs = command_argument_count()
    i = 1
    do while (i <= nargs)
      call get_command_argument(i, arg)
      select case (trim(arg))
      case ('--all-npes')
        runner%all_npes = .true.
      case ('--filter')
        i = i + 1
        call get_command_argument(i, runner%filter)
      case default
        if (runner%world_rank == 0) then
          write(output_unit, '(a)') trim(source) // ': unknown option ' // trim(arg) &
            // ' (options: --all-npes, --filter SUBSTRING)'
        end if
        call MPI_Finalize()
        stop 2
      end select
      i = i + 1
    end do
  end subroutine pf_runner_init

  !> Decide whether test `name` with `npes` ranks (0: serial) runs now, and if so build its
  !! communicator. Collective over MPI_COMM_WORLD when the test runs. `run` is true on the ranks
  !! that execute the test body.
  subroutine pf_test_start(runner, this, name, npes, run)
    type(pf_runner_t), intent(inout) :: runner  !< runner state
    type(MpiTestMethod), intent(inout) :: this  !< test object to set up
    character(len=*), intent(in) :: name        !< test name
    integer, intent(in) :: npes                 !< ranks the test needs (0: serial test)
    logical, intent(out) :: run                 !< this rank runs the test body
    integer :: color, width
    logical :: wanted

    run = .false.
    width = max(npes, 1)
    if (runner%all_npes) then
      wanted = width <= runner%world_size
    else if (npes == 0) then
      wanted = runner%world_size == 1
    else
      wanted = npes == runner%world_size
    end if
    if (len_trim(runner%filter) > 0) wanted = wanted .and. index(name, trim(runner%filter)) > 0
    runner%active = wanted
    runner%npes = npes
    if (.not. wanted) then
      runner%skipped = runner%skipped + 1
      return
    end if

    color = MPI_UNDEFINED
    if (runner%world_rank < width) color = 0
    call MPI_Comm_split(MPI_COMM_WORLD, color, runner%world_rank, this%comm)
    this%rank = 0
    this%npes = 0
    if (this%comm /= MPI_COMM_NULL) then
      call MPI_Comm_rank(this%comm, this%rank)
      call MPI_Comm_size(this%comm, this%npes)
      run = .true.
    end if
    failures_in_test = 0
    current_test = name
    current_rank = this%rank
    current_npes = width
    call MPI_Barrier(MPI_COMM_WORLD)
    runner%start_time = MPI_Wtime()
  end subroutine pf_test_start

  !> Finish the current test: reduce the failure flags over all ranks, report, free the
  !! communicator. Collective over MPI_COMM_WORLD when the test ran.
  subroutine pf_test_end(runner, this)
    type(pf_runner_t), intent(inout) :: runner  !< runner state
    type(MpiTestMethod), intent(inout) :: this  !< test object to release
    integer :: local, global
    real(dp) :: elapsed, slowest
    character(len=64) :: buf
    character(len=16) :: seconds

    if (.not. runner%active) return
    local = 0
    if (failures_in_test > 0) local = 1
    elapsed = MPI_Wtime() - runner%start_time
    call MPI_Allreduce(local, global, 1, MPI_INTEGER, MPI_MAX, MPI_COMM_WORLD)
    call MPI_Allreduce(elapsed, slowest, 1, MPI_DOUBLE_PRECISION, MPI_MAX, MPI_COMM_WORLD)
    if (global > 0) then
      runner%failed = runner%failed + 1
    else
      runner%passed = runner%passed + 1
    end if
    if (runner%world_rank == 0) then
      write(seconds, '(f10.3)') slowest
      if (runner%npes == 0) then
        write(buf, '(a)') '(serial, ' // trim(adjustl(seconds)) // ' s)'
      else
        write(buf, '(a,i0,a)') '(npes=', runner%npes, ', ' // trim(adjustl(seconds)) // ' s)'
      end if
      if (global > 0) then
        write(output_unit, '(a)') '[ FAILED ] ' // trim(current_test) // ' ' // trim(buf)
      else
        write(output_unit, '(a)') '[     OK ] ' // trim(current_test) // ' ' // trim(buf)
      end if
      flush(output_unit)
    end if
    if (this%comm /= MPI_COMM_NULL) call MPI_Comm_free(this%comm)
    this%comm = MPI_COMM_NULL
    this%rank = 0
    this%npes = 0
    failures_in_test = 0
    current_test = '<no test>'
    current_rank = runner%world_rank
    current_npes = runner%world_size
    runner%active = .false.
  end subroutine pf_test_end

  !> Finalize MPI, print the summary on rank 0 and stop with status 1 if a test failed or none
  !! ran. The summary comes last, after MPI_Finalize: ctest requires it (PASS_REGULAR_EXPRESSION,
  !! tests/CMakeLists.txt), so a run that ends early or hangs in MPI_Finalize does not pass.
  subroutine pf_runner_finish(runner)
    type(pf_runner_t), intent(inout) :: runner  !< runner state
    character(len=160) :: line
    call MPI_Finalize()
    if (runner%world_rank == 0) then
      write(line, '(i0,a,i0,a,i0,a,i0,a)') runner%passed, ' passed, ', runner%failed, &
        ' failed (', runner%skipped, ' skipped at ', runner%world_size, ' ranks)'
      write(output_unit, '(a)') trim(runner%source) // ': ' // trim(line)
      if (runner%passed + runner%failed == 0) then
        write(output_unit, '(a)') trim(runner%source) // ': no test ran at this number of ranks'
      end if
      flush(output_unit)
    end if
    ! Only rank 0 reports the (reduced, rank-independent) verdict in its exit status: a rank that
    ! stopped with status 1 first could make the launcher kill rank 0 before its summary.
    if (runner%world_rank /= 0) return
    if (runner%failed > 0 .or. runner%passed + runner%failed == 0) stop 1
  end subroutine pf_runner_finish
end module pfunit_core
