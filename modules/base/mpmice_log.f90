!> Root-only logging to standard output (information) and standard error (warnings), each line
!! also copied to the run's log file `<output_dir>/<name>.log` once it is open.
!!
!! Only rank 0 of the run's communicator prints. The rank flag, verbosity and log-file unit are the
!! module's only state (allowed exception: every routine of the program logs, and passing a logger
!! through every call would obscure the physics interfaces).
module mpmice_log
  use, intrinsic :: iso_fortran_env, only: output_unit, error_unit
  implicit none
  private

  public :: log_init, log_info, log_warning, log_debug, log_is_root, log_set_verbosity
  public :: log_open_file, log_close_file, log_repeated, log_warning_summary

  !> Module state (allowed exception): true on the rank that prints.
  logical :: is_root = .true.
  !> Module state (allowed exception): 0 quiet, 1 normal, 2 debug.
  integer :: verbosity = 1
  !> Module state (allowed exception): unit of the log file on rank 0 and whether it is open.
  integer :: file_unit = 0
  logical :: file_open = .false.

  integer, parameter :: repeat_limit = 10     !< lines printed per kind of warning
  integer, parameter :: max_kinds = 64        !< kinds of warning counted
  integer, parameter :: kind_len = 160        !< characters of a kind's template kept
  integer, parameter :: line_len = 400        !< characters of a suppressed line kept
  !> Module state (allowed exception, part of the log like the verbosity): warnings of one kind
  !! (the same text once the numbers are left out) are printed `repeat_limit` times, then only
  !! counted; `log_warning_summary` reports the counts at the end of the run.
  type :: warning_kinds_t
    integer :: n = 0                                      !< kinds in use
    character(len=kind_len) :: template(max_kinds) = ''   !< text without its numbers
    integer :: count(max_kinds) = 0                       !< warnings of the kind
    character(len=line_len) :: last(max_kinds) = ''       !< the last line of the kind
  end type warning_kinds_t
  type(warning_kinds_t) :: kinds

contains

  !> Set which rank prints (call once after MPI start-up with `rank == 0`).
  subroutine log_init(root)
    logical, intent(in) :: root  !< this rank prints
    is_root = root
  end subroutine log_init

  !> Open the log file `path` on rank 0 (a new run replaces it, a restart appends to it so that a
  !! restart chain keeps one log). `stat` /= 0 and `errmsg` say why it could not be opened.
  subroutine log_open_file(path, append, stat, errmsg)
    character(len=*), intent(in) :: path                  !< log file
    logical, intent(in) :: append                         !< continue an existing log
    integer, intent(out) :: stat                          !< 0 ok
    character(len=:), allocatable, intent(out) :: errmsg  !< reason when stat /= 0
    character(len=256) :: iomsg
    stat = 0
    errmsg = ''
    if (.not. is_root) return
    call log_close_file()
    if (append) then
      open(newunit=file_unit, file=path, status='unknown', position='append', action='write', &
        iostat=stat, iomsg=iomsg)
    else
      open(newunit=file_unit, file=path, status='replace', action='write', iostat=stat, &
        iomsg=iomsg)
    end if
    file_open = stat == 0
    if (stat /= 0) errmsg = trim(iomsg)
  end subroutine log_open_file

  !> Close the log file (if open).
  subroutine log_close_file()
    if (file_open) close(file_unit)
    file_open = .false.
  end subroutine log_close_file

  !> Write one line to the log file (if open).
  subroutine to_file(line)
    character(len=*), intent(in) :: line  !< text
    if (.not. file_open) return
    write(file_unit, '(a)') line
    flush(file_unit)
  end subroutine to_file

  !> Set the verbosity: 0 quiet, 1 normal, 2 debug.
  subroutine log_set_verbosity(level)
    integer, intent(in) :: level  !< new verbosity
    verbosity = level
  end subroutine log_set_verbosity

  !> True on the printing rank.
  logical function log_is_root()
    log_is_root = is_root
  end function log_is_root

  !> An informational line (rank 0, verbosity >= 1).
  subroutine log_info(message)
    character(len=*), intent(in) :: message  !< text to print
    call log_at(1, message)
  end subroutine log_info

  !> A debug line (rank 0, verbosity >= 2).
  subroutine log_debug(message)
    character(len=*), intent(in) :: message  !< text to print
    call log_at(2, message)
  end subroutine log_debug

  !> A line on standard output and in the log file from rank 0 when the verbosity is at least
  !! `level`.
  subroutine log_at(level, message)
    integer, intent(in) :: level             !< least verbosity that prints it
    character(len=*), intent(in) :: message  !< text to print
    if (is_root .and. verbosity >= level) then
      write(output_unit, '(a)') trim(message)
      flush(output_unit)
      call to_file(trim(message))
    end if
  end subroutine log_at

  !> A warning line on standard error (rank 0), `log_repeated` rules.
  subroutine log_warning(message)
    character(len=*), intent(in) :: message  !< text to print
    if (is_root) call log_repeated('mpmice: warning: ' // trim(message))
  end subroutine log_warning

  !> Print the complete line `line` on standard error from the calling rank, unless lines of its
  !! kind (the same text once the numbers are left out) were printed `repeat_limit` times
  !! already: those are counted, and `log_warning_summary` reports them at the end of the run.
  !! The line that reaches the limit says so.
  subroutine log_repeated(line)
    character(len=*), intent(in) :: line  !< the whole line
    character(len=*), parameter :: limit_line = 'mpmice: warning: the last warning was given ' &
      // '10 times: further ones like it are counted and summarised at the end of the run'
    character(len=kind_len) :: key
    integer :: k
    key = number_free(line)
    k = 1
    do while (k <= kinds%n)
      if (kinds%template(k) == key) exit
      k = k + 1
    end do
    if (k > kinds%n .and. kinds%n < max_kinds) then
      kinds%n = kinds%n + 1
      kinds%template(k) = key
    end if
    if (k <= kinds%n) then
      kinds%count(k) = kinds%count(k) + 1
      kinds%last(k) = line
      if (kinds%count(k) > repeat_limit) return
    end if
    write(error_unit, '(a)') trim(line)
    call to_file(trim(line))
    if (k <= kinds%n) then
      if (kinds%count(k) == repeat_limit) then
        write(error_unit, '(a)') limit_line
        call to_file(limit_line)
      end if
    end if
    flush(error_unit)
  end subroutine log_repeated

  !> At the end of a run: one line per kind of warning that was given more than `repeat_limit`
  !! times on this rank, with the total and the last one.
  subroutine log_warning_summary()
    character(len=*), parameter :: prefix = 'mpmice: warning: '
    character(len=line_len) :: last
    integer :: k
    character(len=16) :: total, hidden
    do k = 1, kinds%n
      if (kinds%count(k) <= repeat_limit) cycle
      write(total, '(i0)') kinds%count(k)
      write(hidden, '(i0)') kinds%count(k) - repeat_limit
      last = kinds%last(k)
      if (index(last, prefix) == 1) last = last(len(prefix) + 1:)
      write(error_unit, '(a)') prefix // trim(total) // ' warnings like this one in all, ' // &
        trim(hidden) // ' not printed; the last: ' // trim(last)
      call to_file(prefix // trim(total) // ' warnings like this one in all, ' // &
        trim(hidden) // ' not printed; the last: ' // trim(last))
    end do
    flush(error_unit)
  end subroutine log_warning_summary

  !> `line` without its numbers (digits with their signs, points and exponents): the kind of a
  !! warning, e.g. 'negative mass in  cells at t =  s'.
  pure function number_free(line) result(key)
    character(len=*), intent(in) :: line  !< text
    character(len=kind_len) :: key
    integer :: k, n
    logical :: in_number
    key = ''
    n = 0
    in_number = .false.
    do k = 1, len_trim(line)
      if (in_number) then
        in_number = index('0123456789.eE+-', line(k:k)) > 0
      else
        in_number = index('0123456789', line(k:k)) > 0
      end if
      if (in_number) cycle
      if (n >= kind_len) exit
      n = n + 1
      key(n:n) = line(k:k)
    end do
  end function number_free
end module mpmice_log
