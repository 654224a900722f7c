!> The namelist groups each scene reads, and the checks of a case's groups against them: an
!! input needs a `&run` group, and a group that the chosen scene does not read (`&fluid` in a
!! `scene = 'heat_conduction'` case) is an input error instead of being ignored.
!!
!! The resolved input that `--check` prints, `<name>.used.nml` holds and a checkpoint stores
!! lists every singleton group (`config_echo`); a text that starts with its header line
!! (`echo_header`) may therefore hold singleton groups its scene does not read. Repeated groups
!! (`&fluid`, `&solid`, `&region`, `&boundary`) appear there only when the case had them.
module config_scene_groups
  use config_parse, only: group_error_text
  use config_occurrences, only: is_repeated_group
  use config_text, only: replaced
  implicit none
  private

  public :: echo_header, is_echo_text, check_run_group, check_scene_groups, scene_group_list

  !> First line of a resolved input written by `config_echo` (the text starts with it).
  character(len=*), parameter :: echo_header = '! MPMICE resolved input'

contains

  !> The groups scene `scene` reads, blank-separated, each followed by a blank; '' for an
  !! unknown scene (the scene name itself is checked by `config_validate`).
  pure function scene_group_list(scene) result(list)
    character(len=*), intent(in) :: scene  !< `&run scene`
    character(len=:), allocatable :: list
    character(len=*), parameter :: common = 'run grid time numerics output '
    select case (trim(scene))
    case ('heat_conduction')
      list = common // 'solver heat '
    case ('mpm')
      list = common // 'physics mpm solid boundary '
    case ('ice')
      list = common // 'solver physics ice fluid region boundary '
    case ('mpmice')
      list = common // 'solver physics ice mpm coupling fluid solid region boundary '
    case default
      list = ''
    end select
  end function scene_group_list

  !> True when `text` is a resolved input written by `config_echo`.
  pure logical function is_echo_text(text)
    character(len=*), intent(in) :: text  !< namelist text
    is_echo_text = index(text, echo_header) == 1
  end function is_echo_text

  !> `stat` = 1 with the error line when the groups `groups` of the case file `source` (as
  !! returned by `config_load_text`) hold no `&run` group.
  subroutine check_run_group(groups, source, stat, errmsg)
    character(len=*), intent(in) :: groups                 !< group names, blank-terminated
    character(len=*), intent(in) :: source                 !< input name for messages
    integer, intent(out) :: stat                           !< 0 ok, 1 input error
    character(len=:), allocatable, intent(out) :: errmsg   !< the error line
    stat = 0
    errmsg = ''
    if (index(' ' // groups, ' run ') > 0) return
    stat = 1
    if (len_trim(groups) == 0) then
      errmsg = group_error_text(source, '', 'no namelist group (empty or comments only); a ' // &
        'case needs at least a &run group with its scene')
    else
      errmsg = group_error_text(source, '', 'no &run group; a case needs a &run group with its ' &
        // 'scene (groups found: &' // replaced(trim(groups), ' ', ', &') // ')')
    end if
  end subroutine check_run_group

  !> `stat` = 1 with the error line naming `source` when one of the groups `groups` is not read
  !! by scene `scene`. With `repeated_only` only the repeated groups are looked at (an echo).
  subroutine check_scene_groups(scene, groups, source, repeated_only, stat, errmsg)
    character(len=*), intent(in) :: scene                  !< `&run scene`
    character(len=*), intent(in) :: groups                 !< group names, blank-terminated
    character(len=*), intent(in) :: source                 !< input name for messages
    logical, intent(in) :: repeated_only                   !< look at repeated groups only
    integer, intent(out) :: stat                           !< 0 ok, 1 input error
    character(len=:), allocatable, intent(out) :: errmsg   !< the error line
    character(len=:), allocatable :: used
    integer :: first, last
    stat = 0
    errmsg = ''
    used = scene_group_list(scene)
    if (len(used) == 0) return
    first = 1
    do while (first <= len_trim(groups))
      last = index(groups(first:), ' ') + first - 2
      if (last < first) last = len_trim(groups)
      if (index(' ' // used, ' ' // groups(first:last) // ' ') == 0) then
        if (.not. repeated_only .or. is_repeated_group(groups(first:last))) then
          stat = 1
          errmsg = group_error_text(source, groups(first:last), 'group not used by &run ' // &
            'scene = ''' // trim(scene) // '''; its groups: &' // replaced(trim(used), ' ', ', &'))
          return
        end if
      end if
      first = last + 2
    end do
  end subroutine check_scene_groups
end module config_scene_groups
