!> The nodes a particle interacts with and their 1-D weights per dimension (tensor-product shape
!! functions S_ip = S_x S_y S_z, gradient (S_x' S_y S_z, S_x S_y' S_z, S_x S_y S_z')).
!!
!! Linear: the 2 nodes of the particle's cell. GIMP: the 3 nodes around the nearest node (the
!! support |x_p - x_i| < h + l_p never reaches a fourth node when l_p <= h/2). Inactive dimensions
!! have one node (index 1) with weight 1 and zero derivative. Nodes may lie one layer outside the
!! owned range; node fields need a ghost width of at least 1. Nodes beyond a non-periodic wall get
!! weight 0 (only a GIMP particle closer than l_p to the wall reaches one).
module mpm_shape
  use mpmice_kinds, only: wp
  use grid_layout, only: grid_t
  use mpm_shape_linear, only: linear_1d
  use mpm_shape_gimp, only: gimp_1d
  implicit none
  private

  public :: shape_linear, shape_gimp, max_stencil, shape_kind_from_name, particle_stencil
  public :: node_offsets, nearest_integer

  integer, parameter :: shape_linear = 1   !< linear (tent) functions
  integer, parameter :: shape_gimp = 2     !< uGIMP functions
  integer, parameter :: max_stencil = 3    !< most nodes per dimension

contains

  !> Shape kind of a `&numerics shape_function` value ('linear' or 'gimp'; anything else: gimp).
  pure integer function shape_kind_from_name(name) result(kind)
    character(len=*), intent(in) :: name  !< namelist value
    if (trim(name) == 'linear') then
      kind = shape_linear
    else
      kind = shape_gimp
    end if
  end function shape_kind_from_name

  !> Nodes and 1-D weights of a particle at `xp` with half-width `lp`.
  pure subroutine particle_stencil(kind, grid, xp, lp, first, nn, w, dw)
    integer, intent(in) :: kind                      !< shape_linear or shape_gimp
    type(grid_t), intent(in) :: grid                 !< block geometry
    real(wp), intent(in) :: xp(3)                    !< particle position [m]
    real(wp), intent(in) :: lp(3)                    !< particle half-width [m]
    integer, intent(out) :: first(3)                 !< global index of the first node
    integer, intent(out) :: nn(3)                    !< nodes per dimension
    real(wp), intent(out) :: w(max_stencil, 3)       !< weights [-]
    real(wp), intent(out) :: dw(max_stencil, 3)      !< derivatives [1/m]
    integer :: d, a
    real(wp) :: s, h, r
    w = 0.0_wp
    dw = 0.0_wp
    do d = 1, 3
      if (.not. grid%active(d)) then
        first(d) = 1
        nn(d) = 1
        w(1, d) = 1.0_wp
        cycle
      end if
      h = grid%dx(d)
      s = (xp(d) - grid%lower(d)) / h
      if (kind == shape_linear) then
        first(d) = floor(s) + 1
        nn(d) = 2
        do a = 1, 2
          r = xp(d) - (grid%lower(d) + real(first(d) + a - 2, wp) * h)
          call linear_1d(r, h, w(a, d), dw(a, d))
        end do
      else
        first(d) = nearest_integer(s)
        nn(d) = 3
        do a = 1, 3
          r = xp(d) - (grid%lower(d) + real(first(d) + a - 2, wp) * h)
          call gimp_1d(r, h, lp(d), w(a, d), dw(a, d))
        end do
      end if
      ! nodes beyond a wall take no part (a particle closer than l_p to the wall would reach
      ! them; the reverse halo does not sum such locations, so keeping them would make the
      ! result depend on the decomposition); most stencils lie inside, one test for them
      if (.not. grid%periodic(d) .and. (first(d) < 1 .or. &
        first(d) + nn(d) - 1 > grid%ncells(d) + 1)) then
        do a = 1, nn(d)
          if (first(d) + a - 1 < 1 .or. first(d) + a - 1 > grid%ncells(d) + 1) then
            w(a, d) = 0.0_wp
            dw(a, d) = 0.0_wp
          end if
        end do
      end if
    end do
  end subroutine particle_stencil

  !> nint(s) (the nearest integer, halves away from zero) without the library call of nint:
  !! s - int(s) is exact, so the test of the fraction against 1/2 is too.
  pure integer function nearest_integer(s) result(n)
    real(wp), intent(in) :: s   !< value, |s| < huge(n)
    real(wp) :: frac
    n = int(s)
    frac = s - real(n, wp)
    if (frac >= 0.5_wp) then
      n = n + 1
    else if (frac <= -0.5_wp) then
      n = n - 1
    end if
  end function nearest_integer

  !> Node-minus-particle offsets x_i - x_p [m] of a particle's stencil, per dimension (0 in an
  !! inactive dimension).
  pure subroutine node_offsets(grid, xp, first, nn, off)
    type(grid_t), intent(in) :: grid                 !< block geometry
    real(wp), intent(in) :: xp(3)                    !< particle position [m]
    integer, intent(in) :: first(3)                  !< global index of the first node
    integer, intent(in) :: nn(3)                     !< nodes per dimension
    real(wp), intent(out) :: off(max_stencil, 3)     !< offsets [m]
    integer :: d, a
    off = 0.0_wp
    do d = 1, 3
      if (.not. grid%active(d)) cycle
      do a = 1, nn(d)
        off(a, d) = grid%lower(d) + real(first(d) + a - 2, wp) * grid%dx(d) - xp(d)
      end do
    end do
  end subroutine node_offsets
end module mpm_shape
