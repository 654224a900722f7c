!> Geometry from files (docs/geometry.md): the CSV polygons and profiles that `&solid` and
!! `&region` name in `polygon_file`, `profile_file` and `profile_lower_file`.
!!
!! A CSV file holds one vertex "x, y" [m] per line (comma, semicolon, tab or blank separated);
!! blank lines and lines starting with `#` are skipped, and a first non-comment line that
!! does not start with a number is a header. Every other line must hold exactly two finite
!! numbers. A polygon needs at least 3 distinct vertices, is closed implicitly (a last vertex
!! equal to the first is dropped), must not intersect itself and must enclose a non-zero area;
!! a profile needs at least 2 points with x strictly increasing. Any problem is one input-error
!! line naming the file, the line and what is wrong.
!!
!! Relative paths are taken relative to the folder of the namelist file (of the checkpoint on
!! `--restart`) and stored absolute in the resolved configuration, so the echo, the used
!! namelist and a checkpoint name the file that was read; a restart reads the files again
!! from there. Rank 0 reads the files (`geometry_files_load`); `geometry_files_bcast` gives
!! every rank the vertices.
module config_geometry_files
  use, intrinsic :: iso_c_binding, only: c_char, c_size_t, c_ptr, c_associated, c_null_char
  use mpi_f08, only: MPI_Comm, MPI_Comm_rank, MPI_Bcast, MPI_INTEGER, MPI_DOUBLE_PRECISION
  use mpmice_kinds, only: wp, path_len, msg_len
  use config_types, only: config_t
  use config_materials, only: solid_params_t, region_params_t
  use config_text, only: real_repr, quoted
  use config_check_tools, only: config_error_t, set_error, occurrence_label
  use geometry_shapes, only: file_shape_t, shape_kind_none, shape_kind_polygon, &
    shape_kind_profile, polygon_area, polygon_crossing, level_unset
  implicit none
  private

  public :: read_xy_file, check_polygon_vertices, check_profile_points
  public :: geometry_paths_resolve, geometry_check_variables, geometry_files_load
  public :: geometry_files_bcast, region_shape_names, absolute_path

  integer, parameter :: field_len = 256  !< longest CSV field kept (longer ones are cut)
  integer, parameter :: max_fields = 8   !< CSV fields kept per line (more are counted)
  !> Allowed values of `&region shape`.
  character(len=*), parameter :: region_shape_names(3) = [character(len=8) :: &
    'box', 'polygon', 'profile']

  interface
    !> POSIX getcwd(3).
    function c_getcwd(buf, size) bind(C, name='getcwd') result(p)
      import :: c_char, c_size_t, c_ptr
      character(kind=c_char), intent(out) :: buf(*)
      integer(c_size_t), value :: size
      type(c_ptr) :: p
    end function c_getcwd
  end interface

contains

  !> Read the CSV file `path` of vertices "x, y". `lines(i)` is the line of vertex i. On a
  !! problem `stat` = 1 and `errmsg` is the input-error line ending with `what` (the variable
  !! that named the file).
  subroutine read_xy_file(path, what, x, y, lines, stat, errmsg)
    character(len=*), intent(in) :: path                 !< CSV file
    character(len=*), intent(in) :: what                 !< e.g. "&solid 'bed' profile_file"
    real(wp), allocatable, intent(out) :: x(:), y(:)     !< vertices [m]
    integer, allocatable, intent(out) :: lines(:)        !< line number of each vertex
    integer, intent(out) :: stat                         !< 0 ok, 1 input error
    character(len=:), allocatable, intent(out) :: errmsg !< error line
    character(len=:), allocatable :: text, line
    character(len=field_len) :: fields(max_fields)
    character(len=msg_len) :: iomsg
    integer :: unit, ios, nbytes, start, finish, lineno, n, nf
    logical :: exists, seen_data
    real(wp) :: v(2)

    stat = 1
    errmsg = ''
    allocate(x(0), y(0), lines(0))
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
      if (nf /= 2) then
        errmsg = file_error(path, lineno, 'expected two values "x, y", found ' // &
          int_str(nf) // ': ''' // line // '''', what)
        return
      end if
      do n = 1, 2
        if (.not. is_number(fields(n))) then
          errmsg = file_error(path, lineno, 'not a finite number: ''' // trim(fields(n)) // &
            ''' (expected two numbers "x, y" [m])', what)
          return
        end if
        read(fields(n), *, iostat=ios) v(n)
        if (ios /= 0 .or. .not. (abs(v(n)) <= huge(1.0_wp))) then
          errmsg = file_error(path, lineno, 'not a finite number: ''' // trim(fields(n)) // &
            '''', what)
          return
        end if
      end do
      x = [x, v(1)]
      y = [y, v(2)]
      lines = [lines, lineno]
    end do
    stat = 0
  end subroutine read_xy_file

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
        'found ' // int_str(n), what)
      return
    end if
    do i = 2, n
      if (x(i) == x(i - 1) .and. y(i) == y(i - 1)) then
        errmsg = file_error(path, lines(i), 'vertex repeats the one on line ' // &
          int_str(lines(i - 1)), what)
        return
      end if
    end do
    call polygon_crossing(x, y, a, b)
    if (a > 0) then
      errmsg = file_error(path, lines(b), 'the polygon intersects itself: the edge from ' // &
        'this line''s vertex crosses the edge from line ' // int_str(lines(a)), what)
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
        'found ' // int_str(size(x)), what)
      return
    end if
    do i = 2, size(x)
      if (.not. (x(i) > x(i - 1))) then
        errmsg = file_error(path, lines(i), 'x = ' // real_repr(x(i)) // ' is not greater ' // &
          'than x = ' // real_repr(x(i - 1)) // ' on line ' // int_str(lines(i - 1)) // &
          ' (a profile needs x strictly increasing)', what)
        return
      end if
    end do
    stat = 0
  end subroutine check_profile_points

  !> Make the geometry file names of `cfg` absolute: a relative name is taken relative to the
  !! folder of `source` (the namelist file).
  subroutine geometry_paths_resolve(cfg, source)
    type(config_t), intent(inout) :: cfg   !< configuration
    character(len=*), intent(in) :: source !< namelist file (or checkpoint)
    character(len=:), allocatable :: folder
    integer :: k, slash
    slash = index(source, '/', back=.true.)
    folder = '.'
    if (slash > 1) folder = source(1:slash - 1)
    if (slash == 1) folder = ''
    if (len(folder) == 0 .or. folder(1:1) /= '/') folder = current_folder() // '/' // folder
    do k = 1, cfg%nsolids
      call resolve(cfg%solids(k)%polygon_file)
      call resolve(cfg%solids(k)%profile_file)
      call resolve(cfg%solids(k)%profile_lower_file)
    end do
    do k = 1, cfg%nregions
      call resolve(cfg%regions(k)%polygon_file)
      call resolve(cfg%regions(k)%profile_file)
      call resolve(cfg%regions(k)%profile_lower_file)
    end do
  contains
    subroutine resolve(name)
      character(len=path_len), intent(inout) :: name
      name = absolute_path(name, folder)
    end subroutine resolve
  end subroutine geometry_paths_resolve

  !> `name` unchanged when empty or absolute, else `folder`/`name` with "./" removed.
  pure function absolute_path(name, folder) result(path)
    character(len=*), intent(in) :: name    !< file name
    character(len=*), intent(in) :: folder  !< folder it is relative to
    character(len=:), allocatable :: path
    character(len=:), allocatable :: rest, base
    path = trim(adjustl(name))
    if (len(path) == 0) return
    if (path(1:1) == '/') return
    rest = path
    do while (len(rest) > 2)
      if (rest(1:2) /= './') exit
      rest = rest(3:)
    end do
    base = trim(folder)
    do while (len(base) > 2)
      if (base(len(base) - 1:) /= '/.') exit
      base = base(1:len(base) - 2)
    end do
    if (len(base) > 0) then
      if (base(len(base):) == '/') base = base(1:len(base) - 1)
    end if
    path = base // '/' // rest
  end function absolute_path

  !> The current working folder ('.' if it cannot be found).
  function current_folder() result(folder)
    character(len=:), allocatable :: folder
    character(kind=c_char) :: buf(4096)
    integer :: i
    folder = '.'
    if (.not. c_associated(c_getcwd(buf, int(size(buf), c_size_t)))) return
    folder = ''
    do i = 1, size(buf)
      if (buf(i) == c_null_char) exit
      folder = folder // buf(i)
    end do
  end function current_folder

  !> Checks of the geometry-file variables of `&solid` and `&region` (not the files).
  subroutine geometry_check_variables(cfg, err)
    type(config_t), intent(in) :: cfg           !< configuration
    type(config_error_t), intent(inout) :: err  !< problem record
    integer :: k
    do k = 1, cfg%nsolids
      if (err%found) return
      associate (s => cfg%solids(k))
        if (trim(s%shape) == 'polygon' .and. len_trim(s%polygon_file) > 0 .and. &
          s%npoints /= 0) then
          call set_error(err, occurrence_label('solid', k), 'npoints', int_str(s%npoints), &
            '0 with polygon_file (the vertices come either inline or from the file)')
          return
        end if
        call check_shape_variables(occurrence_label('solid', k), s%shape, s%polygon_file, &
          s%profile_file, s%profile_lower_file, s%layer_thickness, s%profile_lower_level, &
          .false., err)
      end associate
    end do
    do k = 1, cfg%nregions
      if (err%found) return
      associate (r => cfg%regions(k))
        if (all(region_shape_names /= r%shape)) then
          call set_error(err, occurrence_label('region', k), 'shape', '''' // trim(r%shape) // &
            '''', 'one of ''box'', ''polygon'', ''profile''')
          return
        end if
        call check_shape_variables(occurrence_label('region', k), r%shape, r%polygon_file, &
          r%profile_file, r%profile_lower_file, r%layer_thickness, r%profile_lower_level, &
          .true., err)
      end associate
    end do
  end subroutine geometry_check_variables

  !> The file variables fit `shape`: polygon_file only with 'polygon' (and required for a
  !! region); profile variables only with 'profile', at least one profile file, at most one
  !! way to give the lower bound.
  subroutine check_shape_variables(g, shape, polygon_file, profile_file, lower_file, &
    thickness, lower_level, is_region, err)
    character(len=*), intent(in) :: g, shape, polygon_file, profile_file, lower_file
    real(wp), intent(in) :: thickness, lower_level
    logical, intent(in) :: is_region
    type(config_error_t), intent(inout) :: err
    logical :: has_level
    has_level = lower_level /= level_unset
    if (trim(shape) /= 'polygon' .and. len_trim(polygon_file) > 0) then
      call set_error(err, g, 'polygon_file', quoted(polygon_file), 'only with shape = ''polygon''')
    else if (trim(shape) == 'polygon' .and. is_region .and. len_trim(polygon_file) == 0) then
      call set_error(err, g, 'polygon_file', '''''', 'a CSV file of vertices for shape = ' // &
        '''polygon''')
    else if (trim(shape) /= 'profile' .and. (len_trim(profile_file) > 0 .or. &
      len_trim(lower_file) > 0 .or. thickness /= 0.0_wp .or. has_level)) then
      call set_error(err, g, 'shape', quoted(shape), '''profile'' when profile_file, ' // &
        'profile_lower_file, layer_thickness or profile_lower_level is given')
    else if (trim(shape) == 'profile') then
      if (len_trim(profile_file) == 0 .and. len_trim(lower_file) == 0) then
        call set_error(err, g, 'profile_file', '''''', 'a CSV profile (profile_file and/or ' // &
          'profile_lower_file) for shape = ''profile''')
      else if (.not. (thickness >= 0.0_wp .and. thickness <= huge(1.0_wp))) then
        call set_error(err, g, 'layer_thickness', real_repr(thickness), '>= 0 [m]')
      else if (thickness > 0.0_wp .and. (len_trim(profile_file) > 0 .eqv. &
        len_trim(lower_file) > 0)) then
        call set_error(err, g, 'layer_thickness', real_repr(thickness), '0, or > 0 with ' // &
          'exactly one of profile_file (layer below it) and profile_lower_file (layer above it)')
      else if (has_level .and. (thickness > 0.0_wp .or. len_trim(lower_file) > 0 .or. &
        len_trim(profile_file) == 0)) then
        call set_error(err, g, 'profile_lower_level', real_repr(lower_level), 'only with ' // &
          'profile_file and without profile_lower_file or layer_thickness [m]')
      else if (has_level .and. .not. (abs(lower_level) <= huge(1.0_wp))) then
        call set_error(err, g, 'profile_lower_level', real_repr(lower_level), 'finite [m]')
      end if
    end if
  end subroutine check_shape_variables

  !> Rank 0: read and check every geometry file of `cfg` and store the shapes in it.
  subroutine geometry_files_load(cfg, stat, errmsg)
    type(config_t), intent(inout) :: cfg                 !< configuration (validated)
    integer, intent(out) :: stat                         !< 0 ok, 1 input error
    character(len=:), allocatable, intent(out) :: errmsg !< error line
    integer :: k
    stat = 0
    errmsg = ''
    do k = 1, cfg%nsolids
      associate (s => cfg%solids(k))
        call load_shape(s%geometry, '&' // occurrence_label('solid', k), s%shape, &
          s%polygon_file, s%profile_file, s%profile_lower_file, s%layer_thickness, &
          s%profile_lower_level, stat, errmsg)
      end associate
      if (stat /= 0) return
    end do
    do k = 1, cfg%nregions
      associate (r => cfg%regions(k))
        call load_shape(r%geometry, '&' // occurrence_label('region', k), r%shape, &
          r%polygon_file, r%profile_file, r%profile_lower_file, r%layer_thickness, &
          r%profile_lower_level, stat, errmsg)
      end associate
      if (stat /= 0) return
    end do
  end subroutine geometry_files_load

  !> Read the files of one shape into `geo`.
  subroutine load_shape(geo, g, shape, polygon_file, profile_file, lower_file, thickness, &
    lower_level, stat, errmsg)
    type(file_shape_t), intent(inout) :: geo
    character(len=*), intent(in) :: g, shape, polygon_file, profile_file, lower_file
    real(wp), intent(in) :: thickness, lower_level
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer, allocatable :: lines(:)
    geo = file_shape_t()
    stat = 0
    errmsg = ''
    if (trim(shape) == 'polygon' .and. len_trim(polygon_file) > 0) then
      call read_xy_file(trim(polygon_file), g // ' polygon_file', geo%x, geo%y, lines, &
        stat, errmsg)
      if (stat /= 0) return
      call check_polygon_vertices(trim(polygon_file), g // ' polygon_file', geo%x, geo%y, &
        lines, stat, errmsg)
      if (stat /= 0) return
      geo%kind = shape_kind_polygon
    else if (trim(shape) == 'profile') then
      allocate(geo%x(0), geo%y(0), geo%lower_x(0), geo%lower_y(0))
      if (len_trim(profile_file) > 0) then
        call read_xy_file(trim(profile_file), g // ' profile_file', geo%x, geo%y, lines, &
          stat, errmsg)
        if (stat /= 0) return
        call check_profile_points(trim(profile_file), g // ' profile_file', geo%x, lines, &
          stat, errmsg)
        if (stat /= 0) return
      end if
      if (len_trim(lower_file) > 0) then
        call read_xy_file(trim(lower_file), g // ' profile_lower_file', geo%lower_x, &
          geo%lower_y, lines, stat, errmsg)
        if (stat /= 0) return
        call check_profile_points(trim(lower_file), g // ' profile_lower_file', geo%lower_x, &
          lines, stat, errmsg)
        if (stat /= 0) return
      end if
      geo%thickness = thickness
      geo%lower_level = lower_level
      geo%kind = shape_kind_profile
    end if
  end subroutine load_shape

  !> Give every rank of `comm` rank 0's file shapes of `cfg` (collective; the other
  !! parameters must already agree).
  subroutine geometry_files_bcast(cfg, comm)
    type(config_t), intent(inout) :: cfg  !< configuration (shapes significant on rank 0)
    type(MPI_Comm), intent(in) :: comm    !< communicator
    integer :: k
    do k = 1, cfg%nsolids
      call bcast_shape(cfg%solids(k)%geometry, comm)
    end do
    do k = 1, cfg%nregions
      call bcast_shape(cfg%regions(k)%geometry, comm)
    end do
  end subroutine geometry_files_bcast

  !> Broadcast one shape from rank 0.
  subroutine bcast_shape(geo, comm)
    type(file_shape_t), intent(inout) :: geo
    type(MPI_Comm), intent(in) :: comm
    integer :: rank, n(3)
    real(wp) :: levels(2)
    call MPI_Comm_rank(comm, rank)
    n = 0
    if (rank == 0) then
      n(1) = geo%kind
      if (allocated(geo%x)) n(2) = size(geo%x)
      if (allocated(geo%lower_x)) n(3) = size(geo%lower_x)
      levels = [geo%thickness, geo%lower_level]
    end if
    call MPI_Bcast(n, 3, MPI_INTEGER, 0, comm)
    if (n(1) == shape_kind_none) return
    call MPI_Bcast(levels, 2, MPI_DOUBLE_PRECISION, 0, comm)
    if (rank /= 0) then
      geo = file_shape_t()
      geo%kind = n(1)
      geo%thickness = levels(1)
      geo%lower_level = levels(2)
      allocate(geo%x(n(2)), geo%y(n(2)), geo%lower_x(n(3)), geo%lower_y(n(3)))
    end if
    if (n(2) > 0) then
      call MPI_Bcast(geo%x, n(2), MPI_DOUBLE_PRECISION, 0, comm)
      call MPI_Bcast(geo%y, n(2), MPI_DOUBLE_PRECISION, 0, comm)
    end if
    if (n(3) > 0) then
      call MPI_Bcast(geo%lower_x, n(3), MPI_DOUBLE_PRECISION, 0, comm)
      call MPI_Bcast(geo%lower_y, n(3), MPI_DOUBLE_PRECISION, 0, comm)
    end if
  end subroutine bcast_shape

  !> The input-error line for file `path`, line `lineno` (0: none), ending with `what`.
  pure function file_error(path, lineno, problem, what) result(text)
    character(len=*), intent(in) :: path, problem, what
    integer, intent(in) :: lineno
    character(len=:), allocatable :: text
    text = 'mpmice: input error: ' // trim(path)
    if (lineno > 0) text = text // ': line ' // int_str(lineno)
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

  !> Integer as text.
  pure function int_str(i) result(text)
    integer, intent(in) :: i
    character(len=:), allocatable :: text
    character(len=16) :: buffer
    write(buffer, '(i0)') i
    text = trim(buffer)
  end function int_str
end module config_geometry_files
