!> Node fields of the solid materials on this block (allocated once, bounds lbn..ubn): the P2G
!! scatter `q(14, ...)` = (mass, momentum x/y/z, force x/y/z of the deformable materials, mass,
!! momentum x/y/z and mass gradient x/y/z of the rigid ones) and the nodal solution (velocity v^n, velocity after the
!! solve v^L, acceleration a).
module mpm_nodes
  use mpmice_kinds, only: wp
  use grid_layout, only: grid_t
  implicit none
  private

  public :: mpm_nodes_t, nodes_init, nodes_free, nq

  !> Components scattered to the nodes = mass, momentum(3), force(3); rigid mass, momentum(3), mass gradient(3)
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
