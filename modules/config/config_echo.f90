!> The resolved configuration as namelist text: printed by `--check`, written to
!! `<output_dir>/<name>.used.nml` and stored in checkpoints.
!!
!! Every variable of every group is written, defaults included, with reals in the shortest form
!! that reads back bitwise identical, so reading the text with `config_load_text` reproduces the
!! configuration exactly. The text has one `variable = value` per line and no comments after
!! values (postproc/namelist.py reads it).
module config_echo
  use mpmice_kinds, only: msg_len
  use config_types, only: config_t
  use config_text, only: real_repr, reals_repr, ints_repr, logicals_repr, quoted
  implicit none
  private

  public :: config_to_text, config_write_used, config_used_path

  character(len=*), parameter :: nl = achar(10)  !< line end

contains

  !> All groups of `cfg` as namelist text (lines end with a line feed).
  function config_to_text(cfg) result(text)
    type(config_t), intent(in) :: cfg  !< configuration
    character(len=:), allocatable :: text

    text = '! MPMICE resolved input: every variable, defaults included' // nl
    text = text // '&run' // nl
    call add('name', quoted(cfg%run%name))
    call add('scene', quoted(cfg%run%scene))
    call add('output_dir', quoted(cfg%run%output_dir))
    call add('end_time', real_repr(cfg%run%end_time))
    call add('output_interval', real_repr(cfg%run%output_interval))
    call add('checkpoint_interval', real_repr(cfg%run%checkpoint_interval))
    call add('max_steps', ints_repr([cfg%run%max_steps]))
    call add('wall_time_limit', real_repr(cfg%run%wall_time_limit))
    call add('progress_interval', real_repr(cfg%run%progress_interval))
    call add('verbosity', ints_repr([cfg%run%verbosity]))
    text = text // '/' // nl // '&grid' // nl
    call add('ncells', ints_repr(cfg%grid%ncells))
    call add('lower', reals_repr(cfg%grid%lower))
    call add('upper', reals_repr(cfg%grid%upper))
    call add('periodic', logicals_repr(cfg%grid%periodic))
    call add('ghost_width', ints_repr([cfg%grid%ghost_width]))
    call add('dims', ints_repr(cfg%grid%dims))
    text = text // '/' // nl // '&time' // nl
    call add('cfl', real_repr(cfg%time%cfl))
    call add('dt_init', real_repr(cfg%time%dt_init))
    call add('dt_max', real_repr(cfg%time%dt_max))
    call add('dt_min', real_repr(cfg%time%dt_min))
    call add('dt_growth', real_repr(cfg%time%dt_growth))
    text = text // '/' // nl // '&numerics' // nl
    call add('advection_order', ints_repr([cfg%numerics%advection_order]))
    call add('shape_function', quoted(cfg%numerics%shape_function))
    call add('time_theta', real_repr(cfg%numerics%time_theta))
    text = text // '/' // nl // '&solver' // nl
    call add('tolerance', real_repr(cfg%solver%tolerance))
    call add('max_iterations', ints_repr([cfg%solver%max_iterations]))
    call add('print_level', ints_repr([cfg%solver%print_level]))
    text = text // '/' // nl // '&output' // nl
    call add('xdmf', logicals_repr([cfg%output%xdmf]))
    call add('fields', quoted(cfg%output%fields))
    text = text // '/' // nl // '&heat' // nl
    call add('conductivity', real_repr(cfg%heat%conductivity))
    call add('density', real_repr(cfg%heat%density))
    call add('heat_capacity', real_repr(cfg%heat%heat_capacity))
    call add('base_temperature', real_repr(cfg%heat%base_temperature))
    call add('amplitude', real_repr(cfg%heat%amplitude))
    call add('modes', ints_repr(cfg%heat%modes))
    text = text // '/' // nl

  contains

    subroutine add(name, value)
      character(len=*), intent(in) :: name
      character(len=*), intent(in) :: value
      text = text // '  ' // name // ' = ' // value // nl
    end subroutine add
  end function config_to_text

  !> Path of the echo file: `<output_dir>/<name>.used.nml`.
  function config_used_path(cfg) result(path)
    type(config_t), intent(in) :: cfg  !< configuration
    character(len=:), allocatable :: path
    path = trim(cfg%run%output_dir) // '/' // trim(cfg%run%name) // '.used.nml'
  end function config_used_path

  !> Write `config_to_text(cfg)` to `path` (replacing it). Call on one rank; the directory must
  !! exist. Without `stat` a failure is fatal; with it, `stat` /= 0 and `errmsg` say why.
  subroutine config_write_used(cfg, path, stat, errmsg)
    use mpmice_errors, only: fatal
    type(config_t), intent(in) :: cfg                      !< configuration
    character(len=*), intent(in) :: path                   !< file to write
    integer, intent(out), optional :: stat                 !< 0 on success
    character(len=*), intent(out), optional :: errmsg      !< reason on failure
    character(len=msg_len) :: iomsg
    integer :: unit, ios
    open(newunit=unit, file=path, status='replace', action='write', access='stream', &
      form='unformatted', iostat=ios, iomsg=iomsg)
    if (ios == 0) then
      write(unit, iostat=ios, iomsg=iomsg) config_to_text(cfg)
      close(unit)
    end if
    if (present(stat)) stat = ios
    if (present(errmsg)) errmsg = ''
    if (ios /= 0) then
      if (present(errmsg)) errmsg = 'cannot write ' // trim(path) // ': ' // trim(iomsg)
      if (.not. present(stat)) call fatal('cannot write ' // trim(path) // ': ' // trim(iomsg))
    end if
  end subroutine config_write_used
end module config_echo
