!> Parse namelist text into a `config_t`, with one precise error line for any bad input.
!!
!! The text is split into groups (`&name ... /`) and each group into `variable = value`
!! assignments by a small scanner that honours quoted strings and `!` comments. Each assignment is
!! then read on its own through the group's real namelist read (`config_namelist`), in order, which
!! is what a whole-group read does, but a failure names the exact variable and value, which the
!! compiler's `iomsg` does not always do. Checked here: unknown groups, repeated groups, text
!! outside groups, unterminated groups, unknown variables, missing values, unquoted or too long
!! strings and values the compiler cannot read. Range checks are in `config_validate`.
!!
!! Repeated groups (`&fluid`, `&solid`, `&region`, `&boundary`): each occurrence in a case file
!! appends a new element, set to the defaults, to its array (more than the maximum count is an
!! error). In an override text (`--set`, `overrides = .true.`) a `&fluid`/`&solid`/`&boundary`
!! group instead modifies the existing occurrence named by its selector variable (`name`, or
!! `face`), which the group must assign; a `&region` group appends a region (later regions win).
!! Messages and provenance name the occurrence as `&fluid(2)`.
module config_parse
  use mpmice_kinds, only: msg_len, name_len
  use mpmice_errors, only: input_error_text, int_text
  use config_types, only: config_t
  use config_namelist, only: group_names, variables, find_variable, group_variable_names, &
    describe_value, namelist_assign
  use config_occurrences, only: repeated_group_names, is_repeated_group, group_selector, &
    max_occurrences, new_occurrence, find_occurrence, occurrence_selectors
  use config_text, only: lower_case, is_identifier_char, join_names, unquoted, quoted
  implicit none
  private

  public :: config_load_text, config_origin_t, origin_source, group_error_text

  integer, parameter :: key_len = 40   !< length of `group variable` keys

  !> Which input (file or `--set`) last assigned each variable.
  type :: config_origin_t
    integer :: n = 0                                      !< keys in use
    character(len=key_len), allocatable :: key(:)         !< `group variable`
    character(len=msg_len), allocatable :: source(:)      !< file name or `--set`
  end type config_origin_t

contains

  !> Apply the namelist text `text` to `cfg`: variables it assigns change, all others keep the
  !! value `cfg` has (the defaults for a fresh `config_t`). `stat` is 0 on success; otherwise 1 and
  !! `errmsg` is the one-line input error naming `source`, group, variable and value. `cfg` may be
  !! partly updated on failure. `origin`, when given, records the source of every assignment.
  !! With `overrides = .true.` (the `--set` texts) repeated groups select an existing occurrence
  !! instead of appending one (see the module header).
  subroutine config_load_text(cfg, text, source, stat, errmsg, origin, overrides, groups)
    type(config_t), intent(inout) :: cfg                    !< configuration to update
    character(len=*), intent(in) :: text                    !< namelist text (may hold newlines)
    character(len=*), intent(in) :: source                  !< name of the input for messages
    integer, intent(out) :: stat                            !< 0 ok, 1 input error
    character(len=:), allocatable, intent(out) :: errmsg    !< the error line when stat /= 0
    type(config_origin_t), intent(inout), optional :: origin !< provenance of each variable
    logical, intent(in), optional :: overrides              !< `--set` semantics
    !> the names of the groups the text holds, each followed by a blank (`run grid fluid `)
    character(len=:), allocatable, intent(out), optional :: groups
    character(len=len(text)) :: s
    character(len=:), allocatable :: group
    integer :: n, i, j, seen(size(group_names)), g, body_end, k, quote_at
    logical :: select_existing

    select_existing = .false.
    if (present(overrides)) select_existing = overrides

    stat = 0
    errmsg = ''
    seen = 0
    if (present(groups)) groups = ''
    call clean_text(text, s)
    n = len(s)
    i = 1
    do
      do while (i <= n)
        if (s(i:i) /= ' ') exit
        i = i + 1
      end do
      if (i > n) exit
      if (s(i:i) /= '&') then
        call fail(group_error_text(source, '', 'text outside a namelist group: ' // &
          excerpt(s(i:))))
        return
      end if
      j = i + 1
      do while (j <= n)
        if (.not. is_identifier_char(s(j:j))) exit
        j = j + 1
      end do
      group = lower_case(s(i + 1:j - 1))
      g = findloc_name(group)
      if (g == 0 .and. .not. is_repeated_group(group)) then
        call fail(group_error_text(source, group, 'unknown namelist group; known: ' // &
          join_names(group_names, ', ', '&') // ', ' // &
          join_names(repeated_group_names, ', ', '&')))
        return
      end if
      if (g > 0) then
        seen(g) = seen(g) + 1
        if (seen(g) > 1) then
          call fail(group_error_text(source, group, 'group given more than once; allowed: once'))
          return
        end if
      end if
      call find_group_end(s, j, body_end, quote_at)
      if (quote_at > 0) then
        call fail(group_error_text(source, group, 'unterminated quote (' // s(quote_at:quote_at) &
          // ') opened on line ' // int_text(line_number(text, quote_at)) // ': ' // &
          excerpt(line_rest(text, quote_at))))
        return
      end if
      if (body_end <= 0) then
        call fail(group_error_text(source, group, 'group not terminated by ''/'''))
        return
      end if
      if (present(groups)) groups = groups // group // ' '
      if (g > 0) then
        call apply_group(cfg, group, s(j:body_end - 1), source, stat, errmsg, origin)
      else
        call choose_occurrence(cfg, group, s(j:body_end - 1), source, select_existing, k, &
          stat, errmsg)
        if (stat /= 0) return
        call apply_group(cfg, group, s(j:body_end - 1), source, stat, errmsg, origin, k)
      end if
      if (stat /= 0) return
      i = body_end + 1
    end do

  contains

    subroutine fail(message)
      character(len=*), intent(in) :: message
      stat = 1
      errmsg = message
    end subroutine fail
  end subroutine config_load_text

  !> The occurrence of repeated group `group` that the group text `body` applies to: a new one,
  !! or with `select_existing` (and a selector variable) the one its selector names.
  subroutine choose_occurrence(cfg, group, body, source, select_existing, k, stat, errmsg)
    type(config_t), intent(inout) :: cfg                    !< configuration to update
    character(len=*), intent(in) :: group                   !< repeated group name
    character(len=*), intent(in) :: body                    !< text between name and `/`
    character(len=*), intent(in) :: source                  !< input name for messages
    logical, intent(in) :: select_existing                  !< modify instead of append
    integer, intent(out) :: k                               !< the occurrence
    integer, intent(out) :: stat                            !< 0 ok, 1 input error
    character(len=:), allocatable, intent(inout) :: errmsg  !< the error line
    character(len=:), allocatable :: selector, value, content
    character(len=16) :: limit
    logical :: ok, found

    stat = 1
    k = 0
    selector = group_selector(group)
    if (select_existing .and. len(selector) > 0) then
      call find_assignment(body, selector, found, value)
      if (.not. found) then
        errmsg = group_error_text(source, group, 'an override of a repeated group must select ' &
          // 'the occurrence with ' // selector // ' = ''...''; present: ' // &
          present_list(cfg, group))
        return
      end if
      call unquoted(value, content, ok)
      if (ok) k = find_occurrence(cfg, group, content)
      if (k == 0) then
        errmsg = input_error_text(source, group, selector, value, 'no &' // group // &
          ' with this ' // selector // '; present: ' // present_list(cfg, group))
        return
      end if
    else
      call new_occurrence(cfg, group, k)
      if (k == 0) then
        write(limit, '(i0)') max_occurrences(group)
        if (group == 'boundary') then
          selector = 'max_boundaries'
        else
          selector = 'max_' // group // 's'
        end if
        errmsg = group_error_text(source, group, 'more than ' // trim(limit) // &
          ' groups; allowed: at most ' // trim(limit) // ' (' // selector // ')')
        return
      end if
    end if
    stat = 0
  end subroutine choose_occurrence

  !> The selector values of the occurrences of `group`, quoted, or `none`.
  function present_list(cfg, group) result(text)
    type(config_t), intent(in) :: cfg      !< configuration
    character(len=*), intent(in) :: group  !< repeated group name
    character(len=:), allocatable :: text
    character(len=name_len), allocatable :: values(:)
    integer :: k
    allocate(values, source=occurrence_selectors(cfg, group))
    text = ''
    do k = 1, size(values)
      if (k > 1) text = text // ', '
      text = text // quoted(values(k))
    end do
    if (size(values) == 0) text = 'none'
  end function present_list

  !> Index of `group` in `group_names`, 0 if unknown.
  pure integer function findloc_name(group)
    character(len=*), intent(in) :: group  !< lower-case group name
    integer :: k
    findloc_name = 0
    if (len(group) == 0) return
    do k = 1, size(group_names)
      if (group_names(k) == group) findloc_name = k
    end do
  end function findloc_name

  !> `text` with comments and line ends turned into blanks (quoted strings kept intact).
  pure subroutine clean_text(text, s)
    character(len=*), intent(in) :: text        !< raw namelist text
    character(len=len(text)), intent(out) :: s  !< cleaned text, same length
    character :: q, c
    integer :: k
    logical :: in_comment
    s = text
    ! a UTF-8 byte-order mark at the start is not text
    if (len(text) >= 3) then
      if (text(1:3) == char(239) // char(187) // char(191)) s(1:3) = ' '
    end if
    q = ' '
    in_comment = .false.
    do k = 1, len(text)
      c = text(k:k)
      if (in_comment) then
        ! a comment ends at a line end: LF (Unix, Windows) or a lone CR (old Mac)
        if (c == achar(10) .or. c == achar(13)) in_comment = .false.
        s(k:k) = ' '
      else if (q /= ' ') then
        if (c == q) q = ' '
      else if (c == '!') then
        in_comment = .true.
        s(k:k) = ' '
      else if (c == "'" .or. c == '"') then
        q = c
      end if
      if (.not. in_comment .and. q == ' ') then
        if (iachar(s(k:k)) < 32) s(k:k) = ' '
      end if
    end do
  end subroutine clean_text

  !> Position of the `/` that ends the group body starting at `start` (outside strings); 0 if the
  !! text ends first or another group starts first. `quote_at` is the position of a quote that
  !! is never closed (0 if none).
  pure subroutine find_group_end(s, start, pos, quote_at)
    character(len=*), intent(in) :: s  !< cleaned text
    integer, intent(in) :: start       !< first character after the group name
    integer, intent(out) :: pos        !< position of the terminator, 0 if none
    integer, intent(out) :: quote_at   !< position of an unterminated quote, 0 if none
    character :: q
    integer :: k
    q = ' '
    pos = 0
    quote_at = 0
    do k = start, len(s)
      if (q /= ' ') then
        if (s(k:k) == q) q = ' '
      else if (s(k:k) == "'" .or. s(k:k) == '"') then
        q = s(k:k)
        quote_at = k
      else if (s(k:k) == '&') then
        quote_at = 0
        return
      else if (s(k:k) == '/') then
        pos = k
        quote_at = 0
        return
      end if
    end do
    if (q == ' ') quote_at = 0
  end subroutine find_group_end

  !> `text` from `pos` to the end of its line.
  pure function line_rest(text, pos) result(rest)
    character(len=*), intent(in) :: text  !< raw text
    integer, intent(in) :: pos            !< start position
    character(len=:), allocatable :: rest
    integer :: k
    do k = pos, len(text)
      if (text(k:k) == achar(10) .or. text(k:k) == achar(13)) exit
    end do
    rest = text(pos:k - 1)
  end function line_rest

  !> Line number of position `pos` of `text` (lines end with LF, CR LF or a lone CR).
  pure integer function line_number(text, pos)
    character(len=*), intent(in) :: text  !< raw text
    integer, intent(in) :: pos            !< position in it
    integer :: k
    line_number = 1
    do k = 1, min(pos, len(text) + 1) - 1
      if (text(k:k) == achar(10)) then
        line_number = line_number + 1
      else if (text(k:k) == achar(13)) then
        if (k == len(text)) then
          line_number = line_number + 1
        else if (text(k + 1:k + 1) /= achar(10)) then
          line_number = line_number + 1
        end if
      end if
    end do
  end function line_number

  !> Positions of the `=` of each assignment of a group body (outside strings), and where the
  !! name before each starts; `starts(neq + 1)` and `eqs(neq + 1)` are `len(body) + 1`.
  pure subroutine split_assignments(body, neq, eqs, starts)
    character(len=*), intent(in) :: body          !< text between group name and `/`
    integer, intent(out) :: neq                   !< number of assignments
    integer, intent(out) :: eqs(len(body) + 1)    !< position of each `=`
    integer, intent(out) :: starts(len(body) + 1) !< start of each variable name
    integer :: k
    character :: q
    neq = 0
    q = ' '
    do k = 1, len(body)
      if (q /= ' ') then
        if (body(k:k) == q) q = ' '
      else if (body(k:k) == "'" .or. body(k:k) == '"') then
        q = body(k:k)
      else if (body(k:k) == '=') then
        neq = neq + 1
        eqs(neq) = k
        starts(neq) = name_start(body, k)
      end if
    end do
    starts(neq + 1) = len(body) + 1
    eqs(neq + 1) = len(body) + 1
  end subroutine split_assignments

  !> The value text of the first assignment to the scalar `variable` in a group body.
  subroutine find_assignment(body, variable, found, value)
    character(len=*), intent(in) :: body                 !< text between group name and `/`
    character(len=*), intent(in) :: variable             !< lower-case variable name
    logical, intent(out) :: found                        !< the body assigns `variable`
    character(len=:), allocatable, intent(out) :: value  !< its value text
    integer :: k, neq, eqs(len(body) + 1), starts(len(body) + 1)
    found = .false.
    value = ''
    call split_assignments(body, neq, eqs, starts)
    do k = 1, neq
      if (lower_case(trim(adjustl(body(starts(k):eqs(k) - 1)))) == variable) then
        found = .true.
        value = value_text(body(eqs(k) + 1:starts(k + 1) - 1))
        return
      end if
    end do
  end subroutine find_assignment

  !> Split a group body into `name = value` assignments and apply them one by one (to the
  !! occurrence `occurrence` of a repeated group).
  subroutine apply_group(cfg, group, body, source, stat, errmsg, origin, occurrence)
    type(config_t), intent(inout) :: cfg                    !< configuration to update
    character(len=*), intent(in) :: group                   !< lower-case group name
    character(len=*), intent(in) :: body                    !< text between name and `/`
    character(len=*), intent(in) :: source                  !< input name for messages
    integer, intent(out) :: stat                            !< 0 ok, 1 input error
    character(len=:), allocatable, intent(inout) :: errmsg  !< the error line
    type(config_origin_t), intent(inout), optional :: origin !< provenance
    integer, intent(in), optional :: occurrence             !< element of a repeated group
    integer :: k, neq, eqs(len(body) + 1), starts(len(body) + 1), name_end
    character(len=:), allocatable :: label
    character(len=16) :: number

    stat = 0
    label = group
    if (present(occurrence)) then
      write(number, '(i0)') occurrence
      label = group // '(' // trim(number) // ')'
    end if
    call split_assignments(body, neq, eqs, starts)
    if (neq == 0) then
      if (len_trim(body) > 0) then
        stat = 1
        errmsg = group_error_text(source, label, 'expected ''variable = value'', found: ' // &
          excerpt(adjustl(body)))
      end if
      return
    end if
    if (len_trim(body(1:starts(1) - 1)) > 0) then
      stat = 1
      errmsg = group_error_text(source, label, 'expected ''variable = value'', found: ' // &
        excerpt(adjustl(body(1:starts(1) - 1))))
      return
    end if
    do k = 1, neq
      name_end = eqs(k) - 1
      call apply_assignment(cfg, group, label, trim(adjustl(body(starts(k):name_end))), &
        value_text(body(eqs(k) + 1:starts(k + 1) - 1)), source, stat, errmsg, origin, &
        occurrence)
      if (stat /= 0) return
    end do
  end subroutine apply_group

  !> Start of the variable name (with optional subscript) that ends just before `body(eq:eq)`.
  pure integer function name_start(body, eq)
    character(len=*), intent(in) :: body  !< group body
    integer, intent(in) :: eq             !< position of `=`
    integer :: k
    k = eq - 1
    do while (k >= 1)
      if (body(k:k) /= ' ') exit
      k = k - 1
    end do
    if (k >= 1) then
      if (body(k:k) == ')') then
        do while (k >= 1)
          if (body(k:k) == '(') exit
          k = k - 1
        end do
        k = k - 1
      end if
    end if
    do while (k >= 1)
      if (.not. is_identifier_char(body(k:k))) exit
      k = k - 1
    end do
    name_start = k + 1
  end function name_start

  !> The value text of an assignment: blanks and one trailing separator comma removed.
  function value_text(raw) result(text)
    character(len=*), intent(in) :: raw  !< text between `=` and the next name
    character(len=:), allocatable :: text
    integer :: n
    text = trim(adjustl(raw))
    n = len(text)
    if (n > 0) then
      if (text(n:n) == ',') text = trim(text(1:n - 1))
    end if
  end function value_text

  !> Check and apply one assignment `name = value` of `group`.
  subroutine apply_assignment(cfg, group, label, name, value, source, stat, errmsg, origin, &
      occurrence)
    type(config_t), intent(inout) :: cfg                    !< configuration to update
    character(len=*), intent(in) :: group                   !< lower-case group name
    character(len=*), intent(in) :: label                  !< group as named in messages
    character(len=*), intent(in) :: name                    !< variable as written (with subscript)
    character(len=*), intent(in) :: value                   !< value text
    character(len=*), intent(in) :: source                  !< input name for messages
    integer, intent(out) :: stat                            !< 0 ok, 1 input error
    character(len=:), allocatable, intent(inout) :: errmsg  !< the error line
    type(config_origin_t), intent(inout), optional :: origin !< provenance
    integer, intent(in), optional :: occurrence             !< element of a repeated group
    character(len=:), allocatable :: base, content
    character(len=msg_len) :: iomsg
    integer :: v, p, ios
    logical :: ok

    stat = 1
    p = index(name, '(')
    if (p > 0) then
      base = lower_case(trim(name(1:p - 1)))
    else
      base = lower_case(name)
    end if
    v = find_variable(group, base)
    if (v == 0) then
      errmsg = input_error_text(source, label, name, value, &
        'unknown variable; known: ' // group_variable_names(group))
      return
    end if
    if (len(value) == 0) then
      errmsg = input_error_text(source, label, name, '', 'missing value; expected ' // &
        describe_value(variables(v)))
      return
    end if
    if (variables(v)%kind == 'c') then
      call unquoted(value, content, ok)
      if (.not. ok .or. len(content) > variables(v)%length) then
        errmsg = input_error_text(source, label, name, value, describe_value(variables(v)))
        return
      end if
    end if
    call namelist_assign(cfg, group, '&' // group // ' ' // name // ' = ' // value // ' /', &
      ios, iomsg, occurrence)
    if (ios /= 0) then
      errmsg = input_error_text(source, label, name, value, describe_value(variables(v)))
      return
    end if
    stat = 0
    if (present(origin)) call origin_record(origin, label // ' ' // base, source)
  end subroutine apply_assignment

  !> Remember that `source` assigned `key` (the latest assignment wins).
  subroutine origin_record(origin, key, source)
    type(config_origin_t), intent(inout) :: origin  !< provenance
    character(len=*), intent(in) :: key             !< `group variable`
    character(len=*), intent(in) :: source          !< input name
    character(len=key_len), allocatable :: keys(:)
    character(len=msg_len), allocatable :: sources(:)
    integer :: k
    if (.not. allocated(origin%key)) then
      allocate(origin%key(size(variables)), origin%source(size(variables)))
    end if
    do k = 1, origin%n
      if (origin%key(k) == key) then
        origin%source(k) = source
        return
      end if
    end do
    if (origin%n == size(origin%key)) then
      allocate(keys(2 * origin%n), sources(2 * origin%n))
      keys(1:origin%n) = origin%key(1:origin%n)
      sources(1:origin%n) = origin%source(1:origin%n)
      call move_alloc(keys, origin%key)
      call move_alloc(sources, origin%source)
    end if
    origin%n = origin%n + 1
    origin%key(origin%n) = key
    origin%source(origin%n) = source
  end subroutine origin_record

  !> The input that last assigned `variable` of `group`, or `default` if none did.
  function origin_source(origin, group, variable, default) result(source)
    type(config_origin_t), intent(in) :: origin  !< provenance
    character(len=*), intent(in) :: group        !< group name
    character(len=*), intent(in) :: variable     !< variable name
    character(len=*), intent(in) :: default      !< answer for unassigned variables
    character(len=:), allocatable :: source
    integer :: k
    source = default
    do k = 1, origin%n
      if (origin%key(k) == group // ' ' // variable) source = trim(origin%source(k))
    end do
  end function origin_source

  !> One-line input error about a group or the file as a whole:
  !! `mpmice: input error: FILE: &GROUP: PROBLEM` (or `FILE: PROBLEM` without a group).
  pure function group_error_text(source, group, problem) result(text)
    character(len=*), intent(in) :: source   !< file name or `--set`
    character(len=*), intent(in) :: group    !< group name without `&`, may be empty
    character(len=*), intent(in) :: problem  !< what is wrong and what is allowed
    character(len=:), allocatable :: text
    if (len_trim(group) > 0) then
      text = 'mpmice: input error: ' // trim(source) // ': &' // trim(group) // ': ' // &
        trim(problem)
    else
      text = 'mpmice: input error: ' // trim(source) // ': ' // trim(problem)
    end if
  end function group_error_text

  !> The start of `s` (at most 40 characters), quoted, for messages.
  pure function excerpt(s) result(text)
    character(len=*), intent(in) :: s  !< text
    character(len=:), allocatable :: text
    integer :: n
    n = min(len_trim(s), 40)
    text = '''' // s(1:n)
    if (len_trim(s) > 40) text = text // '...'
    text = text // ''''
  end function excerpt
end module config_parse
