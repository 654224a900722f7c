!> The namelist groups of the configuration: the table of groups and variables, and the reads that
!! apply namelist text to a `config_t`.
!!
!! Each group has one routine that presets its namelist variables from the `config_t` (so absent
!! variables keep their value, defaults included), reads and copies back on success. The table
!! `variables` lists every variable with its type; the parser uses it to reject unknown names and
!! to describe the expected value in error messages. The table, `group_names`, the read routines
!! and the group dispatch are generated from the namelist list (modules/config/namelist/*.toml,
!! scripts/generate_namelists.py) into the included files.
module config_namelist
  use, intrinsic :: ieee_exceptions, only: ieee_get_halting_mode, ieee_set_halting_mode, &
    ieee_get_flag, ieee_set_flag, ieee_overflow, ieee_underflow, ieee_invalid, ieee_flag_type
  use mpmice_kinds, only: wp, name_len, path_len, msg_len
  use config_types, only: config_t, run_params_t, grid_params_t, time_params_t, &
    numerics_params_t, solver_params_t, output_params_t, heat_params_t, physics_params_t, &
    ice_params_t, mpm_params_t, coupling_params_t, fluid_params_t, solid_params_t, &
    region_params_t, boundary_params_t, max_polygon_points, max_history_points, max_blocks_per_dim
  use config_occurrences, only: is_repeated_group, occurrence_count
  implicit none
  private

  public :: variable_info_t, group_names, variables, find_variable, group_variable_names
  public :: describe_value, namelist_assign

  !> One namelist variable.
  type :: variable_info_t
    character(len=8) :: group = ''    !< group name without `&`
    character(len=32) :: name = ''    !< variable name
    character :: kind = 'r'           !< `i` integer, `r` real, `l` logical, `c` character
    integer :: size = 1               !< number of entries (1 scalar, 3 per-dimension array)
    integer :: length = 0             !< declared length of a character variable
  end type variable_info_t

  include 'config_nml_table.inc'

contains

  !> Index of `name` (lower case, no subscript) of `group` in `variables`, 0 if unknown.
  pure integer function find_variable(group, name)
    character(len=*), intent(in) :: group  !< group name without `&`
    character(len=*), intent(in) :: name   !< variable name
    integer :: i
    find_variable = 0
    if (len_trim(name) == 0) return
    do i = 1, size(variables)
      if (variables(i)%group == group .and. variables(i)%name == name) then
        find_variable = i
        return
      end if
    end do
  end function find_variable

  !> Names of the variables of `group`, comma separated.
  function group_variable_names(group) result(text)
    character(len=*), intent(in) :: group  !< group name without `&`
    character(len=:), allocatable :: text
    integer :: i
    text = ''
    do i = 1, size(variables)
      if (variables(i)%group /= group .or. len_trim(group) == 0) cycle
      if (len(text) > 0) text = text // ', '
      text = text // trim(variables(i)%name)
    end do
  end function group_variable_names

  !> What a value of variable `info` must look like (for error messages).
  function describe_value(info) result(text)
    type(variable_info_t), intent(in) :: info  !< variable
    character(len=:), allocatable :: text
    character(len=16) :: n
    write(n, '(i0)') info%size
    select case (info%kind)
    case ('i')
      text = 'an integer'
      if (info%size > 1) text = 'up to ' // trim(n) // ' integers'
    case ('r')
      text = 'a real number'
      if (info%size > 1) text = 'up to ' // trim(n) // ' real numbers'
    case ('l')
      text = '.true. or .false.'
      if (info%size > 1) text = 'up to ' // trim(n) // ' of .true./.false.'
    case default
      write(n, '(i0)') info%length
      text = 'a quoted string of at most ' // trim(n) // ' characters'
    end select
  end function describe_value

  !> Read namelist text `text` (one complete `&group ... /`) into `cfg`. On failure `cfg` is
  !! unchanged and `ios`/`iomsg` hold the compiler's status and message. Floating-point traps
  !! (debug builds) are off during the read: a value such as `1e400` reads as infinity, which
  !! validation then rejects, instead of stopping the program.
  !! A repeated group updates its occurrence `occurrence` (1..count; required for those groups).
  subroutine namelist_assign(cfg, group, text, ios, iomsg, occurrence)
    type(config_t), intent(inout) :: cfg     !< configuration to update
    character(len=*), intent(in) :: group    !< group name (lower case, no `&`)
    character(len=*), intent(in) :: text     !< namelist text of that group
    integer, intent(out) :: ios              !< 0 on success
    character(len=msg_len), intent(out) :: iomsg !< compiler message on failure
    integer, intent(in), optional :: occurrence  !< element of a repeated group
    type(ieee_flag_type), parameter :: traps(3) = [ieee_overflow, ieee_underflow, ieee_invalid]
    logical :: halting(3), flags(3)
    integer :: k
    k = 0
    if (present(occurrence)) k = occurrence
    call ieee_get_halting_mode(traps, halting)
    call ieee_get_flag(traps, flags)
    call ieee_set_halting_mode(traps, .false.)
    call assign_group(cfg, group, text, k, ios, iomsg)
    call ieee_set_flag(traps, flags)
    call ieee_set_halting_mode(traps, halting)
  end subroutine namelist_assign

  !> `namelist_assign` without the floating-point trap handling.
  subroutine assign_group(cfg, group, text, k, ios, iomsg)
    type(config_t), intent(inout) :: cfg     !< configuration to update
    character(len=*), intent(in) :: group    !< group name (lower case, no `&`)
    character(len=*), intent(in) :: text     !< namelist text of that group
    integer, intent(in) :: k                 !< occurrence of a repeated group
    integer, intent(out) :: ios              !< 0 on success
    character(len=msg_len), intent(out) :: iomsg !< compiler message on failure
    iomsg = ''
    if (is_repeated_group(group)) then
      if (k < 1 .or. k > occurrence_count(cfg, group)) then
        ios = -1
        iomsg = 'no such occurrence of &' // trim(group)
        return
      end if
    end if
    include 'config_nml_assign.inc'
  end subroutine assign_group

  include 'config_nml_read.inc'
end module config_namelist
