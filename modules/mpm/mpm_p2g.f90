!> Particle-to-grid transfer of one solid material: nodal mass and momentum (eq. 26) and
!! internal force f_i = -sum_p grad S_ip . sigma_p V_p (eq. 27), scattered into the block's node
!! fields and summed into the owners by the reverse halo (copies refreshed, so every allocated
!! node holds its global value). External forces (gravity) are added in the nodal solve.
!! With the APIC transfer (a store with `has_affine`) node i also gets the particle's affine
!! momentum m_p S_ip C_p (x_i - x_p) (Jiang et al. 2015; `mpm_g2p` sets C_p).
module mpm_p2g
  use mpmice_kinds, only: wp
  use grid_layout, only: grid_t
  use parallel_domain, only: domain_t
  use parallel_halo, only: halo_t, halo_reverse_node
  use particles_store, only: particles_t
  use mpm_shape, only: particle_stencil, max_stencil, node_offsets
  use mpm_nodes, only: mpm_nodes_t, node_mass, node_momentum, node_force, node_rigid_mass, &
    node_rigid_momentum, node_rigid_gradient, nq
  implicit none
  private

  public :: p2g_scatter, p2g_accumulate, p2g_accumulate_rigid, p2g_complete

contains

  !> Scatter mass, momentum and internal force of `p` into `nodes%q` (collective: reverse halo).
  subroutine p2g_scatter(p, nodes, kind, dom, grid, halo)
    type(particles_t), intent(in) :: p           !< particles
    type(mpm_nodes_t), intent(inout) :: nodes    !< node fields
    integer, intent(in) :: kind                  !< shape_linear or shape_gimp
    type(domain_t), intent(in) :: dom            !< decomposition
    type(grid_t), intent(in) :: grid             !< block geometry
    type(halo_t), intent(inout) :: halo          !< halo buffers (>= nq components)
    nodes%q(:, :, :, :) = 0.0_wp
    call p2g_accumulate(p, nodes%q, kind, grid)
    call p2g_complete(nodes, dom, grid, halo)
  end subroutine p2g_scatter

  !> Sum the local scatters into the owners and refresh the copies (collective).
  subroutine p2g_complete(nodes, dom, grid, halo)
    type(mpm_nodes_t), intent(inout) :: nodes    !< node fields
    type(domain_t), intent(in) :: dom            !< decomposition
    type(grid_t), intent(in) :: grid             !< block geometry
    type(halo_t), intent(inout) :: halo          !< halo buffers (>= nq components)
    call halo_reverse_node(halo, dom, grid, nodes%q)
  end subroutine p2g_complete

  !> Add the local scatter of `p` to `q` (no communication; the caller zeroes `q` first).
  subroutine p2g_accumulate(p, q, kind, grid)
    type(particles_t), intent(in) :: p           !< particles
    type(grid_t), intent(in) :: grid             !< block geometry
    real(wp), intent(inout) :: q(nq, grid%lbn(1):grid%ubn(1), grid%lbn(2):grid%ubn(2), &
      grid%lbn(3):grid%ubn(3))                   !< node fields (the whole store)
    integer, intent(in) :: kind                  !< shape_linear or shape_gimp
    integer :: ip, i, j, k, a, b, c, first(3), nn(3)
    real(wp) :: w(max_stencil, 3), dw(max_stencil, 3), s, g(3), m, mv(3), sv(6), wjk, gjk(3)
    do ip = 1, p%np
      call particle_stencil(kind, grid, p%x(:, ip), p%half_width, first, nn, w, dw)
      m = p%mass(ip)
      mv = m * p%v(:, ip)
      sv = p%stress(:, ip) * p%volume(ip)
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
            q(node_mass, i, j, k) = q(node_mass, i, j, k) + s * m
            q(node_momentum, i, j, k) = q(node_momentum, i, j, k) + s * mv(1)
            q(node_momentum + 1, i, j, k) = q(node_momentum + 1, i, j, k) + s * mv(2)
            q(node_momentum + 2, i, j, k) = q(node_momentum + 2, i, j, k) + s * mv(3)
            ! eq. 27: f = -sigma . grad S V (sigma symmetric: xx, yy, zz, xy, yz, xz)
            q(node_force, i, j, k) = q(node_force, i, j, k) &
              - (sv(1) * g(1) + sv(4) * g(2) + sv(6) * g(3))
            q(node_force + 1, i, j, k) = q(node_force + 1, i, j, k) &
              - (sv(4) * g(1) + sv(2) * g(2) + sv(5) * g(3))
            q(node_force + 2, i, j, k) = q(node_force + 2, i, j, k) &
              - (sv(6) * g(1) + sv(5) * g(2) + sv(3) * g(3))
          end do
        end do
      end do
      if (p%has_affine) call add_affine_momentum(q, grid, p%x(:, ip), m, p%affine(:, ip), &
        first, nn, w)
    end do
  end subroutine p2g_accumulate

  !> Add a particle's affine momentum m S_i C (x_i - x_p) to the nodes of its stencil (APIC).
  pure subroutine add_affine_momentum(q, grid, xp, m, affine, first, nn, w)
    type(grid_t), intent(in) :: grid             !< block geometry
    real(wp), intent(inout) :: q(:, grid%lbn(1):, grid%lbn(2):, grid%lbn(3):) !< node fields
    real(wp), intent(in) :: xp(3)                !< particle position [m]
    real(wp), intent(in) :: m                    !< particle mass [kg]
    real(wp), intent(in) :: affine(9)            !< C_p, column-major [1/s]
    integer, intent(in) :: first(3)              !< first node per dimension
    integer, intent(in) :: nn(3)                 !< nodes per dimension
    real(wp), intent(in) :: w(max_stencil, 3)    !< 1-D weights
    real(wp) :: off(max_stencil, 3), mc(3, 3), mk(3), mj(3)
    integer :: i, j, k, a, b, c
    call node_offsets(grid, xp, first, nn, off)
    mc = m * reshape(affine, [3, 3])
    do c = 1, nn(3)
      k = first(3) + c - 1
      mk = mc(:, 3) * off(c, 3)
      do b = 1, nn(2)
        j = first(2) + b - 1
        mj = mk + mc(:, 2) * off(b, 2)
        do a = 1, nn(1)
          i = first(1) + a - 1
          q(node_momentum:node_momentum + 2, i, j, k) = q(node_momentum:node_momentum + 2, &
            i, j, k) + (w(a, 1) * w(b, 2) * w(c, 3)) * (mj + mc(:, 1) * off(a, 1))
        end do
      end do
    end do
  end subroutine add_affine_momentum

  !> Add the mass, momentum and mass gradient of the rigid particles `p` to the rigid components
  !! of `q` (`node_rigid_mass`, `node_rigid_momentum`, `node_rigid_gradient`).
  subroutine p2g_accumulate_rigid(p, q, kind, grid)
    type(particles_t), intent(in) :: p           !< rigid particles (velocity set)
    type(grid_t), intent(in) :: grid             !< block geometry
    real(wp), intent(inout) :: q(:, grid%lbn(1):, grid%lbn(2):, grid%lbn(3):) !< node fields
    integer, intent(in) :: kind                  !< shape_linear or shape_gimp
    integer :: ip, i, j, k, a, b, c, first(3), nn(3)
    real(wp) :: w(max_stencil, 3), dw(max_stencil, 3), s, m
    do ip = 1, p%np
      call particle_stencil(kind, grid, p%x(:, ip), p%half_width, first, nn, w, dw)
      m = p%mass(ip)
      do c = 1, nn(3)
        k = first(3) + c - 1
        do b = 1, nn(2)
          j = first(2) + b - 1
          do a = 1, nn(1)
            i = first(1) + a - 1
            s = w(a, 1) * w(b, 2) * w(c, 3) * m
            q(node_rigid_mass, i, j, k) = q(node_rigid_mass, i, j, k) + s
            q(node_rigid_momentum:node_rigid_momentum + 2, i, j, k) = &
              q(node_rigid_momentum:node_rigid_momentum + 2, i, j, k) + s * p%v(:, ip)
            ! mass gradient: the body's outward normal at the node is grad m / |grad m|
            q(node_rigid_gradient, i, j, k) = q(node_rigid_gradient, i, j, k) &
              + m * dw(a, 1) * w(b, 2) * w(c, 3)
            q(node_rigid_gradient + 1, i, j, k) = q(node_rigid_gradient + 1, i, j, k) &
              + m * w(a, 1) * dw(b, 2) * w(c, 3)
            q(node_rigid_gradient + 2, i, j, k) = q(node_rigid_gradient + 2, i, j, k) &
              + m * w(a, 1) * w(b, 2) * dw(c, 3)
          end do
        end do
      end do
    end do
  end subroutine p2g_accumulate_rigid
end module mpm_p2g
