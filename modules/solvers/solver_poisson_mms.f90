!> Manufactured variable-coefficient Poisson problem that verifies the structured solver
!! (`solver_pressure`) in unit tests and benchmarks:
!!   -div(k grad u) + reaction u = f   on the grid's box, u given on walls (Dirichlet),
!! with, on the active dimensions d and xi_d = (x_d - lower_d)/L_d in [0, 1],
!!   u = prod_d g_d(xi_d),   g_d = sin(2 pi xi + phase_d) on periodic dimensions,
!!                           g_d = sin(wall_wavenumber xi + phase_d) on wall dimensions,
!!   k = 1 + 0.5 prod_d sin(2 pi xi_d),
!! and f computed exactly. The discretisation is the one the physics uses: cell-centred finite
!! volumes, face coefficient k(face centre)/dx_d^2, wall value u(face centre) at half a cell
!! (folded into the diagonal and the right-hand side). The discrete solution is second-order
!! accurate at cell centres.
module solver_poisson_mms
  use parallel_comm, only: MPI_Comm, sum_in_place
  use mpmice_kinds, only: wp
  use grid_layout, only: grid_t, cell_centre, node_position
  implicit none
  private

  public :: mms_exact, mms_conductivity, mms_source, mms_build, mms_error_l2

  real(wp), parameter :: pi = acos(-1.0_wp)
  real(wp), parameter :: wall_wavenumber = 2.5_wp              !< [-] on wall dimensions
  real(wp), parameter :: phase(3) = [0.3_wp, 0.7_wp, 1.1_wp]    !< [-] per dimension

contains

  !> Exact solution u at point `x` [m].
  pure function mms_exact(grid, x) result(u)
    type(grid_t), intent(in) :: grid  !< block geometry (box, active and periodic dimensions)
    real(wp), intent(in) :: x(3)      !< position [m]
    real(wp) :: u
    real(wp) :: g(3), gp(3), gpp(3)
    call shape_factors(grid, x, g, gp, gpp)
    u = product(g)
  end function mms_exact

  !> Coefficient k(x) [-] (between 0.5 and 1.5).
  pure function mms_conductivity(grid, x) result(k)
    type(grid_t), intent(in) :: grid  !< block geometry
    real(wp), intent(in) :: x(3)      !< position [m]
    real(wp) :: k
    real(wp) :: s(3), ds(3)
    call coefficient_factors(grid, x, s, ds)
    k = 1.0_wp + 0.5_wp * product(s)
  end function mms_conductivity

  !> Source f = -div(k grad u) + reaction u at `x`.
  pure function mms_source(grid, x, reaction) result(f)
    type(grid_t), intent(in) :: grid  !< block geometry
    real(wp), intent(in) :: x(3)      !< position [m]
    real(wp), intent(in) :: reaction  !< reaction coefficient [1/m^2 in these units]
    real(wp) :: f
    real(wp) :: g(3), gp(3), gpp(3), s(3), ds(3), k, dk, du, d2u
    integer :: d
    call shape_factors(grid, x, g, gp, gpp)
    call coefficient_factors(grid, x, s, ds)
    k = 1.0_wp + 0.5_wp * product(s)
    f = reaction * product(g)
    do d = 1, 3
      if (.not. grid%active(d)) cycle
      du = gp(d) * product(g, mask=[1, 2, 3] /= d)
      d2u = gpp(d) * product(g, mask=[1, 2, 3] /= d)
      dk = 0.5_wp * ds(d) * product(s, mask=[1, 2, 3] /= d)
      f = f - (dk * du + k * d2u)
    end do
  end function mms_source

  !> Operator (`diag`, low-face `coef_x/y/z`) and right-hand side `rhs` of the discrete problem
  !! in the owned cells, in the convention of `struct_solver_set_operator`. Arrays have the
  !! grid's cell bounds; the other entries are set to zero.
  subroutine mms_build(grid, reaction, diag, coef_x, coef_y, coef_z, rhs)
    type(grid_t), intent(in) :: grid   !< block geometry
    real(wp), intent(in) :: reaction   !< reaction coefficient (>= 0)
    real(wp), intent(out) :: diag(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):)   !< centre
    real(wp), intent(out) :: coef_x(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !< x low faces
    real(wp), intent(out) :: coef_y(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !< y low faces
    real(wp), intent(out) :: coef_z(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !< z low faces
    real(wp), intent(out) :: rhs(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):)    !< right-hand side
    integer :: i, j, k, d, f, side, cell(3), face
    real(wp) :: xc(3), xf(3), c
    logical :: wall

    diag = 0.0_wp
    coef_x = 0.0_wp
    coef_y = 0.0_wp
    coef_z = 0.0_wp
    rhs = 0.0_wp
    do k = grid%lo(3), grid%hi(3)
      do j = grid%lo(2), grid%hi(2)
        do i = grid%lo(1), grid%hi(1)
          cell = [i, j, k]
          xc = cell_centre(grid, [1, 2, 3], cell)
          diag(i, j, k) = reaction
          rhs(i, j, k) = mms_source(grid, xc, reaction)
          do f = 1, 6  ! the faces x-, x+, y-, y+, z-, z+
            d = (f + 1) / 2
            side = mod(f + 1, 2)
            if (.not. grid%active(d)) cycle
            face = cell(d) + side
            xf = xc
            xf(d) = node_position(grid, d, face)
            wall = .not. grid%periodic(d) .and. (face == 1 .or. face == grid%ncells(d) + 1)
            c = mms_conductivity(grid, xf) / grid%dx(d)**2
            if (wall) then
              diag(i, j, k) = diag(i, j, k) + 2.0_wp * c
              rhs(i, j, k) = rhs(i, j, k) + 2.0_wp * c * mms_exact(grid, xf)
            else
              diag(i, j, k) = diag(i, j, k) + c
              if (side == 0) then
                if (d == 1) coef_x(i, j, k) = c
                if (d == 2) coef_y(i, j, k) = c
                if (d == 3) coef_z(i, j, k) = c
              end if
            end if
          end do
        end do
      end do
    end do
  end subroutine mms_build

  !> Volume-weighted L2 norm of (x - u_exact) over all owned cells of all ranks of `comm`.
  function mms_error_l2(grid, comm, x) result(error)
    type(grid_t), intent(in) :: grid    !< block geometry
    type(MPI_Comm), intent(in) :: comm  !< communicator of the decomposition
    real(wp), intent(in) :: x(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):)  !< discrete solution
    real(wp) :: error
    real(wp) :: sums(2), xc(3)
    integer :: i, j, k
    sums = 0.0_wp
    do k = grid%lo(3), grid%hi(3)
      do j = grid%lo(2), grid%hi(2)
        do i = grid%lo(1), grid%hi(1)
          xc = cell_centre(grid, [1, 2, 3], [i, j, k])
          sums(1) = sums(1) + grid%cell_volume * (x(i, j, k) - mms_exact(grid, xc))**2
          sums(2) = sums(2) + grid%cell_volume
        end do
      end do
    end do
    call sum_in_place(comm, sums)
    error = sqrt(sums(1) / sums(2))
  end function mms_error_l2

  !> Factors g_d, g_d' and g_d'' (derivatives in x_d [1/m], [1/m^2]) of u on each dimension;
  !! 1, 0, 0 on inactive ones.
  pure subroutine shape_factors(grid, x, g, gp, gpp)
    type(grid_t), intent(in) :: grid  !< block geometry
    real(wp), intent(in) :: x(3)      !< position [m]
    real(wp), intent(out) :: g(3)     !< g_d
    real(wp), intent(out) :: gp(3)    !< dg_d/dx_d
    real(wp), intent(out) :: gpp(3)   !< d2g_d/dx_d2
    real(wp) :: a, xi(3), length(3)
    integer :: d
    g = 1.0_wp
    gp = 0.0_wp
    gpp = 0.0_wp
    call unit_coordinates(grid, x, xi, length)
    do d = 1, 3
      if (.not. grid%active(d)) cycle
      if (grid%periodic(d)) then
        a = 2.0_wp * pi
      else
        a = wall_wavenumber
      end if
      g(d) = sin(a * xi(d) + phase(d))
      gp(d) = a / length(d) * cos(a * xi(d) + phase(d))
      gpp(d) = -(a / length(d))**2 * g(d)
    end do
  end subroutine shape_factors

  !> Factors s_d = sin(2 pi xi_d) of the coefficient and their derivatives ds_d/dx_d [1/m];
  !! 1, 0 on inactive dimensions.
  pure subroutine coefficient_factors(grid, x, s, ds)
    type(grid_t), intent(in) :: grid  !< block geometry
    real(wp), intent(in) :: x(3)      !< position [m]
    real(wp), intent(out) :: s(3)     !< s_d
    real(wp), intent(out) :: ds(3)    !< ds_d/dx_d
    real(wp) :: xi(3), length(3)
    integer :: d
    s = 1.0_wp
    ds = 0.0_wp
    call unit_coordinates(grid, x, xi, length)
    do d = 1, 3
      if (.not. grid%active(d)) cycle
      s(d) = sin(2.0_wp * pi * xi(d))
      ds(d) = 2.0_wp * pi / length(d) * cos(2.0_wp * pi * xi(d))
    end do
  end subroutine coefficient_factors

  !> Domain lengths L_d [m] and the position in them, xi_d = (x_d - lower_d) / L_d, along the
  !! active dimensions (0 and 1 on the inactive ones).
  pure subroutine unit_coordinates(grid, x, xi, length)
    type(grid_t), intent(in) :: grid     !< block geometry
    real(wp), intent(in) :: x(3)         !< position [m]
    real(wp), intent(out) :: xi(3)       !< xi_d
    real(wp), intent(out) :: length(3)   !< L_d [m]
    integer :: d
    xi = 0.0_wp
    length = 1.0_wp
    do d = 1, 3
      if (.not. grid%active(d)) cycle
      length(d) = grid%upper(d) - grid%lower(d)
      xi(d) = (x(d) - grid%lower(d)) / length(d)
    end do
  end subroutine unit_coordinates
end module solver_poisson_mms
