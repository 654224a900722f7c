!> A program that uses the installed MPMICE library (tests/packaging): prints the version constant
!! of module mpmice_build_info and, given a dump, its root attribute `mpmice_version` read through
!! the library's HDF5 layer (module io_hdf5), so it needs the installed .mod files and the MPI and
!! HDF5 link dependencies the CMake package declares.
!!
!!     mpmice_consumer [dump.h5]
program mpmice_consumer
  use mpi_f08, only: MPI_Init, MPI_Finalize, MPI_COMM_WORLD
  use mpmice_build_info, only: mpmice_version
  use io_hdf5, only: h5_file_t, h5_open, h5_close, h5_read_attribute
  implicit none
  type(h5_file_t) :: file
  character(len=4096) :: path
  character(len=:), allocatable :: text

  write(*, '(a)') 'library_version ' // mpmice_version
  if (command_argument_count() < 1) stop
  call get_command_argument(1, path)
  call MPI_Init()
  call h5_open(file, trim(path), MPI_COMM_WORLD)
  call h5_read_attribute(file, 'mpmice_version', text)
  call h5_close(file)
  write(*, '(a)') 'dump_version ' // text
  call MPI_Finalize()
end program mpmice_consumer
