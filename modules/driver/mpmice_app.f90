!> Top-level application: MPI start-up, command line, run, shutdown. (Placeholder until the driver lands.)
module mpmice_app
  use mpi_f08, only: MPI_Init, MPI_Finalize
  implicit none
  private
  public :: app_run
contains
  !> Run MPMICE as the command line asks.
  subroutine app_run()
    call MPI_Init()
    call MPI_Finalize()
  end subroutine app_run
end module mpmice_app
