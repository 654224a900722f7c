!> The command line of `mpmice` (design §1):
!!
!!     mpmice case.nml [--set '&group var = value /' ...]
!!     mpmice --check case.nml [--set ...]
!!     mpmice --restart checkpoint.h5 [--set ...]
!!     mpmice --help | --version
module config_cli
  use mpmice_kinds, only: path_len, msg_len
  use mpmice_errors, only: int_text
  use mpmice_build_info, only: mpmice_version
  implicit none
  private

  public :: cli_t, cli_parse, cli_from_command_line, cli_usage, mpmice_version
  public :: action_run, action_check, action_help, action_version

  integer, parameter :: action_run = 1      !< run the case (or continue a checkpoint)
  integer, parameter :: action_check = 2    !< validate and print the resolved input only
  integer, parameter :: action_help = 3     !< print usage
  integer, parameter :: action_version = 4  !< print the version

  !> What the command line asks for.
  type :: cli_t
    integer :: action = action_run                       !< one of the action_* constants
    character(len=path_len) :: case_file = ''            !< namelist file ('' when restarting)
    character(len=path_len) :: restart_file = ''         !< checkpoint ('' when not restarting)
    integer :: nsets = 0                                 !< number of `--set` texts
    character(len=msg_len), allocatable :: sets(:)       !< `--set` texts in order
  end type cli_t

contains

  !> Usage text (lines end with a line feed).
  function cli_usage() result(text)
    character(len=:), allocatable :: text
    character(len=*), parameter :: nl = achar(10)
    text = 'usage: mpmice [--check] CASE.nml [--set ''&group variable = value /'']...' // nl // &
      '       mpmice [--check] --restart CHECKPOINT.h5 [--set ...]...' // nl // &
      '       mpmice --help | --version' // nl // nl // &
      '  CASE.nml            namelist file describing the scene (see docs/namelists.md)' // nl // &
      '  --check             read and validate only; print the resolved input; write nothing' &
      // nl // &
      '  --set TEXT          namelist text applied after the file, in order (repeatable)' // nl // &
      '  --restart FILE      continue the run stored in checkpoint FILE' // nl // &
      '  --help, -h          print this help' // nl // &
      '  --version           print the version' // nl
  end function cli_usage

  !> Interpret the arguments `args` (without the program name). `stat` /= 0 and `errmsg` (one
  !! line) on a usage error.
  subroutine cli_parse(args, cli, stat, errmsg)
    character(len=*), intent(in) :: args(:)               !< command-line arguments
    type(cli_t), intent(out) :: cli                       !< interpretation
    integer, intent(out) :: stat                          !< 0 ok, 1 usage error
    character(len=:), allocatable, intent(out) :: errmsg  !< error line
    integer :: i
    logical :: check, help, version
    character(len=:), allocatable :: arg, value

    stat = 0
    errmsg = ''
    check = .false.
    help = .false.
    version = .false.
    allocate(cli%sets(size(args)))
    i = 0
    do while (i < size(args))
      i = i + 1
      arg = trim(args(i))
      select case (arg)
      case ('--help', '-h')
        help = .true.
      case ('--version')
        version = .true.
      case ('--check')
        check = .true.
      case default
        if (starts_with(arg, '--set') .or. starts_with(arg, '--restart')) then
          call option_value(arg, value)
          if (stat /= 0) return
          if (starts_with(arg, '--set')) then
            if (len(value) > msg_len) then
              call usage_error('--set text longer than ' // int_text(msg_len) // ' characters')
              return
            end if
            cli%nsets = cli%nsets + 1
            cli%sets(cli%nsets) = value
          else
            if (len_trim(cli%restart_file) > 0) then
              call usage_error('--restart given more than once')
              return
            else if (len(value) > path_len) then
              call usage_error('--restart path longer than ' // int_text(path_len) // ' characters')
              return
            end if
            cli%restart_file = value
          end if
        else if (len(arg) > 1 .and. arg(1:1) == '-') then
          call usage_error('unknown option ''' // arg // '''')
          return
        else if (len_trim(cli%case_file) > 0) then
          call usage_error('more than one case file: ''' // trim(cli%case_file) // ''' and ''' &
            // arg // '''')
          return
        else if (len(arg) == 0 .or. len(arg) > path_len) then
          call usage_error('case file name empty or longer than ' // int_text(path_len) // &
            ' characters')
          return
        else
          cli%case_file = arg
        end if
      end select
    end do

    if (help) then
      cli%action = action_help
    else if (version) then
      cli%action = action_version
    else if (len_trim(cli%case_file) > 0 .and. len_trim(cli%restart_file) > 0) then
      call usage_error('give either a case file or --restart, not both')
    else if (len_trim(cli%case_file) == 0 .and. len_trim(cli%restart_file) == 0) then
      call usage_error('no case file given')
    else if (check) then
      cli%action = action_check
    else
      cli%action = action_run
    end if

  contains

    !> The value of `--opt=value` or of `--opt value` (the next argument).
    subroutine option_value(option, val)
      character(len=*), intent(in) :: option
      character(len=:), allocatable, intent(out) :: val
      integer :: eq
      character(len=:), allocatable :: name
      eq = index(option, '=')
      if (eq > 0) then
        name = option(1:eq - 1)
        val = option(eq + 1:)
      else
        name = option
        if (i >= size(args)) then
          call usage_error(name // ' needs a value')
          val = ''
          return
        end if
        i = i + 1
        val = trim(args(i))
      end if
      if (name /= '--set' .and. name /= '--restart') then
        call usage_error('unknown option ''' // option // '''')
      else if (len_trim(val) == 0) then
        call usage_error(name // ' needs a non-empty value')
      end if
    end subroutine option_value

    subroutine usage_error(message)
      character(len=*), intent(in) :: message
      stat = 1
      errmsg = 'mpmice: usage error: ' // message // ' (see mpmice --help)'
    end subroutine usage_error
  end subroutine cli_parse

  !> `cli_parse` applied to this process's command line.
  subroutine cli_from_command_line(cli, stat, errmsg)
    type(cli_t), intent(out) :: cli                       !< interpretation
    integer, intent(out) :: stat                          !< 0 ok, 1 usage error
    character(len=:), allocatable, intent(out) :: errmsg  !< error line
    character(len=msg_len), allocatable :: args(:)
    integer :: i, n, length
    n = command_argument_count()
    allocate(args(n))
    do i = 1, n
      call get_command_argument(i, args(i), length=length)
      if (length > msg_len) then
        stat = 1
        errmsg = 'mpmice: usage error: argument ' // int_text(i) // ' is longer than ' // &
          int_text(msg_len) // ' characters (see mpmice --help)'
        return
      end if
    end do
    call cli_parse(args, cli, stat, errmsg)
  end subroutine cli_from_command_line

  !> True if `s` starts with `prefix`.
  pure logical function starts_with(s, prefix)
    character(len=*), intent(in) :: s       !< string
    character(len=*), intent(in) :: prefix  !< prefix
    starts_with = .false.
    if (len(s) >= len(prefix)) starts_with = s(1:len(prefix)) == prefix
  end function starts_with
end module config_cli
