!> Transient heat conduction, rho c dT/dt = div(k grad T), solved implicitly (theta scheme) through
!! the hypre Struct PCG+PFMG solver. This is the foundation's first scene: it exercises the grid,
!! the halo exchange, the implicit solver, output and restart without the multiphase physics, and it
!! has an exact solution to validate against (`heat_exact`).
!!
!! Finite volumes on the uniform grid: for cell c with faces f,
!!   rho c V (T_c^{n+1} - T_c^n)/dt = theta L(T^{n+1})_c + (1 - theta) L(T^n)_c,
!!   L(T)_c = sum_f G_f (T_nb(f) - T_c),  G_f = k A_f / dx_d  (interior and periodic faces),
!! and at a wall face the neighbour value is the wall temperature at distance dx/2, G_f = 2 k A_f/dx_d.
!! theta = 1 is backward Euler (first order in time), theta = 1/2 Crank-Nicolson (second order).
module heat_conduction
  use mpmice_kinds, only: wp
  use grid_layout, only: grid_t, cell_centre
  implicit none
  private

  public :: heat_t, heat_init, heat_assemble, heat_exact, heat_decay_rate, heat_free

  real(wp), parameter :: pi = acos(-1.0_wp)

  !> State and work arrays of the heat-conduction scene (cell arrays with the grid's cell bounds).
  type :: heat_t
    real(wp) :: conductivity = 1.0_wp       !< k [W/m/K]
    real(wp) :: density = 1.0_wp            !< rho [kg/m^3]
    real(wp) :: heat_capacity = 1.0_wp      !< c [J/kg/K]
    real(wp) :: wall_temperature = 300.0_wp !< temperature of every wall face [K]
    real(wp) :: base_temperature = 300.0_wp !< base of the initial field [K]
    real(wp) :: amplitude = 1.0_wp          !< amplitude of the initial mode [K]
    integer :: modes(3) = 1                 !< mode numbers per dimension
    real(wp) :: theta = 1.0_wp              !< implicit weight
    real(wp), allocatable :: temperature(:, :, :)  !< T [K]
    real(wp), allocatable :: diag(:, :, :)         !< operator diagonal [W/K]
    real(wp), allocatable :: coef(:, :, :, :)      !< (i,j,k,d) low-face coupling [W/K]
    real(wp), allocatable :: rhs(:, :, :)          !< right-hand side [W]
  end type heat_t

contains

  !> Allocate the state and set the exact solution at t = 0 in every owned cell.
  subroutine heat_init(heat, grid, conductivity, density, heat_capacity, base_temperature, &
      amplitude, modes, theta)
    type(heat_t), intent(out) :: heat          !< scene state
    type(grid_t), intent(in) :: grid           !< block geometry
    real(wp), intent(in) :: conductivity       !< k [W/m/K]
    real(wp), intent(in) :: density            !< rho [kg/m^3]
    real(wp), intent(in) :: heat_capacity      !< c [J/kg/K]
    real(wp), intent(in) :: base_temperature   !< base and wall temperature [K]
    real(wp), intent(in) :: amplitude          !< initial amplitude [K]
    integer, intent(in) :: modes(3)            !< mode numbers per dimension
    real(wp), intent(in) :: theta              !< implicit weight (1 BE, 0.5 CN)
    integer :: i, j, k

    heat%conductivity = conductivity
    heat%density = density
    heat%heat_capacity = heat_capacity
    heat%base_temperature = base_temperature
    heat%wall_temperature = base_temperature
    heat%amplitude = amplitude
    heat%modes = modes
    heat%theta = theta
    associate (lb => grid%lbc, ub => grid%ubc)
      allocate(heat%temperature(lb(1):ub(1), lb(2):ub(2), lb(3):ub(3)), source=base_temperature)
      allocate(heat%diag(lb(1):ub(1), lb(2):ub(2), lb(3):ub(3)), source=0.0_wp)
      allocate(heat%rhs(lb(1):ub(1), lb(2):ub(2), lb(3):ub(3)), source=0.0_wp)
      allocate(heat%coef(lb(1):ub(1), lb(2):ub(2), lb(3):ub(3), 3), source=0.0_wp)
    end associate
    do k = grid%lo(3), grid%hi(3)
      do j = grid%lo(2), grid%hi(2)
        do i = grid%lo(1), grid%hi(1)
          heat%temperature(i, j, k) = heat_exact(heat, grid, [i, j, k], 0.0_wp)
        end do
      end do
    end do
  end subroutine heat_init

  !> Decay rate alpha * |wave vector|^2 [1/s] of the initial mode.
  pure function heat_decay_rate(heat, grid) result(rate)
    type(heat_t), intent(in) :: heat  !< scene state
    type(grid_t), intent(in) :: grid  !< block geometry
    real(wp) :: rate
    real(wp) :: wavenumber, diffusivity
    integer :: d
    diffusivity = heat%conductivity / (heat%density * heat%heat_capacity)
    rate = 0.0_wp
    do d = 1, 3
      if (.not. grid%active(d)) cycle
      if (grid%periodic(d)) then
        wavenumber = 2.0_wp * pi * real(heat%modes(d), wp) / (grid%upper(d) - grid%lower(d))
      else
        wavenumber = pi * real(heat%modes(d), wp) / (grid%upper(d) - grid%lower(d))
      end if
      rate = rate + diffusivity * wavenumber**2
    end do
  end function heat_decay_rate

  !> Exact solution [K] at the centre of cell `cell` (global indices) and time `time` [s]:
  !! T = T_base + A exp(-rate t) prod_d s_d(x_d), with s_d = sin(m pi xi) on wall dimensions and
  !! cos(2 m pi xi) on periodic ones, xi = (x_d - lower_d)/L_d.
  pure function heat_exact(heat, grid, cell, time) result(temperature)
    type(heat_t), intent(in) :: heat  !< scene state
    type(grid_t), intent(in) :: grid  !< block geometry
    integer, intent(in) :: cell(3)    !< global cell index
    real(wp), intent(in) :: time      !< time [s]
    real(wp) :: temperature
    real(wp) :: shape, xi
    integer :: d
    shape = 1.0_wp
    do d = 1, 3
      if (.not. grid%active(d)) cycle
      xi = (cell_centre(grid, d, cell(d)) - grid%lower(d)) / (grid%upper(d) - grid%lower(d))
      if (grid%periodic(d)) then
        shape = shape * cos(2.0_wp * pi * real(heat%modes(d), wp) * xi)
      else
        shape = shape * sin(pi * real(heat%modes(d), wp) * xi)
      end if
    end do
    temperature = heat%base_temperature + heat%amplitude * exp(-heat_decay_rate(heat, grid) * time) &
      * shape
  end function heat_exact

  !> Assemble the implicit system for one step of size `dt` [s] into `diag`, `coef` and `rhs`.
  !! The temperature ghosts must be current (halo exchange) when theta < 1.
  subroutine heat_assemble(heat, grid, dt)
    type(heat_t), intent(inout) :: heat  !< scene state
    type(grid_t), intent(in) :: grid     !< block geometry
    real(wp), intent(in) :: dt           !< time step [s]
    real(wp) :: conductance(3), capacity, flux, g
    integer :: i, j, k, d, side, offset(3), nb(3)
    logical :: wall

    do d = 1, 3
      conductance(d) = heat%conductivity * grid%cell_volume / grid%dx(d)**2
    end do
    capacity = heat%density * heat%heat_capacity * grid%cell_volume / dt
    heat%coef = 0.0_wp
    do k = grid%lo(3), grid%hi(3)
      do j = grid%lo(2), grid%hi(2)
        do i = grid%lo(1), grid%hi(1)
          heat%diag(i, j, k) = capacity
          heat%rhs(i, j, k) = capacity * heat%temperature(i, j, k)
          do d = 1, 3
            if (.not. grid%active(d)) cycle
            offset = 0
            ! low face (-1) then high face (+1)
            do side = -1, 1, 2
              offset(d) = side
              nb = [i, j, k] + offset
              wall = .not. grid%periodic(d) .and. (nb(d) < 1 .or. nb(d) > grid%ncells(d))
              if (wall) then
                g = 2.0_wp * conductance(d)
                flux = g * (heat%wall_temperature - heat%temperature(i, j, k))
                heat%rhs(i, j, k) = heat%rhs(i, j, k) + heat%theta * g * heat%wall_temperature
              else
                g = conductance(d)
                if (heat%theta < 1.0_wp) then
                  flux = g * (heat%temperature(nb(1), nb(2), nb(3)) - heat%temperature(i, j, k))
                else
                  flux = 0.0_wp
                end if
                if (side < 0) heat%coef(i, j, k, d) = heat%theta * g
              end if
              heat%diag(i, j, k) = heat%diag(i, j, k) + heat%theta * g
              heat%rhs(i, j, k) = heat%rhs(i, j, k) + (1.0_wp - heat%theta) * flux
            end do
          end do
        end do
      end do
    end do
  end subroutine heat_assemble

  !> Release the arrays.
  subroutine heat_free(heat)
    type(heat_t), intent(inout) :: heat  !< scene state
    if (allocated(heat%temperature)) deallocate(heat%temperature)
    if (allocated(heat%diag)) deallocate(heat%diag)
    if (allocated(heat%coef)) deallocate(heat%coef)
    if (allocated(heat%rhs)) deallocate(heat%rhs)
  end subroutine heat_free
end module heat_conduction
