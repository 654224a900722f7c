!> The solid's face velocities of a coupled scene and their way back to the MPM nodes (paper
!! eqs. 32-33, 52, 66-67 with errata E5).
!!
!! * Face velocity (eqs. 32-33): the mass-weighted mean of the MPM velocities v^{L-} (eq. 41,
!!   effective stress, gravity and loads) of the face's nodes, minus dt v_s grad p (v_s the grain
!!   specific volume); then the face exchange (eq. 34) and the outer pressure iteration correct
!!   it. Departure from eq. 33: the stress term comes from the nodes (the same forces MPM uses)
!!   instead of the cell-centred stress difference.
!! * Back to the nodes (eqs. 52, 66-67 with errata E5): each node adds the mean increment
!!   (final - nodal face velocity) of the faces it belongs to, then the solid boundary
!!   conditions and eq. 69 a = (v^L - v^n)/dt. In 1D a face is a node, so the particles move
!!   exactly with the velocities the pressure equation used.
module mpmice_face_nodes
  use mpmice_kinds, only: wp
  use grid_layout, only: grid_t
  use grid_sweep, only: sweep_direction
  use parallel_domain, only: domain_t
  use parallel_halo, only: halo_t, halo_exchange_node_vec
  use mpm_nodes, only: mpm_nodes_t, node_mass, node_rigid_mass, node_rigid_momentum
  use ice_state, only: ice_state_t
  use exchange_solid_phase, only: solid_phase_t
  use ice_face_velocity, only: face_range, closed_face, face_index
  use mpmice_rigid_contact, only: body_face
  implicit none
  private

  public :: solid_face_predictor, solid_face_to_nodes

contains

  !> Nodal face velocity u_s,f0 (mass-weighted mean of the face nodes' v^{L-}), the predictor
  !! u_s,f = u_s,f0 - dt v_s (p_R - p_L)/dx (eq. 33, pressure part) on faces where the solid
  !! moves freely, and the rigid-face flags. Faces of the owned cells. With sliding rigid bodies
  !! (`solid_phase_t%sliding`) a face next to a wall cell, or with solid but none of it
  !! deformable (`mpmice_rigid_contact%body_face`), is a wall that moves with the rigid body
  !! (prescribed: the fluids cannot enter the body, whose cells have almost no pore volume); any
  !! other face carries the deformable solid (its mass-weighted nodal velocity); the rigid
  !! bodies' volume flux phi_r,f u_r,f (upwind plane fraction, rigid momentum over mass at the
  !! face's nodes) is kept apart in `rigid_flux`. On a loading platen
  !! (`solid_phase_t%platen`) the face nodes get the pore fluid's share of the load.
  subroutine solid_face_predictor(state, solid, grid, nodes, dt, min_mass)
    type(ice_state_t), intent(inout) :: state   !< solid phase face fields written
    type(solid_phase_t), intent(inout) :: solid !< solid phase
    type(grid_t), intent(in) :: grid            !< block geometry
    type(mpm_nodes_t), intent(in) :: nodes      !< node fields (vel_l = v^{L-})
    real(wp), intent(in) :: dt                  !< time step [s]
    real(wp), intent(in) :: min_mass            !< empty-node threshold [kg]
    integer :: d, i, j, k, o(3), r(2, 3), span(3), a, b, e, n(3), face, inner(3)
    real(wp) :: m, mv, mi, vl, vr, v, mr, mvr, ur
    logical :: rigid
    associate (sp => solid)
      do d = 1, 3
        if (.not. sweep_direction(grid, d, o)) cycle
        span = merge(1, 0, grid%active)
        span(d) = 0
        r = face_range(grid, d)
        do k = r(1, 3), r(2, 3)
          do j = r(1, 2), r(2, 2)
            do i = r(1, 1), r(2, 1)
              m = 0.0_wp
              mv = 0.0_wp
              mr = 0.0_wp
              mvr = 0.0_wp
              rigid = .false.
              do e = 0, span(3)
                do b = 0, span(2)
                  do a = 0, span(1)
                    n = [i + a, j + b, k + e]
                    if (nodes%q(node_rigid_mass, n(1), n(2), n(3)) > min_mass) rigid = .true.
                    if (sp%sliding) then
                      if (nodes%q(node_rigid_mass, n(1), n(2), n(3)) > min_mass) then
                        mr = mr + nodes%q(node_rigid_mass, n(1), n(2), n(3))
                        mvr = mvr + nodes%q(node_rigid_momentum + d - 1, n(1), n(2), n(3))
                      end if
                      mi = nodes%q(node_mass, n(1), n(2), n(3))
                    else
                      mi = nodes%q(node_mass, n(1), n(2), n(3)) + &
                        nodes%q(node_rigid_mass, n(1), n(2), n(3))
                    end if
                    if (mi <= min_mass) cycle
                    m = m + mi
                    mv = mv + mi * nodes%vel_l(d, n(1), n(2), n(3))
                  end do
                end do
              end do
              sp%uface0(i, j, k, d) = 0.0_wp
              if (m > 0.0_wp) sp%uface0(i, j, k, d) = mv / m
              if (sp%sliding) then
                ur = 0.0_wp
                if (mr > 0.0_wp) ur = mvr / mr
                ! a face next to a wall cell, or with solid but no deformable solid on either
                ! side, moves with the rigid body
                rigid = body_face(sp, [i, j, k] - o, [i, j, k])
                if (rigid) sp%uface0(i, j, k, d) = ur
                sp%rigid_flux(i, j, k, d) = 0.0_wp
                if (.not. closed_face(state, grid, d, [i, j, k])) sp%rigid_flux(i, j, k, d) = &
                  ur * merge(sp%rigid_fraction(i, j, k, d), sp%rigid_fraction_hi(i, j, k, d), &
                  ur >= 0.0_wp)
              end if
              sp%uface(i, j, k, d) = sp%uface0(i, j, k, d)
              sp%rigid_face(i, j, k, d) = merge(1.0_wp, 0.0_wp, rigid)
              sp%vface(i, j, k, d) = 0.0_wp
              sp%platen_coef(i, j, k, d) = 0.0_wp
              if (.not. rigid .and. m > 0.0_wp .and. closed_face(state, grid, d, [i, j, k])) then
                face = face_index(d, [i, j, k])
                if (sp%platen(face)) then
                  ! a loading platen: the inner cell's pore pressure above the outside pressure
                  ! pushes the face's nodes outward (the pore fluid's share of the load), with
                  ! acceleration (p - p_b) A / M, M the face's share of its nodes' mass
                  ! (`platen_face_mass`); dp implicitly (ice_pressure)
                  inner = [i, j, k] - merge(o, 0, mod(face, 2) == 0)
                  sp%platen_coef(i, j, k, d) = grid%cell_volume / grid%dx(d) / &
                    platen_face_mass(sp%sliding, grid, nodes, d, [i, j, k], span, min_mass)
                  sp%uface(i, j, k, d) = sp%uface(i, j, k, d) + merge(1.0_wp, -1.0_wp, &
                    mod(face, 2) == 0) * dt * sp%platen_coef(i, j, k, d) * &
                    (state%pressure(inner(1), inner(2), inner(3)) - state%p_boundary(face))
                end if
              end if
              if (rigid .or. closed_face(state, grid, d, [i, j, k])) cycle
              vl = sp%spvol(i - o(1), j - o(2), k - o(3))
              vr = sp%spvol(i, j, k)
              if (sp%sliding) then
                ! the deformable solid's grains only
                if (sp%frac_def(i - o(1), j - o(2), k - o(3)) <= 0.0_wp) vl = 0.0_wp
                if (sp%frac_def(i, j, k) <= 0.0_wp) vr = 0.0_wp
              end if
              if (vl > 0.0_wp .and. vr > 0.0_wp) then
                v = 0.5_wp * (vl + vr)
              else
                v = max(vl, vr)
              end if
              sp%vface(i, j, k, d) = v
              sp%uface(i, j, k, d) = sp%uface(i, j, k, d) - dt * v * &
                (state%pressure(i, j, k) - state%pressure(i - o(1), j - o(2), k - o(3))) / &
                grid%dx(d)
            end do
          end do
        end do
      end do
    end associate
  end subroutine solid_face_predictor

  !> Mass [kg] a loading platen's face (direction d, index c) pushes: each of its nodes' solid
  !! mass shared equally among the domain faces of that plane the node belongs to (1 in 1D, up
  !! to 2 in 2D, 4 in 3D), so the faces of a plane share its nodes' mass exactly and a uniform
  !! pressure gives every node the same acceleration (p - p_b) A / M, edges included.
  pure real(wp) function platen_face_mass(sliding, grid, nodes, d, c, span, min_mass) &
    result(mass)
    logical, intent(in) :: sliding              !< rigid bodies slide (deformable mass only)
    type(grid_t), intent(in) :: grid            !< block geometry
    type(mpm_nodes_t), intent(in) :: nodes      !< node fields
    integer, intent(in) :: d                    !< face direction
    integer, intent(in) :: c(3)                 !< face index
    integer, intent(in) :: span(3)              !< node offsets across the face (0 or 1)
    real(wp), intent(in) :: min_mass            !< empty-node threshold [kg]
    integer :: a, b, e, n(3), t, faces
    real(wp) :: mi
    mass = 0.0_wp
    do e = 0, span(3)
      do b = 0, span(2)
        do a = 0, span(1)
          n = c + [a, b, e]
          mi = nodes%q(node_mass, n(1), n(2), n(3))
          if (.not. sliding) mi = mi + nodes%q(node_rigid_mass, n(1), n(2), n(3))
          if (mi <= min_mass) cycle
          faces = 1
          do t = 1, 3
            if (t == d .or. .not. grid%active(t)) cycle
            if (grid%periodic(t)) then
              faces = faces * 2
            else
              faces = faces * (count([n(t) - 1, n(t)] >= 1 .and. [n(t) - 1, n(t)] <= &
                grid%ncells(t)))
            end if
          end do
          mass = mass + mi / real(max(faces, 1), wp)
        end do
      end do
    end do
  end function platen_face_mass

  !> Eqs. 52, 66-67 (E5) through the faces: every node with solid mass adds the mean of the
  !! increments u_s,f - u_s,f0 of the faces it belongs to. `du` is node-shaped scratch
  !! (3, lbn..ubn): the face of direction d with index i along d and cell indices across sits at
  !! node index (i, j, k), so the node halo exchange fills it everywhere in the domain, domain
  !! faces included. The caller applies the boundary conditions and eq. 69 afterwards. With
  !! sliding rigid bodies the nodes touching one (contact nodes) take the increments too, and
  !! faces that carry the rigid body (prescribed, flag in du(3 + d)) do not count in the mean.
  subroutine solid_face_to_nodes(solid, grid, dom, halo, nodes, du, min_mass)
    type(solid_phase_t), intent(in) :: solid !< solid phase
    type(grid_t), intent(in) :: grid            !< block geometry
    type(domain_t), intent(in) :: dom           !< decomposition
    type(halo_t), intent(inout) :: halo         !< halo buffers (>= 3 components)
    type(mpm_nodes_t), intent(inout) :: nodes   !< vel_l updated
    real(wp), intent(inout) :: du(:, grid%lbn(1):, grid%lbn(2):, grid%lbn(3):) !< scratch
                                                !! (6 components)
    real(wp), intent(in) :: min_mass            !< empty-node threshold [kg]
    integer :: d, i, j, k, r(2, 3), span(3), a, b, e, c(3), cnt
    real(wp) :: s
    logical :: sliding
    sliding = solid%sliding
    du = 0.0_wp
    do d = 1, 3
      if (.not. grid%active(d)) cycle
      r = face_range(grid, d)
      do k = r(1, 3), r(2, 3)
        do j = r(1, 2), r(2, 2)
          do i = r(1, 1), r(2, 1)
            du(d, i, j, k) = solid%uface(i, j, k, d) - solid%uface0(i, j, k, d)
            du(3 + d, i, j, k) = solid%rigid_face(i, j, k, d)
          end do
        end do
      end do
    end do
    call halo_exchange_node_vec(halo, dom, grid, du)
    do d = 1, 3
      if (.not. grid%active(d)) cycle
      span = merge(1, 0, grid%active)
      span(d) = 0
      do k = grid%lbn(3), grid%ubn(3)
        do j = grid%lbn(2), grid%ubn(2)
          do i = grid%lbn(1), grid%ubn(1)
            if (nodes%q(node_mass, i, j, k) <= min_mass) cycle
            if (nodes%q(node_rigid_mass, i, j, k) > min_mass .and. .not. sliding) cycle
            s = 0.0_wp
            cnt = 0
            do e = 0, span(3)
              do b = 0, span(2)
                do a = 0, span(1)
                  c = [i - a, j - b, k - e]
                  if (.not. face_exists(grid, d, c)) cycle
                  if (sliding .and. du(3 + d, c(1), c(2), c(3)) > 0.5_wp) cycle
                  s = s + du(d, c(1), c(2), c(3))
                  cnt = cnt + 1
                end do
              end do
            end do
            if (cnt > 0) nodes%vel_l(d, i, j, k) = nodes%vel_l(d, i, j, k) + s / real(cnt, wp)
          end do
        end do
      end do
    end do
  end subroutine solid_face_to_nodes

  !> True when the face (direction d, index c: node index along d, cell indices across) lies in
  !! the domain and in the node allocation.
  pure logical function face_exists(grid, d, c) result(ok)
    type(grid_t), intent(in) :: grid  !< block geometry
    integer, intent(in) :: d          !< face direction
    integer, intent(in) :: c(3)       !< face index
    integer :: e
    ok = .true.
    do e = 1, 3
      if (.not. grid%active(e)) cycle
      if (c(e) < grid%lbn(e) .or. c(e) > grid%ubn(e)) ok = .false.
      if (grid%periodic(e)) cycle
      if (e == d) then
        if (c(e) < 1 .or. c(e) > grid%ncells(e) + 1) ok = .false.
      else
        if (c(e) < 1 .or. c(e) > grid%ncells(e)) ok = .false.
      end if
    end do
  end function face_exists
end module mpmice_face_nodes
