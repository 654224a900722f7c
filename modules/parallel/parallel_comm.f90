!> Thin wrappers of the MPI calls that the layers above parallel/ need, so that only parallel/
!! talks to MPI. base/ sits below parallel/: `mpi_start` hands `mpmice_errors` the MPI ends of
!! its abort and clean exit (`set_exit_hooks`), and `parallel_timers` reduces the stage timers
!! over the ranks. Each wrapper is one MPI call (or the fixed sequence named) on the communicator
!! it is given; nothing is reordered or summed differently, so results are those of the direct
!! calls.
!!
!! The program's one communicator is `MPI_COMM_WORLD` duplicated by `mpi_start` (`mpmice_app`)
!! and passed down explicitly; `MPI_Comm` is re-exported for the dummies that carry it, and
!! `MPI_COMM_NULL`, `MPI_INFO_NULL` for the parallel HDF5 file access (io/).
module parallel_comm
  use mpi_f08, only: MPI_Comm, MPI_COMM_NULL, MPI_COMM_WORLD, MPI_Init, MPI_Finalize, MPI_Comm_dup, &
    MPI_Comm_free, MPI_Comm_rank, MPI_Comm_size, MPI_Comm_split_type, MPI_COMM_TYPE_SHARED, &
    MPI_INFO_NULL, MPI_Bcast, MPI_Barrier, MPI_Allreduce, MPI_Exscan, MPI_Alltoall, &
    MPI_Alltoallv, MPI_Cart_rank, MPI_Get_library_version, MPI_Initialized, MPI_Finalized, &
    MPI_Abort, MPI_IN_PLACE, MPI_INTEGER, MPI_CHARACTER, &
    MPI_INTEGER8, MPI_LOGICAL, MPI_DOUBLE_PRECISION, MPI_2DOUBLE_PRECISION, MPI_SUM, &
    MPI_MAXLOC, MPI_LAND, MPI_MAX_LIBRARY_VERSION_STRING
  use, intrinsic :: iso_c_binding, only: c_int, c_ptr
  use mpmice_kinds, only: wp, i8
  use mpmice_errors, only: set_exit_hooks
  implicit none
  private

  public :: MPI_Comm, MPI_COMM_NULL, MPI_INFO_NULL
  public :: mpi_start, mpi_stop, comm_dup_world, comm_free, comm_rank, comm_size, barrier, &
    bcast, bcast_text, sum_in_place, node_sum, max_location, all_and, all_or, exscan_sum, &
    alltoall_counts, alltoallv_real, cart_rank, mpi_library_version, world_ranks, abort_world
  public :: c_comm_handle

  !> `bcast(comm, values, root)`: MPI_Bcast from rank `root` of one integer or logical, or of an
  !! integer vector or a real vector or matrix.
  interface bcast
    module procedure bcast_int, bcast_int_array, bcast_logical, bcast_real_array, &
      bcast_real_matrix
  end interface bcast

  interface
    !> C `MPI_Comm MPI_Comm_f2c(MPI_Fint)`: the C handle of a Fortran communicator (Open MPI).
    function c_mpi_comm_f2c(fcomm) bind(c, name='MPI_Comm_f2c') result(ccomm)
      import :: c_int, c_ptr
      integer(c_int), value :: fcomm
      type(c_ptr) :: ccomm
    end function c_mpi_comm_f2c
  end interface

contains

  !> The C `MPI_Comm` handle of an `mpi_f08` communicator, for C libraries that take one (hypre).
  !! The only place that calls `MPI_Comm_f2c`. It assumes Open MPI, whose C `MPI_Comm` is a
  !! pointer (MPICH-derived MPIs use an `int` handle and would need `integer(c_int)` instead).
  function c_comm_handle(comm) result(ccomm)
    type(MPI_Comm), intent(in) :: comm  !< Fortran communicator
    type(c_ptr) :: ccomm
    ccomm = c_mpi_comm_f2c(int(comm%MPI_VAL, c_int))
  end function c_comm_handle

  !> MPI_Init, then the program's communicator: a duplicate of `MPI_COMM_WORLD`; from here on
  !! `fatal` aborts every rank and `exit_cleanly` finalizes MPI (`set_exit_hooks`).
  subroutine mpi_start(comm)
    type(MPI_Comm), intent(out) :: comm  !< the program's communicator
    call MPI_Init()
    call MPI_Comm_dup(MPI_COMM_WORLD, comm)
    call set_exit_hooks(abort_running, finalize_running)
  end subroutine mpi_start

  !> The abort hook of `mpmice_errors%fatal`: MPI_Abort of every rank with exit status `code`
  !! while MPI runs (nothing before MPI_Init or after MPI_Finalize).
  subroutine abort_running(code)
    integer, intent(in) :: code  !< exit status
    if (mpi_running()) call MPI_Abort(MPI_COMM_WORLD, code)
  end subroutine abort_running

  !> The finalize hook of `mpmice_errors%exit_cleanly`: MPI_Finalize while MPI runs.
  subroutine finalize_running()
    if (mpi_running()) call MPI_Finalize()
  end subroutine finalize_running

  !> MPI is initialized and not yet finalized.
  logical function mpi_running() result(running)
    logical :: initialized, finalized
    call MPI_Initialized(initialized)
    call MPI_Finalized(finalized)
    running = initialized .and. .not. finalized
  end function mpi_running

  !> Free the program's communicator, then MPI_Finalize.
  subroutine mpi_stop(comm)
    type(MPI_Comm), intent(inout) :: comm  !< the program's communicator
    call MPI_Comm_free(comm)
    call MPI_Finalize()
  end subroutine mpi_stop

  !> A duplicate of `MPI_COMM_WORLD` (for library users and tests without `mpi_start`).
  subroutine comm_dup_world(comm)
    type(MPI_Comm), intent(out) :: comm  !< new communicator (free with `comm_free`)
    call MPI_Comm_dup(MPI_COMM_WORLD, comm)
  end subroutine comm_dup_world

  !> MPI_Comm_free.
  subroutine comm_free(comm)
    type(MPI_Comm), intent(inout) :: comm  !< communicator to free
    call MPI_Comm_free(comm)
  end subroutine comm_free

  !> This rank's number in `comm`.
  integer function comm_rank(comm) result(rank)
    type(MPI_Comm), intent(in) :: comm  !< communicator
    call MPI_Comm_rank(comm, rank)
  end function comm_rank

  !> Number of ranks in `comm`.
  integer function comm_size(comm) result(n)
    type(MPI_Comm), intent(in) :: comm  !< communicator
    call MPI_Comm_size(comm, n)
  end function comm_size

  !> MPI_Barrier.
  subroutine barrier(comm)
    type(MPI_Comm), intent(in) :: comm  !< communicator
    call MPI_Barrier(comm)
  end subroutine barrier

  !> Broadcast of one integer: an integer vector of length 1.
  subroutine bcast_int(comm, value, root)
    type(MPI_Comm), intent(in) :: comm  !< communicator
    integer, intent(inout) :: value     !< sent by root, received elsewhere
    integer, intent(in) :: root         !< sending rank
    integer :: buffer(1)
    buffer(1) = value
    call bcast_int_array(comm, buffer, root)
    value = buffer(1)
  end subroutine bcast_int

  !> Broadcast of an integer array.
  subroutine bcast_int_array(comm, values, root)
    type(MPI_Comm), intent(in) :: comm             !< communicator
    integer, intent(inout), contiguous :: values(:) !< sent by root, received elsewhere
    integer, intent(in) :: root                    !< sending rank
    call MPI_Bcast(values, size(values), MPI_INTEGER, root, comm)
  end subroutine bcast_int_array

  !> Broadcast of one logical, as the integer 1 (true) or 0 (false).
  subroutine bcast_logical(comm, value, root)
    type(MPI_Comm), intent(in) :: comm  !< communicator
    logical, intent(inout) :: value     !< sent by root, received elsewhere
    integer, intent(in) :: root         !< sending rank
    integer :: flag
    flag = merge(1, 0, value)
    call bcast_int(comm, flag, root)
    value = flag == 1
  end subroutine bcast_logical

  !> Broadcast of a real array.
  subroutine bcast_real_array(comm, values, root)
    type(MPI_Comm), intent(in) :: comm    !< communicator
    real(wp), intent(inout) :: values(:)  !< sent by root, received elsewhere
    integer, intent(in) :: root           !< sending rank
    call MPI_Bcast(values, size(values), MPI_DOUBLE_PRECISION, root, comm)
  end subroutine bcast_real_array

  !> Broadcast of a real matrix.
  subroutine bcast_real_matrix(comm, values, root)
    type(MPI_Comm), intent(in) :: comm                   !< communicator
    real(wp), intent(inout), contiguous :: values(:, :)  !< sent by root, received elsewhere
    integer, intent(in) :: root                          !< sending rank
    call MPI_Bcast(values, size(values), MPI_DOUBLE_PRECISION, root, comm)
  end subroutine bcast_real_matrix

  !> Broadcast of a deferred-length string from rank `root` (allocated on the others).
  subroutine bcast_text(comm, text, root)
    type(MPI_Comm), intent(in) :: comm                    !< communicator
    character(len=:), allocatable, intent(inout) :: text  !< sent by root, received elsewhere
    integer, intent(in) :: root                           !< sending rank
    integer :: n
    n = 0
    if (comm_rank(comm) == root) n = len(text)
    call MPI_Bcast(n, 1, MPI_INTEGER, root, comm)
    if (comm_rank(comm) /= root) then
      if (allocated(text)) deallocate(text)
      allocate(character(len=n) :: text)
    end if
    if (n > 0) call MPI_Bcast(text, n, MPI_CHARACTER, root, comm)
  end subroutine bcast_text

  !> Sum over the ranks, in place (MPI_SUM: the order is MPI's, not reproducible across rank
  !! counts; `parallel_reduce%global_sum` is the reproducible one).
  subroutine sum_in_place(comm, values)
    type(MPI_Comm), intent(in) :: comm    !< communicator
    real(wp), intent(inout) :: values(:)  !< this rank's values in, the sums out
    call MPI_Allreduce(MPI_IN_PLACE, values, size(values), MPI_DOUBLE_PRECISION, MPI_SUM, comm)
  end subroutine sum_in_place

  !> Sum of `value` over the ranks of this rank's shared-memory node, with this rank's number
  !! and the number of ranks on the node.
  subroutine node_sum(comm, value, total, node_rank, node_ranks)
    type(MPI_Comm), intent(in) :: comm     !< communicator
    real(wp), intent(in) :: value          !< this rank's value
    real(wp), intent(out) :: total         !< sum over the node's ranks
    integer, intent(out) :: node_rank      !< this rank on the node
    integer, intent(out) :: node_ranks     !< ranks on the node
    type(MPI_Comm) :: node
    call MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, node)
    call MPI_Comm_rank(node, node_rank)
    call MPI_Comm_size(node, node_ranks)
    call MPI_Allreduce(value, total, 1, MPI_DOUBLE_PRECISION, MPI_SUM, node)
    call MPI_Comm_free(node)
  end subroutine node_sum

  !> MPI_MAXLOC over the ranks: `pair` = (value, location) in, the largest value and its
  !! location out.
  subroutine max_location(comm, pair, largest)
    type(MPI_Comm), intent(in) :: comm  !< communicator
    real(wp), intent(in) :: pair(2)     !< this rank's value and location
    real(wp), intent(out) :: largest(2) !< the largest value and its location
    call MPI_Allreduce(pair, largest, 1, MPI_2DOUBLE_PRECISION, MPI_MAXLOC, comm)
  end subroutine max_location

  !> True when `flag` is true on every rank.
  logical function all_and(comm, flag) result(all_true)
    type(MPI_Comm), intent(in) :: comm  !< communicator
    logical, intent(in) :: flag         !< this rank's flag
    call MPI_Allreduce(flag, all_true, 1, MPI_LOGICAL, MPI_LAND, comm)
  end function all_and

  !> True when `flag` is true on any rank: not false on every rank.
  logical function all_or(comm, flag) result(any_true)
    type(MPI_Comm), intent(in) :: comm  !< communicator
    logical, intent(in) :: flag         !< this rank's flag
    any_true = .not. all_and(comm, .not. flag)
  end function all_or

  !> Exclusive prefix sum of `count` over the ranks (0 on rank 0) and the total.
  subroutine exscan_sum(comm, count, offset, total)
    type(MPI_Comm), intent(in) :: comm  !< communicator
    integer(i8), intent(in) :: count    !< this rank's count
    integer(i8), intent(out) :: offset  !< sum over the lower ranks
    integer(i8), intent(out) :: total   !< sum over all ranks
    call MPI_Exscan(count, offset, 1, MPI_INTEGER8, MPI_SUM, comm)
    if (comm_rank(comm) == 0) offset = 0_i8
    call MPI_Allreduce(count, total, 1, MPI_INTEGER8, MPI_SUM, comm)
  end subroutine exscan_sum

  !> MPI_Alltoall of one integer per rank pair: `received(r)` is what rank r sent here.
  subroutine alltoall_counts(comm, sent, received)
    type(MPI_Comm), intent(in) :: comm       !< communicator
    integer, intent(in) :: sent(0:)          !< (0:nranks-1) one value for each rank
    integer, intent(out) :: received(0:)     !< (0:nranks-1) one value from each rank
    call MPI_Alltoall(sent, 1, MPI_INTEGER, received, 1, MPI_INTEGER, comm)
  end subroutine alltoall_counts

  !> MPI_Alltoallv of reals: `send_counts(r)` values from offset `send_displs(r)` of `send`
  !! go to rank r, `recv_counts(r)` arrive from it at offset `recv_displs(r)` of `recv`.
  subroutine alltoallv_real(comm, send, send_counts, send_displs, recv, recv_counts, &
    recv_displs)
    type(MPI_Comm), intent(in) :: comm          !< communicator
    real(wp), intent(in) :: send(:)             !< values to send
    integer, intent(in) :: send_counts(0:)      !< (0:nranks-1) values for each rank
    integer, intent(in) :: send_displs(0:)      !< (0:nranks-1) their offsets
    real(wp), intent(inout) :: recv(:)          !< received values
    integer, intent(in) :: recv_counts(0:)      !< (0:nranks-1) values from each rank
    integer, intent(in) :: recv_displs(0:)      !< (0:nranks-1) their offsets
    call MPI_Alltoallv(send, send_counts, send_displs, MPI_DOUBLE_PRECISION, recv, &
      recv_counts, recv_displs, MPI_DOUBLE_PRECISION, comm)
  end subroutine alltoallv_real

  !> Rank of the block at Cartesian `coords` of the Cartesian communicator `comm`.
  integer function cart_rank(comm, coords) result(rank)
    type(MPI_Comm), intent(in) :: comm  !< Cartesian communicator
    integer, intent(in) :: coords(:)    !< block coordinates (one per Cartesian dimension)
    call MPI_Cart_rank(comm, coords, rank)
  end function cart_rank

  !> The MPI library's version text.
  function mpi_library_version() result(version)
    character(len=:), allocatable :: version
    character(len=MPI_MAX_LIBRARY_VERSION_STRING) :: text
    integer :: length
    call MPI_Get_library_version(text, length)
    version = text(1:length)
  end function mpi_library_version

  !> Ranks of `MPI_COMM_WORLD` while MPI runs; 1 before `MPI_Init` and after `MPI_Finalize`
  !! (the failure paths that may run then).
  integer function world_ranks() result(n)
    n = 1
    if (mpi_running()) call MPI_Comm_size(MPI_COMM_WORLD, n)
  end function world_ranks

  !> MPI_Abort of every rank with exit status `code`.
  subroutine abort_world(code)
    integer, intent(in) :: code  !< exit status
    call MPI_Abort(MPI_COMM_WORLD, code)
  end subroutine abort_world
end module parallel_comm
