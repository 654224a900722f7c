!> The volume fluxes through the faces in the right-hand side of the pressure equation (eq. 35,
!! `ice_pressure`): rhs -= dt A (F_hi - F_lo) per owned cell and direction, with each face's
!! flux F computed once per row of faces (along x a cell's high face is the next cell's low
!! face, along y the high faces of a row are the low faces of the next; along z both rows are
!! computed). The same products and differences as a per-cell evaluation of both faces, so the
!! right-hand side is bitwise the same. One sweep (`volume_flux_rows`) serves a fluid and the
!! solid, and with the face pressures the Lagrangian values' pressure work of a fluid
!! (`ice_lagrangian`, flux p_f phi_f u_f); each row's flux is one loop over contiguous rows of
!! the face velocity and the two fractions it chooses from (`upwind_flux`). The rows are the
!! state's work storage (`ice_work_t`), passed as explicit-shape arguments.
module ice_pressure_flux
  use mpmice_kinds, only: wp
  use grid_layout, only: grid_t
  use ice_state, only: ice_fluid_t
  use ice_solid_view, only: ice_solid_view_t
  implicit none
  private

  public :: volume_flux_rows, flux_fraction

contains

  !> rhs -= dt A (F_hi - F_lo) on the owned cells for the faces of direction `d`, F the volume
  !! flux through a face (`row_flux`) of fluid `fluid` (phi_f u_f, upwind) or of the solid
  !! `solid` (phi_s,f u_s,f, and the rigid bodies' prescribed flux R: rhs -= dt A (F_hi - F_lo
  !! + R_hi - R_lo), `row_update`); exactly one of the two is given. With the face pressures
  !! `pface` (and a fluid) F is the fluid's p_f phi_f u_f: the pressure work of
  !! `ice_lagrangian`, `rhs` then its cell field and `dt_area` dt V/dx. Each face's F once per
  !! row (along x a cell's high face is the next cell's low face, along y the high faces of a
  !! row are the low faces of the next; along z both rows are computed), the same products and
  !! differences as a per-cell evaluation of both faces. The rows are the state's work storage
  !! (at least this large).
  subroutine volume_flux_rows(grid, dt_area, d, rhs, flux_lo, flux_hi, fluid, solid, pface)
    type(grid_t), intent(in) :: grid              !< block geometry
    real(wp), intent(in) :: dt_area               !< dt A [s m^2]
    integer, intent(in) :: d                      !< face direction
    real(wp), intent(inout) :: rhs(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !< rhs [m^3]
    real(wp), intent(inout) :: flux_lo(grid%lo(1):grid%hi(1) + 1) !< low faces' F [m/s]
    real(wp), intent(inout) :: flux_hi(grid%lo(1):grid%hi(1) + 1) !< high faces' F [m/s]
    type(ice_fluid_t), intent(in), optional :: fluid          !< a fluid
    class(ice_solid_view_t), intent(in), optional :: solid    !< or the solid of a coupled scene
    !> face pressures (i, j, k, direction) [Pa], with `fluid`: F = p_f phi_f u_f
    real(wp), intent(in), optional :: pface(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):, :)
    integer :: j, k, i1, i2, o(3)
    i1 = grid%lo(1)
    i2 = grid%hi(1)
    o = 0
    o(d) = 1
    do k = grid%lo(3), grid%hi(3)
      do j = grid%lo(2), grid%hi(2)
        select case (d)
        case (1)
          ! one row of faces: the high faces are the low faces shifted by one
          call row_flux(grid, d, j, k, i1, i2 + 1, flux_lo, fluid, solid, pface)
          call row_update(grid, dt_area, d, o, j, k, flux_lo(i1 + 1:i2 + 1), flux_lo(i1:i2), &
            rhs, solid)
          cycle
        case (2)
          if (j == grid%lo(2)) then
            call row_flux(grid, d, j, k, i1, i2, flux_lo, fluid, solid, pface)
          else
            flux_lo(i1:i2) = flux_hi(i1:i2)
          end if
          call row_flux(grid, d, j + 1, k, i1, i2, flux_hi, fluid, solid, pface)
        case default
          call row_flux(grid, d, j, k, i1, i2, flux_lo, fluid, solid, pface)
          call row_flux(grid, d, j, k + 1, i1, i2, flux_hi, fluid, solid, pface)
        end select
        call row_update(grid, dt_area, d, o, j, k, flux_hi(i1:i2), flux_lo(i1:i2), rhs, solid)
      end do
    end do
  end subroutine volume_flux_rows

  !> The volume flux [m/s] through the faces of normal d whose high cell is (i, j, k),
  !! i = i1..i2 (`upwind_flux` of the row): of the fluid `fluid` its phi_f u_f with the upwind
  !! cell's fraction (face - o for u >= 0), or, where `solid` is given, the solid's
  !! phi_s,f u_s,f with the fraction on the upwind side of the face plane; with the face
  !! pressures `pface` the fluid's p_f phi_f u_f [Pa m/s].
  pure subroutine row_flux(grid, d, j, k, i1, i2, flux, fluid, solid, pface)
    type(grid_t), intent(in) :: grid          !< block geometry
    integer, intent(in) :: d                  !< face normal
    integer, intent(in) :: j, k               !< the row of high cells
    integer, intent(in) :: i1, i2             !< faces of the row
    real(wp), intent(inout) :: flux(grid%lo(1):grid%hi(1) + 1) !< the faces' flux [m/s] (i1..i2)
    type(ice_fluid_t), intent(in), optional :: fluid       !< a fluid
    class(ice_solid_view_t), intent(in), optional :: solid !< or the solid
    !> face pressures (i, j, k, direction) [Pa]
    real(wp), intent(in), optional :: pface(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):, :)
    integer :: o(3)
    o = 0
    o(d) = 1
    if (present(solid)) then
      call upwind_flux(i2 - i1 + 1, solid%uface(i1:i2, j, k, d), &
        solid%face_fraction(i1:i2, j, k, d), solid%face_fraction_hi(i1:i2, j, k, d), flux(i1:i2))
    else if (present(pface)) then
      call upwind_flux(i2 - i1 + 1, fluid%uface(i1:i2, j, k, d), &
        fluid%vfrac(i1 - o(1):i2 - o(1), j - o(2), k - o(3)), fluid%vfrac(i1:i2, j, k), &
        flux(i1:i2), pface(i1:i2, j, k, d))
    else
      call upwind_flux(i2 - i1 + 1, fluid%uface(i1:i2, j, k, d), &
        fluid%vfrac(i1 - o(1):i2 - o(1), j - o(2), k - o(3)), fluid%vfrac(i1:i2, j, k), flux(i1:i2))
    end if
  end subroutine row_flux

  !> flux = phi u through a row of n faces, phi the fraction upwind of each face
  !! (`flux_fraction`): `low` (the face's low side) for u >= 0, `high` otherwise; with the face
  !! pressures `p`, flux = phi (p u).
  pure subroutine upwind_flux(n, u, low, high, flux, p)
    integer, intent(in) :: n           !< faces in the row
    real(wp), intent(in) :: u(n)       !< face velocity [m/s]
    real(wp), intent(in) :: low(n)     !< fraction on the low side of each face [-]
    real(wp), intent(in) :: high(n)    !< fraction on its high side [-]
    real(wp), intent(out) :: flux(n)   !< phi u [m/s] (with p: phi p u [Pa m/s])
    real(wp), intent(in), optional :: p(n) !< face pressure [Pa]
    integer :: i
    if (present(p)) then
      do i = 1, n
        flux(i) = flux_fraction(u(i), low(i), high(i)) * (p(i) * u(i))
      end do
    else
      do i = 1, n
        flux(i) = flux_fraction(u(i), low(i), high(i)) * u(i)
      end do
    end if
  end subroutine upwind_flux

  !> rhs(i, j, k) -= dt A (F_hi(i) - F_lo(i)) on the row (j, k) of owned cells, and with the
  !! solid `solid` its rigid bodies' prescribed flux R as well: dt A (F_hi - F_lo + R_hi - R_lo)
  !! (R_hi on the cell's face of offset `o`, R_lo on its own).
  pure subroutine row_update(grid, dt_area, d, o, j, k, flux_hi, flux_lo, rhs, solid)
    type(grid_t), intent(in) :: grid              !< block geometry
    real(wp), intent(in) :: dt_area               !< dt A [s m^2]
    integer, intent(in) :: d                      !< face direction
    integer, intent(in) :: o(3)                   !< unit offset of d
    integer, intent(in) :: j, k                   !< the row of cells
    real(wp), intent(in) :: flux_hi(grid%lo(1):grid%hi(1)) !< the cells' high faces' F [m/s]
    real(wp), intent(in) :: flux_lo(grid%lo(1):grid%hi(1)) !< their low faces' F [m/s]
    real(wp), intent(inout) :: rhs(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !< rhs [m^3]
    class(ice_solid_view_t), intent(in), optional :: solid !< the solid of a coupled scene
    integer :: i, i1, i2
    if (present(solid)) then
      i1 = grid%lo(1)
      i2 = grid%hi(1)
      call rigid_row_update(i2 - i1 + 1, dt_area, flux_hi, flux_lo, &
        solid%rigid_flux(i1 + o(1):i2 + o(1), j + o(2), k + o(3), d), &
        solid%rigid_flux(i1:i2, j, k, d), rhs(i1:i2, j, k))
    else
      do i = grid%lo(1), grid%hi(1)
        rhs(i, j, k) = rhs(i, j, k) - dt_area * (flux_hi(i) - flux_lo(i))
      end do
    end if
  end subroutine row_update

  !> rhs -= dt A (F_hi - F_lo + R_hi - R_lo) on a row of n cells (`row_update` with a solid, R
  !! its rigid bodies' prescribed flux), the rows contiguous.
  pure subroutine rigid_row_update(n, dt_area, flux_hi, flux_lo, rigid_hi, rigid_lo, rhs)
    integer, intent(in) :: n               !< cells in the row
    real(wp), intent(in) :: dt_area        !< dt A [s m^2]
    real(wp), intent(in) :: flux_hi(n)     !< the cells' high faces' F [m/s]
    real(wp), intent(in) :: flux_lo(n)     !< their low faces' F [m/s]
    real(wp), intent(in) :: rigid_hi(n)    !< R of the high faces [m/s]
    real(wp), intent(in) :: rigid_lo(n)    !< R of the low faces [m/s]
    real(wp), intent(inout) :: rhs(n)      !< rhs of the row [m^3]
    integer :: i
    do i = 1, n
      rhs(i) = rhs(i) - dt_area * (flux_hi(i) - flux_lo(i) + rigid_hi(i) - rigid_lo(i))
    end do
  end subroutine rigid_row_update

  !> The fraction that crosses a face with velocity `u`: the one on the face's low side (`low`)
  !! for u >= 0, on its high side (`high`) otherwise (the solid's: on either side of the face
  !! plane; a fluid's: of the upwind cell).
  elemental real(wp) function flux_fraction(u, low, high) result(phi)
    real(wp), intent(in) :: u     !< face velocity [m/s]
    real(wp), intent(in) :: low   !< fraction on the low side of the face [-]
    real(wp), intent(in) :: high  !< fraction on its high side [-]
    if (u >= 0.0_wp) then
      phi = low
    else
      phi = high
    end if
  end function flux_fraction
end module ice_pressure_flux
