!> Parallel HDF5 files: open/create/close with MPI-IO, groups on demand, dataset handles, and
!! the error check every HDF5 call of the output layer goes through.
!!
!! All routines here are collective over the file's communicator unless stated otherwise: every
!! rank of the communicator given to `h5_create`/`h5_open` calls them in the same order with the
!! same object paths. Object paths are relative to the file root; a leading `/` is allowed
!! (`/cell/pressure` and `cell/pressure` name the same dataset).
!!
!! Files are created with the HDF5 1.8 object format (`libver` bounds v18..v18): readable by every
!! HDF5 >= 1.8 (h5py, ParaView, VisIt) and able to hold attributes larger than 64 KiB (the
!! resolved namelist text of a checkpoint).
!!
!! Raw-data transfers are collective MPI-IO, except where Open MPI's OMPIO component may serve
!! the file (`mpiio_collective_is_safe`): there they are independent, because OMPIO's collective
!! writes corrupted datasets in our tests (docs/io.md). `io_select_mpiio` avoids OMPIO.
module io_hdf5_file
  use parallel_comm, only: MPI_Comm, MPI_COMM_NULL, MPI_INFO_NULL, comm_rank, comm_size, &
    barrier, all_and, mpi_library_version
  use hdf5, only: hid_t, hsize_t, h5open_f, h5fcreate_f, h5fopen_f, h5fclose_f, &
    h5pcreate_f, h5pclose_f, h5pset_fapl_mpio_f, h5pset_libver_bounds_f, h5pset_dxpl_mpio_f, &
    h5lexists_f, h5gcreate_f, h5gclose_f, h5dcreate_f, h5dopen_f, h5dclose_f, h5dget_space_f, &
    h5screate_simple_f, h5sclose_f, h5sget_simple_extent_ndims_f, h5sget_simple_extent_dims_f, &
    H5P_FILE_ACCESS_F, H5P_DATASET_XFER_F, H5F_ACC_TRUNC_F, H5F_ACC_RDONLY_F, H5F_ACC_RDWR_F, &
    H5F_LIBVER_V18_F, H5FD_MPIO_COLLECTIVE_F, H5FD_MPIO_INDEPENDENT_F, h5eset_auto_f, h5eprint_f
  use mpmice_kinds, only: path_len
  use mpmice_errors, only: fatal
  use io_files, only: io_file_exists
  use io_write_failure, only: io_system_error, io_write_failed
  implicit none
  private

  public :: h5_file_t, h5_create, h5_open, h5_close, h5_exists, h5_make_groups
  public :: h5_check, h5_clean_path, h5_parent_path, h5_require_writable
  public :: h5_dataset_create_or_open, h5_dataset_open_read, h5_collective_xfer
  public :: mpiio_collective_is_safe

  !> An HDF5 file opened by all ranks of a communicator (MPI-IO driver).
  type :: h5_file_t
    integer(hid_t) :: id = -1_hid_t                !< HDF5 file identifier
    type(MPI_Comm) :: comm = MPI_COMM_NULL         !< communicator that opened the file (not owned)
    integer :: rank = 0                            !< rank of this process in `comm`
    integer :: nranks = 1                          !< size of `comm`
    logical :: readonly = .false.                  !< opened read-only
    logical :: collective = .true.                 !< collective MPI-IO (see h5_collective_xfer)
    logical :: is_open = .false.                   !< set by h5_create/h5_open, cleared by h5_close
    character(len=path_len) :: path = ''           !< file name (for messages)
    !> created by h5_create: a failed call ends the run as a failed write (io_write_failure)
    logical :: output = .false.
    character(len=path_len) :: final_path = ''     !< name the file gets when complete ('' path)
  end type h5_file_t

contains

  !> Create (truncate) `path` collectively over `comm` for writing. A failing HDF5 call on the
  !! file (a full disk, a missing permission) ends the run with one line and exit status 3 and
  !! removes `path` (`io_write_failed`); the message names `final_path` when given (the name the
  !! caller renames `path` to when it is complete).
  subroutine h5_create(file, path, comm, final_path)
    type(h5_file_t), intent(inout) :: file  !< file handle to fill (must not be open)
    character(len=*), intent(in) :: path    !< file name
    type(MPI_Comm), intent(in) :: comm      !< communicator of all writers
    character(len=*), intent(in), optional :: final_path !< final name, for messages
    integer(hid_t) :: fapl
    integer :: hdferr

    call start_open(file, path, comm)
    file%output = .true.
    file%final_path = path
    if (present(final_path)) file%final_path = final_path
    call make_fapl(file, fapl)
    call h5fcreate_f(trim(path), H5F_ACC_TRUNC_F, file%id, hdferr, access_prp=fapl)
    call h5_check(hdferr, 'h5fcreate_f (create file)', file)
    call h5pclose_f(fapl, hdferr)
    call h5_check(hdferr, 'h5pclose_f (file access list)', file)
    file%readonly = .false.
    file%is_open = .true.
  end subroutine h5_create

  !> Open the existing file `path` collectively over `comm`, read-only unless `readonly` is false.
  subroutine h5_open(file, path, comm, readonly)
    type(h5_file_t), intent(inout) :: file     !< file handle to fill (must not be open)
    character(len=*), intent(in) :: path       !< file name
    type(MPI_Comm), intent(in) :: comm         !< communicator of all readers/writers
    logical, intent(in), optional :: readonly  !< open read-only (default .true.)
    integer(hid_t) :: fapl
    integer :: hdferr, flags
    logical :: ro

    ro = .true.
    if (present(readonly)) ro = readonly
    call start_open(file, path, comm)
    file%output = .false.
    if (.not. io_file_exists(path)) call fatal('h5_open: no such file: ' // trim(path))
    call make_fapl(file, fapl)
    flags = H5F_ACC_RDWR_F
    if (ro) flags = H5F_ACC_RDONLY_F
    call h5fopen_f(trim(path), flags, file%id, hdferr, access_prp=fapl)
    call h5_check(hdferr, 'h5fopen_f (open file)', file)
    call h5pclose_f(fapl, hdferr)
    call h5_check(hdferr, 'h5pclose_f (file access list)', file)
    file%readonly = ro
    file%is_open = .true.
  end subroutine h5_open

  !> Close the file (collective). Closing a handle that is not open does nothing.
  subroutine h5_close(file)
    type(h5_file_t), intent(inout) :: file  !< file to close
    integer :: hdferr
    if (.not. file%is_open) return
    call h5fclose_f(file%id, hdferr)
    call h5_check(hdferr, 'h5fclose_f (close file)', file)
    ! MPI-IO makes one rank's writes visible to another after close and a later open only when
    ! the close has completed everywhere first: a collective close is not a barrier.
    call barrier(file%comm)
    file%id = -1_hid_t
    file%is_open = .false.
    file%output = .false.
    file%comm = MPI_COMM_NULL
  end subroutine h5_close

  !> Common start of h5_create/h5_open: library start-up, rank bookkeeping.
  subroutine start_open(file, path, comm)
    type(h5_file_t), intent(inout) :: file  !< file handle
    character(len=*), intent(in) :: path    !< file name
    type(MPI_Comm), intent(in) :: comm      !< communicator
    integer :: hdferr
    if (file%is_open) call fatal('HDF5: handle already holds open file ' // trim(file%path) &
      // ' while opening ' // trim(path))
    if (len_trim(path) > path_len) call fatal('HDF5: file name too long: ' // trim(path))
    file%path = path
    ! h5open_f initialises the Fortran interface; calling it again is harmless.
    call h5open_f(hdferr)
    call h5_check(hdferr, 'h5open_f (library start-up)', file)
    ! no automatic error stacks: h5_check reports a failure in one line (and prints the stack
    ! of a failed read before stopping)
    call h5eset_auto_f(0, hdferr)
    file%comm = comm
    file%rank = comm_rank(comm)
    file%nranks = comm_size(comm)
    ! All ranks must agree on the transfer mode.
    file%collective = all_and(comm, mpiio_collective_is_safe())
  end subroutine start_open

  !> False when Open MPI's OMPIO component may serve MPI-IO: its default collective-write module
  !! (fcoll/vulcan, Open MPI 4.1) was seen to leave parts of collectively written HDF5 datasets
  !! as zeros at 2 and 4 ranks on ext4, while ROMIO (`OMPI_MCA_io=^ompio`, see
  !! `io_select_mpiio`) and independent transfers were always correct. OMPIO counts as possible
  !! unless `OMPI_MCA_io` excludes it (`^ompio`) or names other components only (`romio321`).
  function mpiio_collective_is_safe() result(safe)
    logical :: safe
    character(len=256) :: setting
    integer :: length, status
    safe = .true.
    if (index(mpi_library_version(), 'Open MPI') == 0) return
    call get_environment_variable('OMPI_MCA_io', setting, length, status)
    if (status /= 0 .or. length == 0) then
      safe = .false.
    else
      setting = adjustl(setting)
      if (setting(1:1) == '^') then
        safe = index(setting, 'ompio') > 0
      else
        safe = index(setting, 'ompio') == 0
      end if
    end if
  end function mpiio_collective_is_safe

  !> File access property list: MPI-IO over the file's communicator, 1.8 object format.
  subroutine make_fapl(file, fapl)
    type(h5_file_t), intent(in) :: file   !< file being opened
    integer(hid_t), intent(out) :: fapl   !< new property list (caller closes it)
    integer :: hdferr
    call h5pcreate_f(H5P_FILE_ACCESS_F, fapl, hdferr)
    call h5_check(hdferr, 'h5pcreate_f (file access list)', file)
    call h5pset_fapl_mpio_f(fapl, file%comm%MPI_VAL, MPI_INFO_NULL%MPI_VAL, hdferr)
    call h5_check(hdferr, 'h5pset_fapl_mpio_f', file)
    call h5pset_libver_bounds_f(fapl, H5F_LIBVER_V18_F, H5F_LIBVER_V18_F, hdferr)
    call h5_check(hdferr, 'h5pset_libver_bounds_f', file)
  end subroutine make_fapl

  !> Stop with a message naming the operation, the file and the object when `hdferr` < 0.
  subroutine h5_check(hdferr, operation, file, object)
    integer, intent(in) :: hdferr                   !< HDF5 return code
    character(len=*), intent(in) :: operation       !< what was attempted
    type(h5_file_t), intent(in) :: file             !< file concerned
    character(len=*), intent(in), optional :: object !< object path inside the file
    integer :: code, ignored
    if (hdferr >= 0) return
    code = io_system_error()   ! first: any later call may change errno
    if (file%output) call io_write_failed(file%path, file%final_path, 'HDF5 ' // operation, code)
    call h5eprint_f(ignored)
    if (present(object)) then
      call fatal('HDF5: ' // operation // ' failed on ' // trim(file%path) // ':/' &
        // h5_clean_path(object))
    else
      call fatal('HDF5: ' // operation // ' failed on ' // trim(file%path))
    end if
  end subroutine h5_check

  !> Stop unless the file is open for writing.
  subroutine h5_require_writable(file, object)
    type(h5_file_t), intent(in) :: file      !< file to write to
    character(len=*), intent(in) :: object   !< object about to be written
    if (.not. file%is_open) call fatal('HDF5: write of ' // trim(object) // ' to a closed file')
    if (file%readonly) call fatal('HDF5: write of ' // trim(object) // ' to read-only file ' &
      // trim(file%path))
  end subroutine h5_require_writable

  !> Object path without surrounding blanks and `/` (`''` is the root group).
  pure function h5_clean_path(path) result(clean)
    character(len=*), intent(in) :: path  !< path as given
    character(len=:), allocatable :: clean
    integer :: first, last
    first = 1
    last = len_trim(path)
    do while (first <= last)
      if (path(first:first) /= '/' .and. path(first:first) /= ' ') exit
      first = first + 1
    end do
    do while (last >= first)
      if (path(last:last) /= '/') exit
      last = last - 1
    end do
    clean = path(first:last)
  end function h5_clean_path

  !> Group part of an object path (`cell/water/density` -> `cell/water`; `x` -> `''`).
  pure function h5_parent_path(path) result(parent)
    character(len=*), intent(in) :: path  !< object path
    character(len=:), allocatable :: parent
    character(len=:), allocatable :: clean
    integer :: slash
    clean = h5_clean_path(path)
    slash = index(clean, '/', back=.true.)
    if (slash == 0) then
      parent = ''
    else
      parent = clean(1:slash - 1)
    end if
  end function h5_parent_path

  !> True if every component of `path` exists (the root always exists). Collective.
  function h5_exists(file, path) result(exists)
    type(h5_file_t), intent(in) :: file    !< open file
    character(len=*), intent(in) :: path   !< object path
    logical :: exists
    character(len=:), allocatable :: clean
    integer :: i
    clean = h5_clean_path(path)
    exists = .true.
    if (len(clean) == 0) return
    do i = 1, len(clean) + 1
      if (.not. component_end(clean, i)) cycle
      exists = link_exists(file, clean(1:i - 1))
      if (.not. exists) return
    end do
  end function h5_exists

  !> True when position `i` of the clean path `clean` ends a path component (a '/' or the end).
  pure logical function component_end(clean, i) result(at_end)
    character(len=*), intent(in) :: clean  !< path without leading, trailing or double '/'
    integer, intent(in) :: i               !< position 1..len(clean) + 1
    at_end = .true.
    if (i <= len(clean)) at_end = clean(i:i) == '/'
  end function component_end

  !> True when the link `path` (its parents existing) exists in the file. Collective.
  logical function link_exists(file, path) result(exists)
    type(h5_file_t), intent(in) :: file    !< open file
    character(len=*), intent(in) :: path   !< object path
    integer :: hdferr
    call h5lexists_f(file%id, path, exists, hdferr)
    call h5_check(hdferr, 'h5lexists_f', file, path)
  end function link_exists

  !> Create the group `path` and any missing parents. Collective.
  subroutine h5_make_groups(file, path)
    type(h5_file_t), intent(in) :: file    !< file open for writing
    character(len=*), intent(in) :: path   !< group path, e.g. `cell/water`
    character(len=:), allocatable :: clean
    integer(hid_t) :: group_id
    integer :: i, hdferr
    clean = h5_clean_path(path)
    if (len(clean) == 0) return
    do i = 1, len(clean) + 1
      if (.not. component_end(clean, i)) cycle
      if (link_exists(file, clean(1:i - 1))) cycle
      call h5gcreate_f(file%id, clean(1:i - 1), group_id, hdferr)
      call h5_check(hdferr, 'h5gcreate_f (create group)', file, clean(1:i - 1))
      call h5gclose_f(group_id, hdferr)
      call h5_check(hdferr, 'h5gclose_f', file, clean(1:i - 1))
    end do
  end subroutine h5_make_groups

  !> Dataset `path` of global extent `dims` (Fortran order) and type `type_id`: created with its
  !! parent groups if missing, opened (after checking its extent) if it exists. Collective.
  subroutine h5_dataset_create_or_open(file, path, type_id, dims, dset_id)
    type(h5_file_t), intent(in) :: file        !< file open for writing
    character(len=*), intent(in) :: path       !< dataset path
    integer(hid_t), intent(in) :: type_id      !< file data type
    integer(hsize_t), intent(in) :: dims(:)    !< global extent, Fortran order
    integer(hid_t), intent(out) :: dset_id     !< open dataset (caller closes)
    integer(hid_t) :: space_id
    integer(hsize_t), allocatable :: old_dims(:)
    integer :: hdferr

    call h5_require_writable(file, path)
    if (h5_exists(file, path)) then
      call h5_dataset_open_read(file, path, dset_id, old_dims)
      if (size(old_dims) /= size(dims)) then
        call fatal('HDF5: dataset ' // trim(file%path) // ':/' // h5_clean_path(path) &
          // ' exists with a different rank')
      end if
      if (any(old_dims /= dims)) then
        call fatal('HDF5: dataset ' // trim(file%path) // ':/' // h5_clean_path(path) &
          // ' exists with a different shape')
      end if
      return
    end if
    call h5_make_groups(file, h5_parent_path(path))
    call h5screate_simple_f(size(dims), dims, space_id, hdferr)
    call h5_check(hdferr, 'h5screate_simple_f', file, path)
    call h5dcreate_f(file%id, h5_clean_path(path), type_id, space_id, dset_id, hdferr)
    call h5_check(hdferr, 'h5dcreate_f (create dataset)', file, path)
    call h5sclose_f(space_id, hdferr)
    call h5_check(hdferr, 'h5sclose_f', file, path)
  end subroutine h5_dataset_create_or_open

  !> Open the existing dataset `path` and return its extent (Fortran order). Stops with the path
  !! when the dataset is missing. Collective.
  subroutine h5_dataset_open_read(file, path, dset_id, dims)
    type(h5_file_t), intent(in) :: file                 !< open file
    character(len=*), intent(in) :: path                !< dataset path
    integer(hid_t), intent(out) :: dset_id              !< open dataset (caller closes)
    integer(hsize_t), allocatable, intent(out) :: dims(:) !< extent, Fortran order
    integer(hsize_t), allocatable :: maxdims(:)
    integer(hid_t) :: space_id
    integer :: hdferr, rank

    if (.not. file%is_open) call fatal('HDF5: read of ' // trim(path) // ' from a closed file')
    if (.not. h5_exists(file, path)) then
      call fatal('HDF5: no dataset ' // h5_clean_path(path) // ' in ' // trim(file%path))
    end if
    call h5dopen_f(file%id, h5_clean_path(path), dset_id, hdferr)
    call h5_check(hdferr, 'h5dopen_f (open dataset)', file, path)
    call h5dget_space_f(dset_id, space_id, hdferr)
    call h5_check(hdferr, 'h5dget_space_f', file, path)
    call h5sget_simple_extent_ndims_f(space_id, rank, hdferr)
    call h5_check(hdferr, 'h5sget_simple_extent_ndims_f', file, path)
    allocate(dims(rank), maxdims(rank))
    call h5sget_simple_extent_dims_f(space_id, dims, maxdims, hdferr)
    call h5_check(hdferr, 'h5sget_simple_extent_dims_f', file, path)
    call h5sclose_f(space_id, hdferr)
    call h5_check(hdferr, 'h5sclose_f', file, path)
  end subroutine h5_dataset_open_read

  !> Dataset transfer property list (caller closes it with h5pclose_f): collective MPI-IO, or
  !! independent MPI-IO when `file%collective` is false (OMPIO, see `mpiio_collective_is_safe`).
  !! Every rank still calls each read and write, so callers need not care which one is used.
  subroutine h5_collective_xfer(file, xfer_id)
    type(h5_file_t), intent(in) :: file      !< file being accessed
    integer(hid_t), intent(out) :: xfer_id   !< new property list
    integer :: hdferr
    call h5pcreate_f(H5P_DATASET_XFER_F, xfer_id, hdferr)
    call h5_check(hdferr, 'h5pcreate_f (transfer list)', file)
    if (file%collective) then
      call h5pset_dxpl_mpio_f(xfer_id, H5FD_MPIO_COLLECTIVE_F, hdferr)
      call h5_check(hdferr, 'h5pset_dxpl_mpio_f (collective)', file)
    else
      call h5pset_dxpl_mpio_f(xfer_id, H5FD_MPIO_INDEPENDENT_F, hdferr)
      call h5_check(hdferr, 'h5pset_dxpl_mpio_f (independent)', file)
    end if
  end subroutine h5_collective_xfer
end module io_hdf5_file
