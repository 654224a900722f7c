!> Lagrangian values of the fluids (paper eqs. 42-46, fluid part) and the Lagrangian specific
!! volume, written as mass-specific quantities for the advection step.
!!
!! Per owned cell and fluid m (mass M = rho_bar V, face area A_d = V/dx_d, outward sums over the
!! two faces of each active direction):
!!   (M u)_L = M u - dt V phi (p_f,hi - p_f,lo)/dx + dt M g + viscous      (eqs. 42, 45)
!!   (M e)_L = M cv T + V phi kappa p dp_total + (M / M_cell) D + conduction (eqs. 43, 46)
!!   (M v)_L = M v - V phi kappa dp_total                                 (eqs. 56-57)
!! The work V phi kappa p dp_total is Uintah's p dV form (the fluid's share phi kappa dp of the
!! dilatation). Departure from eq. 43 (docs/ice.md): without a solid phase the cell's energy
!! defect
!!   D = - dt sum_f A p_f sum_m phi_m,f u_m,f - sum_m [V phi_m kappa_m p dp_total
!!       + (1/2) M_m (|u_m,L|^2 - |u_m|^2) - W_g,m]
!! (phi_m,f the upwind face volume fraction, the fluid's own volume flux as in eq. 35; W_g,m the
!! work of the gravity components that `ice_advection` does not carry as potential energy, see
!! there) is added to the fluids of the cell in proportion to their masses: the Lagrangian phase
!! then conserves the total energy of the mixture exactly (the face terms telescope), the kinetic
!! energy removed by viscosity reappears as heat, and a fluid with a tiny mass in a cell gets a
!! tiny share (the per-fluid face form gave it the whole work of the volume flux entering it:
!! runaway temperatures at an air-water interface). With one fluid this is the face form
!!   (M e)_L = M cv T - dt sum_f A p_f phi_f u_f - (1/2) M (|u_L|^2 - |u|^2) + W_g,
!! which gives the exact Sod plateau (the p dV form alone left the post-shock state 0.7 % low).
!! With a solid phase (MPMICE) the p dV form alone is used. The specific-volume change
!! uses the pressure change of the implicit solve (phi kappa dp = -dt div(phi u_f) at
!! convergence), as Uintah's ICE does. Viscous momentum and conducted heat come from
!! `ice_viscous` (explicit, state at time n).
module ice_lagrangian
  use mpmice_kinds, only: wp
  use grid_layout, only: grid_t
  use ice_state, only: ice_state_t
  use ice_solid_view, only: ice_solid_view_t
  use ice_advection, only: potential_gravity
  use ice_pressure_flux, only: volume_flux_rows
  implicit none
  private

  public :: ice_lagrangian_values

contains

  !> Fill `lag(:,:,:,1:5)` = (u, v, w, cv T, v) after the Lagrangian sources, owned cells.
  !! Needs the face pressures and face velocities of the owned cells. The cell field and the rows
  !! of the mixture correction are the state's work storage (`ice_work_t`): nothing is allocated
  !! here.
  subroutine ice_lagrangian_values(state, grid, dt, gravity, sources, solid)
    type(ice_state_t), intent(inout) :: state  !< fluids and pressure fields
    type(grid_t), intent(in) :: grid           !< block geometry
    real(wp), intent(in) :: dt                 !< time step [s]
    real(wp), intent(in) :: gravity(3)         !< gravitational acceleration [m/s^2]
    !> viscous momentum (1:3) [kg m/s] and conducted heat (4) [J] of the step per fluid,
    !! (i, j, k, 4, fluid), from `ice_viscous_sources`
    real(wp), intent(in) :: sources(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):, :, :)
    !> the solid phase of a coupled scene (no mixture-energy correction with it)
    class(ice_solid_view_t), intent(in), optional :: solid
    call lagrangian_rows(state, grid, dt, gravity, sources, state%work%pressure_work, &
      state%work%flux_lo, state%work%flux_hi, solid)
  end subroutine ice_lagrangian_values

  !> `ice_lagrangian_values` with its work as explicit-shape arguments (from the work storage,
  !! which is at least this large; not referenced through `state` here).
  subroutine lagrangian_rows(state, grid, dt, gravity, sources, pressure_work, flux_lo, flux_hi, &
    solid)
    type(ice_state_t), intent(inout) :: state  !< fluids and pressure fields
    type(grid_t), intent(in) :: grid           !< block geometry
    real(wp), intent(in) :: dt                 !< time step [s]
    real(wp), intent(in) :: gravity(3)         !< gravitational acceleration [m/s^2]
    !> viscous momentum (1:3) [kg m/s] and conducted heat (4) [J] per fluid
    real(wp), intent(in) :: sources(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):, :, :)
    !> the pressure work of a fluid through the faces of each cell [J]
    real(wp), intent(inout) :: pressure_work(grid%lbc(1):grid%ubc(1), grid%lbc(2):grid%ubc(2), &
      grid%lbc(3):grid%ubc(3))
    ! the face fluxes p_f u_f phi_f of a row's low and high faces (face i between cells i - o
    ! and i)
    real(wp), intent(inout) :: flux_lo(grid%lo(1):grid%hi(1) + 1)     !< low faces [Pa m/s]
    real(wp), intent(inout) :: flux_hi(grid%lo(1):grid%hi(1) + 1)     !< high faces [Pa m/s]
    !> the solid phase of a coupled scene (no mixture-energy correction with it)
    class(ice_solid_view_t), intent(in), optional :: solid
    integer :: d, m, i, j, k, o(3)
    real(wp) :: mass, vol, mom, work, phi, g_kinetic(3)
    logical :: mixture

    vol = grid%cell_volume
    ! the conservative mixture-energy correction (module header), not with a solid phase
    mixture = .not. present(solid)
    ! gravity work that stays kinetic: the components not carried as potential energy
    g_kinetic = gravity - potential_gravity(grid, gravity)
    ! energy defect and cell mass of the mixture correction: preallocated work storage
    if (mixture) state%lag_work(grid%lo(1):grid%hi(1), grid%lo(2):grid%hi(2), &
      grid%lo(3):grid%hi(3), :) = 0.0_wp
    do m = 1, state%nfluids
      associate (f => state%fluid(m))
        ! pressure work through the faces with the fluid's upwind volume flux, also where the
        ! fluid has no mass (its volume flux into a neighbour works on the cell): the sweep of
        ! the pressure equation's volume flux (`volume_flux_rows`) with the flux p_f phi_f u_f,
        ! each face's flux once
        if (mixture) then
          pressure_work(grid%lo(1):grid%hi(1), grid%lo(2):grid%hi(2), grid%lo(3):grid%hi(3)) = &
            0.0_wp
          do d = 1, 3
            if (.not. grid%active(d)) cycle
            call volume_flux_rows(grid, dt * vol / grid%dx(d), d, pressure_work, flux_lo, &
              flux_hi, fluid=f, pface=state%pface)
          end do
        end if
        do k = grid%lo(3), grid%hi(3)
          do j = grid%lo(2), grid%hi(2)
            do i = grid%lo(1), grid%hi(1)
              mass = f%rho(i, j, k) * vol
              phi = f%vfrac(i, j, k)
              work = 0.0_wp
              if (mixture) work = pressure_work(i, j, k)
              if (mass <= 0.0_wp) then
                f%lag(i, j, k, 1:3) = 0.0_wp
                f%lag(i, j, k, 4) = f%eos%cv * f%temp(i, j, k)
                f%lag(i, j, k, 5) = f%spvol(i, j, k)
                if (mixture) state%lag_work(i, j, k, 1) = state%lag_work(i, j, k, 1) + work
                cycle
              end if
              do d = 1, 3
                mom = mass * (f%vel(i, j, k, d) + dt * gravity(d)) + sources(i, j, k, d, m)
                if (grid%active(d)) then
                  o = 0
                  o(d) = 1
                  mom = mom - dt * vol * phi * (state%pface(i + o(1), j + o(2), k + o(3), d) - &
                    state%pface(i, j, k, d)) / grid%dx(d)
                end if
                f%lag(i, j, k, d) = mom / mass
              end do
              ! Uintah's p dV work: the fluid's share phi kappa dp of the dilatation
              f%lag(i, j, k, 4) = f%eos%cv * f%temp(i, j, k) + (vol * phi * f%kappa(i, j, k) * &
                state%pressure(i, j, k) * state%dp_total(i, j, k) + sources(i, j, k, 4, m)) / mass
              if (mixture) then
                state%lag_work(i, j, k, 1) = state%lag_work(i, j, k, 1) + work - vol * phi * &
                  f%kappa(i, j, k) * state%pressure(i, j, k) * state%dp_total(i, j, k) - &
                  0.5_wp * mass * (sum(f%lag(i, j, k, 1:3)**2) - sum(f%vel(i, j, k, 1:3)**2)) + &
                  dt * mass * dot_product(g_kinetic, 0.5_wp * (f%lag(i, j, k, 1:3) + &
                  f%vel(i, j, k, 1:3)))
                state%lag_work(i, j, k, 2) = state%lag_work(i, j, k, 2) + mass
              end if
              f%lag(i, j, k, 5) = f%spvol(i, j, k) - &
                vol * phi * f%kappa(i, j, k) * state%dp_total(i, j, k) / mass
            end do
          end do
        end do
      end associate
    end do
    if (.not. mixture) return
    ! the defect to the fluids by mass: the same energy per unit mass for every fluid
    do m = 1, state%nfluids
      associate (f => state%fluid(m))
        do k = grid%lo(3), grid%hi(3)
          do j = grid%lo(2), grid%hi(2)
            do i = grid%lo(1), grid%hi(1)
              if (f%rho(i, j, k) <= 0.0_wp) cycle
              f%lag(i, j, k, 4) = f%lag(i, j, k, 4) + state%lag_work(i, j, k, 1) / &
                state%lag_work(i, j, k, 2)
            end do
          end do
        end do
      end associate
    end do
  end subroutine lagrangian_rows
end module ice_lagrangian
