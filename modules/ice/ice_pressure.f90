!> The implicit pressure equation (paper eq. 35) in the form Uintah's impICE solves it,
!! multiplied by dt V:
!!   V sum_kappa dp - dt^2 sum_faces (A/dx) (sum_m phi_m,f v_m,f) (dp_nb - dp)
!!     = -V sum_kappa dp_total - dt sum_faces A sum_m phi_m,f u_m,f (outward),
!! with kappa_m = v_m/c_m^2, phi_m,f the upwind face volume fraction and v_m,f the harmonic-mean
!! face specific volume (eq. 31). The outer iteration (driven by the scene) solves for dp,
!! adds it to p and dp_total (eq. 36) and corrects the face velocities
!! u_m,f -= dt v_m,f (dp_R - dp_L)/dx, until max |rhs|/V (the volume-fraction constraint
!! sum phi = 1 at the end of the step) is below the outer tolerance.
!! The face pressures of eq. 37: `ice_face_pressures`.
module ice_pressure
  use mpmice_log, only: log_repeated
  use mpmice_kinds, only: wp
  use mpmice_errors, only: real_short_text
  use grid_layout, only: grid_t, cell_centre
  use grid_sweep, only: sweep_direction
  use ice_state, only: ice_state_t
  use ice_solid_view, only: ice_solid_view_t
  use ice_face_velocity, only: face_range, open_face_range, held_plane
  use ice_pressure_flux, only: volume_flux_rows, flux_fraction
  implicit none
  private

  public :: ice_pressure_assemble, ice_pressure_rhs, ice_pressure_correct, pore_min
  public :: solid_face_fraction, platen_fluid_faces, report_pressure_failure

  !> smallest pore fraction in the face weights (platen faces, `ice_face_pressures`)
  real(wp), parameter :: pore_min = 1.0e-3_wp

contains

  !> Operator of eq. 35: low-face coefficients `state%coef` and diagonal `state%diag`
  !! (hypre's convention of `solver_pressure`); boundary faces do not couple (walls: zero
  !! normal velocity and a homogeneous Neumann condition on dp; a loading platen adds
  !! theta dt^2 A c to its inner cell's diagonal, `platen_fluid_faces`). Written as one sweep per
  !! direction and material over the faces (branch-free, no calls per face) with the sums in
  !! the same order as a per-face loop over the materials.
  subroutine ice_pressure_assemble(state, grid, dt, theta, solid)
    type(ice_state_t), intent(inout) :: state  !< fluids (uface, vface, vfrac read)
    type(grid_t), intent(in) :: grid           !< block geometry
    real(wp), intent(in) :: dt                 !< time step [s]
    real(wp), intent(in) :: theta              !< implicit weight of the pressure change
    !> the solid phase of a coupled scene: its face specific volume joins the coefficients, a
    !! loading platen the diagonal
    class(ice_solid_view_t), intent(in), optional :: solid
    integer :: d, m, i, j, k, o(3), r(2, 3), side, c(3)
    real(wp) :: area, w_lo, w_hi

    state%coef = 0.0_wp
    do d = 1, 3
      if (.not. sweep_direction(grid, d, o)) cycle
      r = face_range(grid, d)
      area = grid%cell_volume / grid%dx(d)
      ! coef holds sum_m phi_m,f v_m,f first, then the coefficient
      do m = 1, state%nfluids
        associate (f => state%fluid(m))
          do k = r(1, 3), r(2, 3)
            do j = r(1, 2), r(2, 2)
              do i = r(1, 1), r(2, 1)
                state%coef(i, j, k, d) = state%coef(i, j, k, d) + merge(f%vfrac(i - o(1), &
                  j - o(2), k - o(3)), f%vfrac(i, j, k), f%uface(i, j, k, d) >= 0.0_wp) * &
                  f%vface(i, j, k, d)
              end do
            end do
          end do
        end associate
      end do
      if (present(solid)) call solid_coefficients(state, solid, grid, d, o, r)
      do k = r(1, 3), r(2, 3)
        do j = r(1, 2), r(2, 2)
          do i = r(1, 1), r(2, 1)
            state%coef(i, j, k, d) = theta * dt**2 * area / grid%dx(d) * state%coef(i, j, k, d)
          end do
        end do
      end do
      call zero_closed_faces(state, grid, d, r, state%coef(:, :, :, d))
    end do
    do k = grid%lo(3), grid%hi(3)
      do j = grid%lo(2), grid%hi(2)
        do i = grid%lo(1), grid%hi(1)
          state%diag(i, j, k) = grid%cell_volume * state%sum_kappa(i, j, k)
        end do
      end do
    end do
    do d = 1, 3
      if (.not. sweep_direction(grid, d, o)) cycle
      ! an open face (dp = 0 there, ghost dp = -dp) counts twice
      do k = grid%lo(3), grid%hi(3)
        do j = grid%lo(2), grid%hi(2)
          do i = grid%lo(1), grid%hi(1)
            w_lo = merge(2.0_wp, 1.0_wp, on_boundary(grid, d, i * o(1) + j * o(2) + k * o(3)))
            w_hi = merge(2.0_wp, 1.0_wp, on_boundary(grid, d, i * o(1) + j * o(2) + k * o(3) + 1))
            state%diag(i, j, k) = state%diag(i, j, k) + state%coef(i, j, k, d) * w_lo + &
              state%coef(i + o(1), j + o(2), k + o(3), d) * w_hi
          end do
        end do
      end do
      ! a loading platen: dp of the inner cell pushes the platen and the skeleton behind it
      ! outward by theta dt c dp (`solid_face_predictor`), and the outward volume flux with it
      if (.not. present(solid)) cycle
      area = grid%cell_volume / grid%dx(d)
      side = 0
      do while (next_platen_face(solid, grid, d, side, i, j, k))
        c = [i, j, k] - merge(o, 0, side == 2)
        state%diag(c(1), c(2), c(3)) = state%diag(c(1), c(2), c(3)) + theta * dt**2 * area * &
          solid%platen_coef(i, j, k, d)
      end do
    end do
  end subroutine ice_pressure_assemble

  !> Right-hand side of eq. 35 with the current face velocities and dp_total; returns this
  !! rank's max |rhs|/V (the volume-fraction constraint residual). One sweep per direction and
  !! material, each cell's sum in the order of a per-cell loop over the directions and
  !! materials; each face's volume flux once per row of faces (`ice_pressure_flux`).
  function ice_pressure_rhs(state, grid, dt, solid) result(residual)
    type(ice_state_t), intent(inout) :: state  !< fluids and pressure fields
    type(grid_t), intent(in) :: grid           !< block geometry
    real(wp), intent(in) :: dt                 !< time step [s]
    !> the solid phase of a coupled scene: its volume flux (phi_s,f u_s,f and the rigid
    !! bodies' prescribed flux) and its fraction source join the right-hand side
    class(ice_solid_view_t), intent(in), optional :: solid
    real(wp) :: residual
    integer :: d, m, i, j, k, o(3)
    real(wp) :: area

    do k = grid%lo(3), grid%hi(3)
      do j = grid%lo(2), grid%hi(2)
        do i = grid%lo(1), grid%hi(1)
          state%rhs(i, j, k) = -grid%cell_volume * state%sum_kappa(i, j, k) * &
            state%dp_total(i, j, k)
        end do
      end do
    end do
    do d = 1, 3
      if (.not. sweep_direction(grid, d, o, area)) cycle
      do m = 1, state%nfluids
        call volume_flux_rows(grid, dt * area, d, state%rhs, state%work%flux_lo, &
          state%work%flux_hi, fluid=state%fluid(m))
      end do
      if (present(solid)) call solid_volume_flux(state, solid, grid, dt, d, o, area)
    end do
    if (present(solid)) then
      ! a coupled scene: solid volume the particles hold beyond the tracked fraction
      associate (source => solid%source)
        do k = grid%lo(3), grid%hi(3)
          do j = grid%lo(2), grid%hi(2)
            do i = grid%lo(1), grid%hi(1)
              state%rhs(i, j, k) = state%rhs(i, j, k) + grid%cell_volume * source(i, j, k)
            end do
          end do
        end do
      end associate
    end if
    residual = 0.0_wp
    do k = grid%lo(3), grid%hi(3)
      do j = grid%lo(2), grid%hi(2)
        do i = grid%lo(1), grid%hi(1)
          residual = max(residual, abs(state%rhs(i, j, k)) / grid%cell_volume)
        end do
      end do
    end do
  end function ice_pressure_rhs

  !> The solid phase's part of the operator's low-face coefficients of direction `d`
  !! (`ice_pressure_assemble`): the open domain planes' shift and phi_s,f v_s,f.
  subroutine solid_coefficients(state, solid, grid, d, o, r)
    type(ice_state_t), intent(inout) :: state        !< coefficients (coef updated)
    class(ice_solid_view_t), intent(in) :: solid     !< solid phase of a coupled scene
    type(grid_t), intent(in) :: grid                 !< block geometry
    integer, intent(in) :: d                         !< face direction
    integer, intent(in) :: o(3)                      !< unit offset of d
    integer, intent(in) :: r(2, 3)                   !< face range of d
    integer :: i, j, k, side, lo(3), hi(3)
    do side = 1, 2
      if (.not. held_plane(grid, d, r, side, lo, hi, .not. state%closed)) cycle
      do k = lo(3), hi(3)
        do j = lo(2), hi(2)
          do i = lo(1), hi(1)
            state%coef(i, j, k, d) = state%coef(i, j, k, d) + &
              open_face_shift(state, d, o, i, j, k, side == 2, .false.)
          end do
        end do
      end do
    end do
    ! the solid's phi_s,f v_s,f (phi_s,f the fraction that crosses, `solid_face_fraction`)
    associate (us => solid%uface, low => solid%face_fraction, &
      high => solid%face_fraction_hi, vs => solid%vface)
      do k = r(1, 3), r(2, 3)
        do j = r(1, 2), r(2, 2)
          do i = r(1, 1), r(2, 1)
            state%coef(i, j, k, d) = state%coef(i, j, k, d) + flux_fraction(us(i, j, k, d), &
              low(i, j, k, d), high(i, j, k, d)) * vs(i, j, k, d)
          end do
        end do
      end do
    end associate
  end subroutine solid_coefficients

  !> The solid phase's part of the right-hand side of direction `d` (`ice_pressure_rhs`): the
  !! open domain planes' shift, the solid's volume flux phi_s,f u_s,f and the rigid bodies'.
  subroutine solid_volume_flux(state, solid, grid, dt, d, o, area)
    type(ice_state_t), intent(inout) :: state        !< right-hand side (rhs updated)
    class(ice_solid_view_t), intent(in) :: solid     !< solid phase of a coupled scene
    type(grid_t), intent(in) :: grid                 !< block geometry
    real(wp), intent(in) :: dt                       !< time step [s]
    integer, intent(in) :: d                         !< face direction
    integer, intent(in) :: o(3)                      !< unit offset of d
    real(wp), intent(in) :: area                     !< face area [m^2]
    integer :: i, j, k, side, lo(3), hi(3), c(3), r(2, 3)
    r = face_range(grid, d)
    do side = 1, 2
      if (.not. held_plane(grid, d, r, side, lo, hi, .not. state%closed)) cycle
      ! the plane's cells: above the low plane, below the high one (outward flux sign)
      do k = lo(3), hi(3)
        do j = lo(2), hi(2)
          do i = lo(1), hi(1)
            c = [i, j, k] - merge(o, 0, side == 2)
            state%rhs(c(1), c(2), c(3)) = state%rhs(c(1), c(2), c(3)) - dt * area * &
              merge(1.0_wp, -1.0_wp, side == 2) * &
              open_face_shift(state, d, o, i, j, k, side == 2, .true.)
          end do
        end do
      end do
    end do
    ! the solid's volume flux phi_s,f u_s,f and the rigid bodies' prescribed one
    call volume_flux_rows(grid, dt * area, d, state%rhs, state%work%flux_lo, &
      state%work%flux_hi, solid=solid)
  end subroutine solid_volume_flux

  !> A failed outer iteration: the rank that holds the cell of the largest |rhs|/V (`residual`,
  !! the global maximum) writes one line on standard error with the cell's centre [m], its
  !! residual, the fractions of the solid (tracked, and the particles' excess as `source`) and
  !! of each fluid, the pressure [Pa], dp_total [Pa] and the operator's diagonal: where and why
  !! the volume constraint could not be met.
  subroutine report_pressure_failure(state, grid, residual, solid)
    type(ice_state_t), intent(in) :: state  !< fields after the last outer iteration
    type(grid_t), intent(in) :: grid        !< block geometry
    real(wp), intent(in) :: residual        !< global max |rhs|/V
    class(ice_solid_view_t), intent(in), optional :: solid !< solid phase of a coupled scene
    character(len=:), allocatable :: text
    integer :: c(3), d, m
    c = maxloc(abs(state%rhs(grid%lo(1):grid%hi(1), grid%lo(2):grid%hi(2), &
      grid%lo(3):grid%hi(3)))) + grid%lo - 1
    if (abs(state%rhs(c(1), c(2), c(3))) / grid%cell_volume < residual) return
    text = 'mpmice: warning: pressure constraint worst in the cell at'
    do d = 1, grid%ndim
      text = text // ' ' // real_short_text(cell_centre(grid, d, c(d)))
    end do
    text = text // ' m: |rhs|/V ' // real_short_text(residual) // ','
    if (present(solid)) text = text // ' solid fraction ' // &
      real_short_text(solid%vfrac(c(1), c(2), c(3))) // ' source ' // &
      real_short_text(solid%source(c(1), c(2), c(3))) // ','
    do m = 1, state%nfluids
      text = text // ' ' // trim(state%fluid(m)%name) // ' fraction ' // &
        real_short_text(state%fluid(m)%vfrac(c(1), c(2), c(3))) // ','
    end do
    text = text // ' pressure ' // real_short_text(state%pressure(c(1), c(2), c(3))) // &
      ' Pa, dp_total ' // real_short_text(state%dp_total(c(1), c(2), c(3))) // &
      ' Pa, diagonal ' // real_short_text(state%diag(c(1), c(2), c(3)))
    call log_repeated(text)
  end subroutine report_pressure_failure

  !> After a solve (dp valid in one ghost layer): p += dp, dp_total += dp on the owned cells and
  !! u_m,f -= dt v_m,f (dp_R - dp_L)/dx on the faces of the owned cells; on a loading platen the
  !! solid's u_s,f += theta dt c dp (outward, c = `platen_coef`) and the fluids' follow it.
  subroutine ice_pressure_correct(state, grid, dt, theta, solid)
    type(ice_state_t), intent(inout) :: state  !< fluids and pressure fields
    type(grid_t), intent(in) :: grid           !< block geometry
    real(wp), intent(in) :: dt                 !< time step [s]
    real(wp), intent(in) :: theta              !< implicit weight of the pressure change
    !> the solid phase of a coupled scene: its face velocity corrected as well
    class(ice_solid_view_t), intent(inout), optional :: solid
    integer :: d, m, i, j, k, o(3), r(2, 3), side, c(3)
    real(wp) :: g

    associate (lo => grid%lo, hi => grid%hi)
      state%pressure(lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)) = &
        state%pressure(lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)) + &
        state%dp(lo(1):hi(1), lo(2):hi(2), lo(3):hi(3))
      state%dp_total(lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)) = &
        state%dp_total(lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)) + &
        state%dp(lo(1):hi(1), lo(2):hi(2), lo(3):hi(3))
    end associate
    do d = 1, 3
      if (.not. sweep_direction(grid, d, o)) cycle
      ! the closed domain faces (whole planes) keep their velocities
      r = open_face_range(state, grid, d)
      do m = 1, state%nfluids
        associate (f => state%fluid(m))
          do k = r(1, 3), r(2, 3)
            do j = r(1, 2), r(2, 2)
              do i = r(1, 1), r(2, 1)
                g = theta * (state%dp(i, j, k) - state%dp(i - o(1), j - o(2), k - o(3))) / &
                  grid%dx(d)
                f%uface(i, j, k, d) = f%uface(i, j, k, d) - dt * f%vface(i, j, k, d) * g
              end do
            end do
          end do
        end associate
      end do
      if (.not. present(solid)) cycle
      do k = r(1, 3), r(2, 3)
        do j = r(1, 2), r(2, 2)
          do i = r(1, 1), r(2, 1)
            g = theta * (state%dp(i, j, k) - state%dp(i - o(1), j - o(2), k - o(3))) / grid%dx(d)
            solid%uface(i, j, k, d) = solid%uface(i, j, k, d) - &
              dt * solid%vface(i, j, k, d) * g
          end do
        end do
      end do
      ! loading platens: the skeleton's face velocity with the inner cell's dp (outward for
      ! dp > 0), the fluids' from it
      side = 0
      do while (next_platen_face(solid, grid, d, side, i, j, k))
        c = [i, j, k] - merge(o, 0, side == 2)
        solid%uface(i, j, k, d) = solid%uface(i, j, k, d) + merge(1.0_wp, -1.0_wp, side == 2) * &
          theta * dt * solid%platen_coef(i, j, k, d) * state%dp(c(1), c(2), c(3))
      end do
    end do
    call platen_fluid_faces(state, grid, solid)
  end subroutine ice_pressure_correct

  !> Fluid face velocities of the loading platens (`ice_solid_view_t%platen`: a closed domain
  !! face where the skeleton carries a surface load). The platen is impermeable and moves with
  !! the skeleton (no relative flow through it), so the mixture's outward volume flux there is
  !! the solid's face velocity u_s. The solid crosses the plane with its own flux phi_s,f u_s
  !! (`solid_face_fraction`: none while the skeleton moves inward, its particles staying inside
  !! the domain); the fluids fill the rest: each gets u = (1 - phi_s,f) u_s / sum_m phi_m,up,
  !! phi_m,up the upwind fractions of eq. 35. Without solid at the face (u_s = 0) a plain wall.
  subroutine platen_fluid_faces(state, grid, solid)
    type(ice_state_t), intent(inout) :: state  !< fluids (uface on platen faces written)
    type(grid_t), intent(in) :: grid           !< block geometry
    class(ice_solid_view_t), intent(in), optional :: solid !< solid phase of a coupled scene
    integer :: d, m, i, j, k, o(3), side
    real(wp) :: us, phi_up, u
    if (.not. present(solid)) return
    if (.not. any(solid%platen)) return
    do d = 1, 3
      if (.not. sweep_direction(grid, d, o)) cycle
      side = 0
      do while (next_platen_face(solid, grid, d, side, i, j, k))
        us = solid%uface(i, j, k, d)
        phi_up = 0.0_wp
        do m = 1, state%nfluids
          phi_up = phi_up + merge(state%fluid(m)%vfrac(i - o(1), j - o(2), k - o(3)), &
            state%fluid(m)%vfrac(i, j, k), us >= 0.0_wp)
        end do
        u = 0.0_wp
        if (phi_up > pore_min) u = (1.0_wp - solid_face_fraction(solid, d, o, i, j, k)) * us / &
          phi_up
        do m = 1, state%nfluids
          state%fluid(m)%uface(i, j, k, d) = u
        end do
      end do
    end do
  end subroutine platen_fluid_faces

  !> The next face of the loading platens of direction `d` that this rank holds
  !! (`ice_solid_view_t%platen`), the low plane before the high one, then k, j, i: a sweep reads `side = 0`
  !! then `do while (next_platen_face(solid, grid, d, side, i, j, k))`; false after the last.
  logical function next_platen_face(solid, grid, d, side, i, j, k) result(more)
    class(ice_solid_view_t), intent(in) :: solid !< solid phase
    type(grid_t), intent(in) :: grid        !< block geometry
    integer, intent(in) :: d                !< face direction
    integer, intent(inout) :: side          !< plane of the face (0 before the first face)
    integer, intent(inout) :: i, j, k       !< face index
    integer :: lo(3), hi(3)
    more = .true.
    if (side > 0) then
      more = held_plane(grid, d, face_range(grid, d), side, lo, hi, solid%platen)
      if (box_step(lo, hi, i, j, k)) return
    end if
    do while (side < 2)
      side = side + 1
      if (.not. held_plane(grid, d, face_range(grid, d), side, lo, hi, solid%platen)) cycle
      i = lo(1)
      j = lo(2)
      k = lo(3)
      return
    end do
    more = .false.
  end function next_platen_face

  !> Advance (i, j, k) to the next index of the box `lo`..`hi`, i fastest; false past its last
  !! index.
  logical function box_step(lo, hi, i, j, k) result(inside)
    integer, intent(in) :: lo(3), hi(3)     !< corners of the box
    integer, intent(inout) :: i, j, k       !< index
    inside = .true.
    i = i + 1
    if (i <= hi(1)) return
    i = lo(1)
    j = j + 1
    if (j <= hi(2)) return
    j = lo(2)
    k = k + 1
    inside = k <= hi(3)
  end function box_step

  !> Solid volume fraction of the low face of cell (i,j,k) in direction d for the solid's
  !! volume flux of eq. 35: the grain fraction the particles place on the upwind side of the face
  !! plane (`mpmice_solid_cells`), so that the flux phi_s,f u_s,f is the grain volume that
  !! actually crosses the face: zero where a free surface of the soil moves away from the face,
  !! the full fraction inside a body (a cell-averaged upwind value is wrong at such a surface).
  pure real(wp) function solid_face_fraction(solid, d, o, i, j, k) result(phi)
    class(ice_solid_view_t), intent(in) :: solid !< solid phase
    integer, intent(in) :: d                !< face direction
    integer, intent(in) :: o(3)             !< unit offset along d (unused: kept for symmetry)
    integer, intent(in) :: i, j, k          !< face index (low face of cell i,j,k)
    if (.false.) phi = real(o(1), wp)
    phi = flux_fraction(solid%uface(i, j, k, d), solid%face_fraction(i, j, k, d), &
      solid%face_fraction_hi(i, j, k, d))
  end function solid_face_fraction

  !> True when face `idx` (global index along d) lies on a non-periodic domain boundary
  !! (`boundary_face` for one index, without the index vector).
  pure logical function on_boundary(grid, d, idx)
    type(grid_t), intent(in) :: grid  !< block geometry
    integer, intent(in) :: d          !< face direction
    integer, intent(in) :: idx        !< face index along d
    on_boundary = .not. grid%periodic(d) .and. (idx == 1 .or. idx == grid%ncells(d) + 1)
  end function on_boundary

  !> Zero the entries of a face field on the closed domain faces of direction d (`closed_face`)
  !! within the face range r of this rank.
  subroutine zero_closed_faces(state, grid, d, r, face)
    type(ice_state_t), intent(in) :: state  !< fluids (closed faces)
    type(grid_t), intent(in) :: grid        !< block geometry
    integer, intent(in) :: d                !< face direction
    integer, intent(in) :: r(2, 3)          !< face range of this rank
    real(wp), intent(inout) :: face(grid%lbc(1):, grid%lbc(2):, grid%lbc(3):) !< face field
    integer :: side, idx, lo(3), hi(3)
    if (grid%periodic(d)) return
    do side = 1, 2
      idx = merge(1, grid%ncells(d) + 1, side == 1)
      if (.not. state%closed(2 * d - 2 + side)) cycle
      if (idx < r(1, d) .or. idx > r(2, d)) cycle
      lo = r(1, :)
      hi = r(2, :)
      lo(d) = idx
      hi(d) = idx
      face(lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)) = 0.0_wp
    end do
  end subroutine zero_closed_faces

  !> Open domain face of a scene with a solid phase: sum over the fluids of (phi_inner -
  !! phi_upwind) w, w the face specific volume (coefficient) or the face velocity (flux). The
  !! ghosts beyond an open face hold a free-fluid reservoir (mpmice `open_face_reservoirs`);
  !! the fluid crosses the face through the pores of the inner cell in either direction (the
  !! face's control volume is the inner half cell, as for the face exchange), so its face
  !! fraction is the inner cell's. The upwind reservoir fraction (1 instead of the porosity
  !! whenever the flow turned inward) grew an odd-even pressure mode at the drained face of a
  !! consolidation column at small time steps (docs/accuracy.md, stability map (a)).
  pure real(wp) function open_face_shift(state, d, o, i, j, k, inner_low, by_velocity) &
    result(shift)
    type(ice_state_t), intent(in) :: state  !< fluids
    integer, intent(in) :: d                !< face direction
    integer, intent(in) :: o(3)             !< unit offset along d
    integer, intent(in) :: i, j, k          !< face (low face of cell i, j, k)
    logical, intent(in) :: inner_low        !< the inner cell is the low one (high plane)
    logical, intent(in) :: by_velocity      !< weight: face velocity (else specific volume)
    integer :: m
    real(wp) :: u, lo_frac, hi_frac
    shift = 0.0_wp
    do m = 1, state%nfluids
      associate (f => state%fluid(m))
        u = f%uface(i, j, k, d)
        lo_frac = f%vfrac(i - o(1), j - o(2), k - o(3))
        hi_frac = f%vfrac(i, j, k)
        shift = shift + (merge(lo_frac, hi_frac, inner_low) - merge(lo_frac, hi_frac, &
          u >= 0.0_wp)) * merge(u, f%vface(i, j, k, d), by_velocity)
      end associate
    end do
  end function open_face_shift
end module ice_pressure
