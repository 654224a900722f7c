!> Kind parameters used throughout MPMICE.
module mpmice_kinds
  use, intrinsic :: iso_fortran_env, only: real64, int32, int64
  implicit none
  private

  integer, parameter, public :: wp = real64  !< working precision for all reals
  integer, parameter, public :: i4 = int32   !< default integer kind (local indices, counts)
  integer, parameter, public :: i8 = int64   !< global counts, global ids, HDF5 offsets

  integer, parameter, public :: name_len = 64     !< length of material/field/stage names
  integer, parameter, public :: path_len = 512    !< length of file paths
  integer, parameter, public :: msg_len = 1024    !< length of messages
end module mpmice_kinds
