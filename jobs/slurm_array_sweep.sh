#!/usr/bin/env bash
# Slurm job array: a parameter sweep with --set, one array task per value, each in its own
# output directory. Example: the heat-conduction resolution study.
#   sbatch jobs/slurm_array_sweep.sh
#SBATCH --job-name=mpmice-sweep
#SBATCH --array=0-3
#SBATCH --ntasks=4
#SBATCH --time=01:00:00
#SBATCH --signal=USR1@120
#SBATCH --output=%x-%A_%a.out
#
#   module load gcc/12 openmpi/4.1 hdf5/1.10-mpi hypre/2.26
set -euo pipefail
cd "${SLURM_SUBMIT_DIR:-.}"
CASE="${CASE:-namelists/heat_conduction_1d.nml}"
cells=(32 64 128 256)                    # the swept values, indexed by the array task id
n="${cells[$SLURM_ARRAY_TASK_ID]}"
dt="$(awk -v n="$n" 'BEGIN { printf "%.17g", 0.064 / n }')"
export MPMICE_LAUNCH="srun"
jobs/mpmice_chain.sh "$CASE" \
  --set "&grid ncells = $n, 1, 1 /" \
  --set "&time dt_init = $dt, dt_max = $dt /" \
  --set "&run name = 'sweep_$n', output_dir = 'output/sweep/n$n' /"
