!> Initial state of the ICE fluids from `&fluid` and `&region`, optionally in hydrostatic
!! balance (`&physics hydrostatic_init`).
!!
!! Each fluid starts from its `&fluid` values; every `&region` naming it and containing the cell
!! centre (in its box and in its file shape, `geometry_shapes`) overrides them (later regions
!! win). Without hydrostatic initialisation the bulk density
!! is phi rho(p, T) with the fluid's or region's pressure. With it, gravity must point along one
!! active axis; the pressure is integrated down every column from `&physics reference_pressure`
!! at the top face in the discrete form the step keeps in balance:
!!   p_top_cell = p_ref + rho_c |g| dx/2,   p_below = p_above + |g| dx (rho_above + rho_below)/2,
!! rho = sum_m phi_m rho_m(p, T_m) (fixed-point iteration to round-off per cell). With these
!! pressures the face velocities (eq. 31) and the cell momentum with the face pressures of
!! eq. 37 are in exact balance in cells holding one fluid. Every rank integrates the columns
!! through its own block from the global top, so the result does not depend on the ranks; each
!! column once, down to the block's last cell (O(cells in the column), not its square).
module ice_initial
  use mpmice_kinds, only: wp
  use mpmice_errors, only: fatal, real_short_text
  use scene_params, only: ice_scene_params_t
  use grid_layout, only: grid_t, cell_centre
  use geometry_shapes, only: file_shape_contains
  use ice_eos, only: eos_density
  use ice_state, only: ice_state_t
  implicit none
  private

  public :: ice_initial_state

contains

  !> Fill rho, temp, vel, spvol and pressure of the owned cells.
  subroutine ice_initial_state(state, par, grid)
    type(ice_state_t), intent(inout) :: state  !< fluids (parameters set)
    type(ice_scene_params_t), intent(in) :: par  !< the ICE scene's groups
    type(grid_t), intent(in) :: grid           !< block geometry
    integer :: i, j, k, m, dg, c
    real(wp) :: phi(par%nfluids), t(par%nfluids), p(par%nfluids), v(3, par%nfluids), fsum
    real(wp), allocatable :: p_hydro(:, :, :)

    dg = 0
    if (par%physics%hydrostatic_init) then
      do c = 1, 3
        if (par%physics%gravity(c) /= 0.0_wp) then
          if (dg /= 0 .or. .not. grid%active(c)) call fatal('ice scene: hydrostatic_init ' // &
            'needs gravity along one active axis')
          dg = c
        end if
      end do
    end if
    if (dg /= 0) then
      allocate(p_hydro(grid%lo(1):grid%hi(1), grid%lo(2):grid%hi(2), grid%lo(3):grid%hi(3)))
      call hydrostatic_pressures(state, par, grid, dg, p_hydro)
    end if
    do k = grid%lo(3), grid%hi(3)
      do j = grid%lo(2), grid%hi(2)
        do i = grid%lo(1), grid%hi(1)
          call material_state(par, grid, [i, j, k], phi, t, p, v)
          fsum = sum(phi)
          if (abs(fsum - 1.0_wp) > 1.0e-6_wp) call fatal('ice scene: initial volume fractions '&
            // 'sum to ' // real_short_text(fsum) // ' in a cell, not 1 (check &fluid and ' // &
            '&region volume_fraction)')
          if (dg /= 0) p = p_hydro(i, j, k)
          do m = 1, par%nfluids
            associate (f => state%fluid(m))
              f%rho(i, j, k) = phi(m) * eos_density(f%eos, p(m), t(m))
              f%temp(i, j, k) = t(m)
              f%vel(i, j, k, :) = v(:, m)
              f%spvol(i, j, k) = 1.0_wp / eos_density(f%eos, p(m), t(m))
            end associate
          end do
          state%pressure(i, j, k) = sum(phi * p)
        end do
      end do
    end do
  end subroutine ice_initial_state

  !> Volume fraction, temperature, pressure and velocity of every fluid in global cell `idx`.
  subroutine material_state(par, grid, idx, phi, t, p, v)
    type(ice_scene_params_t), intent(in) :: par  !< the ICE scene's groups
    type(grid_t), intent(in) :: grid      !< block geometry
    integer, intent(in) :: idx(3)         !< global cell index
    real(wp), intent(out) :: phi(:)       !< volume fractions
    real(wp), intent(out) :: t(:)         !< temperatures [K]
    real(wp), intent(out) :: p(:)         !< pressures [Pa]
    real(wp), intent(out) :: v(:, :)      !< velocities (3, fluid) [m/s]
    integer :: m, r
    real(wp) :: x(3)
    x = cell_centre(grid, [1, 2, 3], idx)
    do m = 1, par%nfluids
      associate (c => par%fluids(m))
        phi(m) = c%volume_fraction
        t(m) = c%temperature
        p(m) = c%pressure
        v(:, m) = c%velocity
        do r = 1, par%nregions
          if (par%regions(r)%material /= c%name) cycle
          if (all(x >= par%regions(r)%lower .and. x <= par%regions(r)%upper .or. &
            .not. grid%active) .and. file_shape_contains(par%regions(r)%geometry, x)) then
            phi(m) = par%regions(r)%volume_fraction
            t(m) = par%regions(r)%temperature
            p(m) = par%regions(r)%pressure
            v(:, m) = par%regions(r)%velocity
          end if
        end do
      end associate
    end do
  end subroutine material_state

  !> Hydrostatic pressure [Pa] of every owned cell, each column (gravity along dimension `dg`)
  !! integrated once from the global top face down to the block's last cell.
  subroutine hydrostatic_pressures(state, par, grid, dg, p_hydro)
    type(ice_state_t), intent(in) :: state  !< fluids (EOS parameters)
    type(ice_scene_params_t), intent(in) :: par  !< the ICE scene's groups
    type(grid_t), intent(in) :: grid        !< block geometry
    integer, intent(in) :: dg               !< gravity dimension
    !> pressure of the owned cells [Pa]
    real(wp), intent(out) :: p_hydro(grid%lo(1):, grid%lo(2):, grid%lo(3):)
    integer :: i, j, k, c, top, last, step, it, idx(3), lo(3), hi(3)
    real(wp) :: g, h, rho, rho_prev, p_prev, pnew, pc
    real(wp) :: phi(par%nfluids), t(par%nfluids), p(par%nfluids), v(3, par%nfluids)

    g = abs(par%physics%gravity(dg))
    h = 0.5_wp * g * grid%dx(dg)
    if (par%physics%gravity(dg) < 0.0_wp) then
      top = grid%ncells(dg)
      last = grid%lo(dg)
      step = -1
    else
      top = 1
      last = grid%hi(dg)
      step = 1
    end if
    ! one pass per column: the loops run over the other two dimensions only
    lo = grid%lo
    hi = grid%hi
    lo(dg) = 1
    hi(dg) = 1
    do k = lo(3), hi(3)
      do j = lo(2), hi(2)
        do i = lo(1), hi(1)
          idx = [i, j, k]
          p_prev = par%physics%reference_pressure
          rho_prev = 0.0_wp
          pc = p_prev
          do c = top, last, step
            idx(dg) = c
            call material_state(par, grid, idx, phi, t, p, v)
            do it = 1, 200
              rho = mixture_density(state, phi, t, pc)
              pnew = p_prev + h * (rho_prev + rho)
              if (abs(pnew - pc) <= 4.0_wp * epsilon(1.0_wp) * abs(pnew)) exit
              pc = pnew
            end do
            pc = pnew
            p_prev = pc
            rho_prev = mixture_density(state, phi, t, pc)
            if (c >= grid%lo(dg) .and. c <= grid%hi(dg)) p_hydro(idx(1), idx(2), idx(3)) = pc
          end do
        end do
      end do
    end do
  end subroutine hydrostatic_pressures

  !> Mixture bulk density sum_m phi_m rho_m(p, T_m) [kg/m^3].
  pure function mixture_density(state, phi, t, p) result(rho)
    type(ice_state_t), intent(in) :: state  !< fluids (EOS parameters)
    real(wp), intent(in) :: phi(:)          !< volume fractions
    real(wp), intent(in) :: t(:)            !< temperatures [K]
    real(wp), intent(in) :: p               !< pressure [Pa]
    real(wp) :: rho
    integer :: m
    rho = 0.0_wp
    do m = 1, size(phi)
      if (phi(m) > 0.0_wp) rho = rho + phi(m) * eos_density(state%fluid(m)%eos, p, t(m))
    end do
  end function mixture_density
end module ice_initial
