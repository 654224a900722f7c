!> Explicit viscous momentum and heat-conduction sources of the Lagrangian step (paper eqs. 23-25
!! without the turbulence model, and the conduction term of eq. 43, errata E9: q = -k grad T).
!!
!! Per fluid m and owned cell, with face coefficients the harmonic means of phi mu and phi k of
!! the two cells (zero when the fluid is absent on either side):
!!   d(M u_c) = dt sum_d A_d [mu_f (u_c,R - u_c,L)/dx_d]_lo^hi     (Laplacian form of div tau)
!!   d(M e)   = dt sum_d A_d [k_f (T_R - T_L)/dx_d]_lo^hi
!! Simplification (docs/ice.md): the Laplacian form mu lap(u) of div tau, i.e. without the
!! (mu/3) grad(div u) part and without Smagorinsky; exact for the shear flows used to validate it.
!! Walls: the mirrored ghosts make both fluxes zero (free slip, adiabatic). Needs velocity and
!! temperature valid in one ghost layer. The stability limit of the explicit update is
!! `ice_viscous_dt`.
module ice_viscous
  use mpmice_kinds, only: wp
  use grid_layout, only: grid_t
  use ice_state, only: ice_state_t
  implicit none
  private

  public :: ice_viscous_sources, ice_viscous_dt

contains

  !> Add dt times the viscous force [kg m/s] to `mom(:,:,:,1:3)` and dt times the conducted
  !! heat [J] to `heat(:,:,:)` of fluid m (owned cells).
  subroutine ice_viscous_sources(state, grid, m, dt, mom, heat)
    type(ice_state_t), intent(in) :: state     !< fluids
    type(grid_t), intent(in) :: grid           !< block geometry
    integer, intent(in) :: m                   !< fluid
    real(wp), intent(in) :: dt                 !< time step [s]
    real(wp), intent(inout) :: mom(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):, :) !< momentum [kg m/s]
    real(wp), intent(inout) :: heat(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):)   !< energy [J]
    integer :: d, i, j, k, o(3), c
    real(wp) :: area, mu_lo, mu_hi, k_lo, k_hi, phi_lo, phi_hi

    associate (f => state%fluid(m))
      if (f%viscosity <= 0.0_wp .and. f%conductivity <= 0.0_wp) return
      do d = 1, 3
        if (.not. grid%active(d)) cycle
        o = 0
        o(d) = 1
        area = grid%cell_volume / grid%dx(d)
        do k = grid%lo(3), grid%hi(3)
          do j = grid%lo(2), grid%hi(2)
            do i = grid%lo(1), grid%hi(1)
              phi_lo = face_mean(f%vfrac(i - o(1), j - o(2), k - o(3)), f%vfrac(i, j, k))
              phi_hi = face_mean(f%vfrac(i, j, k), f%vfrac(i + o(1), j + o(2), k + o(3)))
              mu_lo = phi_lo * f%viscosity
              mu_hi = phi_hi * f%viscosity
              k_lo = phi_lo * f%conductivity
              k_hi = phi_hi * f%conductivity
              do c = 1, 3
                mom(i, j, k, c) = mom(i, j, k, c) + dt * area / grid%dx(d) * &
                  (mu_hi * (f%vel(i + o(1), j + o(2), k + o(3), c) - f%vel(i, j, k, c)) - &
                  mu_lo * (f%vel(i, j, k, c) - f%vel(i - o(1), j - o(2), k - o(3), c)))
              end do
              heat(i, j, k) = heat(i, j, k) + dt * area / grid%dx(d) * &
                (k_hi * (f%temp(i + o(1), j + o(2), k + o(3)) - f%temp(i, j, k)) - &
                k_lo * (f%temp(i, j, k) - f%temp(i - o(1), j - o(2), k - o(3))))
            end do
          end do
        end do
      end do
    end associate
  end subroutine ice_viscous_sources

  !> Stability limit [s] of the explicit diffusion on this rank: 0.5 / (sum_d 1/dx_d^2) divided
  !! by the largest diffusivity, mu v (momentum) or k v / cv (heat), over fluids and owned
  !! cells; huge when there is no diffusion.
  function ice_viscous_dt(state, grid) result(dt)
    type(ice_state_t), intent(in) :: state  !< fluids
    type(grid_t), intent(in) :: grid        !< block geometry
    real(wp) :: dt
    real(wp) :: diffusivity, s, rho_min
    integer :: m
    diffusivity = 0.0_wp
    do m = 1, state%nfluids
      associate (f => state%fluid(m), lo => grid%lo, hi => grid%hi)
        if (f%viscosity <= 0.0_wp .and. f%conductivity <= 0.0_wp) cycle
        if (.not. any(f%rho(lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)) > 0.0_wp)) cycle
        ! cells where the fluid is present, not a trace: the specific volume of a trace
        ! (advected m v over a vanishing m) is not a physical one and must not set the step
        rho_min = 1.0e-6_wp * maxval(f%rho(lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)))
        s = maxval(f%spvol(lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)), &
          mask=f%rho(lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)) > rho_min)
        diffusivity = max(diffusivity, f%viscosity * s, f%conductivity * s / f%eos%cv)
      end associate
    end do
    if (diffusivity > 0.0_wp) then
      dt = 0.5_wp / (sum(merge(1.0_wp / grid%dx**2, 0.0_wp, grid%active)) * diffusivity)
    else
      dt = huge(1.0_wp)
    end if
  end function ice_viscous_dt

  !> Harmonic mean of two volume fractions (0 when either is 0).
  pure real(wp) function face_mean(a, b)
    real(wp), intent(in) :: a  !< low cell
    real(wp), intent(in) :: b  !< high cell
    if (a > 0.0_wp .and. b > 0.0_wp) then
      face_mean = 2.0_wp * a * b / (a + b)
    else
      face_mean = 0.0_wp
    end if
  end function face_mean
end module ice_viscous
