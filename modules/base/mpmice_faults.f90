!> Fault injection for the tests of the failure paths (docs/testing.md): the environment
!! variable `MPMICE_FAULT=<fault>:<step>` makes the run meet the fault at that step.
!!
!! | fault | what happens |
!! |---|---|
!! | `nan_pressure_step:N` | a NaN enters the right-hand side of the pressure equation in step N (ICE and MPMICE scenes) |
!! | `huge_pressure_step:N` | the same with 1e153 instead of NaN: finite, but hypre's PCG overflows and stops with an error |
!! | `enospc_dump_step:N` | the dump of step N fails as on a full disk (ENOSPC) |
!!
!! Unset (the normal case) every query returns -1 and nothing changes.
module mpmice_faults
  implicit none
  private

  public :: fault_step

contains

  !> The step N of `MPMICE_FAULT=<fault>:N`, -1 when the variable is unset or names another
  !! fault.
  !! Read the environment once (at initialisation), not in the time loop.
  function fault_step(fault) result(step)
    character(len=*), intent(in) :: fault  !< fault name, e.g. 'nan_pressure_step'
    integer :: step
    character(len=128) :: value
    integer :: length, status, ios
    step = -1
    call get_environment_variable('MPMICE_FAULT', value, length, status)
    if (status /= 0 .or. length == 0) return
    if (index(value, fault // ':') /= 1) return
    read(value(len(fault) + 2:), *, iostat=ios) step
    if (ios /= 0) step = -1
  end function fault_step
end module mpmice_faults
