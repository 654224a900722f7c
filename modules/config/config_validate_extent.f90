!> Checks of where `&region` and `&solid` lie against the domain of `&grid`, and whether the
!! initial fluid volume fractions sum to one in every cell, done before anything is allocated.
!!
!! A cell belongs to a `&region` when its centre lies in [lower, upper] along every active
!! dimension (the rule of `ice_initial`). The fluid volume fractions of a cell depend only on
!! which regions contain it, and that pattern changes along dimension d only next to a region
!! bound; the sum is therefore checked on the cells next to each bound (and the first and last
!! cell) of every dimension and their products, at most (6 nregions + 2)^3 cells whatever the
!! grid size.
module config_validate_extent
  use mpmice_kinds, only: wp
  use config_types, only: config_t
  use config_text, only: real_repr, reals_repr, ints_repr
  use config_check_tools, only: config_error_t, set_error, occurrence_label
  implicit none
  private

  public :: check_extents, volume_fraction_tolerance

  real(wp), parameter :: volume_fraction_tolerance = 1.0e-6_wp !< |sum phi - 1| allowed

contains

  !> Regions and solids inside the domain; fluid fractions summing to one (scenes with fluids).
  subroutine check_extents(cfg, err)
    type(config_t), intent(in) :: cfg           !< configuration
    type(config_error_t), intent(inout) :: err  !< problem record
    call check_regions_inside(cfg, err)
    call check_solids_inside(cfg, err)
    if (cfg%run%scene == 'ice' .or. cfg%run%scene == 'mpmice') call check_fraction_sum(cfg, err)
  end subroutine check_extents

  !> Each `&region` contains at least one cell centre.
  subroutine check_regions_inside(cfg, err)
    type(config_t), intent(in) :: cfg           !< configuration
    type(config_error_t), intent(inout) :: err  !< problem record
    integer :: k, d, first, last
    do k = 1, cfg%nregions
      if (err%found) return
      associate (r => cfg%regions(k))
        do d = 1, 3
          if (cfg%grid%ncells(d) <= 1) cycle
          call cells_between(cfg, d, r%lower(d), r%upper(d), first, last)
          if (first > last) then
            call set_error(err, occurrence_label('region', k), 'upper', reals_repr(r%upper), &
              'a box (lower = ' // reals_repr(r%lower) // ') holding at least one cell centre ' &
              // 'of the domain &grid lower = ' // reals_repr(cfg%grid%lower) // ', upper = ' &
              // reals_repr(cfg%grid%upper) // ' [m]')
            return
          end if
        end do
      end associate
    end do
  end subroutine check_regions_inside

  !> Each `&solid` (box without rotation, or polygon) overlaps the domain along every active
  !! dimension; a half space or rotated box is not checked here.
  subroutine check_solids_inside(cfg, err)
    type(config_t), intent(in) :: cfg           !< configuration
    type(config_error_t), intent(inout) :: err  !< problem record
    real(wp) :: lo(3), hi(3)
    character(len=:), allocatable :: variable, value
    integer :: k, n
    do k = 1, cfg%nsolids
      if (err%found) return
      associate (s => cfg%solids(k))
        select case (s%shape)
        case ('box')
          if (s%rotation_deg /= 0.0_wp) cycle
          lo = s%lower
          hi = s%upper
          variable = 'upper'
          value = reals_repr(s%upper)
        case ('polygon')
          n = s%npoints
          if (n < 1) cycle
          lo = [minval(s%polygon_x(1:n)), minval(s%polygon_y(1:n)), cfg%grid%lower(3)]
          hi = [maxval(s%polygon_x(1:n)), maxval(s%polygon_y(1:n)), cfg%grid%upper(3)]
          variable = 'polygon_x'
          value = reals_repr(s%polygon_x(1:n))
        case default
          cycle
        end select
        if (any(cfg%grid%ncells > 1 .and. (hi <= cfg%grid%lower .or. lo >= cfg%grid%upper))) then
          call set_error(err, occurrence_label('solid', k), variable, value, 'a solid ' // &
            '(bounding box ' // reals_repr(lo) // ' to ' // reals_repr(hi) // ') overlapping ' &
            // 'the domain &grid lower = ' // reals_repr(cfg%grid%lower) // ', upper = ' // &
            reals_repr(cfg%grid%upper) // ' [m]')
        end if
      end associate
    end do
  end subroutine check_solids_inside

  !> The `&fluid` and `&region` volume fractions sum to one in every cell.
  subroutine check_fraction_sum(cfg, err)
    type(config_t), intent(in) :: cfg           !< configuration
    type(config_error_t), intent(inout) :: err  !< problem record
    integer, allocatable :: cand_x(:), cand_y(:), cand_z(:)
    integer :: a, b, c, idx(3), m, last_region
    real(wp) :: phi(cfg%nfluids), fsum
    if (err%found .or. cfg%nfluids < 1) return
    call candidates(cfg, 1, cand_x)
    call candidates(cfg, 2, cand_y)
    call candidates(cfg, 3, cand_z)
    do c = 1, size(cand_z)
      do b = 1, size(cand_y)
        do a = 1, size(cand_x)
          idx = [cand_x(a), cand_y(b), cand_z(c)]
          call cell_fractions(cfg, idx, phi, last_region)
          fsum = sum(phi)
          if (abs(fsum - 1.0_wp) <= volume_fraction_tolerance) cycle
          if (last_region > 0) then
            call set_error(err, occurrence_label('region', last_region), 'volume_fraction', &
              real_repr(cfg%regions(last_region)%volume_fraction), fraction_text(cfg, phi, &
              fsum, idx))
          else
            m = maxloc(phi, 1)
            call set_error(err, occurrence_label('fluid', m), 'volume_fraction', &
              real_repr(cfg%fluids(m)%volume_fraction), fraction_text(cfg, phi, fsum, idx))
          end if
          return
        end do
      end do
    end do
  end subroutine check_fraction_sum

  !> Allowed-range text of a bad fraction sum in cell `idx`.
  function fraction_text(cfg, phi, fsum, idx) result(text)
    type(config_t), intent(in) :: cfg  !< configuration
    real(wp), intent(in) :: phi(:)     !< fractions of the cell
    real(wp), intent(in) :: fsum       !< their sum
    integer, intent(in) :: idx(3)      !< cell index
    character(len=:), allocatable :: text
    text = 'fluid volume fractions summing to 1 in every cell (cell ' // ints_repr(idx) // &
      ' at x = ' // reals_repr(centre(cfg, idx)) // ' m has ' // reals_repr(phi) // &
      ', sum ' // real_repr(fsum) // ')'
  end function fraction_text

  !> Fractions of every fluid in cell `idx` (later regions win, as in `ice_initial`) and the
  !! last region that set one (0: none).
  subroutine cell_fractions(cfg, idx, phi, last_region)
    type(config_t), intent(in) :: cfg     !< configuration
    integer, intent(in) :: idx(3)         !< cell index
    real(wp), intent(out) :: phi(:)       !< fractions
    integer, intent(out) :: last_region   !< last region applied
    integer :: m, r
    real(wp) :: x(3)
    logical :: active(3)
    x = centre(cfg, idx)
    active = cfg%grid%ncells > 1
    last_region = 0
    do m = 1, cfg%nfluids
      phi(m) = cfg%fluids(m)%volume_fraction
      do r = 1, cfg%nregions
        if (cfg%regions(r)%material /= cfg%fluids(m)%name) cycle
        if (all(x >= cfg%regions(r)%lower .and. x <= cfg%regions(r)%upper .or. &
          .not. active)) then
          phi(m) = cfg%regions(r)%volume_fraction
          last_region = max(last_region, r)
        end if
      end do
    end do
  end subroutine cell_fractions

  !> Centre of global cell `idx` [m].
  pure function centre(cfg, idx) result(x)
    type(config_t), intent(in) :: cfg  !< configuration
    integer, intent(in) :: idx(3)      !< cell index
    real(wp) :: x(3)
    x = cfg%grid%lower + (real(idx, wp) - 0.5_wp) * (cfg%grid%upper - cfg%grid%lower) / &
      real(cfg%grid%ncells, wp)
  end function centre

  !> Cells of dimension `d` next to which the region pattern may change.
  subroutine candidates(cfg, d, cand)
    type(config_t), intent(in) :: cfg           !< configuration
    integer, intent(in) :: d                    !< dimension
    integer, allocatable, intent(out) :: cand(:)
    integer :: r, n, i, first, last, list(6 * cfg%nregions + 2), count
    n = cfg%grid%ncells(d)
    count = 2
    list(1) = 1
    list(2) = n
    if (n > 1) then
      do r = 1, cfg%nregions
        call cells_between(cfg, d, cfg%regions(r)%lower(d), cfg%regions(r)%upper(d), first, last)
        list(count + 1:count + 3) = [first - 1, first, first + 1]
        list(count + 4:count + 6) = [last - 1, last, last + 1]
        count = count + 6
      end do
    end if
    list(1:count) = min(max(list(1:count), 1), n)
    cand = pack(list(1:count), [(all(list(1:i - 1) /= list(i)), i = 1, count)])
  end subroutine candidates

  !> The cells of dimension `d` whose centres lie in [`lower`, `upper`]: `first` to `last`
  !! (none when `first > last`). A centre that lies on a bound counts as inside.
  pure subroutine cells_between(cfg, d, lower, upper, first, last)
    type(config_t), intent(in) :: cfg  !< configuration
    integer, intent(in) :: d           !< dimension
    real(wp), intent(in) :: lower      !< low bound [m]
    real(wp), intent(in) :: upper      !< high bound [m]
    integer, intent(out) :: first      !< first cell whose centre is >= lower (ncells + 1: none)
    integer, intent(out) :: last       !< last cell whose centre is <= upper (0: none)
    real(wp) :: h, s
    integer :: n
    n = cfg%grid%ncells(d)
    call cell_coordinate(cfg, d, lower, h, s)
    first = max(1, ceiling(s))
    call cell_coordinate(cfg, d, upper, h, s)
    last = min(n, floor(s))
    ! s is rounded: the centre next to each end may still lie on the bound
    if (first > 1) then
      if (cell_centre(cfg, d, first - 1, h) >= lower) first = first - 1
    end if
    if (last < n) then
      if (cell_centre(cfg, d, last + 1, h) <= upper) last = last + 1
    end if
  end subroutine cells_between

  !> Centre of cell `i` of dimension `d` of cell width `h` [m].
  pure real(wp) function cell_centre(cfg, d, i, h)
    type(config_t), intent(in) :: cfg  !< configuration
    integer, intent(in) :: d           !< dimension
    integer, intent(in) :: i           !< cell index
    real(wp), intent(in) :: h          !< cell width [m]
    cell_centre = cfg%grid%lower(d) + (real(i, wp) - 0.5_wp) * h
  end function cell_centre

  !> Cell width `h` of dimension `d` and the position of bound `b` in cells, `s` = (b - lower)/h
  !! + 1/2 (cell i has its centre at s = i), clamped to [0, ncells + 1].
  pure subroutine cell_coordinate(cfg, d, b, h, s)
    type(config_t), intent(in) :: cfg  !< configuration
    integer, intent(in) :: d           !< dimension
    real(wp), intent(in) :: b          !< bound [m]
    real(wp), intent(out) :: h         !< cell width [m]
    real(wp), intent(out) :: s         !< bound in cell units
    h = (cfg%grid%upper(d) - cfg%grid%lower(d)) / real(cfg%grid%ncells(d), wp)
    s = (b - cfg%grid%lower(d)) / h + 0.5_wp
    s = min(max(s, 0.0_wp), real(cfg%grid%ncells(d) + 1, wp))
  end subroutine cell_coordinate
end module config_validate_extent
