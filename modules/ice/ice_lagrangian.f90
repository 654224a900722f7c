!> Lagrangian values of the fluids (paper eqs. 42-46, fluid part) and the Lagrangian specific
!! volume, written as mass-specific quantities for the advection step.
!!
!! Per owned cell and fluid m (mass M = rho_bar V, face area A_d = V/dx_d, outward sums over the
!! two faces of each active direction):
!!   (M u)_L = M u - dt V phi (p_f,hi - p_f,lo)/dx + dt M g + viscous      (eqs. 42, 45)
!!   (M e)_L = M cv T - dt sum_f A p_f phi_f u_f - (1/2) M (|u_L|^2 - |u|^2) + conduction
!!                                                                        (eqs. 43, 46)
!! with phi_f the upwind face volume fraction (the fluid's own volume flux, as in eq. 35)
!!   (M v)_L = M v - V phi kappa dp_total                                 (eqs. 56-57)
!! Departure from eq. 43 for ONE fluid (docs/ice.md): the work term is the pressure work through
!! the faces minus the change of kinetic energy, so that the Lagrangian phase conserves total
!! energy exactly (the face terms telescope). Uintah's p dV form, V phi kappa p dp, left the Sod
!! post-shock state 0.7 % low in pressure (a wrong shock jump); this form gives the exact plateau.
!! With several fluids the Uintah form (M e)_L = M cv T + V phi kappa p dp_total is used: the
!! face form gives a fluid with a tiny mass in a cell the whole work of the volume flux entering
!! it (measured: runaway temperatures at an air-water interface). The specific-volume change
!! uses the pressure change of the implicit solve (phi kappa dp = -dt div(phi u_f) at
!! convergence), as Uintah's ICE does. Viscous momentum and conducted heat come from
!! `ice_viscous` (explicit, state at time n).
module ice_lagrangian
  use mpmice_kinds, only: wp
  use grid_layout, only: grid_t
  use ice_state, only: ice_state_t
  use ice_face_velocity, only: upwind
  implicit none
  private

  public :: ice_lagrangian_values

contains

  !> Fill `lag(:,:,:,1:5)` = (u, v, w, cv T, v) after the Lagrangian sources, owned cells.
  !! Needs the face pressures and face velocities of the owned cells.
  subroutine ice_lagrangian_values(state, grid, dt, gravity, sources)
    type(ice_state_t), intent(inout) :: state  !< fluids and pressure fields
    type(grid_t), intent(in) :: grid           !< block geometry
    real(wp), intent(in) :: dt                 !< time step [s]
    real(wp), intent(in) :: gravity(3)         !< gravitational acceleration [m/s^2]
    !> viscous momentum (1:3) [kg m/s] and conducted heat (4) [J] of the step per fluid,
    !! (i, j, k, 4, fluid), from `ice_viscous_sources`
    real(wp), intent(in) :: sources(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):, :, :)
    integer :: d, m, i, j, k, o(3)
    real(wp) :: mass, vol, mom, work, phi, uh, ul

    vol = grid%cell_volume
    do m = 1, state%nfluids
      associate (f => state%fluid(m))
        do k = grid%lo(3), grid%hi(3)
          do j = grid%lo(2), grid%hi(2)
            do i = grid%lo(1), grid%hi(1)
              mass = f%rho(i, j, k) * vol
              phi = f%vfrac(i, j, k)
              if (mass <= 0.0_wp) then
                f%lag(i, j, k, 1:3) = 0.0_wp
                f%lag(i, j, k, 4) = f%eos%cv * f%temp(i, j, k)
                f%lag(i, j, k, 5) = f%spvol(i, j, k)
                cycle
              end if
              work = 0.0_wp
              do d = 1, 3
                mom = mass * (f%vel(i, j, k, d) + dt * gravity(d)) + sources(i, j, k, d, m)
                if (grid%active(d)) then
                  o = 0
                  o(d) = 1
                  mom = mom - dt * vol * phi * (state%pface(i + o(1), j + o(2), k + o(3), d) - &
                    state%pface(i, j, k, d)) / grid%dx(d)
                  if (state%nfluids == 1 .and. .not. state%solid%present) then
                    uh = f%uface(i + o(1), j + o(2), k + o(3), d)
                    ul = f%uface(i, j, k, d)
                    work = work - dt * vol / grid%dx(d) * &
                      (state%pface(i + o(1), j + o(2), k + o(3), d) * uh * upwind(uh, phi, &
                      f%vfrac(i + o(1), j + o(2), k + o(3))) - state%pface(i, j, k, d) * ul * &
                      upwind(ul, f%vfrac(i - o(1), j - o(2), k - o(3)), phi))
                  end if
                end if
                f%lag(i, j, k, d) = mom / mass
              end do
              if (state%nfluids == 1 .and. .not. state%solid%present) then
                ! gravity work stays kinetic: remove it from the kinetic-energy change
                work = work - 0.5_wp * mass * (sum(f%lag(i, j, k, 1:3)**2) - &
                  sum(f%vel(i, j, k, 1:3)**2)) + dt * mass * &
                  dot_product(gravity, 0.5_wp * (f%lag(i, j, k, 1:3) + f%vel(i, j, k, 1:3)))
              else
                ! Uintah's p dV work: the fluid's share phi kappa dp of the dilatation
                work = vol * phi * f%kappa(i, j, k) * state%pressure(i, j, k) * &
                  state%dp_total(i, j, k)
              end if
              f%lag(i, j, k, 4) = f%eos%cv * f%temp(i, j, k) + (work + sources(i, j, k, 4, m)) &
                / mass
              f%lag(i, j, k, 5) = f%spvol(i, j, k) - &
                vol * phi * f%kappa(i, j, k) * state%dp_total(i, j, k) / mass
            end do
          end do
        end do
      end associate
    end do
  end subroutine ice_lagrangian_values
end module ice_lagrangian
