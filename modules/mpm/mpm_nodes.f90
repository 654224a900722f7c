!> Node fields of the solid materials on this block (allocated once, bounds lbn..ubn): the P2G
!! scatter `q(nq, ...)` and the nodal solution (velocity v^n, velocity after the solve v^L,
!! acceleration a). The components of `q`:
!!
!! | index | content |
!! |---|---|
!! | `node_mass` | mass of the deformable materials [kg] |
!! | `node_momentum` + 0..2 | their momentum x/y/z [kg m/s] |
!! | `node_force` + 0..2 | their internal and external force x/y/z [N] |
!! | `node_rigid_mass` | mass of the rigid materials [kg] (> 0: the node touches a rigid body) |
!! | `node_rigid_momentum` + 0..2 | their momentum x/y/z [kg m/s] |
!! | `node_rigid_gradient` + 0..2 | their mass gradient x/y/z [kg/m] (the contact normal) |
!!
!! `node_rigid_mass:nq` is the rigid materials' share.
module mpm_nodes
  use mpmice_kinds, only: wp
  use grid_layout, only: grid_t
  implicit none
  private

  public :: mpm_nodes_t, nodes_init, nodes_free, nq, node_mass, node_momentum, node_force, &
    node_rigid_mass, node_rigid_momentum, node_rigid_gradient

  integer, parameter :: node_mass = 1            !< deformable mass [kg]
  integer, parameter :: node_momentum = 2        !< first of the deformable momentum (3) [kg m/s]
  integer, parameter :: node_force = 5           !< first of the deformable force (3) [N]
  integer, parameter :: node_rigid_mass = 8      !< rigid mass [kg]
  integer, parameter :: node_rigid_momentum = 9  !< first of the rigid momentum (3) [kg m/s]
  integer, parameter :: node_rigid_gradient = 12 !< first of the rigid mass gradient (3) [kg/m]
  !> Components scattered to the nodes.
  integer, parameter :: nq = 14

  !> Node fields of one solid material.
  type :: mpm_nodes_t
    real(wp), allocatable :: q(:, :, :, :)     !< (nq, i, j, k): [kg], [kg m/s], [N], [kg], [kg m/s],
                                               !! [kg/m]
    real(wp), allocatable :: vel(:, :, :, :)   !< (3, i, j, k) velocity v^n [m/s]
    real(wp), allocatable :: vel_l(:, :, :, :) !< (3, i, j, k) velocity after the solve v^L [m/s]
    real(wp), allocatable :: acc(:, :, :, :)   !< (3, i, j, k) acceleration (eq. 69) [m/s^2]
  end type mpm_nodes_t

contains

  !> Allocate the node fields of `grid` (zeroed).
  subroutine nodes_init(nodes, grid)
    type(mpm_nodes_t), intent(inout) :: nodes  !< node fields
    type(grid_t), intent(in) :: grid           !< block geometry
    call nodes_free(nodes)
    allocate(nodes%q(nq, grid%lbn(1):grid%ubn(1), grid%lbn(2):grid%ubn(2), &
      grid%lbn(3):grid%ubn(3)), source=0.0_wp)
    allocate(nodes%vel(3, grid%lbn(1):grid%ubn(1), grid%lbn(2):grid%ubn(2), &
      grid%lbn(3):grid%ubn(3)), source=0.0_wp)
    allocate(nodes%vel_l, nodes%acc, mold=nodes%vel)
    nodes%vel_l(:, :, :, :) = 0.0_wp
    nodes%acc(:, :, :, :) = 0.0_wp
  end subroutine nodes_init

  !> Release the node fields.
  subroutine nodes_free(nodes)
    type(mpm_nodes_t), intent(inout) :: nodes  !< node fields
    if (allocated(nodes%q)) deallocate(nodes%q, nodes%vel, nodes%vel_l, nodes%acc)
  end subroutine nodes_free
end module mpm_nodes
