!> The solid skeleton on the ICE cells and faces (paper eqs. 28, 32-33, 48, 52, 66-69 with E5):
!! what the pressure equation and the exchange of a coupled scene see of the MPM particles, and the
!! way their results go back to the MPM nodes. The coupled scene's one entry point; each concept
!! has its own module:
!!
!! * `mpmice_deposit`: the particles' deposit of mass, grain volume, heat and face-plane
!!   fractions on the cells (eq. 28; layout `mpmice_deposit_layout`).
!! * `mpmice_solid_fields`: the solid phase's cell fields from the deposit (fraction, density,
!!   drag, heat), its cell velocity from the nodes, the tracked fraction, the pore pressure.
!! * `mpmice_face_nodes`: the solid's face velocities from the nodes (eqs. 32-33) and their
!!   increments back to the nodes (eqs. 52, 66-67 with E5).
!! * `mpmice_porous_fluid`: the fluids' face predictor and cell velocity next to porous solid.
module mpmice_solid_cells
  use mpmice_deposit, only: solid_deposit, overlap_weights, deformed_half_widths
  use mpmice_solid_fields, only: solid_cell_fields, solid_cell_velocity, solid_track_fraction, &
    solid_pore_pressure
  use mpmice_face_nodes, only: solid_face_predictor, solid_face_to_nodes
  use mpmice_porous_fluid, only: fluid_face_blend, fluid_face_predictor_porous
  implicit none
  private

  public :: solid_deposit, solid_cell_fields, solid_face_predictor, &
    solid_face_to_nodes, solid_track_fraction, solid_cell_velocity, solid_pore_pressure, &
    fluid_face_blend, fluid_face_predictor_porous, overlap_weights, deformed_half_widths
end module mpmice_solid_cells
