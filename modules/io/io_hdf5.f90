!> The HDF5 output layer in one `use`: files, attributes, grid fields, particle arrays and the
!! root attributes every dump and checkpoint carries (design §7).
!!
!! Typical dump (all ranks, collective):
!!
!!     call h5_create(file, trim(dir) // '/' // io_dump_stem(name, step) // '.h5', dom%comm)
!!     call h5_write_dump_header(file, time, step, dt, grid)
!!     call h5_write_cell_field(file, 'cell/pressure', grid, pressure)
!!     call h5_write_particles(file, 'particles/sand/x', x_local)
!!     call h5_close(file)
!!
!! See `docs/io.md` for the file layout, the array order seen from Python and the checkpoints.
module io_hdf5
  use mpmice_kinds, only: wp
  use grid_layout, only: grid_t
  use io_hdf5_file, only: h5_file_t, h5_create, h5_open, h5_close, h5_exists, h5_make_groups
  use io_hdf5_attributes, only: h5_write_attribute, h5_read_attribute, h5_attribute_exists, &
    h5_attribute_size
  use io_hdf5_fields, only: h5_write_cell_field, h5_read_cell_field, h5_write_node_field, &
    h5_read_node_field, node_extent
  use io_hdf5_particles, only: h5_write_particles, h5_read_particles, h5_particle_count
  implicit none
  private

  public :: h5_file_t, h5_create, h5_open, h5_close, h5_exists, h5_make_groups
  public :: h5_write_attribute, h5_read_attribute, h5_attribute_exists, h5_attribute_size
  public :: h5_write_cell_field, h5_read_cell_field, h5_write_node_field, h5_read_node_field
  public :: node_extent
  public :: h5_write_particles, h5_read_particles, h5_particle_count
  public :: h5_write_dump_header, h5_read_dump_header

contains

  !> Root attributes of a dump or checkpoint: `time` [s], `step`, `dt` [s], `ndim`, `ncells(3)`,
  !! `lower(3)` [m], `upper(3)` [m], `dx(3)` [m], `periodic(3)` (0/1), `nranks` (writers).
  !! Collective; every rank passes the same values.
  subroutine h5_write_dump_header(file, time, step, dt, grid)
    type(h5_file_t), intent(in) :: file  !< file open for writing
    real(wp), intent(in) :: time         !< simulated time [s]
    integer, intent(in) :: step          !< time step number
    real(wp), intent(in) :: dt           !< current time step [s]
    type(grid_t), intent(in) :: grid     !< any block of the grid (global values are used)
    call h5_write_attribute(file, 'time', time)
    call h5_write_attribute(file, 'step', step)
    call h5_write_attribute(file, 'dt', dt)
    call h5_write_attribute(file, 'ndim', grid%ndim)
    call h5_write_attribute(file, 'ncells', grid%ncells)
    call h5_write_attribute(file, 'lower', grid%lower)
    call h5_write_attribute(file, 'upper', grid%upper)
    call h5_write_attribute(file, 'dx', grid%dx)
    call h5_write_attribute(file, 'periodic', merge(1, 0, grid%periodic))
    call h5_write_attribute(file, 'nranks', file%nranks)
  end subroutine h5_write_dump_header

  !> Read back the root attributes written by `h5_write_dump_header`. Collective.
  subroutine h5_read_dump_header(file, time, step, dt, ncells, lower, upper)
    type(h5_file_t), intent(in) :: file                !< open file
    real(wp), intent(out) :: time                      !< simulated time [s]
    integer, intent(out) :: step                       !< time step number
    real(wp), intent(out) :: dt                        !< time step [s]
    integer, intent(out), optional :: ncells(3)        !< global cells per dimension
    real(wp), intent(out), optional :: lower(3)        !< low corner [m]
    real(wp), intent(out), optional :: upper(3)        !< high corner [m]
    call h5_read_attribute(file, 'time', time)
    call h5_read_attribute(file, 'step', step)
    call h5_read_attribute(file, 'dt', dt)
    if (present(ncells)) call h5_read_attribute(file, 'ncells', ncells)
    if (present(lower)) call h5_read_attribute(file, 'lower', lower)
    if (present(upper)) call h5_read_attribute(file, 'upper', upper)
  end subroutine h5_read_dump_header
end module io_hdf5
