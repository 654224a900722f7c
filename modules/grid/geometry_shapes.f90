!> Shapes read from files (docs/geometry.md): a closed polygon in the x-y plane of any number of
!! vertices, and the band between two profiles y = f(x) (bathymetry: the bed below a profile,
!! a layer between two profiles). Used by `&solid` seeding (`particles_seeding`) and `&region`
!! filling (`ice_initial`); the vertices are read by `config_geometry_files`.
!!
!! A polygon holds the points inside by the even-odd rule (a vertex list in either orientation,
!! closed implicitly from the last vertex back to the first). A profile band holds the points
!! (x, y) with x_1 <= x <= x_n of the profile(s) and lower(x) <= y <= upper(x), where upper is
!! the piecewise-linear interpolation of `profile_file` (+infinity without one) and lower that
!! of `profile_lower_file`, or `profile_lower_level` (-infinity when none is given: the band
!! reaches the domain bottom). With `layer_thickness` t > 0 and one profile the band is the
!! layer of thickness t (measured along y) below `profile_file` (lower = upper - t) or above
!! `profile_lower_file` (upper = lower + t). Outside the x range of a profile a point is
!! outside the band. Only x and y are tested: in 3D the shape is extruded along z. In 3D the
!! profiles may be height maps z = f(x, y) on a rectangular grid (bilinear between its
!! points): the band then holds the points with lower(x, y) <= z <= upper(x, y) inside the
!! maps' x-y rectangles, with the same choices of lower bound.
module geometry_shapes
  use mpmice_kinds, only: wp
  implicit none
  private

  public :: file_shape_t, shape_kind_none, shape_kind_polygon, shape_kind_profile
  public :: file_shape_contains, polygon_contains, profile_height, profile_band_contains
  public :: polygon_area, polygon_crossing, segments_intersect, level_unset
  public :: height_map_t, map_height, map_band_contains

  integer, parameter :: shape_kind_none = 0     !< no file shape (the inline shape applies)
  integer, parameter :: shape_kind_polygon = 1  !< closed polygon (x, y)
  integer, parameter :: shape_kind_profile = 2  !< band between profiles
  !> Value of an unset `profile_lower_level` (the band reaches the domain bottom).
  real(wp), parameter :: level_unset = -huge(1.0_wp)

  !> A height map z(x, y) on the grid x(1:nx) x y(1:ny) (both strictly increasing).
  type :: height_map_t
    real(wp), allocatable :: x(:)      !< grid x [m]
    real(wp), allocatable :: y(:)      !< grid y [m]
    real(wp), allocatable :: z(:, :)   !< heights (nx, ny) [m]
  end type height_map_t

  !> A shape read from files. Allocatable: any number of vertices.
  type :: file_shape_t
    integer :: kind = shape_kind_none             !< one of shape_kind_*
    real(wp), allocatable :: x(:)                 !< polygon or upper profile x [m]
    real(wp), allocatable :: y(:)                 !< polygon or upper profile y [m]
    real(wp), allocatable :: lower_x(:)           !< lower profile x [m] (may be empty)
    real(wp), allocatable :: lower_y(:)           !< lower profile y [m]
    real(wp) :: thickness = 0.0_wp                !< > 0: layer of that thickness [m]
    real(wp) :: lower_level = level_unset         !< constant lower bound [m]
    logical :: is_map = .false.                   !< profiles are height maps (3D band in z)
    type(height_map_t) :: upper_map               !< upper height map (z unallocated: none)
    type(height_map_t) :: lower_map               !< lower height map (z unallocated: none)
  end type file_shape_t

contains

  !> True when the x-y coordinates of `p` lie in `shape` (always true for `shape_kind_none`).
  pure logical function file_shape_contains(shape, p) result(inside)
    type(file_shape_t), intent(in) :: shape  !< shape
    real(wp), intent(in) :: p(:)             !< point (x, y, ...) [m]
    select case (shape%kind)
    case (shape_kind_polygon)
      inside = polygon_contains(shape%x, shape%y, p(1), p(2))
    case (shape_kind_profile)
      if (shape%is_map) then
        inside = map_band_contains(shape, p)
      else
        inside = profile_band_contains(shape, p(1), p(2))
      end if
    case default
      inside = .true.
    end select
  end function file_shape_contains

  !> Even-odd rule: (px, py) inside the closed polygon (x, y).
  pure logical function polygon_contains(x, y, px, py) result(inside)
    real(wp), intent(in) :: x(:), y(:)  !< vertices [m]
    real(wp), intent(in) :: px, py      !< point [m]
    integer :: i, j, n
    n = size(x)
    inside = .false.
    if (n < 3) return
    j = n
    do i = 1, n
      if ((y(i) > py) .neqv. (y(j) > py)) then
        if (px < (x(j) - x(i)) * (py - y(i)) / (y(j) - y(i)) + x(i)) inside = .not. inside
      end if
      j = i
    end do
  end function polygon_contains

  !> Height of the polyline (x, y) (x strictly increasing) at `px` by linear interpolation;
  !! `covered` false (and h = 0) when px lies outside [x(1), x(n)].
  pure subroutine profile_height(x, y, px, h, covered)
    real(wp), intent(in) :: x(:), y(:)  !< polyline [m]
    real(wp), intent(in) :: px          !< abscissa [m]
    real(wp), intent(out) :: h          !< height [m]
    logical, intent(out) :: covered     !< px within the polyline's x range
    integer :: lo
    real(wp) :: s
    h = 0.0_wp
    covered = size(x) >= 2
    if (.not. covered) return
    call bracket(x, px, lo, s, covered)    ! x(lo) <= px <= x(lo + 1)
    if (.not. covered) return
    h = y(lo) + s * (y(lo + 1) - y(lo))
  end subroutine profile_height

  !> (px, py) inside the profile band of `shape` (see the module description).
  pure logical function profile_band_contains(shape, px, py) result(inside)
    type(file_shape_t), intent(in) :: shape  !< shape of kind shape_kind_profile
    real(wp), intent(in) :: px, py           !< point [m]
    real(wp) :: top, bottom
    logical :: covered, has_upper
    inside = .false.
    has_upper = .false.
    if (allocated(shape%x)) has_upper = size(shape%x) >= 2
    top = huge(1.0_wp)
    if (has_upper) then
      call profile_height(shape%x, shape%y, px, top, covered)
      if (.not. covered) return
    end if
    bottom = shape%lower_level
    if (allocated(shape%lower_x)) then
      if (size(shape%lower_x) >= 2) then
        call profile_height(shape%lower_x, shape%lower_y, px, bottom, covered)
        if (.not. covered) return
      end if
    end if
    inside = in_band(shape%thickness, has_upper, top, bottom, py)
  end function profile_band_contains

  !> `z` between `bottom` and `top`; with `thickness` > 0 the band is a layer of that thickness on
  !! the one surface given (below the upper one when `has_upper`, else above the lower one).
  pure logical function in_band(thickness, has_upper, top, bottom, z) result(inside)
    real(wp), intent(in) :: thickness  !< layer thickness (<= 0: the band between both) [m]
    logical, intent(in) :: has_upper   !< an upper surface is given
    real(wp), intent(in) :: top        !< upper surface height [m]
    real(wp), intent(in) :: bottom     !< lower surface height [m]
    real(wp), intent(in) :: z          !< point height [m]
    real(wp) :: upper, lower
    upper = top
    lower = bottom
    if (thickness > 0.0_wp) then
      if (has_upper) then
        lower = top - thickness
      else
        upper = bottom + thickness
      end if
    end if
    inside = z <= upper .and. z >= lower
  end function in_band

  !> Height of `map` at (px, py) by bilinear interpolation; `covered` false (h = 0) outside
  !! its x-y rectangle.
  pure subroutine map_height(map, px, py, h, covered)
    type(height_map_t), intent(in) :: map  !< height map
    real(wp), intent(in) :: px, py         !< point [m]
    real(wp), intent(out) :: h             !< height [m]
    logical, intent(out) :: covered        !< inside the rectangle
    integer :: i, j
    real(wp) :: s, t
    h = 0.0_wp
    covered = .false.
    if (.not. allocated(map%z)) return
    if (size(map%x) < 2 .or. size(map%y) < 2) return
    call bracket(map%x, px, i, s, covered)
    if (.not. covered) return
    call bracket(map%y, py, j, t, covered)
    if (.not. covered) return
    h = (1.0_wp - s) * (1.0_wp - t) * map%z(i, j) + s * (1.0_wp - t) * map%z(i + 1, j) &
      + (1.0_wp - s) * t * map%z(i, j + 1) + s * t * map%z(i + 1, j + 1)
  end subroutine map_height

  !> Interval [g(i), g(i+1)] of the increasing grid `g` holding `v` and the fraction `s` of
  !! the way; `covered` false outside [g(1), g(n)].
  pure subroutine bracket(g, v, i, s, covered)
    real(wp), intent(in) :: g(:)    !< grid
    real(wp), intent(in) :: v       !< value
    integer, intent(out) :: i       !< interval
    real(wp), intent(out) :: s      !< fraction 0..1
    logical, intent(out) :: covered !< v within the grid
    integer :: hi, mid, n
    n = size(g)
    i = 1
    s = 0.0_wp
    covered = v >= g(1) .and. v <= g(n)
    if (.not. covered) return
    hi = n
    do while (hi - i > 1)
      mid = (i + hi) / 2
      if (g(mid) <= v) then
        i = mid
      else
        hi = mid
      end if
    end do
    s = (v - g(i)) / (g(i + 1) - g(i))
  end subroutine bracket

  !> `p` (x, y, z) inside the band between the height maps of `shape` (is_map).
  pure logical function map_band_contains(shape, p) result(inside)
    type(file_shape_t), intent(in) :: shape  !< shape of kind shape_kind_profile, is_map
    real(wp), intent(in) :: p(:)             !< point (x, y, z) [m]
    real(wp) :: top, bottom
    logical :: covered, has_upper
    inside = .false.
    has_upper = allocated(shape%upper_map%z)
    top = huge(1.0_wp)
    if (has_upper) then
      call map_height(shape%upper_map, p(1), p(2), top, covered)
      if (.not. covered) return
    end if
    bottom = shape%lower_level
    if (allocated(shape%lower_map%z)) then
      call map_height(shape%lower_map, p(1), p(2), bottom, covered)
      if (.not. covered) return
    end if
    inside = in_band(shape%thickness, has_upper, top, bottom, p(3))
  end function map_band_contains

  !> Signed area of the closed polygon (x, y) [m^2] (> 0: counter-clockwise).
  pure real(wp) function polygon_area(x, y) result(area)
    real(wp), intent(in) :: x(:), y(:)  !< vertices [m]
    integer :: n
    n = size(x)
    area = 0.0_wp
    if (n < 3) return
    area = 0.5_wp * sum(x * cshift(y, 1) - cshift(x, 1) * y)
  end function polygon_area

  !> True when the closed segments a1-a2 and b1-b2 share a point (touching and collinear
  !! overlap included).
  pure logical function segments_intersect(a1, a2, b1, b2) result(hit)
    real(wp), intent(in) :: a1(2), a2(2), b1(2), b2(2)  !< end points [m]
    real(wp) :: d1, d2, d3, d4
    d1 = orient(b1, b2, a1)
    d2 = orient(b1, b2, a2)
    d3 = orient(a1, a2, b1)
    d4 = orient(a1, a2, b2)
    if (((d1 > 0.0_wp .and. d2 < 0.0_wp) .or. (d1 < 0.0_wp .and. d2 > 0.0_wp)) .and. &
      ((d3 > 0.0_wp .and. d4 < 0.0_wp) .or. (d3 < 0.0_wp .and. d4 > 0.0_wp))) then
      hit = .true.
    else
      hit = (d1 == 0.0_wp .and. on_segment(b1, b2, a1)) .or. &
        (d2 == 0.0_wp .and. on_segment(b1, b2, a2)) .or. &
        (d3 == 0.0_wp .and. on_segment(a1, a2, b1)) .or. &
        (d4 == 0.0_wp .and. on_segment(a1, a2, b2))
    end if
  end function segments_intersect

  !> First pair of edges (i, j), i < j, of the closed polygon (x, y) that cross or touch
  !! other than at the vertex that adjacent edges share; edge i runs from vertex i to vertex
  !! i+1 (edge n back to vertex 1). Adjacent edges that fold back onto each other (collinear
  !! overlap) count as crossing. (0, 0) when the polygon is simple. O(n^2).
  pure subroutine polygon_crossing(x, y, i, j)
    real(wp), intent(in) :: x(:), y(:)  !< vertices [m]
    integer, intent(out) :: i, j        !< crossing edges, 0 if none
    integer :: n, a, b, a2, b2
    real(wp) :: pa1(2), pa2(2), pb1(2), pb2(2)
    n = size(x)
    i = 0
    j = 0
    do a = 1, n
      a2 = merge(1, a + 1, a == n)
      pa1 = [x(a), y(a)]
      pa2 = [x(a2), y(a2)]
      do b = a + 1, n
        b2 = merge(1, b + 1, b == n)
        pb1 = [x(b), y(b)]
        pb2 = [x(b2), y(b2)]
        if (b == a2 .or. b2 == a) then
          ! adjacent: they share one vertex; a fold back makes them overlap along a line
          if (.not. folds_back(pa1, pa2, pb1, pb2, b == a2)) cycle
        else if (.not. segments_intersect(pa1, pa2, pb1, pb2)) then
          cycle
        end if
        i = a
        j = b
        return
      end do
    end do
  end subroutine polygon_crossing

  !> Adjacent edges p1-p2 and q1-q2 (sharing p2 = q1 when `forward`, else q2 = p1) overlap
  !! along a line (the polygon folds back on itself).
  pure logical function folds_back(p1, p2, q1, q2, forward) result(folds)
    real(wp), intent(in) :: p1(2), p2(2), q1(2), q2(2)  !< end points [m]
    logical, intent(in) :: forward                      !< shared vertex is p2 = q1
    real(wp) :: u(2), v(2)
    if (forward) then
      u = p1 - p2
      v = q2 - q1
    else
      u = p2 - p1
      v = q1 - q2
    end if
    folds = u(1) * v(2) - u(2) * v(1) == 0.0_wp .and. sum(u * v) > 0.0_wp
  end function folds_back

  !> Twice the signed area of the triangle (a, b, c).
  pure real(wp) function orient(a, b, c)
    real(wp), intent(in) :: a(2), b(2), c(2)  !< points [m]
    orient = (b(1) - a(1)) * (c(2) - a(2)) - (b(2) - a(2)) * (c(1) - a(1))
  end function orient

  !> The point c, collinear with a-b, lies within the segment's bounding box.
  pure logical function on_segment(a, b, c)
    real(wp), intent(in) :: a(2), b(2), c(2)  !< points [m]
    on_segment = c(1) >= min(a(1), b(1)) .and. c(1) <= max(a(1), b(1)) .and. &
      c(2) >= min(a(2), b(2)) .and. c(2) <= max(a(2), b(2))
  end function on_segment
end module geometry_shapes
