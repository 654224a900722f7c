!> HDF5 attributes on the root group, a group or a dataset: real and integer scalars and 1-D
!! arrays, 64-bit integer scalars and fixed-length strings, written and read back.
!!
!! All routines are collective over the file's communicator and every rank passes the same
!! values (HDF5 metadata must be identical on all ranks). `object` is an object path (default:
!! the root group); when writing, a missing group is created. Writing an attribute that exists
!! replaces it. Scalars are stored with a scalar dataspace (h5py: numpy scalar), arrays with a
!! 1-D dataspace; strings as fixed-length, NUL-padded ASCII (h5py: `bytes`, decode as ASCII).
module io_hdf5_attributes
  use hdf5, only: hid_t, hsize_t, size_t, h5oopen_f, h5oclose_f, h5aexists_f, h5adelete_f, &
    h5acreate_f, h5aopen_f, h5aclose_f, h5awrite_f, h5aread_f, h5aget_space_f, h5aget_type_f, &
    h5sget_simple_extent_npoints_f, h5screate_f, h5screate_simple_f, h5sclose_f, h5tcopy_f, &
    h5tset_size_f, h5tset_strpad_f, h5tget_size_f, h5tclose_f, h5tis_variable_str_f, &
    h5kind_to_type, H5S_SCALAR_F, H5_REAL_KIND, H5_INTEGER_KIND, H5T_FORTRAN_S1, H5T_STR_NULLPAD_F
  use, intrinsic :: iso_c_binding, only: c_ptr, c_loc
  use mpmice_kinds, only: wp, i8
  use mpmice_errors, only: fatal
  use io_hdf5_file, only: h5_file_t, h5_check, h5_clean_path, h5_exists, h5_make_groups, &
    h5_require_writable
  implicit none
  private

  public :: h5_write_attribute, h5_read_attribute, h5_attribute_exists, h5_attribute_size

  !> Write (or replace) an attribute: `call h5_write_attribute(file, name, value [, object])`.
  interface h5_write_attribute
    module procedure write_real, write_real_array, write_int, write_int_array, write_i8, &
      write_string
  end interface h5_write_attribute

  !> Read an attribute: `call h5_read_attribute(file, name, value [, object])`; arrays must have
  !! the stored length, strings are `character(len=:), allocatable`.
  interface h5_read_attribute
    module procedure read_real, read_real_array, read_int, read_int_array, read_i8, read_string
  end interface h5_read_attribute

contains

  !> Real scalar attribute.
  subroutine write_real(file, name, value, object)
    type(h5_file_t), intent(in) :: file                !< file open for writing
    character(len=*), intent(in) :: name               !< attribute name
    real(wp), intent(in) :: value                      !< value [any unit]
    character(len=*), intent(in), optional :: object   !< object path (default root)
    real(wp), target :: buffer(1)
    buffer(1) = value
    call write_values(file, name, object, h5kind_to_type(wp, H5_REAL_KIND), -1, c_loc(buffer))
  end subroutine write_real

  !> Real 1-D array attribute.
  subroutine write_real_array(file, name, values, object)
    type(h5_file_t), intent(in) :: file                !< file open for writing
    character(len=*), intent(in) :: name               !< attribute name
    real(wp), intent(in) :: values(:)                  !< values [any unit]
    character(len=*), intent(in), optional :: object   !< object path (default root)
    real(wp), target :: buffer(size(values))
    buffer = values
    call write_values(file, name, object, h5kind_to_type(wp, H5_REAL_KIND), size(values), &
      c_loc(buffer))
  end subroutine write_real_array

  !> Integer scalar attribute.
  subroutine write_int(file, name, value, object)
    type(h5_file_t), intent(in) :: file                !< file open for writing
    character(len=*), intent(in) :: name               !< attribute name
    integer, intent(in) :: value                       !< value
    character(len=*), intent(in), optional :: object   !< object path (default root)
    integer, target :: buffer(1)
    buffer(1) = value
    call write_values(file, name, object, h5kind_to_type(kind(value), H5_INTEGER_KIND), -1, &
      c_loc(buffer))
  end subroutine write_int

  !> Integer 1-D array attribute.
  subroutine write_int_array(file, name, values, object)
    type(h5_file_t), intent(in) :: file                !< file open for writing
    character(len=*), intent(in) :: name               !< attribute name
    integer, intent(in) :: values(:)                   !< values
    character(len=*), intent(in), optional :: object   !< object path (default root)
    integer, target :: buffer(size(values))
    buffer = values
    call write_values(file, name, object, h5kind_to_type(kind(values), H5_INTEGER_KIND), &
      size(values), c_loc(buffer))
  end subroutine write_int_array

  !> 64-bit integer scalar attribute (global counts, ids).
  subroutine write_i8(file, name, value, object)
    type(h5_file_t), intent(in) :: file                !< file open for writing
    character(len=*), intent(in) :: name               !< attribute name
    integer(i8), intent(in) :: value                   !< value
    character(len=*), intent(in), optional :: object   !< object path (default root)
    integer(i8), target :: buffer(1)
    buffer(1) = value
    call write_values(file, name, object, h5kind_to_type(i8, H5_INTEGER_KIND), -1, c_loc(buffer))
  end subroutine write_i8

  !> Create attribute `name` with a scalar (`n` < 0) or 1-D (`n` values) dataspace and write the
  !! memory at `buffer` (of type `type_id`) into it: the one write path of every numeric kind.
  subroutine write_values(file, name, object, type_id, n, buffer)
    type(h5_file_t), intent(in) :: file                !< file open for writing
    character(len=*), intent(in) :: name               !< attribute name
    character(len=*), intent(in), optional :: object   !< object path (default root)
    integer(hid_t), intent(in) :: type_id              !< memory and file data type
    integer, intent(in) :: n                           !< values (< 0: scalar, one value)
    type(c_ptr), intent(in) :: buffer                  !< address of the values
    integer(hid_t) :: obj_id, attr_id
    integer :: hdferr
    call create_attribute(file, name, object, type_id, n, obj_id, attr_id)
    call h5awrite_f(attr_id, type_id, buffer, hdferr)
    call h5_check(hdferr, 'h5awrite_f', file, where(name, object))
    call close_attribute(file, name, object, obj_id, attr_id)
  end subroutine write_values

  !> String attribute (stored exactly, trailing blanks included; pass `trim(text)` to drop them).
  subroutine write_string(file, name, value, object)
    type(h5_file_t), intent(in) :: file                !< file open for writing
    character(len=*), intent(in) :: name               !< attribute name
    character(len=*), intent(in) :: value              !< text (may be empty)
    character(len=*), intent(in), optional :: object   !< object path (default root)
    integer(hid_t) :: obj_id, attr_id, type_id
    integer :: hdferr
    character(len=:), allocatable :: buffer
    ! HDF5 has no zero-length fixed strings: an empty text is stored as one NUL.
    if (len(value) == 0) then
      buffer = achar(0)
    else
      buffer = value
    end if
    call h5tcopy_f(H5T_FORTRAN_S1, type_id, hdferr)
    call h5_check(hdferr, 'h5tcopy_f', file, where(name, object))
    call h5tset_size_f(type_id, int(len(buffer), size_t), hdferr)
    call h5_check(hdferr, 'h5tset_size_f', file, where(name, object))
    call h5tset_strpad_f(type_id, H5T_STR_NULLPAD_F, hdferr)
    call h5_check(hdferr, 'h5tset_strpad_f', file, where(name, object))
    call create_attribute(file, name, object, type_id, -1, obj_id, attr_id)
    call h5awrite_f(attr_id, type_id, buffer, [1_hsize_t], hdferr)
    call h5_check(hdferr, 'h5awrite_f', file, where(name, object))
    call close_attribute(file, name, object, obj_id, attr_id)
    call h5tclose_f(type_id, hdferr)
    call h5_check(hdferr, 'h5tclose_f', file, where(name, object))
  end subroutine write_string

  !> Real scalar attribute.
  subroutine read_real(file, name, value, object)
    type(h5_file_t), intent(in) :: file                !< open file
    character(len=*), intent(in) :: name               !< attribute name
    real(wp), intent(out) :: value                     !< value read
    character(len=*), intent(in), optional :: object   !< object path (default root)
    real(wp), target :: buffer(1)
    call read_values(file, name, object, h5kind_to_type(wp, H5_REAL_KIND), 1, c_loc(buffer))
    value = buffer(1)
  end subroutine read_real

  !> Real 1-D array attribute; `values` must have the stored length.
  subroutine read_real_array(file, name, values, object)
    type(h5_file_t), intent(in) :: file                !< open file
    character(len=*), intent(in) :: name               !< attribute name
    real(wp), intent(out) :: values(:)                 !< values read
    character(len=*), intent(in), optional :: object   !< object path (default root)
    real(wp), target :: buffer(size(values))
    call read_values(file, name, object, h5kind_to_type(wp, H5_REAL_KIND), size(values), &
      c_loc(buffer))
    values = buffer
  end subroutine read_real_array

  !> Integer scalar attribute.
  subroutine read_int(file, name, value, object)
    type(h5_file_t), intent(in) :: file                !< open file
    character(len=*), intent(in) :: name               !< attribute name
    integer, intent(out) :: value                      !< value read
    character(len=*), intent(in), optional :: object   !< object path (default root)
    integer, target :: buffer(1)
    call read_values(file, name, object, h5kind_to_type(kind(value), H5_INTEGER_KIND), 1, &
      c_loc(buffer))
    value = buffer(1)
  end subroutine read_int

  !> Integer 1-D array attribute; `values` must have the stored length.
  subroutine read_int_array(file, name, values, object)
    type(h5_file_t), intent(in) :: file                !< open file
    character(len=*), intent(in) :: name               !< attribute name
    integer, intent(out) :: values(:)                  !< values read
    character(len=*), intent(in), optional :: object   !< object path (default root)
    integer, target :: buffer(size(values))
    call read_values(file, name, object, h5kind_to_type(kind(values), H5_INTEGER_KIND), &
      size(values), c_loc(buffer))
    values = buffer
  end subroutine read_int_array

  !> 64-bit integer scalar attribute.
  subroutine read_i8(file, name, value, object)
    type(h5_file_t), intent(in) :: file                !< open file
    character(len=*), intent(in) :: name               !< attribute name
    integer(i8), intent(out) :: value                  !< value read
    character(len=*), intent(in), optional :: object   !< object path (default root)
    integer(i8), target :: buffer(1)
    call read_values(file, name, object, h5kind_to_type(i8, H5_INTEGER_KIND), 1, c_loc(buffer))
    value = buffer(1)
  end subroutine read_i8

  !> Read the `n` values of attribute `name` (stop if it holds another number) as `type_id` into
  !! the memory at `buffer`: the one read path of every numeric kind.
  subroutine read_values(file, name, object, type_id, n, buffer)
    type(h5_file_t), intent(in) :: file                !< open file
    character(len=*), intent(in) :: name               !< attribute name
    character(len=*), intent(in), optional :: object   !< object path (default root)
    integer(hid_t), intent(in) :: type_id              !< memory data type
    integer, intent(in) :: n                           !< values expected
    type(c_ptr), value :: buffer                       !< address of room for `n` values
    integer(hid_t) :: obj_id, attr_id
    integer :: hdferr
    call open_attribute(file, name, object, n, obj_id, attr_id)
    call h5aread_f(attr_id, type_id, buffer, hdferr)
    call h5_check(hdferr, 'h5aread_f', file, where(name, object))
    call close_attribute(file, name, object, obj_id, attr_id)
  end subroutine read_values

  !> Fixed-length string attribute; trailing NULs are removed.
  subroutine read_string(file, name, value, object)
    type(h5_file_t), intent(in) :: file                    !< open file
    character(len=*), intent(in) :: name                   !< attribute name
    character(len=:), allocatable, intent(out) :: value    !< text read
    character(len=*), intent(in), optional :: object       !< object path (default root)
    integer(hid_t) :: obj_id, attr_id, type_id
    integer(size_t) :: nchar
    integer :: hdferr, nul
    logical :: variable
    call open_attribute(file, name, object, 1, obj_id, attr_id)
    call h5aget_type_f(attr_id, type_id, hdferr)
    call h5_check(hdferr, 'h5aget_type_f', file, where(name, object))
    call h5tis_variable_str_f(type_id, variable, hdferr)
    call h5_check(hdferr, 'h5tis_variable_str_f', file, where(name, object))
    if (variable) call fatal('HDF5: attribute ' // where(name, object) // ' in ' &
      // trim(file%path) // ' is a variable-length string (not supported)')
    call h5tget_size_f(type_id, nchar, hdferr)
    call h5_check(hdferr, 'h5tget_size_f', file, where(name, object))
    allocate(character(len=int(nchar)) :: value)
    call h5aread_f(attr_id, type_id, value, [1_hsize_t], hdferr)
    call h5_check(hdferr, 'h5aread_f', file, where(name, object))
    call h5tclose_f(type_id, hdferr)
    call h5_check(hdferr, 'h5tclose_f', file, where(name, object))
    call close_attribute(file, name, object, obj_id, attr_id)
    nul = index(value, achar(0))
    if (nul > 0) value = value(1:nul - 1)
  end subroutine read_string

  !> True if attribute `name` exists on `object` (default root; false if the object is missing).
  function h5_attribute_exists(file, name, object) result(exists)
    type(h5_file_t), intent(in) :: file                !< open file
    character(len=*), intent(in) :: name               !< attribute name
    character(len=*), intent(in), optional :: object   !< object path (default root)
    logical :: exists
    integer(hid_t) :: obj_id
    integer :: hdferr
    exists = .false.
    if (present(object)) then
      if (.not. h5_exists(file, object)) return
    end if
    call open_object(file, object, .false., obj_id)
    call h5aexists_f(obj_id, name, exists, hdferr)
    call h5_check(hdferr, 'h5aexists_f', file, where(name, object))
    call h5oclose_f(obj_id, hdferr)
    call h5_check(hdferr, 'h5oclose_f', file, where(name, object))
  end function h5_attribute_exists

  !> Number of values of attribute `name` (1 for scalars and strings).
  function h5_attribute_size(file, name, object) result(n)
    type(h5_file_t), intent(in) :: file                !< open file
    character(len=*), intent(in) :: name               !< attribute name
    character(len=*), intent(in), optional :: object   !< object path (default root)
    integer :: n
    integer(hid_t) :: obj_id, attr_id
    call open_attribute(file, name, object, -1, obj_id, attr_id, n)
    call close_attribute(file, name, object, obj_id, attr_id)
  end function h5_attribute_size

  !> `object@name` for messages.
  function where(name, object) result(text)
    character(len=*), intent(in) :: name               !< attribute name
    character(len=*), intent(in), optional :: object   !< object path
    character(len=:), allocatable :: text
    if (present(object)) then
      text = h5_clean_path(object) // '@' // trim(name)
    else
      text = '@' // trim(name)
    end if
  end function where

  !> Open the object an attribute belongs to (root when `object` is absent or empty).
  subroutine open_object(file, object, create, obj_id)
    type(h5_file_t), intent(in) :: file                !< open file
    character(len=*), intent(in), optional :: object   !< object path
    logical, intent(in) :: create                      !< create missing groups
    integer(hid_t), intent(out) :: obj_id              !< open object (close with h5oclose_f)
    character(len=:), allocatable :: clean
    integer :: hdferr
    if (.not. file%is_open) call fatal('HDF5: attribute access on a closed file')
    clean = ''
    if (present(object)) clean = h5_clean_path(object)
    if (len(clean) == 0) clean = '/'
    if (.not. h5_exists(file, clean)) then
      if (.not. create) call fatal('HDF5: no object ' // clean // ' in ' // trim(file%path))
      call h5_make_groups(file, clean)
    end if
    call h5oopen_f(file%id, clean, obj_id, hdferr)
    call h5_check(hdferr, 'h5oopen_f', file, clean)
  end subroutine open_object

  !> Create attribute `name` (replacing an existing one) with a scalar (`n` < 0) or 1-D (`n`
  !! values) dataspace.
  subroutine create_attribute(file, name, object, type_id, n, obj_id, attr_id)
    type(h5_file_t), intent(in) :: file                !< file open for writing
    character(len=*), intent(in) :: name               !< attribute name
    character(len=*), intent(in), optional :: object   !< object path
    integer(hid_t), intent(in) :: type_id              !< file data type
    integer, intent(in) :: n                           !< values (< 0: scalar)
    integer(hid_t), intent(out) :: obj_id              !< open object
    integer(hid_t), intent(out) :: attr_id             !< new attribute
    integer(hid_t) :: space_id
    integer :: hdferr
    logical :: exists
    call h5_require_writable(file, where(name, object))
    call open_object(file, object, .true., obj_id)
    call h5aexists_f(obj_id, name, exists, hdferr)
    call h5_check(hdferr, 'h5aexists_f', file, where(name, object))
    if (exists) then
      call h5adelete_f(obj_id, name, hdferr)
      call h5_check(hdferr, 'h5adelete_f', file, where(name, object))
    end if
    if (n < 0) then
      call h5screate_f(H5S_SCALAR_F, space_id, hdferr)
    else
      call h5screate_simple_f(1, [int(n, hsize_t)], space_id, hdferr)
    end if
    call h5_check(hdferr, 'h5screate_f', file, where(name, object))
    call h5acreate_f(obj_id, name, type_id, space_id, attr_id, hdferr)
    call h5_check(hdferr, 'h5acreate_f', file, where(name, object))
    call h5sclose_f(space_id, hdferr)
    call h5_check(hdferr, 'h5sclose_f', file, where(name, object))
  end subroutine create_attribute

  !> Open attribute `name`; stop if it is missing or (when `n` >= 0) does not hold `n` values.
  subroutine open_attribute(file, name, object, n, obj_id, attr_id, npoints)
    type(h5_file_t), intent(in) :: file                !< open file
    character(len=*), intent(in) :: name               !< attribute name
    character(len=*), intent(in), optional :: object   !< object path
    integer, intent(in) :: n                           !< expected values (< 0: any)
    integer(hid_t), intent(out) :: obj_id              !< open object
    integer(hid_t), intent(out) :: attr_id             !< open attribute
    integer, intent(out), optional :: npoints          !< values stored
    integer(hid_t) :: space_id
    integer(hsize_t) :: stored
    integer :: hdferr
    logical :: exists
    call open_object(file, object, .false., obj_id)
    call h5aexists_f(obj_id, name, exists, hdferr)
    call h5_check(hdferr, 'h5aexists_f', file, where(name, object))
    if (.not. exists) call fatal('HDF5: no attribute ' // where(name, object) // ' in ' &
      // trim(file%path))
    call h5aopen_f(obj_id, name, attr_id, hdferr)
    call h5_check(hdferr, 'h5aopen_f', file, where(name, object))
    call h5aget_space_f(attr_id, space_id, hdferr)
    call h5_check(hdferr, 'h5aget_space_f', file, where(name, object))
    call h5sget_simple_extent_npoints_f(space_id, stored, hdferr)
    call h5_check(hdferr, 'h5sget_simple_extent_npoints_f', file, where(name, object))
    call h5sclose_f(space_id, hdferr)
    call h5_check(hdferr, 'h5sclose_f', file, where(name, object))
    if (n >= 0 .and. stored /= int(n, hsize_t)) then
      call fatal('HDF5: attribute ' // where(name, object) // ' in ' // trim(file%path) &
        // ' has a different number of values than requested')
    end if
    if (present(npoints)) npoints = int(stored)
  end subroutine open_attribute

  !> Close an attribute and its object.
  subroutine close_attribute(file, name, object, obj_id, attr_id)
    type(h5_file_t), intent(in) :: file                !< open file
    character(len=*), intent(in) :: name               !< attribute name (for messages)
    character(len=*), intent(in), optional :: object   !< object path (for messages)
    integer(hid_t), intent(in) :: obj_id               !< open object
    integer(hid_t), intent(in) :: attr_id              !< open attribute
    integer :: hdferr
    call h5aclose_f(attr_id, hdferr)
    call h5_check(hdferr, 'h5aclose_f', file, where(name, object))
    call h5oclose_f(obj_id, hdferr)
    call h5_check(hdferr, 'h5oclose_f', file, where(name, object))
  end subroutine close_attribute
end module io_hdf5_attributes
