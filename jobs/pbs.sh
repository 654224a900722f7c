#!/usr/bin/env bash
# PBS Pro / Torque template: one link of a self-resubmitting restart chain.
#   qsub -v CASE=namelists/my_case.nml jobs/pbs.sh
#PBS -N mpmice
#PBS -l select=2:ncpus=64:mpiprocs=64
#PBS -l walltime=24:00:00
#PBS -j oe
#
# Site modules (examples):
#   module load gcc/12 openmpi/4.1 hdf5/1.10-mpi hypre/2.26
# PBS sends SIGTERM to the job shortly before killing it at the wall time, which mpirun does not
# forward as a checkpoint request: set &run wall_time_limit a few minutes under walltime instead,
# e.g. MPMICE_SET='&run wall_time_limit = 85800 /' for 24 h.
set -euo pipefail
cd "${PBS_O_WORKDIR:-.}"
: "${CASE:?set CASE to the namelist file (qsub -v CASE=...)}"
export MPMICE_LAUNCH="mpirun"
export OMPI_MCA_io="${OMPI_MCA_io:-^ompio}"
state="$(jobs/mpmice_chain.sh "$CASE" ${MPMICE_SET:+--set "$MPMICE_SET"} | tail -n 1)"
if [ "$state" = stopped ]; then
  qsub -v CASE="$CASE",MPMICE_SET="${MPMICE_SET:-}" "$0"   # next link of the chain
fi
