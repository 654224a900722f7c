!> The volume fluxes through the faces in the right-hand side of the pressure equation (eq. 35,
!! `ice_pressure`): rhs -= dt A (F_hi - F_lo) per owned cell and direction, with each face's
!! flux F computed once per row of faces (along x a cell's high face is the next cell's low
!! face, along y the high faces of a row are the low faces of the next; along z both rows are
!! computed). The same products and differences as a per-cell evaluation of both faces, so the
!! right-hand side is bitwise the same. The rows are the state's work storage (`ice_work_t`),
!! passed as explicit-shape arguments.
module ice_pressure_flux
  use mpmice_kinds, only: wp
  use grid_layout, only: grid_t
  use ice_state, only: ice_fluid_t
  use ice_solid_view, only: ice_solid_view_t
  implicit none
  private

  public :: fluid_flux_rows, solid_flux_rows, flux_fraction

contains

  !> rhs -= dt A (F_hi - F_lo) on the owned cells for the faces of direction `d` of fluid `f`,
  !! F = phi_f u_f its upwind volume flux through a face (`row_volume_flux`): each face's F once
  !! per row (along x a cell's high face is the next cell's low face, along y the high faces of
  !! a row are the low faces of the next; along z both rows are computed), the same products
  !! and differences as a per-cell evaluation of both faces. The rows are the state's work
  !! storage (at least this large).
  subroutine fluid_flux_rows(f, grid, dt_area, d, rhs, flux_lo, flux_hi)
    type(ice_fluid_t), intent(in) :: f            !< the fluid
    type(grid_t), intent(in) :: grid              !< block geometry
    real(wp), intent(in) :: dt_area               !< dt A [s m^2]
    integer, intent(in) :: d                      !< face direction
    real(wp), intent(inout) :: rhs(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !< rhs [m^3]
    real(wp), intent(inout) :: flux_lo(grid%lo(1):grid%hi(1) + 1) !< low faces' F [m/s]
    real(wp), intent(inout) :: flux_hi(grid%lo(1):grid%hi(1) + 1) !< high faces' F [m/s]
    integer :: i, j, k, i1, i2
    i1 = grid%lo(1)
    i2 = grid%hi(1)
    do k = grid%lo(3), grid%hi(3)
      do j = grid%lo(2), grid%hi(2)
        select case (d)
        case (1)
          call row_volume_flux(f, grid, d, j, k, i1, i2 + 1, flux_lo)
          do i = i1, i2
            rhs(i, j, k) = rhs(i, j, k) - dt_area * (flux_lo(i + 1) - flux_lo(i))
          end do
          cycle
        case (2)
          if (j == grid%lo(2)) then
            call row_volume_flux(f, grid, d, j, k, i1, i2, flux_lo)
          else
            flux_lo(i1:i2) = flux_hi(i1:i2)
          end if
          call row_volume_flux(f, grid, d, j + 1, k, i1, i2, flux_hi)
        case default
          call row_volume_flux(f, grid, d, j, k, i1, i2, flux_lo)
          call row_volume_flux(f, grid, d, j, k + 1, i1, i2, flux_hi)
        end select
        do i = i1, i2
          rhs(i, j, k) = rhs(i, j, k) - dt_area * (flux_hi(i) - flux_lo(i))
        end do
      end do
    end do
  end subroutine fluid_flux_rows

  !> The upwind volume flux phi_f u_f [m/s] of fluid `f` through the faces of normal d whose
  !! high cell is (i, j, k), i = i1..i2 (the upwind cell's fraction: face - o for u >= 0).
  pure subroutine row_volume_flux(f, grid, d, j, k, i1, i2, flux)
    type(ice_fluid_t), intent(in) :: f        !< the fluid
    type(grid_t), intent(in) :: grid          !< block geometry
    integer, intent(in) :: d                  !< face normal
    integer, intent(in) :: j, k               !< the row of high cells
    integer, intent(in) :: i1, i2             !< faces of the row
    real(wp), intent(inout) :: flux(grid%lo(1):) !< phi_f u_f [m/s] (i1..i2 written)
    integer :: i, o(3)
    real(wp) :: u
    o = 0
    o(d) = 1
    do i = i1, i2
      u = f%uface(i, j, k, d)
      flux(i) = merge(f%vfrac(i - o(1), j - o(2), k - o(3)), f%vfrac(i, j, k), u >= 0.0_wp) * u
    end do
  end subroutine row_volume_flux

  !> rhs -= dt A (S_hi - S_lo + R_hi - R_lo) on the owned cells for the faces of direction `d`:
  !! S = phi_s,f u_s,f the solid's volume flux through a face (`row_solid_flux`, once per face
  !! as in `fluid_flux_rows`), R the rigid bodies' prescribed flux (`rigid_flux`).
  subroutine solid_flux_rows(solid, grid, dt_area, d, rhs, flux_lo, flux_hi)
    class(ice_solid_view_t), intent(in) :: solid  !< solid phase of a coupled scene
    type(grid_t), intent(in) :: grid              !< block geometry
    real(wp), intent(in) :: dt_area               !< dt A [s m^2]
    integer, intent(in) :: d                      !< face direction
    real(wp), intent(inout) :: rhs(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !< rhs [m^3]
    real(wp), intent(inout) :: flux_lo(grid%lo(1):grid%hi(1) + 1) !< low faces' S [m/s]
    real(wp), intent(inout) :: flux_hi(grid%lo(1):grid%hi(1) + 1) !< high faces' S [m/s]
    integer :: i, j, k, i1, i2, o(3)
    i1 = grid%lo(1)
    i2 = grid%hi(1)
    o = 0
    o(d) = 1
    associate (rigid => solid%rigid_flux)
      do k = grid%lo(3), grid%hi(3)
        do j = grid%lo(2), grid%hi(2)
          select case (d)
          case (1)
            call row_solid_flux(solid, grid, d, j, k, i1, i2 + 1, flux_lo)
            do i = i1, i2
              rhs(i, j, k) = rhs(i, j, k) - dt_area * (flux_lo(i + 1) - flux_lo(i) + &
                rigid(i + 1, j, k, d) - rigid(i, j, k, d))
            end do
            cycle
          case (2)
            if (j == grid%lo(2)) then
              call row_solid_flux(solid, grid, d, j, k, i1, i2, flux_lo)
            else
              flux_lo(i1:i2) = flux_hi(i1:i2)
            end if
            call row_solid_flux(solid, grid, d, j + 1, k, i1, i2, flux_hi)
          case default
            call row_solid_flux(solid, grid, d, j, k, i1, i2, flux_lo)
            call row_solid_flux(solid, grid, d, j, k + 1, i1, i2, flux_hi)
          end select
          do i = i1, i2
            rhs(i, j, k) = rhs(i, j, k) - dt_area * (flux_hi(i) - flux_lo(i) + &
              rigid(i + o(1), j + o(2), k + o(3), d) - rigid(i, j, k, d))
          end do
        end do
      end do
    end associate
  end subroutine solid_flux_rows

  !> The solid's volume flux phi_s,f u_s,f [m/s] through the faces of normal d whose high cell
  !! is (i, j, k), i = i1..i2 (`flux_fraction` of the face planes' fractions).
  pure subroutine row_solid_flux(solid, grid, d, j, k, i1, i2, flux)
    class(ice_solid_view_t), intent(in) :: solid !< solid phase
    type(grid_t), intent(in) :: grid          !< block geometry
    integer, intent(in) :: d                  !< face normal
    integer, intent(in) :: j, k               !< the row of high cells
    integer, intent(in) :: i1, i2             !< faces of the row
    real(wp), intent(inout) :: flux(grid%lo(1):) !< phi_s,f u_s,f [m/s] (i1..i2 written)
    integer :: i
    associate (us => solid%uface, low => solid%face_fraction, high => solid%face_fraction_hi)
      do i = i1, i2
        flux(i) = flux_fraction(us(i, j, k, d), low(i, j, k, d), high(i, j, k, d)) * us(i, j, k, d)
      end do
    end associate
  end subroutine row_solid_flux

  !> The solid fraction that crosses a face with solid velocity `u`: the one on the face plane's
  !! low side (`low`) for u >= 0, on its high side (`high`) otherwise.
  elemental real(wp) function flux_fraction(u, low, high) result(phi)
    real(wp), intent(in) :: u     !< solid face velocity [m/s]
    real(wp), intent(in) :: low   !< fraction on the low side of the face plane [-]
    real(wp), intent(in) :: high  !< fraction on its high side [-]
    if (u >= 0.0_wp) then
      phi = low
    else
      phi = high
    end if
  end function flux_fraction
end module ice_pressure_flux
