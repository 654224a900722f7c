#!/usr/bin/env bash
# Slurm job: the earthquake-induced submarine landslide (issue 7, scene 3) at full resolution,
# 0.05 m cells (260 x 80, 83,000 sediment particles), 3 cycles of shaking (1.5 s), as one link
# of a self-resubmitting restart chain (jobs/mpmice_chain.sh). Submit from the repository root:
#   sbatch jobs/slurm_earthquake_slope.sh
# Postproc afterwards:
#   python -m postproc.mpmice_earthquake_slope --dir output/mpmice_earthquake_slope_2d_5cm
# Size: the 0.125 m run takes 46 s on one core (docs/applications.md); 0.05 m has 6x the cells
# and 2.5x the steps: ~15x the work, ~12 min on one core, a few minutes on 8 ranks. Note: the
# 0.1 and 0.05 m runs fail at t = 0.767 / 0.778 s on one rank (docs/applications.md): this job
# is ready for when that failure is fixed.
#SBATCH --job-name=quake5cm
#SBATCH --nodes=1
#SBATCH --ntasks-per-node=8
#SBATCH --cpus-per-task=1
#SBATCH --time=02:00:00
#SBATCH --signal=USR1@300          # SIGUSR1 to every rank 5 min before the limit: checkpoint + stop
#SBATCH --output=%x-%j.out
#
# Site modules (examples; names differ between clusters):
#   module load gcc/12 openmpi/4.1 hdf5/1.10-mpi hypre/2.26
set -euo pipefail
cd "${SLURM_SUBMIT_DIR:-.}"
export MPMICE_LAUNCH="srun --kill-on-bad-exit=1"
export OMPI_MCA_io="${OMPI_MCA_io:-^ompio}"
CASE=namelists/mpmice_earthquake_slope_2d.nml
SET="&grid ncells = 260, 80, 1 / &run output_dir = 'output/mpmice_earthquake_slope_2d_5cm', checkpoint_interval = 0.25 /"
state="$(jobs/mpmice_chain.sh "$CASE" --set "$SET" | tail -n 1)"
if [ "$state" = stopped ]; then
  sbatch "$0"                      # next link of the chain
fi
