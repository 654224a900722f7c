!> Particle arrays as global HDF5 datasets: every rank's particles concatenated in rank order.
!!
!! Each rank passes its own particles (any number, zero included). The offset of a rank's chunk
!! is the exclusive prefix sum (`MPI_Exscan`) of the 64-bit counts; all ranks write their chunk
!! with one collective call. 1-D arrays `values(n)` become datasets of extent `N` (h5py shape
!! `(N,)`); 2-D arrays `values(ncomp, n)` become extent `(ncomp, N)` (h5py shape `(N, ncomp)`,
!! one row per particle).
!!
!! The per-rank counts are stored once per particle group in the int64 dataset
!! `<group>/rank_counts` (length = number of ranks), e.g. `/particles/sand/rank_counts`. All
!! arrays of one group must therefore have the same per-rank lengths (checked when writing), and
!! `rank_counts` is a reserved name. On reading, a run with the same number of ranks gets back
!! exactly the chunk it wrote (restart without migration); with a different number of ranks, or
!! when `rank_counts` is absent, the `N` particles are split evenly in file order (the first
!! `mod(N, nranks)` ranks get one more) and the caller migrates them to their owners.
module io_hdf5_particles
  use parallel_comm, only: exscan_sum, all_or
  use hdf5, only: hid_t, hsize_t, h5dwrite_f, h5dread_f, h5dclose_f, h5dget_space_f, &
    h5screate_simple_f, h5sselect_hyperslab_f, h5sselect_none_f, h5sclose_f, h5pclose_f, &
    h5kind_to_type, H5S_SELECT_SET_F, H5_REAL_KIND, H5_INTEGER_KIND
  use, intrinsic :: iso_c_binding, only: c_ptr, c_null_ptr, c_loc
  use mpmice_kinds, only: wp, i8
  use mpmice_errors, only: fatal
  use io_hdf5_file, only: h5_file_t, h5_check, h5_clean_path, h5_parent_path, h5_exists, &
    h5_dataset_create_or_open, h5_dataset_open_read, h5_collective_xfer
  implicit none
  private

  public :: h5_write_particles, h5_read_particles, h5_particle_count

  character(len=*), parameter :: counts_name = 'rank_counts'  !< reserved dataset name

  !> Collective write of this rank's particles: `call h5_write_particles(file, path, values)`
  !! with `values(:)` real(wp) or integer(i8), or `values(:, :)` real(wp) `(ncomp, n)`.
  interface h5_write_particles
    module procedure write_real, write_int8, write_real_2d
  end interface h5_write_particles

  !> Collective read of this rank's chunk into an allocatable array (see module notes).
  interface h5_read_particles
    module procedure read_real, read_int8, read_real_2d
  end interface h5_read_particles

  !> Open dataset, selections and transfer list of one particle transfer.
  type :: transfer_t
    integer(hid_t) :: dset = -1_hid_t        !< dataset
    integer(hid_t) :: mem_space = -1_hid_t   !< memory selection
    integer(hid_t) :: file_space = -1_hid_t  !< file selection
    integer(hid_t) :: xfer = -1_hid_t        !< collective transfer list
    integer(hsize_t) :: mem_dims(2) = 1_hsize_t  !< memory buffer extent (>= 1 per dimension)
    integer :: n = 0                         !< this rank's particles
    integer(i8) :: total = 0_i8              !< particles of all ranks
    integer :: ncomp = 1                     !< components per particle
    integer(hid_t) :: type_id = -1_hid_t     !< memory data type (the file's when writing)
    type(c_ptr) :: buffer = c_null_ptr       !< this rank's values (set when `n` > 0)
  end type transfer_t

contains

  !> Real 1-D particle array.
  subroutine write_real(file, path, values)
    type(h5_file_t), intent(in) :: file   !< file open for writing
    character(len=*), intent(in) :: path  !< dataset path, e.g. `particles/sand/mass`
    real(wp), intent(in), target, contiguous :: values(:)  !< this rank's values [any unit]
    type(transfer_t) :: t
    call begin_write(file, path, h5kind_to_type(wp, H5_REAL_KIND), 0, size(values), t)
    if (t%n > 0) t%buffer = c_loc(values)
    call move_chunk(file, path, .true., t)
  end subroutine write_real

  !> 64-bit integer 1-D particle array (ids).
  subroutine write_int8(file, path, values)
    type(h5_file_t), intent(in) :: file   !< file open for writing
    character(len=*), intent(in) :: path  !< dataset path, e.g. `particles/sand/id`
    integer(i8), intent(in), target, contiguous :: values(:)  !< this rank's values
    type(transfer_t) :: t
    call begin_write(file, path, h5kind_to_type(i8, H5_INTEGER_KIND), 0, size(values), t)
    if (t%n > 0) t%buffer = c_loc(values)
    call move_chunk(file, path, .true., t)
  end subroutine write_int8

  !> Real 2-D particle array `(ncomp, n)`.
  subroutine write_real_2d(file, path, values)
    type(h5_file_t), intent(in) :: file    !< file open for writing
    character(len=*), intent(in) :: path   !< dataset path, e.g. `checkpoint/particles/sand/F`
    real(wp), intent(in), target, contiguous :: values(:, :) !< this rank's values (ncomp, n)
    type(transfer_t) :: t
    call begin_write(file, path, h5kind_to_type(wp, H5_REAL_KIND), size(values, 1), &
      size(values, 2), t)
    if (t%n > 0) t%buffer = c_loc(values)
    call move_chunk(file, path, .true., t)
  end subroutine write_real_2d

  !> Real 1-D particle array: this rank's chunk.
  subroutine read_real(file, path, values)
    type(h5_file_t), intent(in) :: file                 !< open file
    character(len=*), intent(in) :: path                !< dataset path
    real(wp), allocatable, target, intent(out) :: values(:)  !< this rank's values
    type(transfer_t) :: t
    call begin_read(file, path, 1, h5kind_to_type(wp, H5_REAL_KIND), t)
    allocate(values(t%n))
    if (t%n > 0) t%buffer = c_loc(values)
    call move_chunk(file, path, .false., t)
  end subroutine read_real

  !> 64-bit integer 1-D particle array: this rank's chunk.
  subroutine read_int8(file, path, values)
    type(h5_file_t), intent(in) :: file                 !< open file
    character(len=*), intent(in) :: path                !< dataset path
    integer(i8), allocatable, target, intent(out) :: values(:)  !< this rank's values
    type(transfer_t) :: t
    call begin_read(file, path, 1, h5kind_to_type(i8, H5_INTEGER_KIND), t)
    allocate(values(t%n))
    if (t%n > 0) t%buffer = c_loc(values)
    call move_chunk(file, path, .false., t)
  end subroutine read_int8

  !> Real 2-D particle array `(ncomp, n)`: this rank's chunk.
  subroutine read_real_2d(file, path, values)
    type(h5_file_t), intent(in) :: file                 !< open file
    character(len=*), intent(in) :: path                !< dataset path
    real(wp), allocatable, target, intent(out) :: values(:, :)  !< this rank's values (ncomp, n)
    type(transfer_t) :: t
    call begin_read(file, path, 2, h5kind_to_type(wp, H5_REAL_KIND), t)
    allocate(values(t%ncomp, t%n))
    if (t%n > 0) t%buffer = c_loc(values)
    call move_chunk(file, path, .false., t)
  end subroutine read_real_2d

  !> The collective transfer of this rank's chunk between `t%buffer` and the file, then close
  !! it: the one transfer of every particle array. An empty dataset has no storage that a
  !! transfer could address (nothing moves); a rank without particles joins the collective call
  !! with a zeroed placeholder of the memory extent (its selection is empty).
  subroutine move_chunk(file, path, write, t)
    type(h5_file_t), intent(in) :: file    !< open file
    character(len=*), intent(in) :: path   !< dataset path
    logical, intent(in) :: write           !< write (else read)
    type(transfer_t), intent(inout) :: t   !< transfer state, closed on return
    real(wp), allocatable, target :: empty(:)
    type(c_ptr) :: buffer
    integer :: hdferr
    hdferr = 0
    if (t%total > 0_i8) then
      buffer = t%buffer
      if (t%n == 0) then
        allocate(empty(product(t%mem_dims)))
        empty = 0.0_wp
        buffer = c_loc(empty)
      end if
      if (write) then
        call h5dwrite_f(t%dset, t%type_id, buffer, hdferr, mem_space_id=t%mem_space, &
          file_space_id=t%file_space, xfer_prp=t%xfer)
      else
        call h5dread_f(t%dset, t%type_id, buffer, hdferr, mem_space_id=t%mem_space, &
          file_space_id=t%file_space, xfer_prp=t%xfer)
      end if
    end if
    if (write) then
      call h5_check(hdferr, 'h5dwrite_f (collective)', file, path)
    else
      call h5_check(hdferr, 'h5dread_f (collective)', file, path)
    end if
    call end_transfer(file, path, t)
  end subroutine move_chunk

  !> Number of particles of dataset `path` that `h5_read_particles` gives this rank. Collective.
  function h5_particle_count(file, path) result(n)
    type(h5_file_t), intent(in) :: file   !< open file
    character(len=*), intent(in) :: path  !< dataset path
    integer :: n
    integer(hid_t) :: dset
    integer(hsize_t), allocatable :: dims(:)
    integer(i8) :: offset
    integer :: hdferr
    call h5_dataset_open_read(file, path, dset, dims)
    call h5dclose_f(dset, hdferr)
    call h5_check(hdferr, 'h5dclose_f', file, path)
    call rank_chunk(file, path, int(dims(size(dims)), i8), offset, n)
  end function h5_particle_count

  !> Path of the rank-count dataset of the group holding `path`.
  function counts_path(path) result(cpath)
    character(len=*), intent(in) :: path  !< particle dataset path
    character(len=:), allocatable :: cpath
    character(len=:), allocatable :: parent
    parent = h5_parent_path(path)
    if (len(parent) == 0) then
      cpath = counts_name
    else
      cpath = parent // '/' // counts_name
    end if
  end function counts_path

  !> Open (creating) the dataset, record/check the rank counts, select this rank's chunk.
  subroutine begin_write(file, path, type_id, ncomp, n, t)
    type(h5_file_t), intent(in) :: file    !< file open for writing
    character(len=*), intent(in) :: path   !< dataset path
    integer(hid_t), intent(in) :: type_id  !< data type
    integer, intent(in) :: ncomp           !< components (0: 1-D array)
    integer, intent(in) :: n               !< this rank's particles
    type(transfer_t), intent(out) :: t     !< transfer state
    integer(i8) :: count, offset, total
    integer :: nd

    if (h5_clean_path(path) == counts_path(path)) then
      call fatal('HDF5: ' // counts_name // ' is reserved in particle groups (' // &
        trim(file%path) // ':/' // h5_clean_path(path) // ')')
    end if
    count = int(n, i8)
    call exscan_sum(file%comm, count, offset, total)
    call record_rank_counts(file, path, count)

    t%n = n
    t%total = total
    t%type_id = type_id
    t%ncomp = max(ncomp, 1)
    nd = 1
    if (ncomp > 0) nd = 2
    if (nd == 1) then
      call h5_dataset_create_or_open(file, path, type_id, [int(total, hsize_t)], t%dset)
    else
      call h5_dataset_create_or_open(file, path, type_id, [int(ncomp, hsize_t), &
        int(total, hsize_t)], t%dset)
    end if
    call select_chunk(file, path, nd, offset, t)
  end subroutine begin_write

  !> Open the dataset and select this rank's chunk for reading.
  subroutine begin_read(file, path, nd, type_id, t)
    type(h5_file_t), intent(in) :: file    !< open file
    character(len=*), intent(in) :: path   !< dataset path
    integer, intent(in) :: nd              !< expected rank of the dataset (1 or 2)
    integer(hid_t), intent(in) :: type_id  !< memory data type
    type(transfer_t), intent(out) :: t     !< transfer state
    integer(hsize_t), allocatable :: dims(:)
    integer(i8) :: offset
    call h5_dataset_open_read(file, path, t%dset, dims)
    if (size(dims) /= nd) then
      call fatal('HDF5: particle dataset ' // trim(file%path) // ':/' // h5_clean_path(path) &
        // ' has a different rank than the array it is read into')
    end if
    t%type_id = type_id
    t%ncomp = 1
    if (nd == 2) t%ncomp = int(dims(1))
    t%total = int(dims(nd), i8)
    call rank_chunk(file, path, t%total, offset, t%n)
    call select_chunk(file, path, nd, offset, t)
  end subroutine begin_read

  !> Memory and file selections of `t%n` particles at `offset` (none when `t%n` = 0).
  subroutine select_chunk(file, path, nd, offset, t)
    type(h5_file_t), intent(in) :: file      !< file (for messages)
    character(len=*), intent(in) :: path     !< dataset path (for messages)
    integer, intent(in) :: nd                !< dataset rank
    integer(i8), intent(in) :: offset        !< first particle of this rank (0-based)
    type(transfer_t), intent(inout) :: t     !< transfer state
    integer(hsize_t) :: start(2), count(2)
    integer :: hdferr
    t%mem_dims = 1_hsize_t
    if (nd == 1) then
      t%mem_dims(1) = int(max(t%n, 1), hsize_t)
      start(1) = int(offset, hsize_t)
      count(1) = int(t%n, hsize_t)
    else
      t%mem_dims(1) = int(t%ncomp, hsize_t)
      t%mem_dims(2) = int(max(t%n, 1), hsize_t)
      start = [0_hsize_t, int(offset, hsize_t)]
      count = [int(t%ncomp, hsize_t), int(t%n, hsize_t)]
    end if
    call h5screate_simple_f(nd, t%mem_dims(1:nd), t%mem_space, hdferr)
    call h5_check(hdferr, 'h5screate_simple_f (memory space)', file, path)
    call h5dget_space_f(t%dset, t%file_space, hdferr)
    call h5_check(hdferr, 'h5dget_space_f', file, path)
    if (t%n > 0) then
      call h5sselect_hyperslab_f(t%file_space, H5S_SELECT_SET_F, start(1:nd), count(1:nd), hdferr)
      call h5_check(hdferr, 'h5sselect_hyperslab_f (file)', file, path)
    else
      call h5sselect_none_f(t%mem_space, hdferr)
      call h5_check(hdferr, 'h5sselect_none_f (memory)', file, path)
      call h5sselect_none_f(t%file_space, hdferr)
      call h5_check(hdferr, 'h5sselect_none_f (file)', file, path)
    end if
    call h5_collective_xfer(file, t%xfer)
  end subroutine select_chunk

  !> Close the identifiers of one transfer.
  subroutine end_transfer(file, path, t)
    type(h5_file_t), intent(in) :: file     !< file (for messages)
    character(len=*), intent(in) :: path    !< dataset path (for messages)
    type(transfer_t), intent(inout) :: t    !< transfer state
    integer :: hdferr
    call h5pclose_f(t%xfer, hdferr)
    call h5_check(hdferr, 'h5pclose_f (transfer list)', file, path)
    call h5sclose_f(t%mem_space, hdferr)
    call h5_check(hdferr, 'h5sclose_f (memory space)', file, path)
    call h5sclose_f(t%file_space, hdferr)
    call h5_check(hdferr, 'h5sclose_f (file space)', file, path)
    call h5dclose_f(t%dset, hdferr)
    call h5_check(hdferr, 'h5dclose_f', file, path)
  end subroutine end_transfer

  !> Write this rank's count into `<group>/rank_counts`, or check it against the stored one.
  subroutine record_rank_counts(file, path, count)
    type(h5_file_t), intent(in) :: file   !< file open for writing
    character(len=*), intent(in) :: path  !< particle dataset path
    integer(i8), intent(in) :: count      !< this rank's particles
    integer(hid_t) :: dset, mem_space, file_space, xfer, type_id
    integer(hsize_t), allocatable :: dims(:)
    integer(i8) :: stored(1)
    integer :: hdferr
    logical :: exists, bad, any_bad

    type_id = h5kind_to_type(i8, H5_INTEGER_KIND)
    exists = h5_exists(file, counts_path(path))
    if (exists) then
      call h5_dataset_open_read(file, counts_path(path), dset, dims)
      if (size(dims) /= 1 .or. dims(1) /= int(file%nranks, hsize_t)) then
        call fatal('HDF5: ' // trim(file%path) // ':/' // counts_path(path) &
          // ' was written by a different number of ranks')
      end if
    else
      call h5_dataset_create_or_open(file, counts_path(path), type_id, &
        [int(file%nranks, hsize_t)], dset)
    end if
    call h5screate_simple_f(1, [1_hsize_t], mem_space, hdferr)
    call h5_check(hdferr, 'h5screate_simple_f (memory space)', file, counts_path(path))
    call h5dget_space_f(dset, file_space, hdferr)
    call h5_check(hdferr, 'h5dget_space_f', file, counts_path(path))
    call h5sselect_hyperslab_f(file_space, H5S_SELECT_SET_F, [int(file%rank, hsize_t)], &
      [1_hsize_t], hdferr)
    call h5_check(hdferr, 'h5sselect_hyperslab_f (file)', file, counts_path(path))
    call h5_collective_xfer(file, xfer)
    if (exists) then
      call h5dread_f(dset, type_id, stored, [1_hsize_t], hdferr, mem_space_id=mem_space, &
        file_space_id=file_space, xfer_prp=xfer)
      call h5_check(hdferr, 'h5dread_f (collective)', file, counts_path(path))
      bad = stored(1) /= count
    else
      stored(1) = count
      call h5dwrite_f(dset, type_id, stored, [1_hsize_t], hdferr, mem_space_id=mem_space, &
        file_space_id=file_space, xfer_prp=xfer)
      call h5_check(hdferr, 'h5dwrite_f (collective)', file, counts_path(path))
      bad = .false.
    end if
    call h5pclose_f(xfer, hdferr)
    call h5_check(hdferr, 'h5pclose_f (transfer list)', file, counts_path(path))
    call h5sclose_f(mem_space, hdferr)
    call h5_check(hdferr, 'h5sclose_f (memory space)', file, counts_path(path))
    call h5sclose_f(file_space, hdferr)
    call h5_check(hdferr, 'h5sclose_f (file space)', file, counts_path(path))
    call h5dclose_f(dset, hdferr)
    call h5_check(hdferr, 'h5dclose_f', file, counts_path(path))
    ! Decide together so that no rank is left waiting in a later collective call.
    any_bad = all_or(file%comm, bad)
    if (any_bad) then
      call fatal('HDF5: particle arrays of one group must have the same per-rank lengths: ' &
        // trim(file%path) // ':/' // h5_clean_path(path))
    end if
  end subroutine record_rank_counts

  !> First particle (0-based) and number of particles of this rank's chunk of a dataset of
  !! `total` particles: the stored rank counts when they match this run, otherwise an even split.
  subroutine rank_chunk(file, path, total, offset, n)
    type(h5_file_t), intent(in) :: file   !< open file
    character(len=*), intent(in) :: path  !< particle dataset path
    integer(i8), intent(in) :: total      !< particles in the dataset
    integer(i8), intent(out) :: offset    !< first particle of this rank (0-based)
    integer, intent(out) :: n             !< particles of this rank
    integer(i8), allocatable :: counts(:)
    integer(hsize_t), allocatable :: dims(:)
    integer(hid_t) :: dset, xfer, type_id
    integer(i8) :: base, extra, r
    integer :: hdferr

    type_id = h5kind_to_type(i8, H5_INTEGER_KIND)
    if (h5_exists(file, counts_path(path))) then
      call h5_dataset_open_read(file, counts_path(path), dset, dims)
      if (size(dims) == 1 .and. dims(1) == int(file%nranks, hsize_t)) then
        allocate(counts(file%nranks))
        call h5_collective_xfer(file, xfer)
        call h5dread_f(dset, type_id, counts, dims, hdferr, xfer_prp=xfer)
        call h5_check(hdferr, 'h5dread_f (collective)', file, counts_path(path))
        call h5pclose_f(xfer, hdferr)
        call h5_check(hdferr, 'h5pclose_f (transfer list)', file, counts_path(path))
      end if
      call h5dclose_f(dset, hdferr)
      call h5_check(hdferr, 'h5dclose_f', file, counts_path(path))
    end if
    if (allocated(counts)) then
      if (sum(counts) /= total) then
        call fatal('HDF5: ' // trim(file%path) // ':/' // counts_path(path) &
          // ' does not add up to the length of ' // h5_clean_path(path))
      end if
      offset = sum(counts(1:file%rank))
      n = int(counts(file%rank + 1))
    else
      r = int(file%rank, i8)
      base = total / int(file%nranks, i8)
      extra = mod(total, int(file%nranks, i8))
      offset = r * base + min(r, extra)
      n = int(base)
      if (r < extra) n = n + 1
    end if
  end subroutine rank_chunk
end module io_hdf5_particles
