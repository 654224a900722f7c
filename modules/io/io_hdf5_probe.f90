!> Look inside an HDF5 file that may be broken, without stopping: the checks a restart makes
!! on its checkpoint before anything is written.
!!
!! Unlike the rest of the output layer (`io_hdf5_file`, whose errors are fatal), every routine
!! here runs on the calling rank only, opens the file with HDF5's default (serial) driver, turns
!! HDF5's automatic error-stack printing off while it works, and reports a failure as `stat` /= 0
!! with a one-line reason instead of stopping. The printing is turned back on after a successful
!! probe only: after a failed read of a corrupt file HDF5 1.10 keeps internal objects that it
!! cannot free, and with printing on it reports "infinite loop closing library" when the
!! process ends; a failed probe ends the run (input error), so printing stays off.
module io_hdf5_probe
  use hdf5, only: hid_t, hsize_t, size_t, h5open_f, h5eset_auto_f, h5fopen_f, h5fclose_f, &
    h5lexists_f, h5aexists_f, h5aopen_f, h5aclose_f, h5aread_f, h5aget_space_f, &
    h5aget_type_f, h5sget_simple_extent_npoints_f, h5sclose_f, h5tget_size_f, h5tclose_f, &
    h5tget_class_f, h5kind_to_type, H5F_ACC_RDONLY_F, H5_REAL_KIND, H5_INTEGER_KIND, &
    H5T_STRING_F, h5pcreate_f, h5pclose_f, h5pset_fclose_degree_f, H5P_FILE_ACCESS_F, &
    H5F_CLOSE_STRONG_F, h5gn_members_f, h5gget_obj_info_idx_f, h5dopen_f, h5dclose_f, &
    h5dget_space_f, H5G_GROUP_F, H5G_DATASET_F
  use, intrinsic :: iso_c_binding, only: c_ptr, c_loc
  use mpmice_kinds, only: wp
  implicit none
  private

  public :: checkpoint_probe_t, h5_probe_checkpoint

  !> What a checkpoint's root holds (valid when `h5_probe_checkpoint` returned `stat` = 0).
  type :: checkpoint_probe_t
    integer :: version = 0                   !< `checkpoint_version` attribute
    integer :: step = 0                      !< `step` attribute
    integer :: ncells(3) = 0                 !< `ncells` attribute
    real(wp) :: lower(3) = 0.0_wp            !< `lower` attribute [m]
    real(wp) :: upper(3) = 0.0_wp            !< `upper` attribute [m]
    real(wp) :: time = 0.0_wp                !< `time` attribute [s]
    character(len=:), allocatable :: namelist !< resolved input stored in `namelist`
  end type checkpoint_probe_t

  !> Root attributes every checkpoint carries (besides those read into `checkpoint_probe_t`).
  character(len=*), parameter :: clock_attributes(*) = [character(len=16) :: 'dt', 'dt_next', &
    'output_index', 'checkpoint_index']

contains

  !> Open `path` read-only on this rank and read what a restart needs to judge it: a file HDF5
  !! cannot open (truncated, corrupt), a dump or other file without the checkpoint attributes
  !! and the `/checkpoint` group, or an attribute of the wrong type or length gives `stat` = 1
  !! and `reason` (one line, without the path). HDF5 prints nothing.
  subroutine h5_probe_checkpoint(path, info, stat, reason)
    character(len=*), intent(in) :: path                   !< file to examine
    type(checkpoint_probe_t), intent(out) :: info          !< what it holds
    integer, intent(out) :: stat                           !< 0 usable, 1 not
    character(len=:), allocatable, intent(out) :: reason   !< why not
    integer(hid_t) :: file_id, fapl
    integer :: hdferr, ignored, i
    logical :: exists

    stat = 1
    reason = ''
    call h5open_f(hdferr)
    call h5eset_auto_f(0, hdferr)
    ! closing the file closes whatever a failed read left open in it
    call h5pcreate_f(H5P_FILE_ACCESS_F, fapl, hdferr)
    call h5pset_fclose_degree_f(fapl, H5F_CLOSE_STRONG_F, hdferr)
    call h5fopen_f(trim(path), H5F_ACC_RDONLY_F, file_id, hdferr, access_prp=fapl)
    call h5pclose_f(fapl, ignored)
    if (hdferr < 0) then
      reason = 'HDF5 cannot open it (truncated or corrupt file)'
      return
    end if

    call h5aexists_f(file_id, 'checkpoint_version', exists, hdferr)
    if (hdferr < 0) then
      reason = 'its root attributes cannot be read (corrupt file)'
    else if (.not. exists) then
      reason = 'not a checkpoint (no checkpoint_version attribute: a dump or another file?); ' &
        // 'restart from a <name>_checkpoint_<step>.h5 file'
    else
      call read_ints(file_id, 'checkpoint_version', 1, reason, scalar=info%version)
      if (len(reason) == 0) call read_ints(file_id, 'step', 1, reason, scalar=info%step)
      if (len(reason) == 0) call read_ints(file_id, 'ncells', 3, reason, values=info%ncells)
      if (len(reason) == 0) call read_reals(file_id, 'lower', 3, reason, values=info%lower)
      if (len(reason) == 0) call read_reals(file_id, 'upper', 3, reason, values=info%upper)
      if (len(reason) == 0) call read_reals(file_id, 'time', 1, reason, scalar=info%time)
      if (len(reason) == 0) call read_text(file_id, 'namelist', info%namelist, reason)
      do i = 1, size(clock_attributes)
        if (len(reason) > 0) exit
        call h5aexists_f(file_id, trim(clock_attributes(i)), exists, hdferr)
        if (hdferr < 0 .or. .not. exists) reason = 'attribute ' // trim(clock_attributes(i)) &
          // ' missing or unreadable (corrupt checkpoint)'
      end do
      if (len(reason) == 0) then
        call h5lexists_f(file_id, 'checkpoint', exists, hdferr)
        if (hdferr < 0 .or. .not. exists) reason = 'no /checkpoint group (corrupt checkpoint)'
      end if
      if (len(reason) == 0) call walk_group(file_id, 'checkpoint', reason)
    end if
    call h5fclose_f(file_id, ignored)
    if (len(reason) == 0) then
      stat = 0
      call h5eset_auto_f(1, ignored)
    end if
  end subroutine h5_probe_checkpoint

  !> Open every group and dataset below `group` and read each dataset's extent: the object
  !! headers a restart will read are intact (the raw data are not read).
  recursive subroutine walk_group(file_id, group, reason)
    integer(hid_t), intent(in) :: file_id                  !< open file
    character(len=*), intent(in) :: group                  !< group path
    character(len=:), allocatable, intent(inout) :: reason !< set on failure
    character(len=256) :: member
    character(len=:), allocatable :: path
    integer(hid_t) :: dset_id, space_id
    integer(hsize_t) :: npoints
    integer :: nmembers, i, object_type, hdferr, ignored
    call h5gn_members_f(file_id, group, nmembers, hdferr)
    if (hdferr < 0) then
      reason = 'group /' // group // ' unreadable (corrupt checkpoint)'
      return
    end if
    do i = 0, nmembers - 1
      call h5gget_obj_info_idx_f(file_id, group, i, member, object_type, hdferr)
      if (hdferr < 0) then
        reason = 'group /' // group // ' unreadable (corrupt checkpoint)'
        return
      end if
      path = group // '/' // trim(member)
      if (object_type == H5G_GROUP_F) then
        call walk_group(file_id, path, reason)
        if (len(reason) > 0) return
      else if (object_type == H5G_DATASET_F) then
        call h5dopen_f(file_id, path, dset_id, hdferr)
        if (hdferr >= 0) then
          call h5dget_space_f(dset_id, space_id, hdferr)
          if (hdferr >= 0) then
            call h5sget_simple_extent_npoints_f(space_id, npoints, hdferr)
            call h5sclose_f(space_id, ignored)
          end if
          call h5dclose_f(dset_id, ignored)
        end if
        if (hdferr < 0) then
          reason = 'dataset /' // path // ' unreadable (corrupt checkpoint)'
          return
        end if
      end if
    end do
  end subroutine walk_group

  !> Integer attribute `name` of `n` values into `scalar` (n = 1) or `values`.
  subroutine read_ints(file_id, name, n, reason, scalar, values)
    integer(hid_t), intent(in) :: file_id                  !< open file
    character(len=*), intent(in) :: name                   !< attribute of the root
    integer, intent(in) :: n                               !< values expected
    character(len=:), allocatable, intent(inout) :: reason !< set on failure
    integer, intent(out), optional :: scalar               !< value when n = 1
    integer, intent(out), optional :: values(n)            !< values when n > 1
    integer, target :: buffer(n)
    call read_numbers(file_id, name, n, h5kind_to_type(kind(buffer), H5_INTEGER_KIND), &
      c_loc(buffer), reason)
    if (len(reason) > 0) return
    if (present(scalar)) scalar = buffer(1)
    if (present(values)) values = buffer
  end subroutine read_ints

  !> Real attribute `name` of `n` values into `scalar` (n = 1) or `values`.
  subroutine read_reals(file_id, name, n, reason, scalar, values)
    integer(hid_t), intent(in) :: file_id                  !< open file
    character(len=*), intent(in) :: name                   !< attribute of the root
    integer, intent(in) :: n                               !< values expected
    character(len=:), allocatable, intent(inout) :: reason !< set on failure
    real(wp), intent(out), optional :: scalar              !< value when n = 1
    real(wp), intent(out), optional :: values(n)           !< values when n > 1
    real(wp), target :: buffer(n)
    call read_numbers(file_id, name, n, h5kind_to_type(wp, H5_REAL_KIND), c_loc(buffer), reason)
    if (len(reason) > 0) return
    if (present(scalar)) scalar = buffer(1)
    if (present(values)) values = buffer
  end subroutine read_reals

  !> Read the `n` values of root attribute `name` as `type_id` into the memory at `buffer`: the
  !! one read path of every numeric kind. `reason` is set on failure.
  subroutine read_numbers(file_id, name, n, type_id, buffer, reason)
    integer(hid_t), intent(in) :: file_id                  !< open file
    character(len=*), intent(in) :: name                   !< attribute of the root
    integer, intent(in) :: n                               !< values expected
    integer(hid_t), intent(in) :: type_id                  !< memory data type
    type(c_ptr), value :: buffer                           !< address of room for `n` values
    character(len=:), allocatable, intent(inout) :: reason !< set on failure
    integer(hid_t) :: attr_id
    integer :: hdferr, ignored
    call open_attribute(file_id, name, n, attr_id, reason)
    if (len(reason) > 0) return
    call h5aread_f(attr_id, type_id, buffer, hdferr)
    call h5aclose_f(attr_id, ignored)
    if (hdferr < 0) reason = 'attribute ' // name // ' unreadable (corrupt checkpoint)'
  end subroutine read_numbers

  !> Fixed-length string attribute `name` (trailing NULs removed).
  subroutine read_text(file_id, name, text, reason)
    integer(hid_t), intent(in) :: file_id                  !< open file
    character(len=*), intent(in) :: name                   !< attribute of the root
    character(len=:), allocatable, intent(out) :: text     !< its text
    character(len=:), allocatable, intent(inout) :: reason !< set on failure
    integer(hid_t) :: attr_id, type_id
    integer(size_t) :: nchar
    integer :: hdferr, ignored, class, nul
    text = ''
    call open_attribute(file_id, name, 1, attr_id, reason)
    if (len(reason) > 0) return
    call h5aget_type_f(attr_id, type_id, hdferr)
    if (hdferr >= 0) then
      call h5tget_class_f(type_id, class, hdferr)
      if (hdferr >= 0 .and. class /= H5T_STRING_F) hdferr = -1
      if (hdferr >= 0) call h5tget_size_f(type_id, nchar, hdferr)
      if (hdferr >= 0) then
        deallocate(text)
        allocate(character(len=int(nchar)) :: text)
        call h5aread_f(attr_id, type_id, text, [1_hsize_t], hdferr)
      end if
      call h5tclose_f(type_id, ignored)
    end if
    call h5aclose_f(attr_id, ignored)
    if (hdferr < 0) then
      reason = 'attribute ' // name // ' unreadable (corrupt checkpoint)'
      text = ''
      return
    end if
    nul = index(text, achar(0))
    if (nul > 0) text = text(1:nul - 1)
  end subroutine read_text

  !> Open the root attribute `name` and check it holds `n` values.
  subroutine open_attribute(file_id, name, n, attr_id, reason)
    integer(hid_t), intent(in) :: file_id                  !< open file
    character(len=*), intent(in) :: name                   !< attribute of the root
    integer, intent(in) :: n                               !< values expected
    integer(hid_t), intent(out) :: attr_id                 !< open attribute (caller closes)
    character(len=:), allocatable, intent(inout) :: reason !< set on failure
    integer(hid_t) :: space_id
    integer(hsize_t) :: npoints
    integer :: hdferr, ignored
    logical :: exists
    attr_id = -1_hid_t
    call h5aexists_f(file_id, name, exists, hdferr)
    if (hdferr < 0 .or. .not. exists) then
      reason = 'attribute ' // name // ' missing (corrupt checkpoint)'
      return
    end if
    call h5aopen_f(file_id, name, attr_id, hdferr)
    if (hdferr >= 0) call h5aget_space_f(attr_id, space_id, hdferr)
    if (hdferr >= 0) then
      call h5sget_simple_extent_npoints_f(space_id, npoints, hdferr)
      call h5sclose_f(space_id, ignored)
      if (hdferr >= 0 .and. npoints /= int(n, hsize_t)) hdferr = -1
    end if
    if (hdferr < 0) then
      if (attr_id >= 0) call h5aclose_f(attr_id, ignored)
      attr_id = -1_hid_t
      reason = 'attribute ' // name // ' unreadable or of the wrong size (corrupt checkpoint)'
    end if
  end subroutine open_attribute
end module io_hdf5_probe
