!> Implicit momentum and heat exchange between the fluids of a cell or face with constant
!! coefficients (paper eqs. 34 and 50-53 written for N fluids, errata E8: beta = dt K v phi).
!!
!! For fluids m, n: beta_mn = dt v_m phi_n K (dimensionless; v_m the intrinsic specific volume,
!! phi_n the volume fraction, K [kg/m^3/s]), so the drag per unit volume is phi_m phi_n K du
!! (Uintah's convention, implementation notes §3). The increments solve
!!   (1 + sum_n beta_mn) du_m - sum_n beta_mn du_n = sum_n beta_mn (u_n - u_m),
!! in closed form for two fluids and by LAPACK dgesv for more. At faces the same matrix applied
!! to the face specific volumes gives the exchange-modified v_f used by the pressure equation
!! (Uintah's sp_vol_FC). In cells the velocities and, with H > 0, the temperatures
!! (beta = dt H v_m phi_n / cv_m) are exchanged; the kinetic energy the drag removes is added to
!! the internal energies in proportion to mass, so total energy is conserved.
module ice_exchange
  use mpmice_kinds, only: wp
  use mpmice_errors, only: fatal
  use grid_layout, only: grid_t
  use ice_state, only: ice_state_t
  use ice_face_velocity, only: closed_face, face_range
  implicit none
  private

  public :: ice_exchange_faces, ice_exchange_cells, exchange_solve

  integer, parameter :: max_n = 8  !< most fluids handled (config_materials%max_fluids)

  interface
    subroutine dgesv(n, nrhs, a, lda, ipiv, b, ldb, info)
      import :: wp
      integer, intent(in) :: n, nrhs, lda, ldb
      real(wp), intent(inout) :: a(lda, *), b(ldb, *)
      integer, intent(out) :: ipiv(*), info
    end subroutine dgesv
  end interface

contains

  !> Exchange at the faces of the owned cells: u_f += du and v_f := A^-1 v_f. No-op for one
  !! fluid or K = 0.
  subroutine ice_exchange_faces(state, grid, dt, k_exchange)
    type(ice_state_t), intent(inout) :: state  !< fluids (uface, vface updated)
    type(grid_t), intent(in) :: grid           !< block geometry
    real(wp), intent(in) :: dt                 !< time step [s]
    real(wp), intent(in) :: k_exchange         !< K [kg/m^3/s]
    integer :: d, m, n, i, j, k, o(3), r(2, 3), nf
    real(wp) :: beta(max_n, max_n), rhs(max_n, 2), phi(max_n), v(max_n), w(max_n)

    nf = state%nfluids
    if (nf < 2 .or. k_exchange <= 0.0_wp) return
    do d = 1, 3
      if (.not. grid%active(d)) cycle
      o = 0
      o(d) = 1
      r = face_range(grid, d)
      do k = r(1, 3), r(2, 3)
        do j = r(1, 2), r(2, 2)
          do i = r(1, 1), r(2, 1)
            if (closed_face(state, grid, d, [i, j, k])) cycle
            do m = 1, nf
              phi(m) = 0.5_wp * (state%fluid(m)%vfrac(i - o(1), j - o(2), k - o(3)) + &
                state%fluid(m)%vfrac(i, j, k))
              v(m) = state%fluid(m)%vface(i, j, k, d)
              rhs(m, 1) = state%fluid(m)%uface(i, j, k, d)
            end do
            do m = 1, nf
              do n = 1, nf
                beta(m, n) = dt * v(m) * phi(n) * k_exchange
              end do
              beta(m, m) = 0.0_wp
            end do
            rhs(1:nf, 2) = v(1:nf)
            w(1:nf) = phi(1:nf) / v(1:nf)
            call exchange_solve(nf, beta, rhs(:, 1:1), 1, w)
            call exchange_solve(nf, beta, rhs(:, 2:2), 1)
            do m = 1, nf
              state%fluid(m)%uface(i, j, k, d) = rhs(m, 1)
              state%fluid(m)%vface(i, j, k, d) = rhs(m, 2)
            end do
          end do
        end do
      end do
    end do
  end subroutine ice_exchange_faces

  !> Exchange of the Lagrangian velocities (and temperatures when h_exchange > 0) in the owned
  !! cells, `lag(:,:,:,1:4)` updated. No-op for one fluid.
  subroutine ice_exchange_cells(state, grid, dt, k_exchange, h_exchange)
    type(ice_state_t), intent(inout) :: state  !< fluids (lag updated)
    type(grid_t), intent(in) :: grid           !< block geometry
    real(wp), intent(in) :: dt                 !< time step [s]
    real(wp), intent(in) :: k_exchange         !< K [kg/m^3/s]
    real(wp), intent(in) :: h_exchange         !< H [W/m^3/K]
    integer :: m, n, i, j, k, nf
    real(wp) :: beta(max_n, max_n), rhs(max_n, 3), phi(max_n), v(max_n), mass(max_n)
    real(wp) :: ke_old, ke_new, total_mass

    nf = state%nfluids
    if (nf < 2) return
    do k = grid%lo(3), grid%hi(3)
      do j = grid%lo(2), grid%hi(2)
        do i = grid%lo(1), grid%hi(1)
          do m = 1, nf
            phi(m) = state%fluid(m)%vfrac(i, j, k)
            v(m) = state%fluid(m)%spvol(i, j, k)
            mass(m) = state%fluid(m)%rho(i, j, k)
          end do
          total_mass = sum(mass(1:nf))
          if (k_exchange > 0.0_wp) then
            ke_old = 0.0_wp
            do m = 1, nf
              rhs(m, 1:3) = state%fluid(m)%lag(i, j, k, 1:3)
              ke_old = ke_old + 0.5_wp * mass(m) * sum(rhs(m, 1:3)**2)
              do n = 1, nf
                beta(m, n) = dt * v(m) * phi(n) * k_exchange
              end do
              beta(m, m) = 0.0_wp
            end do
            call exchange_solve(nf, beta, rhs, 3, mass)
            ke_new = 0.0_wp
            do m = 1, nf
              ke_new = ke_new + 0.5_wp * mass(m) * sum(rhs(m, 1:3)**2)
              state%fluid(m)%lag(i, j, k, 1:3) = rhs(m, 1:3)
            end do
            ! dissipated kinetic energy becomes heat, shared by mass
            if (total_mass > 0.0_wp) then
              do m = 1, nf
                state%fluid(m)%lag(i, j, k, 4) = state%fluid(m)%lag(i, j, k, 4) + &
                  (ke_old - ke_new) / total_mass
              end do
            end if
          end if
          if (h_exchange > 0.0_wp) then
            do m = 1, nf
              rhs(m, 1) = state%fluid(m)%lag(i, j, k, 4) / state%fluid(m)%eos%cv
              do n = 1, nf
                beta(m, n) = dt * v(m) * phi(n) * h_exchange / state%fluid(m)%eos%cv
              end do
              beta(m, m) = 0.0_wp
            end do
            call exchange_solve(nf, beta, rhs, 1)
            do m = 1, nf
              state%fluid(m)%lag(i, j, k, 4) = rhs(m, 1) * state%fluid(m)%eos%cv
            end do
          end if
        end do
      end do
    end do
  end subroutine ice_exchange_cells

  !> Apply the exchange to `nrhs` columns of values x(1:n, :): x := x + dx with
  !! (I + diag(sum_n beta_mn) - beta) dx = sum_n beta_mn (x_n - x_m) for column 1 of a velocity-
  !! like quantity, i.e. x_new = A^-1 x_old for every column (A = I + diag(rowsum beta) - beta).
  !! Closed form for n = 2, dgesv otherwise. `beta` has a zero diagonal.
  subroutine exchange_solve(n, beta, x, nrhs, weight)
    integer, intent(in) :: n                      !< number of fluids
    real(wp), intent(in) :: beta(max_n, max_n)    !< beta_mn, zero diagonal
    real(wp), intent(inout) :: x(max_n, *)        !< values in, exchanged values out
    integer, intent(in) :: nrhs                   !< columns
    real(wp), intent(in), optional :: weight(max_n) !< masses per volume phi/v (n > 2: restore
                                                    !! sum weight x, which LU round-off breaks)
    real(wp) :: a(max_n, max_n), det, x1, x2, x_old(max_n, 3), defect
    integer :: m, c, ipiv(max_n), info

    if (n == 2) then
      ! A = [1 + b12, -b12; -b21, 1 + b21]; A^-1 = [1 + b21, b12; b21, 1 + b12] / det
      det = 1.0_wp + beta(1, 2) + beta(2, 1)
      do c = 1, nrhs
        x1 = x(1, c)
        x2 = x(2, c)
        x(1, c) = ((1.0_wp + beta(2, 1)) * x1 + beta(1, 2) * x2) / det
        x(2, c) = (beta(2, 1) * x1 + (1.0_wp + beta(1, 2)) * x2) / det
      end do
      return
    end if
    a(1:n, 1:n) = -beta(1:n, 1:n)
    do m = 1, n
      a(m, m) = 1.0_wp + sum(beta(m, 1:n))
    end do
    x_old(1:n, 1:nrhs) = x(1:n, 1:nrhs)
    call dgesv(n, nrhs, a, max_n, ipiv, x, max_n, info)
    if (info /= 0) call fatal('ice_exchange: singular exchange matrix')
    if (present(weight)) then
      ! with weights w_m beta_mn symmetric, A conserves sum w x exactly; dgesv's round-off
      ! (condition ~ beta) does not: remove the defect by a uniform shift
      if (sum(weight(1:n)) > 0.0_wp) then
        do c = 1, nrhs
          defect = sum(weight(1:n) * (x(1:n, c) - x_old(1:n, c))) / sum(weight(1:n))
          x(1:n, c) = x(1:n, c) - defect
        end do
      end if
    end if
  end subroutine exchange_solve
end module ice_exchange
