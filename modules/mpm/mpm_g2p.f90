!> Grid-to-particle update of one solid material (eqs. 70-75 with errata E6: sums over S_ip):
!! velocity (FLIP/PIC blend), position, velocity gradient, deformation gradient, volume, then
!! the constitutive update.
!!   FLIP: v_p <- v_p + sum S_ip a_i dt (eq. 70);  PIC: v_p <- sum S_ip v^L_i
!!   v_p <- flip v_FLIP + (1 - flip) v_PIC  (`&mpm flip_fraction`)
!!   APIC (`&mpm velocity_transfer = 'apic'`, a store with `has_affine`; Jiang et al. 2015):
!!   v_p <- v_PIC,  C_p = B_p D_p^-1,  B_p = sum S_ip v^L_i (x_i - x_p)^T,
!!   D_p = sum S_ip (x_i - x_p)(x_i - x_p)^T (diagonal for tensor-product shape functions)
!!   x_p <- x_p + sum S_ip v^L_i dt (eq. 71);  L_p = sum v^L_i (grad S_ip)^T (eq. 72)
!!   F_p <- (I + L_p dt) F_p (eq. 74);  V_p = det(F_p) V_p^0 (eq. 75)
!! Temperature (eq. 73) is unchanged in the solid-only scene (no heat sources).
module mpm_g2p
  use mpmice_kinds, only: wp
  use grid_layout, only: grid_t
  use particles_store, only: particles_t
  use mpm_shape, only: particle_stencil, max_stencil, node_offsets
  use mpm_nodes, only: mpm_nodes_t
  use mpm_tensor, only: det3, mul3
  use mpm_constitutive, only: material_t, constitutive_update, model_rigid
  implicit none
  private

  public :: g2p_update

contains

  !> Update every particle of `p` from the solved node fields.
  subroutine g2p_update(p, nodes, mat, kind, grid, dt, flip)
    type(particles_t), intent(inout) :: p        !< particles
    type(mpm_nodes_t), intent(in) :: nodes       !< solved node fields
    type(material_t), intent(in) :: mat          !< constitutive model
    integer, intent(in) :: kind                  !< shape_linear or shape_gimp
    type(grid_t), intent(in) :: grid             !< block geometry
    real(wp), intent(in) :: dt                   !< step [s]
    real(wp), intent(in) :: flip                 !< FLIP fraction 0..1
    call g2p_particles(p, nodes, nodes%acc, nodes%vel_l, mat, kind, grid, dt, flip)
  end subroutine g2p_update

  !> `g2p_update` with the node accelerations and velocities as explicit-shape arrays (their
  !! bounds in registers: through the node store's descriptors the gather cost a third more).
  subroutine g2p_particles(p, nodes, acc, vel_l, mat, kind, grid, dt, flip)
    type(particles_t), intent(inout) :: p        !< particles
    type(mpm_nodes_t), intent(in) :: nodes       !< solved node fields (APIC's affine part)
    type(grid_t), intent(in) :: grid             !< block geometry
    real(wp), intent(in) :: acc(3, grid%lbn(1):grid%ubn(1), grid%lbn(2):grid%ubn(2), &
      grid%lbn(3):grid%ubn(3))                   !< node accelerations a [m/s^2]
    real(wp), intent(in) :: vel_l(3, grid%lbn(1):grid%ubn(1), grid%lbn(2):grid%ubn(2), &
      grid%lbn(3):grid%ubn(3))                   !< node velocities v^L [m/s]
    type(material_t), intent(in) :: mat          !< constitutive model
    integer, intent(in) :: kind                  !< shape_linear or shape_gimp
    real(wp), intent(in) :: dt                   !< step [s]
    real(wp), intent(in) :: flip                 !< FLIP fraction 0..1
    integer :: ip, i, j, k, a, b, c, first(3), nn(3)
    real(wp) :: w(max_stencil, 3), dw(max_stencil, 3), s, g(3), wjk, gjk(3)
    real(wp) :: ap(3), vlp(3), l(3, 3), f(3, 3), fnew(3, 3), vl(3), gap
    ! the sums in scalars (kept in registers; as arrays they went through memory every node)
    real(wp) :: ax, ay, az, px, py, pz, l11, l21, l31, l12, l22, l32, l13, l23, l33
    do ip = 1, p%np
      call particle_stencil(kind, grid, p%x(:, ip), p%half_width, first, nn, w, dw)
      ax = 0.0_wp
      ay = 0.0_wp
      az = 0.0_wp
      px = 0.0_wp
      py = 0.0_wp
      pz = 0.0_wp
      l11 = 0.0_wp
      l21 = 0.0_wp
      l31 = 0.0_wp
      l12 = 0.0_wp
      l22 = 0.0_wp
      l32 = 0.0_wp
      l13 = 0.0_wp
      l23 = 0.0_wp
      l33 = 0.0_wp
      do c = 1, nn(3)
        k = first(3) + c - 1
        do b = 1, nn(2)
          j = first(2) + b - 1
          wjk = w(b, 2) * w(c, 3)
          gjk(2) = dw(b, 2) * w(c, 3)
          gjk(3) = w(b, 2) * dw(c, 3)
          do a = 1, nn(1)
            i = first(1) + a - 1
            s = w(a, 1) * wjk
            g(1) = dw(a, 1) * wjk
            g(2) = w(a, 1) * gjk(2)
            g(3) = w(a, 1) * gjk(3)
            vl = vel_l(:, i, j, k)
            ax = ax + s * acc(1, i, j, k)
            ay = ay + s * acc(2, i, j, k)
            az = az + s * acc(3, i, j, k)
            px = px + s * vl(1)
            py = py + s * vl(2)
            pz = pz + s * vl(3)
            l11 = l11 + vl(1) * g(1)
            l21 = l21 + vl(2) * g(1)
            l31 = l31 + vl(3) * g(1)
            l12 = l12 + vl(1) * g(2)
            l22 = l22 + vl(2) * g(2)
            l32 = l32 + vl(3) * g(2)
            l13 = l13 + vl(1) * g(3)
            l23 = l23 + vl(2) * g(3)
            l33 = l33 + vl(3) * g(3)
          end do
        end do
      end do
      ap = [ax, ay, az]
      vlp = [px, py, pz]
      l(:, 1) = [l11, l21, l31]
      l(:, 2) = [l12, l22, l32]
      l(:, 3) = [l13, l23, l33]
      if (p%has_affine) then
        p%v(:, ip) = vlp                                                  ! APIC: PIC velocity
        call affine_velocity(nodes, grid, p%x(:, ip), first, nn, w, p%affine(:, ip))
      else
        p%v(:, ip) = flip * (p%v(:, ip) + ap * dt) + (1.0_wp - flip) * vlp  ! eq. 70 + PIC blend
      end if
      p%x(:, ip) = p%x(:, ip) + vlp * dt                                  ! eq. 71
      if (mat%model == model_rigid) cycle
      f(:, 1) = p%f(1:3, ip)
      f(:, 2) = p%f(4:6, ip)
      f(:, 3) = p%f(7:9, ip)
      fnew = f + dt * mul3(l, f)                                        ! eq. 74
      p%f(1:3, ip) = fnew(:, 1)
      p%f(4:6, ip) = fnew(:, 2)
      p%f(7:9, ip) = fnew(:, 3)
      p%volume(ip) = det3(fnew) * p%volume0(ip)                           ! eq. 75
      ! the model-specific state only where the store carries it (`particles_store`); the gap
      ! through a scalar, which `constitutive_update` uses only with `tension_gap`
      gap = 0.0_wp
      if (p%has_gap) gap = p%gap(ip)
      if (p%has_hardening .and. p%has_cyclic) then
        call constitutive_update(mat, fnew, l, dt, p%stress_unrot(:, ip), p%stress(:, ip), &
          p%plastic_strain(ip), p%hardening(ip), p%cyclic(:, ip), gap)
      else if (p%has_hardening) then
        call constitutive_update(mat, fnew, l, dt, p%stress_unrot(:, ip), p%stress(:, ip), &
          p%plastic_strain(ip), hardening=p%hardening(ip), gap=gap)
      else if (p%has_cyclic) then
        call constitutive_update(mat, fnew, l, dt, p%stress_unrot(:, ip), p%stress(:, ip), &
          p%plastic_strain(ip), cyclic=p%cyclic(:, ip), gap=gap)
      else
        call constitutive_update(mat, fnew, l, dt, p%stress_unrot(:, ip), p%stress(:, ip), &
          p%plastic_strain(ip), gap=gap)
      end if
      if (p%has_gap) p%gap(ip) = gap
    end do
  end subroutine g2p_particles

  !> APIC's affine velocity C_p = B_p D_p^-1 of a particle at `xp` from the nodes' v^L, B_p =
  !! sum S_ip v^L_i (x_i - x_p)^T, D_p = sum S_ip (x_i - x_p)(x_i - x_p)^T (diagonal: the
  !! weights are tensor products, and each 1-D sum of w (x_i - x_p) vanishes). An inactive
  !! dimension (one node at offset 0) has D = 0 and C = 0.
  pure subroutine affine_velocity(nodes, grid, xp, first, nn, w, affine)
    type(mpm_nodes_t), intent(in) :: nodes       !< solved node fields
    type(grid_t), intent(in) :: grid             !< block geometry
    real(wp), intent(in) :: xp(3)                !< particle position at the start of the step [m]
    integer, intent(in) :: first(3)              !< first node per dimension
    integer, intent(in) :: nn(3)                 !< nodes per dimension
    real(wp), intent(in) :: w(max_stencil, 3)    !< 1-D weights
    real(wp), intent(out) :: affine(9)           !< C_p, column-major [1/s]
    real(wp) :: off(max_stencil, 3), bmat(3, 3), dmat(3), s
    integer :: i, j, k, a, b, c, d
    call node_offsets(grid, xp, first, nn, off)
    bmat = 0.0_wp
    dmat = 0.0_wp
    do c = 1, nn(3)
      k = first(3) + c - 1
      do b = 1, nn(2)
        j = first(2) + b - 1
        do a = 1, nn(1)
          i = first(1) + a - 1
          s = w(a, 1) * w(b, 2) * w(c, 3)
          bmat(:, 1) = bmat(:, 1) + (s * off(a, 1)) * nodes%vel_l(:, i, j, k)
          bmat(:, 2) = bmat(:, 2) + (s * off(b, 2)) * nodes%vel_l(:, i, j, k)
          bmat(:, 3) = bmat(:, 3) + (s * off(c, 3)) * nodes%vel_l(:, i, j, k)
          dmat = dmat + s * [off(a, 1)**2, off(b, 2)**2, off(c, 3)**2]
        end do
      end do
    end do
    do d = 1, 3
      if (dmat(d) > 0.0_wp) then
        affine(3 * d - 2:3 * d) = bmat(:, d) / dmat(d)
      else
        affine(3 * d - 2:3 * d) = 0.0_wp
      end if
    end do
  end subroutine affine_velocity
end module mpm_g2p
