!> The resolved configuration as namelist text: printed by `--check`, written to
!! `<output_dir>/<name>.used.nml` and stored in checkpoints.
!!
!! Every variable of every group is written, defaults included, with reals in the shortest form that
!! reads back bitwise identical, so reading the text with `config_load_text` reproduces the
!! configuration exactly. The text has one `variable = value` per line and no comments after values
!! (postproc/namelist.py reads it). Repeated groups (`&fluid`, `&solid`, `&region`, `&boundary`)
!! follow the singletons, one group per occurrence in order; reading the text appends them again in
!! the same order. Of a table with unset entries (a `&boundary` velocity history) the entries in use
!! are written, or a comment when none is. The echo function of each group (`echo_run`, ...) is
!! generated from the namelist list (modules/config/namelist/*.toml, scripts/generate_namelists.py)
!! into the included file.
module config_echo
  use mpmice_kinds, only: wp, msg_len
  use config_types, only: config_t, run_params_t, grid_params_t, time_params_t, &
    numerics_params_t, solver_params_t, output_params_t, heat_params_t, physics_params_t, &
    ice_params_t, mpm_params_t, coupling_params_t, fluid_params_t, solid_params_t, &
    region_params_t, boundary_params_t, history_unset
  use config_text, only: real_repr, reals_repr, ints_repr, logicals_repr, quoted
  use parallel_domain, only: blocks_given
  use io_write_failure, only: io_check_size, io_remove_file
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
    text = text // echo_groups(cfg)
  end function config_to_text

  include 'config_nml_echo.inc'

  !> One echo line: `  name = value`.
  pure function echo_line(name, value) result(line)
    character(len=*), intent(in) :: name   !< variable name
    character(len=*), intent(in) :: value  !< value as namelist text
    character(len=:), allocatable :: line
    line = '  ' // name // ' = ' // value // nl
  end function echo_line

  !> The echo line of a table: its entries in use, or a comment saying that none is set
  !! (reading the echo back leaves the table unset either way).
  pure function echo_table_line(name, value) result(line)
    character(len=*), intent(in) :: name   !< variable name
    character(len=*), intent(in) :: value  !< entries in use as namelist text ('' if none)
    character(len=:), allocatable :: line
    if (len(value) > 0) then
      line = echo_line(name, value)
    else
      line = '  ! ' // name // ' = unset' // nl
    end if
  end function echo_table_line

  !> A table with trailing unused entries (`history_unset`): the entries up to the last one in
  !! use (an empty text when none is); the unused tail keeps its default when read back.
  function table_repr(x) result(text)
    real(wp), intent(in) :: x(:)  !< table
    character(len=:), allocatable :: text
    integer :: n
    n = size(x)
    do while (n > 0)
      if (x(n) /= history_unset) exit
      n = n - 1
    end do
    text = ''
    if (n > 0) text = reals_repr(x(1:n))
  end function table_repr

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
    character(len=:), allocatable :: text, reason
    integer :: unit, ios
    text = config_to_text(cfg)
    open(newunit=unit, file=path, status='replace', action='write', access='stream', &
      form='unformatted', iostat=ios, iomsg=iomsg)
    if (ios == 0) then
      write(unit, iostat=ios, iomsg=iomsg) text
      close(unit)
      ! a full disk: gfortran reports nothing, the size on disk tells; no partial file stays
      if (ios == 0) call io_check_size(path, len(text), ios, reason)
      if (ios /= 0) then
        if (allocated(reason)) iomsg = reason
        call io_remove_file(path)
      end if
    end if
    if (present(stat)) stat = ios
    if (present(errmsg)) errmsg = ''
    if (ios /= 0) then
      if (present(errmsg)) errmsg = 'cannot write ' // trim(path) // ': ' // trim(iomsg)
      if (.not. present(stat)) call fatal('cannot write ' // trim(path) // ': ' // trim(iomsg))
    end if
  end subroutine config_write_used

  !> The entries of a `block_cells` column up to its last non-zero one ('0' when all are zero).
  function blocks_repr(cells) result(text)
    integer, intent(in) :: cells(:)  !< cells per block, zero-padded
    character(len=:), allocatable :: text
    integer :: n
    n = blocks_given(cells)
    if (n == 0) then
      text = '0'
    else
      text = ints_repr(cells(1:n))
    end if
  end function blocks_repr
end module config_echo
