!> Trace fluids of a coupled scene's cells (`ice_stage_advect` with `traces`): a fluid with a
!! vanishing share of a cell's mass takes the cell's mass-weighted temperature and velocity.
module ice_trace_fluids
  use mpmice_kinds, only: wp
  use grid_layout, only: grid_t
  use ice_state, only: ice_state_t
  implicit none
  private

  public :: tame_trace_fluids

contains

  !> A fluid with a vanishing share of a cell's mass (below 1e-10 of it: e.g. air numerically
  !! left in water-filled pores) takes the mass-weighted temperature and velocity of the cell.
  !! Its own values come from energy and momentum divided by that vanishing mass and drift
  !! without bound (a trace of air reached 1e17 K in a submerged sand block, until its volume
  !! broke the pressure equilibration). A trace whose advected mass came out negative (the
  !! second-order fluxes' undershoot of a 1e-100 kg/m^3 trace inside the bed) is set to zero:
  !! a change below 1e-10 of the cell's fluid mass. `negative` counts the cells left with a
  !! negative mass beyond that (a real defect, logged). Owned cells.
  pure subroutine tame_trace_fluids(state, grid, negative)
    type(ice_state_t), intent(inout) :: state  !< fluids (temp, vel of traces updated)
    type(grid_t), intent(in) :: grid           !< block geometry
    integer, intent(out) :: negative           !< cells with a negative mass beyond a trace
    real(wp), parameter :: trace = 1.0e-10_wp  !< share of the cell's fluid mass
    integer :: i, j, k, m, nf
    real(wp) :: total, t_mix, u_mix(3)
    nf = state%nfluids
    negative = 0
    if (nf < 2) then
      negative = count(state%fluid(1)%rho(grid%lo(1):grid%hi(1), grid%lo(2):grid%hi(2), &
        grid%lo(3):grid%hi(3)) < 0.0_wp)
      return
    end if
    do k = grid%lo(3), grid%hi(3)
      do j = grid%lo(2), grid%hi(2)
        do i = grid%lo(1), grid%hi(1)
          total = 0.0_wp
          t_mix = 0.0_wp
          u_mix = 0.0_wp
          do m = 1, nf
            associate (f => state%fluid(m))
              if (f%rho(i, j, k) < 0.0_wp) cycle
              total = total + f%rho(i, j, k)
              t_mix = t_mix + f%rho(i, j, k) * f%temp(i, j, k)
              u_mix = u_mix + f%rho(i, j, k) * f%vel(i, j, k, :)
            end associate
          end do
          do m = 1, nf
            if (state%fluid(m)%rho(i, j, k) >= -trace * total) cycle
            negative = negative + 1
            exit
          end do
          if (total <= 0.0_wp) cycle
          do m = 1, nf
            associate (f => state%fluid(m))
              if (f%rho(i, j, k) >= trace * total) cycle
              if (f%rho(i, j, k) < 0.0_wp .and. f%rho(i, j, k) >= -trace * total) then
                f%rho(i, j, k) = 0.0_wp
              end if
              f%temp(i, j, k) = t_mix / total
              f%vel(i, j, k, :) = u_mix / total
            end associate
          end do
        end do
      end do
    end do
  end subroutine tame_trace_fluids
end module ice_trace_fluids
