#!/usr/bin/env bash
# Slurm: the application scenes of issue 7 at full resolution (docs/applications.md), one link of
# the restart chain of jobs/slurm.sh with the grid set for the scene.
#   sbatch --export=ALL,SCENE=debris_flow jobs/slurm_applications.sh   (5 mm, 800 x 400 cells)
#   SCENE: debris_flow | obstacle_water | obstacle_air; CELL (m, default 0.005) sets the grid;
#   SAND_E (Pa, optional) sets the sand's Young's modulus, e.g. SAND_E=5.0e6 for the softer sand
#   of the 5 mm run in docs/applications.md (3 times fewer steps than the shipped 50 MPa).
#SBATCH --job-name=mpmice-app
#SBATCH --nodes=2
#SBATCH --ntasks-per-node=64
#SBATCH --cpus-per-task=1
#SBATCH --time=24:00:00
#SBATCH --signal=USR1@300
#SBATCH --output=%x-%j.out
set -euo pipefail
cd "${SLURM_SUBMIT_DIR:-.}"
: "${SCENE:?set SCENE (debris_flow, obstacle_water or obstacle_air)}"
CELL="${CELL:-0.005}"
case "$SCENE" in
  debris_flow) CASE=namelists/mpmice_debris_flow_2d.nml ;;
  obstacle_water) CASE=namelists/mpmice_obstacle_water_2d.nml ;;
  obstacle_air) CASE=namelists/mpmice_obstacle_air_2d.nml ;;
  *) echo "unknown SCENE '$SCENE'" >&2; exit 2 ;;
esac
# the 4 m x 2 m tank, depth one cell (plane strain)
nx="$(python3 -c "print(round(4.0 / $CELL))")"
ny="$(python3 -c "print(round(2.0 / $CELL))")"
export CASE
MPMICE_SET="&grid ncells = $nx, $ny, 1, upper = 4.0, 2.0, $CELL / &run checkpoint_interval = 0.05, output_dir = 'output/${SCENE}_${CELL}' /"
if [ -n "${SAND_E:-}" ]; then
  MPMICE_SET="$MPMICE_SET &solid name = 'sand', youngs_modulus = $SAND_E /"
fi
export MPMICE_SET
exec jobs/slurm.sh
