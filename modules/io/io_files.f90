!> File-system helpers for the output layer: directories, names of dump files, atomic renames.
!!
!! Directory creation and renames go through the C library (`mkdir`, `access`, `rename`) because
!! Fortran 2008 has no portable way to do either. These routines act on the calling rank only;
!! in a parallel run rank 0 calls them and the other ranks wait at the next collective operation
!! (e.g. the collective `h5_create` of the first dump).
module io_files
  use, intrinsic :: iso_c_binding, only: c_int
  use io_posix, only: c_mkdir, c_access, c_setenv, c_rename, c_string
  use mpmice_errors, only: fatal
  implicit none
  private

  public :: io_make_directory, io_directory_exists, io_file_exists, io_rename, io_select_mpiio
  public :: io_dump_stem, io_join_path, io_basename, io_dirname, io_open_series

  integer(c_int), parameter :: directory_mode = int(o'755', c_int)  !< permissions of new folders
  integer(c_int), parameter :: access_exists = 0_c_int              !< `F_OK` of `access(2)`


contains

  !> Create the folder `path` and any missing parents (like `mkdir -p`). An existing folder is
  !! fine. On failure: `stat` /= 0 if present, otherwise `fatal` naming the path.
  subroutine io_make_directory(path, stat)
    character(len=*), intent(in) :: path           !< folder to create (absolute or relative)
    integer, intent(out), optional :: stat         !< 0 on success
    character(len=:), allocatable :: full
    integer :: i
    integer(c_int) :: ignored

    if (present(stat)) stat = 0
    full = trim(path)
    if (len(full) == 0) full = '.'
    ! Create every prefix ending before a '/', then the full path; failures of intermediate
    ! calls (already exists, permission on a parent that exists) are judged by the final check.
    do i = 2, len(full)
      if (full(i:i) == '/' .and. full(i - 1:i - 1) /= '/') then
        ignored = c_mkdir(c_string(full(1:i - 1)), directory_mode)
      end if
    end do
    ignored = c_mkdir(c_string(full), directory_mode)
    if (.not. io_directory_exists(full)) then
      if (present(stat)) then
        stat = 1
      else
        call fatal('io_make_directory: cannot create folder ' // full)
      end if
    end if
  end subroutine io_make_directory

  !> True if `path` names an existing folder.
  function io_directory_exists(path) result(exists)
    character(len=*), intent(in) :: path  !< folder to test
    logical :: exists
    ! "path/." resolves only when path is a folder.
    exists = c_access(c_string(trim(path) // '/.'), access_exists) == 0_c_int
  end function io_directory_exists

  !> True if `path` names an existing file or folder.
  function io_file_exists(path) result(exists)
    character(len=*), intent(in) :: path  !< file to test
    logical :: exists
    exists = c_access(c_string(trim(path)), access_exists) == 0_c_int
  end function io_file_exists

  !> Choose the MPI-IO implementation for HDF5 output; call it before `MPI_Init`. Under Open MPI
  !! it sets `OMPI_MCA_io=^ompio` (use ROMIO) unless `OMPI_MCA_io` is already set, because
  !! collective writes through OMPIO's default module corrupted HDF5 datasets in our tests (see
  !! `docs/io.md`); other MPI libraries ignore the variable. Without it the output layer still
  !! writes correct files, with independent instead of collective MPI-IO transfers.
  subroutine io_select_mpiio()
    integer(c_int) :: ignored
    ignored = c_setenv(c_string('OMPI_MCA_io'), c_string('^ompio'), 0_c_int)
  end subroutine io_select_mpiio

  !> Rename `old` to `new` (atomic within one file system; replaces `new`). Fatal on failure.
  subroutine io_rename(old, new)
    character(len=*), intent(in) :: old  !< existing file
    character(len=*), intent(in) :: new  !< new name
    if (c_rename(c_string(trim(old)), c_string(trim(new))) /= 0_c_int) then
      call fatal('io_rename: cannot rename ' // trim(old) // ' to ' // trim(new))
    end if
  end subroutine io_rename

  !> Stem of a dump file: `<name>_<step:06d>` (more digits when step >= 10^6).
  function io_dump_stem(name, step) result(stem)
    character(len=*), intent(in) :: name  !< run name (`&run name`)
    integer, intent(in) :: step           !< time step number (>= 0)
    character(len=:), allocatable :: stem
    character(len=24) :: digits
    write(digits, '(i6.6)') step
    if (step >= 1000000) write(digits, '(i0)') step
    stem = trim(name) // '_' // trim(digits)
  end function io_dump_stem

  !> `dir/file`, or `file` alone when `dir` is empty.
  function io_join_path(dir, file) result(path)
    character(len=*), intent(in) :: dir   !< folder
    character(len=*), intent(in) :: file  !< name inside it
    character(len=:), allocatable :: path
    integer :: n
    n = len_trim(dir)
    if (n == 0) then
      path = trim(file)
    else if (dir(n:n) == '/') then
      path = dir(1:n) // trim(file)
    else
      path = dir(1:n) // '/' // trim(file)
    end if
  end function io_join_path

  !> Last component of a path (`a/b/c.h5` -> `c.h5`).
  function io_basename(path) result(base)
    character(len=*), intent(in) :: path  !< file path
    character(len=:), allocatable :: base
    integer :: slash
    slash = index(trim(path), '/', back=.true.)
    base = trim(path(slash + 1:))
  end function io_basename

  !> Folder part of a path (`a/b/c.h5` -> `a/b`, `c.h5` -> `.`).
  function io_dirname(path) result(dir)
    character(len=*), intent(in) :: path  !< file path
    character(len=:), allocatable :: dir
    integer :: slash
    slash = index(trim(path), '/', back=.true.)
    if (slash == 0) then
      dir = '.'
    else if (slash == 1) then
      dir = '/'
    else
      dir = path(1:slash - 1)
    end if
  end function io_dirname
  !> Open the CSV time series `path` (rank 0) to add a line: the first time in a run (`started`
  !! false; set here) it is replaced, `fresh` telling the caller to write the header line first,
  !! unless the run continues a checkpoint (`restored`): then, as every later time, the lines
  !! are appended.
  subroutine io_open_series(path, restored, started, unit, fresh)
    character(len=*), intent(in) :: path     !< series file
    logical, intent(in) :: restored          !< the run continues a checkpoint
    logical, intent(inout) :: started        !< the series was opened before in this run
    integer, intent(out) :: unit             !< the open unit (close it after the line)
    logical, intent(out) :: fresh            !< the file is new: write the header first
    fresh = .false.
    if (.not. started) then
      if (restored) then
        open(newunit=unit, file=path, status='unknown', position='append', action='write')
      else
        open(newunit=unit, file=path, status='replace', action='write')
        fresh = .true.
      end if
      started = .true.
    else
      open(newunit=unit, file=path, status='old', position='append', action='write')
    end if
  end subroutine io_open_series
end module io_files
