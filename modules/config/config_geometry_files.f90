!> Geometry from files (docs/geometry.md): the CSV polygons and profiles that `&solid` and
!! `&region` name in `polygon_file`, `profile_file` and `profile_lower_file` (read and checked
!! by `config_geometry_csv`); the checks of these variables; the files' domain overlap.
!!
!! Relative paths are taken relative to the folder of the namelist file (of the checkpoint on
!! `--restart`) and stored absolute in the resolved configuration, so the echo, the used
!! namelist and a checkpoint name the file that was read; a restart reads the files again
!! from there. Rank 0 reads the files (`geometry_files_load`); `geometry_files_bcast` gives
!! every rank the vertices.
module config_geometry_files
  use, intrinsic :: iso_c_binding, only: c_char, c_size_t, c_ptr, c_associated, c_null_char
  use parallel_comm, only: MPI_Comm, comm_rank, bcast
  use mpmice_kinds, only: wp, path_len
  use mpmice_errors, only: int_text
  use config_types, only: config_t, grid_params_t
  use config_materials, only: solid_params_t, region_params_t
  use config_text, only: real_repr, quoted
  use config_check_tools, only: config_error_t, set_error, occurrence_label
  use geometry_shapes, only: file_shape_t, shape_kind_none, shape_kind_polygon, &
    shape_kind_profile, level_unset, height_map_t
  use config_geometry_csv, only: read_xy_file, check_polygon_vertices, check_profile_points, &
    file_error, height_map_from_points
  implicit none
  private

  public :: geometry_paths_resolve, geometry_check_variables, geometry_files_load
  public :: geometry_files_bcast, region_shape_names, absolute_path

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
          call set_error(err, occurrence_label('solid', k), 'npoints', int_text(s%npoints), &
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
        call load_shape(s%geometry, cfg%grid, '&' // occurrence_label('solid', k), s%shape, &
          s%polygon_file, s%profile_file, s%profile_lower_file, s%layer_thickness, &
          s%profile_lower_level, stat, errmsg)
      end associate
      if (stat /= 0) return
    end do
    do k = 1, cfg%nregions
      associate (r => cfg%regions(k))
        call load_shape(r%geometry, cfg%grid, '&' // occurrence_label('region', k), r%shape, &
          r%polygon_file, r%profile_file, r%profile_lower_file, r%layer_thickness, &
          r%profile_lower_level, stat, errmsg)
      end associate
      if (stat /= 0) return
    end do
  end subroutine geometry_files_load

  !> A file shape must reach into the domain: the polygon's bounding box overlaps it along x
  !! and y (active dimensions), a profile's x range overlaps it along x.
  subroutine check_overlap(grid, geo, polygon_file, profile_file, lower_file, g, stat, errmsg)
    type(grid_params_t), intent(in) :: grid
    type(file_shape_t), intent(in) :: geo
    character(len=*), intent(in) :: polygon_file, profile_file, lower_file, g
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    logical :: active(2)
    real(wp) :: lo(2), hi(2)
    character(len=:), allocatable :: domain
    stat = 0
    active = grid%ncells(1:2) > 1
    lo = grid%lower(1:2)
    hi = grid%upper(1:2)
    domain = ' lies outside the domain &grid lower = ' // real_repr(lo(1)) // ', ' // &
      real_repr(lo(2)) // ', upper = ' // real_repr(hi(1)) // ', ' // real_repr(hi(2)) // ' [m]'
    select case (geo%kind)
    case (shape_kind_polygon)
      if (any(active .and. ([maxval(geo%x), maxval(geo%y)] <= lo .or. &
        [minval(geo%x), minval(geo%y)] >= hi))) then
        stat = 1
        errmsg = file_error(trim(polygon_file), 0, 'the polygon (x ' // real_repr(minval(geo%x)) &
          // '..' // real_repr(maxval(geo%x)) // ', y ' // real_repr(minval(geo%y)) // '..' // &
          real_repr(maxval(geo%y)) // ')' // domain, g // ' polygon_file')
      end if
    case (shape_kind_profile)
      if (geo%is_map) then
        call check_map_overlap(grid, geo, profile_file, lower_file, g, stat, errmsg)
        return
      end if
      if (active(1) .and. size(geo%x) > 0) then
        if (geo%x(size(geo%x)) <= lo(1) .or. geo%x(1) >= hi(1)) then
          stat = 1
          errmsg = file_error(trim(profile_file), 0, 'the profile (x ' // real_repr(geo%x(1)) &
            // '..' // real_repr(geo%x(size(geo%x))) // ')' // domain, g // ' profile_file')
          return
        end if
      end if
      if (active(1) .and. size(geo%lower_x) > 0) then
        if (geo%lower_x(size(geo%lower_x)) <= lo(1) .or. geo%lower_x(1) >= hi(1)) then
          stat = 1
          errmsg = file_error(trim(lower_file), 0, 'the profile (x ' // &
            real_repr(geo%lower_x(1)) // '..' // real_repr(geo%lower_x(size(geo%lower_x))) // &
            ')' // domain, g // ' profile_lower_file')
        end if
      end if
    case default
      continue
    end select
  end subroutine check_overlap

  !> A height map needs an active z and must overlap the domain in x and y.
  subroutine check_map_overlap(grid, geo, profile_file, lower_file, g, stat, errmsg)
    type(grid_params_t), intent(in) :: grid
    type(file_shape_t), intent(in) :: geo
    character(len=*), intent(in) :: profile_file, lower_file, g
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    character(len=:), allocatable :: path, variable
    stat = 0
    if (allocated(geo%upper_map%z)) then
      call one(geo%upper_map, profile_file, 'profile_file')
      if (stat /= 0) return
    end if
    if (allocated(geo%lower_map%z)) call one(geo%lower_map, lower_file, 'profile_lower_file')
  contains
    subroutine one(map, file, name)
      type(height_map_t), intent(in) :: map
      character(len=*), intent(in) :: file, name
      logical :: active(2)
      path = trim(file)
      variable = g // ' ' // name
      if (grid%ncells(3) <= 1) then
        stat = 1
        errmsg = file_error(path, 0, 'a height map "x, y, z" needs a 3D grid (&grid ' // &
          'ncells(3) > 1); a 2D bed is a profile "x, y"', variable)
        return
      end if
      active = grid%ncells(1:2) > 1
      if (any(active .and. ([map%x(size(map%x)), map%y(size(map%y))] <= &
        grid%lower(1:2) .or. [map%x(1), map%y(1)] >= grid%upper(1:2)))) then
        stat = 1
        errmsg = file_error(path, 0, 'the height map (x ' // real_repr(map%x(1)) // '..' // &
          real_repr(map%x(size(map%x))) // ', y ' // real_repr(map%y(1)) // '..' // &
          real_repr(map%y(size(map%y))) // ') lies outside the domain &grid lower = ' // &
          real_repr(grid%lower(1)) // ', ' // real_repr(grid%lower(2)) // &
          ', upper = ' // real_repr(grid%upper(1)) // ', ' // &
          real_repr(grid%upper(2)) // ' [m]', variable)
      end if
    end subroutine one
  end subroutine check_map_overlap

  !> Read the files of one shape into `geo` and check that it reaches into the domain of `grid`
  !! (`check_overlap`).
  subroutine load_shape(geo, grid, g, shape, polygon_file, profile_file, lower_file, thickness, &
    lower_level, stat, errmsg)
    type(file_shape_t), intent(inout) :: geo
    type(grid_params_t), intent(in) :: grid
    character(len=*), intent(in) :: g, shape, polygon_file, profile_file, lower_file
    real(wp), intent(in) :: thickness, lower_level
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer, allocatable :: lines(:)
    logical :: has_map
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
        call read_profile(trim(profile_file), g // ' profile_file', geo%x, geo%y, &
          geo%upper_map, has_map, stat, errmsg)
        if (stat /= 0) return
        geo%is_map = has_map
      end if
      if (len_trim(lower_file) > 0) then
        call read_profile(trim(lower_file), g // ' profile_lower_file', geo%lower_x, &
          geo%lower_y, geo%lower_map, has_map, stat, errmsg)
        if (stat /= 0) return
        if (len_trim(profile_file) > 0 .and. (has_map .neqv. geo%is_map)) then
          stat = 1
          errmsg = file_error(trim(lower_file), 0, 'a ' // trim(merge('height map "x, y, z"', &
            'profile "x, y"      ', geo%is_map)) // ' like profile_file is needed', &
            g // ' profile_lower_file')
          return
        end if
        geo%is_map = has_map
      end if
      geo%thickness = thickness
      geo%lower_level = lower_level
      geo%kind = shape_kind_profile
    end if
    call check_overlap(grid, geo, polygon_file, profile_file, lower_file, g, stat, errmsg)
  end subroutine load_shape

  !> Read a profile "x, y" (into x, y; `has_map` false) or a height map "x, y, z" (into
  !! `map`; x, y left empty) from `path` and check it.
  subroutine read_profile(path, what, x, y, map, has_map, stat, errmsg)
    character(len=*), intent(in) :: path, what
    real(wp), allocatable, intent(inout) :: x(:), y(:)
    type(height_map_t), intent(inout) :: map
    logical, intent(out) :: has_map
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(wp), allocatable :: z(:)
    integer, allocatable :: lines(:)
    call read_xy_file(path, what, x, y, lines, stat, errmsg, z)
    has_map = .false.
    if (stat /= 0) return
    has_map = size(z) > 0
    if (has_map) then
      call height_map_from_points(path, what, x, y, z, lines, map, stat, errmsg)
      deallocate(x, y)
      allocate(x(0), y(0))
    else
      call check_profile_points(path, what, x, lines, stat, errmsg)
    end if
  end subroutine read_profile

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
    integer :: rank, n(4)
    real(wp) :: levels(2)
    rank = comm_rank(comm)
    n = 0
    if (rank == 0) then
      n(1) = geo%kind
      if (allocated(geo%x)) n(2) = size(geo%x)
      if (allocated(geo%lower_x)) n(3) = size(geo%lower_x)
      n(4) = merge(1, 0, geo%is_map)
      levels = [geo%thickness, geo%lower_level]
    end if
    call bcast(comm, n, 0)
    if (n(1) == shape_kind_none) return
    call bcast(comm, levels, 0)
    if (rank /= 0) then
      geo = file_shape_t()
      geo%kind = n(1)
      geo%thickness = levels(1)
      geo%lower_level = levels(2)
      geo%is_map = n(4) == 1
      allocate(geo%x(n(2)), geo%y(n(2)), geo%lower_x(n(3)), geo%lower_y(n(3)))
    end if
    if (geo%is_map) then
      call bcast_map(geo%upper_map, rank, comm)
      call bcast_map(geo%lower_map, rank, comm)
    end if
    if (n(2) > 0) then
      call bcast(comm, geo%x, 0)
      call bcast(comm, geo%y, 0)
    end if
    if (n(3) > 0) then
      call bcast(comm, geo%lower_x, 0)
      call bcast(comm, geo%lower_y, 0)
    end if
  end subroutine bcast_shape

  !> Broadcast one height map from rank 0 (z unallocated there: none).
  subroutine bcast_map(map, rank, comm)
    type(height_map_t), intent(inout) :: map
    integer, intent(in) :: rank
    type(MPI_Comm), intent(in) :: comm
    integer :: n(2)
    n = 0
    if (rank == 0 .and. allocated(map%z)) n = shape(map%z)
    call bcast(comm, n, 0)
    if (n(1) == 0) return
    if (rank /= 0) allocate(map%x(n(1)), map%y(n(2)), map%z(n(1), n(2)))
    call bcast(comm, map%x, 0)
    call bcast(comm, map%y, 0)
    call bcast(comm, map%z, 0)
  end subroutine bcast_map

end module config_geometry_files
