!> CSV files of geometry (docs/geometry.md): the reader of "x, y" vertex files and the checks
!! of polygons and profiles, each problem one input-error line naming the file, the line and
!! what is wrong. Used by `config_geometry_files`.
!!
!! A CSV file holds one vertex "x, y" [m] per line (comma, semicolon, tab or blank separated);
!! blank lines and lines starting with `#` are skipped, and a first non-comment line that
!! does not start with a number is a header. Every other line must hold exactly two finite
!! numbers. A polygon needs at least 3 distinct vertices, is closed implicitly (a last vertex
!! equal to the first is dropped), must not intersect itself and must enclose a non-zero area;
!! a profile needs at least 2 points with x strictly increasing.
module config_geometry_csv
  use mpmice_kinds, only: wp, msg_len
  use mpmice_errors, only: int_text
  use config_text, only: real_repr
  use geometry_shapes, only: polygon_area, polygon_crossing, height_map_t
  implicit none
  private

  public :: read_xy_file, check_polygon_vertices, check_profile_points, file_error
  public :: height_map_from_points

  integer, parameter :: field_len = 256  !< longest CSV field kept (longer ones are cut)
  integer, parameter :: max_fields = 8   !< CSV fields kept per line (more are counted)

contains

  !> Read the CSV file `path` of vertices "x, y". `lines(i)` is the line of vertex i. On a
  !! problem `stat` = 1 and `errmsg` is the input-error line ending with `what` (the variable
  !! that named the file). With `z` present the file may hold "x, y, z" points instead (a
  !! height map): the first data line sets the number of values of every line, and `z` gets
  !! them (size 0 for a file of "x, y").
  subroutine read_xy_file(path, what, x, y, lines, stat, errmsg, z)
    character(len=*), intent(in) :: path                 !< CSV file
    character(len=*), intent(in) :: what                 !< e.g. "&solid 'bed' profile_file"
    real(wp), allocatable, intent(out) :: x(:), y(:)     !< vertices [m]
    integer, allocatable, intent(out) :: lines(:)        !< line number of each vertex
    integer, intent(out) :: stat                         !< 0 ok, 1 input error
    character(len=:), allocatable, intent(out) :: errmsg !< error line
    real(wp), allocatable, intent(out), optional :: z(:) !< heights [m] (3 values per line)
    character(len=:), allocatable :: text, line, expected
    character(len=field_len) :: fields(max_fields)
    character(len=msg_len) :: iomsg
    integer :: unit, ios, nbytes, start, finish, lineno, n, nf, f, ncols, first_line
    logical :: exists, seen_data
    real(wp) :: v(3)
    real(wp), allocatable :: zz(:), tmp(:)

    stat = 1
    errmsg = ''
    n = 0
    ncols = 0
    first_line = 0
    allocate(x(64), y(64), lines(64), zz(64))
    if (present(z)) allocate(z(0))
    inquire(file=path, exist=exists)
    if (.not. exists) then
      errmsg = file_error(path, 0, 'cannot read the file: no such file', what)
      return
    end if
    open(newunit=unit, file=path, status='old', action='read', access='stream', &
      form='unformatted', iostat=ios, iomsg=iomsg)
    if (ios /= 0) then
      errmsg = file_error(path, 0, 'cannot read the file: ' // trim(iomsg), what)
      return
    end if
    inquire(unit=unit, size=nbytes)
    if (nbytes < 0) then
      close(unit)
      errmsg = file_error(path, 0, 'cannot read the file: not a regular file', what)
      return
    end if
    allocate(character(len=nbytes) :: text)
    ios = 0
    if (nbytes > 0) read(unit, iostat=ios, iomsg=iomsg) text
    close(unit)
    if (ios /= 0) then
      errmsg = file_error(path, 0, 'cannot read the file: ' // trim(iomsg), what)
      return
    end if

    start = 1
    lineno = 0
    seen_data = .false.
    do while (start <= len(text))
      finish = index(text(start:), achar(10))
      if (finish == 0) then
        finish = len(text) + 1
      else
        finish = start + finish - 1
      end if
      line = text(start:finish - 1)
      start = finish + 1
      lineno = lineno + 1
      line = trim(adjustl(replace_separators(line)))
      if (len(line) == 0) cycle
      if (line(1:1) == '#') cycle
      call split_fields(line, fields, nf)
      if (.not. seen_data .and. .not. is_number(fields(1))) then
        seen_data = .true.     ! the header: only before the first vertex
        cycle
      end if
      seen_data = .true.
      if (ncols == 0) then
        ncols = 2
        if (present(z) .and. nf == 3) ncols = 3
        first_line = lineno
      end if
      if (nf /= ncols) then
        if (ncols == 3) then
          expected = 'three values "x, y, z" (as on line ' // int_text(first_line) // ')'
        else if (present(z) .and. lineno == first_line) then
          expected = 'two values "x, y" or three "x, y, z"'
        else if (present(z)) then
          expected = 'two values "x, y" (as on line ' // int_text(first_line) // ')'
        else
          expected = 'two values "x, y"'
        end if
        errmsg = file_error(path, lineno, 'expected ' // expected // ', found ' // &
          int_text(nf) // ': ''' // line // '''', what)
        return
      end if
      v = 0.0_wp
      do f = 1, ncols
        if (.not. is_number(fields(f))) then
          errmsg = file_error(path, lineno, 'not a finite number: ''' // trim(fields(f)) // &
            ''' (expected ' // trim(merge('two numbers "x, y" [m]     ', &
            'three numbers "x, y, z" [m]', ncols == 2)) // ')', what)
          return
        end if
        read(fields(f), *, iostat=ios) v(f)
        if (ios /= 0 .or. .not. (abs(v(f)) <= huge(1.0_wp))) then
          errmsg = file_error(path, lineno, 'not a finite number: ''' // trim(fields(f)) // &
            '''', what)
          return
        end if
      end do
      n = n + 1
      if (n > size(x)) then
        allocate(tmp(2 * size(zz)))
        tmp(1:size(zz)) = zz
        call move_alloc(tmp, zz)
        call grow(x, y, lines)
      end if
      x(n) = v(1)
      y(n) = v(2)
      zz(n) = v(3)
      lines(n) = lineno
    end do
    x = x(1:n)
    y = y(1:n)
    lines = lines(1:n)
    if (present(z) .and. ncols == 3) z = zz(1:n)
    stat = 0
  end subroutine read_xy_file

  !> The height map of the points (x, y, z) read from `path`: rows of constant y in strictly
  !! increasing y, each row the same x values (at least 2, strictly increasing) in the same
  !! order as the first row; at least 2 rows.
  subroutine height_map_from_points(path, what, x, y, z, lines, map, stat, errmsg)
    character(len=*), intent(in) :: path                 !< CSV file
    character(len=*), intent(in) :: what                 !< variable that named it
    real(wp), intent(in) :: x(:), y(:), z(:)             !< points [m]
    integer, intent(in) :: lines(:)                      !< their line numbers
    type(height_map_t), intent(out) :: map               !< the map
    integer, intent(out) :: stat                         !< 0 ok, 1 input error
    character(len=:), allocatable, intent(out) :: errmsg !< error line
    character(len=*), parameter :: layout = ' (a height map lists rows of constant y, y ' // &
      'increasing, each with the x values of the first row)'
    integer :: n, nx, ny, r, c, i
    stat = 1
    errmsg = ''
    n = size(x)
    nx = 1
    do while (nx < n)
      if (y(nx + 1) /= y(1)) exit
      nx = nx + 1
    end do
    if (nx < 2 .or. n < 2 * nx) then
      errmsg = file_error(path, last_line(lines), 'a height map needs at least 2 rows of at ' // &
        'least 2 points, found ' // int_text(n) // ' points in rows of ' // int_text(nx) // &
        layout, what)
      return
    end if
    ny = (n + nx - 1) / nx
    do i = 1, n
      r = (i - 1) / nx
      c = i - r * nx
      if (r == 0 .and. c > 1) then
        if (.not. (x(i) > x(i - 1))) then
          errmsg = file_error(path, lines(i), 'x = ' // real_repr(x(i)) // ' is not greater ' &
            // 'than x = ' // real_repr(x(i - 1)) // ' on line ' // int_text(lines(i - 1)) // &
            layout, what)
          return
        end if
      else if (r > 0 .and. c == 1) then
        if (.not. (y(i) > y(i - nx))) then
          errmsg = file_error(path, lines(i), 'y = ' // real_repr(y(i)) // ' is not greater ' &
            // 'than y = ' // real_repr(y(i - nx)) // ' of the row before (line ' // &
            int_text(lines(i - nx)) // ')' // layout, what)
          return
        end if
      end if
      if (r > 0 .and. (x(i) /= x(c) .or. y(i) /= y(r * nx + 1))) then
        errmsg = file_error(path, lines(i), 'expected the point x = ' // real_repr(x(c)) // &
          ', y = ' // real_repr(y(r * nx + 1)) // ', found x = ' // real_repr(x(i)) // &
          ', y = ' // real_repr(y(i)) // layout, what)
        return
      end if
    end do
    if (n /= nx * ny) then
      errmsg = file_error(path, last_line(lines), 'the last row holds ' // &
        int_text(n - (ny - 1) * nx) // ' points, the first ' // int_text(nx) // layout, what)
      return
    end if
    map%x = x(1:nx)
    map%y = y(1:n:nx)
    map%z = reshape(z, [nx, ny])
    stat = 0
  end subroutine height_map_from_points

  !> Double the capacity of the vertex arrays, keeping their content.
  pure subroutine grow(x, y, lines)
    real(wp), allocatable, intent(inout) :: x(:), y(:)  !< vertices
    integer, allocatable, intent(inout) :: lines(:)     !< line numbers
    real(wp), allocatable :: tmp(:)
    integer, allocatable :: itmp(:)
    integer :: n
    n = size(x)
    allocate(tmp(2 * n))
    tmp(1:n) = x
    call move_alloc(tmp, x)
    allocate(tmp(2 * n))
    tmp(1:n) = y
    call move_alloc(tmp, y)
    allocate(itmp(2 * n))
    itmp(1:n) = lines
    call move_alloc(itmp, lines)
  end subroutine grow

  !> Check the vertices of a polygon read from `path` (drops a closing vertex equal to the
  !! first): at least 3 vertices, no vertex repeated next to itself, no self-intersection,
  !! a non-zero area.
  subroutine check_polygon_vertices(path, what, x, y, lines, stat, errmsg)
    character(len=*), intent(in) :: path                 !< CSV file
    character(len=*), intent(in) :: what                 !< variable that named it
    real(wp), allocatable, intent(inout) :: x(:), y(:)   !< vertices [m]
    integer, allocatable, intent(inout) :: lines(:)      !< their line numbers
    integer, intent(out) :: stat                         !< 0 ok, 1 input error
    character(len=:), allocatable, intent(out) :: errmsg !< error line
    integer :: n, i, a, b
    stat = 1
    errmsg = ''
    n = size(x)
    if (n >= 2) then
      if (x(n) == x(1) .and. y(n) == y(1)) then
        x = x(1:n - 1)
        y = y(1:n - 1)
        lines = lines(1:n - 1)
        n = n - 1
      end if
    end if
    if (n < 3) then
      errmsg = file_error(path, last_line(lines), 'a polygon needs at least 3 vertices, ' // &
        'found ' // int_text(n), what)
      return
    end if
    do i = 2, n
      if (x(i) == x(i - 1) .and. y(i) == y(i - 1)) then
        errmsg = file_error(path, lines(i), 'vertex repeats the one on line ' // &
          int_text(lines(i - 1)), what)
        return
      end if
    end do
    call polygon_crossing(x, y, a, b)
    if (a > 0) then
      errmsg = file_error(path, lines(b), 'the polygon intersects itself: the edge from ' // &
        'this line''s vertex crosses the edge from line ' // int_text(lines(a)), what)
      return
    end if
    if (.not. (abs(polygon_area(x, y)) > 0.0_wp)) then
      errmsg = file_error(path, last_line(lines), 'the polygon encloses no area', what)
      return
    end if
    stat = 0
  end subroutine check_polygon_vertices

  !> Check a profile y = f(x) read from `path`: at least 2 points, x strictly increasing.
  subroutine check_profile_points(path, what, x, lines, stat, errmsg)
    character(len=*), intent(in) :: path                 !< CSV file
    character(len=*), intent(in) :: what                 !< variable that named it
    real(wp), intent(in) :: x(:)                         !< abscissae [m]
    integer, intent(in) :: lines(:)                      !< their line numbers
    integer, intent(out) :: stat                         !< 0 ok, 1 input error
    character(len=:), allocatable, intent(out) :: errmsg !< error line
    integer :: i
    stat = 1
    errmsg = ''
    if (size(x) < 2) then
      errmsg = file_error(path, last_line(lines), 'a profile needs at least 2 points, ' // &
        'found ' // int_text(size(x)), what)
      return
    end if
    do i = 2, size(x)
      if (.not. (x(i) > x(i - 1))) then
        errmsg = file_error(path, lines(i), 'x = ' // real_repr(x(i)) // ' is not greater ' // &
          'than x = ' // real_repr(x(i - 1)) // ' on line ' // int_text(lines(i - 1)) // &
          ' (a profile needs x strictly increasing)', what)
        return
      end if
    end do
    stat = 0
  end subroutine check_profile_points

  !> The input-error line for file `path`, line `lineno` (0: none), ending with `what`.
  pure function file_error(path, lineno, problem, what) result(text)
    character(len=*), intent(in) :: path, problem, what
    integer, intent(in) :: lineno
    character(len=:), allocatable :: text
    text = 'mpmice: input error: ' // trim(path)
    if (lineno > 0) text = text // ': line ' // int_text(lineno)
    text = text // ': ' // problem // ' (' // trim(what) // ')'
  end function file_error

  !> Last line number in `lines` (0 when empty).
  pure integer function last_line(lines)
    integer, intent(in) :: lines(:)
    last_line = 0
    if (size(lines) > 0) last_line = lines(size(lines))
  end function last_line

  !> `s` with each separator (comma, semicolon, tab, carriage return) replaced by a blank.
  pure function replace_separators(s) result(t)
    character(len=*), intent(in) :: s
    character(len=len(s)) :: t
    integer :: i
    t = s
    do i = 1, len(t)
      if (t(i:i) == ',' .or. t(i:i) == ';' .or. t(i:i) == achar(9) .or. &
        t(i:i) == achar(13)) t(i:i) = ' '
    end do
  end function replace_separators

  !> Blank-separated fields of `line`: `nf` counts them all, the first `size(fields)` are
  !! stored.
  pure subroutine split_fields(line, fields, nf)
    character(len=*), intent(in) :: line
    character(len=*), intent(out) :: fields(:)
    integer, intent(out) :: nf
    integer :: i, start
    fields = ''
    nf = 0
    i = 1
    do while (i <= len(line))
      if (line(i:i) == ' ') then
        i = i + 1
        cycle
      end if
      start = i
      do while (i <= len(line))
        if (line(i:i) == ' ') exit
        i = i + 1
      end do
      nf = nf + 1
      if (nf <= size(fields)) fields(nf) = line(start:i - 1)
    end do
  end subroutine split_fields

  !> `s` is a decimal number: optional sign, digits with at most one point, optional exponent
  !! (e/E/d/D, optional sign, digits).
  pure logical function is_number(s)
    character(len=*), intent(in) :: s
    integer :: i, n, digits, exp_digits
    logical :: point, in_exp
    character :: c
    is_number = .false.
    n = len_trim(s)
    if (n == 0) return
    digits = 0
    exp_digits = 0
    point = .false.
    in_exp = .false.
    do i = 1, n
      c = s(i:i)
      if (c >= '0' .and. c <= '9') then
        if (in_exp) then
          exp_digits = exp_digits + 1
        else
          digits = digits + 1
        end if
      else if (c == '+' .or. c == '-') then
        if (i /= 1) then
          if (.not. in_exp .or. index('eEdD', s(i - 1:i - 1)) == 0) return
        end if
      else if (c == '.') then
        if (point .or. in_exp) return
        point = .true.
      else if (index('eEdD', c) > 0) then
        if (in_exp .or. digits == 0) return
        in_exp = .true.
      else
        return
      end if
    end do
    is_number = digits > 0 .and. (.not. in_exp .or. exp_digits > 0)
  end function is_number
end module config_geometry_csv
