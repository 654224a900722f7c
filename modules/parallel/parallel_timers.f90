!> The end-of-run table of the stage timers (`mpmice_timers`, base/) over all ranks: each
!! stage's largest and summed total are reduced here, where MPI may be called, and printed by
!! `timer_table` (rank 0).
module parallel_timers
  use mpi_f08, only: MPI_Comm, MPI_Allreduce, MPI_MAX, MPI_SUM, MPI_DOUBLE_PRECISION
  use mpmice_kinds, only: wp
  use mpmice_timers, only: timer_set_t, timer_table, max_stages
  use parallel_comm, only: comm_size
  implicit none
  private

  public :: timer_summary

contains

  !> Print the per-stage table: calls, maximum and mean total time over the ranks of `comm`
  !! (collective; rank 0 prints). `run_s` is the wall time of the whole run used for the
  !! percentage column.
  subroutine timer_summary(timers, comm, run_s)
    type(timer_set_t), intent(in) :: timers  !< timer set (same stages on every rank)
    type(MPI_Comm), intent(in) :: comm       !< communicator of the run
    real(wp), intent(in) :: run_s            !< wall time of the run [s]
    real(wp) :: tmax(max_stages), tsum(max_stages)
    integer :: n
    n = timers%nstages
    if (n == 0) return
    call MPI_Allreduce(timers%total_s, tmax, n, MPI_DOUBLE_PRECISION, MPI_MAX, comm)
    call MPI_Allreduce(timers%total_s, tsum, n, MPI_DOUBLE_PRECISION, MPI_SUM, comm)
    call timer_table(timers, tmax(1:n), tsum(1:n), comm_size(comm), run_s)
  end subroutine timer_summary
end module parallel_timers
