!> Bookkeeping of the repeated namelist groups (`&fluid`, `&solid`, `&region`, `&boundary`):
!! their names, maximum counts, selector variables, and appending or finding an occurrence.
!!
!! `new_occurrence` appends an element set to the type's defaults; `find_occurrence` looks one up
!! by its selector variable (`group_selector`: `name`, or `face` for `&boundary`), which is how a
!! `--set` modifies one (`config_parse`).
module config_occurrences
  use mpmice_kinds, only: name_len
  use config_types, only: config_t, fluid_params_t, solid_params_t, region_params_t, &
    boundary_params_t, max_fluids, max_solids, max_regions, max_boundaries
  implicit none
  private

  public :: repeated_group_names, is_repeated_group, group_selector, max_occurrences
  public :: occurrence_count, new_occurrence, find_occurrence, occurrence_selectors

  !> Known repeated groups, in echo order (after the singletons).
  character(len=*), parameter :: repeated_group_names(4) = [character(len=8) :: &
    'fluid', 'solid', 'region', 'boundary']

contains

  !> True if `group` may appear several times.
  pure logical function is_repeated_group(group)
    character(len=*), intent(in) :: group  !< group name without `&`
    is_repeated_group = len_trim(group) > 0 .and. any(repeated_group_names == group)
  end function is_repeated_group

  !> The variable that identifies an occurrence of repeated group `group` for `--set`: `name`
  !! (`&fluid`, `&solid`), `face` (`&boundary`), '' when there is none (`&region`).
  pure function group_selector(group) result(name)
    character(len=*), intent(in) :: group  !< group name without `&`
    character(len=:), allocatable :: name
    select case (group)
    case ('fluid', 'solid')
      name = 'name'
    case ('boundary')
      name = 'face'
    case default
      name = ''
    end select
  end function group_selector

  include 'config_nml_occurrences.inc'

  !> Append a new occurrence of repeated group `group`, set to the type's defaults. `k` is its
  !! index, 0 when the group already has `max_occurrences(group)` occurrences.
  subroutine new_occurrence(cfg, group, k)
    type(config_t), intent(inout) :: cfg   !< configuration to update
    character(len=*), intent(in) :: group  !< repeated group name
    integer, intent(out) :: k              !< index of the new occurrence, 0 if full
    k = occurrence_count(cfg, group) + 1
    if (k > max_occurrences(group) .or. .not. is_repeated_group(group)) then
      k = 0
      return
    end if
    call reset_occurrence(cfg, group, k)
  end subroutine new_occurrence

  !> Selector values (`group_selector`) of the occurrences of `group`, in order.
  pure function occurrence_selectors(cfg, group) result(values)
    type(config_t), intent(in) :: cfg      !< configuration
    character(len=*), intent(in) :: group  !< repeated group name
    character(len=name_len), allocatable :: values(:)
    integer :: k, n
    n = occurrence_count(cfg, group)
    allocate(values(n))
    do k = 1, n
      select case (group)
      case ('fluid')
        values(k) = cfg%fluids(k)%name
      case ('solid')
        values(k) = cfg%solids(k)%name
      case ('boundary')
        values(k) = cfg%boundaries(k)%face
      case default
        values(k) = ''
      end select
    end do
  end function occurrence_selectors

  !> Index of the first occurrence of `group` whose selector value is `value`, 0 if none.
  pure integer function find_occurrence(cfg, group, value)
    type(config_t), intent(in) :: cfg      !< configuration
    character(len=*), intent(in) :: group  !< repeated group name
    character(len=*), intent(in) :: value  !< selector value
    character(len=name_len), allocatable :: values(:)
    integer :: k
    find_occurrence = 0
    if (len(group_selector(group)) == 0) return
    values = occurrence_selectors(cfg, group)
    do k = 1, size(values)
      if (values(k) == value) then
        find_occurrence = k
        return
      end if
    end do
  end function find_occurrence
end module config_occurrences
