#!/usr/bin/env bash
# Slurm template: one link of a self-resubmitting restart chain.
#   sbatch --export=ALL,CASE=namelists/my_case.nml jobs/slurm.sh
#SBATCH --job-name=mpmice
#SBATCH --nodes=2
#SBATCH --ntasks-per-node=64
#SBATCH --cpus-per-task=1
#SBATCH --time=24:00:00
#SBATCH --signal=USR1@300          # SIGUSR1 to every rank 5 min before the limit: checkpoint + stop
#SBATCH --output=%x-%j.out
#
# Site modules (examples; names differ between clusters):
#   module load gcc/12 openmpi/4.1 hdf5/1.10-mpi hypre/2.26
set -euo pipefail
cd "${SLURM_SUBMIT_DIR:-.}"
: "${CASE:?set CASE to the namelist file (sbatch --export=ALL,CASE=...)}"
export MPMICE_LAUNCH="srun --kill-on-bad-exit=1"
# Open MPI: ROMIO for MPI-IO (see docs/io.md); mpmice also sets it itself when unset.
export OMPI_MCA_io="${OMPI_MCA_io:-^ompio}"
# Optional second guard besides the signal: &run wall_time_limit (seconds) via --set.
state="$(jobs/mpmice_chain.sh "$CASE" ${MPMICE_SET:+--set "$MPMICE_SET"} | tail -n 1)"
if [ "$state" = stopped ]; then
  sbatch --export=ALL,CASE="$CASE" "$0"     # next link of the chain
fi
