!> Cell and node fields of the block-decomposed grid as global HDF5 datasets.
!!
!! A field is a rank-3 `real(wp)` array of one block, allocated with the cell bounds
!! `grid%lbc..grid%ubc` (cell fields) or the node bounds `grid%lbn..grid%ubn` (node fields). Each
!! rank writes only the part it owns (`lo..hi` or `nlo..nhi`) into one global dataset, as if the
!! whole grid were one block, with hyperslab selections and collective MPI-IO; ghost layers are
!! neither written nor read. Reading fills the owned part and leaves ghosts unchanged, so a file
!! written with one decomposition reads back with any other.
!!
!! On-disk order: the Fortran dataset extent is `(ni, nj, nk)`; HDF5 stores it C-ordered, so C
!! and Python (h5py) see shape `(nk, nj, ni)` and index `[k-1, j-1, i-1]`.
!! `postproc/mpmice_io.py` transposes on read to give `[i-1, j-1, k-1]`.
!!
!! Global extents: cells `ncells`; nodes `ncells + 1` in active non-periodic dimensions,
!! `ncells` in periodic ones (node `ncells + 1` is node 1 there) and 1 in inactive ones.
module io_hdf5_fields
  use hdf5, only: hid_t, hsize_t, h5dwrite_f, h5dread_f, h5dclose_f, h5dget_space_f, &
    h5screate_simple_f, h5sselect_hyperslab_f, h5sclose_f, h5pclose_f, h5kind_to_type, &
    H5S_SELECT_SET_F, H5_REAL_KIND
  use mpmice_kinds, only: wp
  use mpmice_errors, only: fatal
  use grid_layout, only: grid_t
  use io_hdf5_file, only: h5_file_t, h5_check, h5_clean_path, h5_dataset_create_or_open, &
    h5_dataset_open_read, h5_collective_xfer
  implicit none
  private

  public :: h5_write_cell_field, h5_read_cell_field, h5_write_node_field, h5_read_node_field
  public :: node_extent

  !> Where a block's owned region sits in its local array and in the global dataset.
  type :: block_map_t
    integer(hsize_t) :: global(3) = 1_hsize_t   !< global dataset extent
    integer(hsize_t) :: local(3) = 1_hsize_t    !< local array extent (ghosts included)
    integer(hsize_t) :: local_offset(3) = 0_hsize_t  !< first owned entry in the local array
    integer(hsize_t) :: global_offset(3) = 0_hsize_t !< first owned entry in the dataset
    integer(hsize_t) :: count(3) = 1_hsize_t    !< owned entries
  end type block_map_t

contains

  !> Write the owned cells of `field` to the global dataset `path` (created if missing).
  !! Collective.
  subroutine h5_write_cell_field(file, path, grid, field)
    type(h5_file_t), intent(in) :: file       !< file open for writing
    character(len=*), intent(in) :: path      !< dataset path, e.g. `cell/pressure`
    type(grid_t), intent(in) :: grid          !< this rank's block
    real(wp), intent(in), contiguous :: field(:, :, :) !< cell field, bounds lbc..ubc [any unit]
    call write_block(file, path, cell_map(grid), field)
  end subroutine h5_write_cell_field

  !> Fill the owned cells of `field` from the global dataset `path` (ghosts untouched).
  !! Collective.
  subroutine h5_read_cell_field(file, path, grid, field)
    type(h5_file_t), intent(in) :: file         !< open file
    character(len=*), intent(in) :: path        !< dataset path
    type(grid_t), intent(in) :: grid            !< this rank's block
    real(wp), intent(inout), contiguous :: field(:, :, :) !< cell field, bounds lbc..ubc
    call read_block(file, path, cell_map(grid), field)
  end subroutine h5_read_cell_field

  !> Write the owned nodes of `field` to the global dataset `path` (created if missing).
  !! Collective.
  subroutine h5_write_node_field(file, path, grid, field)
    type(h5_file_t), intent(in) :: file       !< file open for writing
    character(len=*), intent(in) :: path      !< dataset path, e.g. `checkpoint/node/mass`
    type(grid_t), intent(in) :: grid          !< this rank's block
    real(wp), intent(in), contiguous :: field(:, :, :) !< node field, bounds lbn..ubn [any unit]
    call write_block(file, path, node_map(grid), field)
  end subroutine h5_write_node_field

  !> Fill the owned nodes of `field` from the global dataset `path` (ghosts untouched).
  !! Collective.
  subroutine h5_read_node_field(file, path, grid, field)
    type(h5_file_t), intent(in) :: file         !< open file
    character(len=*), intent(in) :: path        !< dataset path
    type(grid_t), intent(in) :: grid            !< this rank's block
    real(wp), intent(inout), contiguous :: field(:, :, :) !< node field, bounds lbn..ubn
    call read_block(file, path, node_map(grid), field)
  end subroutine h5_read_node_field

  !> Global number of nodes per dimension stored in node datasets.
  pure function node_extent(grid) result(n)
    type(grid_t), intent(in) :: grid  !< any block of the grid
    integer :: n(3)
    integer :: d
    do d = 1, 3
      if (.not. grid%active(d)) then
        n(d) = 1
      else if (grid%periodic(d)) then
        n(d) = grid%ncells(d)
      else
        n(d) = grid%ncells(d) + 1
      end if
    end do
  end function node_extent

  !> Block map of the owned cells.
  pure function cell_map(grid) result(map)
    type(grid_t), intent(in) :: grid  !< this rank's block
    type(block_map_t) :: map
    map%global = int(grid%ncells, hsize_t)
    map%local = int(grid%ubc - grid%lbc + 1, hsize_t)
    map%local_offset = int(grid%lo - grid%lbc, hsize_t)
    map%global_offset = int(grid%lo - 1, hsize_t)
    map%count = int(grid%hi - grid%lo + 1, hsize_t)
  end function cell_map

  !> Block map of the owned nodes.
  pure function node_map(grid) result(map)
    type(grid_t), intent(in) :: grid  !< this rank's block
    type(block_map_t) :: map
    map%global = int(node_extent(grid), hsize_t)
    map%local = int(grid%ubn - grid%lbn + 1, hsize_t)
    map%local_offset = int(grid%nlo - grid%lbn, hsize_t)
    map%global_offset = int(grid%nlo - 1, hsize_t)
    map%count = int(grid%nhi - grid%nlo + 1, hsize_t)
  end function node_map

  !> Stop unless `field` has the local extent of the map.
  subroutine check_shape(file, path, map, field)
    type(h5_file_t), intent(in) :: file      !< file (for messages)
    character(len=*), intent(in) :: path     !< dataset path (for messages)
    type(block_map_t), intent(in) :: map     !< expected layout
    real(wp), intent(in) :: field(:, :, :)   !< field passed by the caller
    if (any(int(shape(field), hsize_t) /= map%local)) then
      call fatal('HDF5: field for ' // trim(file%path) // ':/' // h5_clean_path(path) &
        // ' does not have the allocation bounds of the grid block')
    end if
  end subroutine check_shape

  !> Memory and file dataspaces selecting the owned region.
  subroutine select_block(file, path, dset_id, map, mem_space, file_space)
    type(h5_file_t), intent(in) :: file        !< file (for messages)
    character(len=*), intent(in) :: path       !< dataset path (for messages)
    integer(hid_t), intent(in) :: dset_id      !< open dataset
    type(block_map_t), intent(in) :: map       !< layout
    integer(hid_t), intent(out) :: mem_space   !< selection in the local array
    integer(hid_t), intent(out) :: file_space  !< selection in the dataset
    integer :: hdferr
    call h5screate_simple_f(3, map%local, mem_space, hdferr)
    call h5_check(hdferr, 'h5screate_simple_f (memory space)', file, path)
    call h5sselect_hyperslab_f(mem_space, H5S_SELECT_SET_F, map%local_offset, map%count, hdferr)
    call h5_check(hdferr, 'h5sselect_hyperslab_f (memory)', file, path)
    call h5dget_space_f(dset_id, file_space, hdferr)
    call h5_check(hdferr, 'h5dget_space_f', file, path)
    call h5sselect_hyperslab_f(file_space, H5S_SELECT_SET_F, map%global_offset, map%count, hdferr)
    call h5_check(hdferr, 'h5sselect_hyperslab_f (file)', file, path)
  end subroutine select_block

  !> Collective write of the owned region of `field`.
  subroutine write_block(file, path, map, field)
    type(h5_file_t), intent(in) :: file      !< file open for writing
    character(len=*), intent(in) :: path     !< dataset path
    type(block_map_t), intent(in) :: map     !< layout
    real(wp), intent(in), contiguous :: field(:, :, :)   !< local array
    integer(hid_t) :: dset_id, mem_space, file_space, xfer, type_id
    integer :: hdferr
    call check_shape(file, path, map, field)
    type_id = h5kind_to_type(wp, H5_REAL_KIND)
    call h5_dataset_create_or_open(file, path, type_id, map%global, dset_id)
    call select_block(file, path, dset_id, map, mem_space, file_space)
    call h5_collective_xfer(file, xfer)
    call h5dwrite_f(dset_id, type_id, field, map%local, hdferr, mem_space_id=mem_space, &
      file_space_id=file_space, xfer_prp=xfer)
    call h5_check(hdferr, 'h5dwrite_f (collective)', file, path)
    call release(file, path, dset_id, mem_space, file_space, xfer)
  end subroutine write_block

  !> Collective read of the owned region of `field`.
  subroutine read_block(file, path, map, field)
    type(h5_file_t), intent(in) :: file        !< open file
    character(len=*), intent(in) :: path       !< dataset path
    type(block_map_t), intent(in) :: map       !< layout
    real(wp), intent(inout), contiguous :: field(:, :, :)  !< local array
    integer(hid_t) :: dset_id, mem_space, file_space, xfer, type_id
    integer(hsize_t), allocatable :: dims(:)
    integer :: hdferr
    call check_shape(file, path, map, field)
    type_id = h5kind_to_type(wp, H5_REAL_KIND)
    call h5_dataset_open_read(file, path, dset_id, dims)
    if (size(dims) /= 3) then
      call fatal('HDF5: dataset ' // trim(file%path) // ':/' // h5_clean_path(path) &
        // ' is not a 3-D grid field')
    end if
    if (any(dims /= map%global)) then
      call fatal('HDF5: dataset ' // trim(file%path) // ':/' // h5_clean_path(path) &
        // ' does not match the grid size')
    end if
    call select_block(file, path, dset_id, map, mem_space, file_space)
    call h5_collective_xfer(file, xfer)
    call h5dread_f(dset_id, type_id, field, map%local, hdferr, mem_space_id=mem_space, &
      file_space_id=file_space, xfer_prp=xfer)
    call h5_check(hdferr, 'h5dread_f (collective)', file, path)
    call release(file, path, dset_id, mem_space, file_space, xfer)
  end subroutine read_block

  !> Close the identifiers of one transfer.
  subroutine release(file, path, dset_id, mem_space, file_space, xfer)
    type(h5_file_t), intent(in) :: file      !< file (for messages)
    character(len=*), intent(in) :: path     !< dataset path (for messages)
    integer(hid_t), intent(in) :: dset_id    !< dataset
    integer(hid_t), intent(in) :: mem_space  !< memory space
    integer(hid_t), intent(in) :: file_space !< file space
    integer(hid_t), intent(in) :: xfer       !< transfer property list
    integer :: hdferr
    call h5pclose_f(xfer, hdferr)
    call h5_check(hdferr, 'h5pclose_f (transfer list)', file, path)
    call h5sclose_f(mem_space, hdferr)
    call h5_check(hdferr, 'h5sclose_f (memory space)', file, path)
    call h5sclose_f(file_space, hdferr)
    call h5_check(hdferr, 'h5sclose_f (file space)', file, path)
    call h5dclose_f(dset_id, hdferr)
    call h5_check(hdferr, 'h5dclose_f', file, path)
  end subroutine release
end module io_hdf5_fields
