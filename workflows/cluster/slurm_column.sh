#!/bin/bash
# The paper's live column collapse (workflows/column_collapse/column.json) on a Slurm cluster: one
# MPI rank per task, OpenMP threads per rank from --cpus-per-task. Submit from the repository root,
# after ./run.sh test (or a build of your own: GRAINBANK_BUILD_DIR):
#   sbatch workflows/cluster/slurm_column.sh [OUT]
# Resubmitting the same job resumes from the newest OUT/run_<n>/restart.h5 into OUT/run_<n+1>: a run
# writes one at its end, when Slurm's SIGTERM ends the allocation (every rank stops after the same
# step), and as a checkpoint every 10 minutes (a killed job).
#SBATCH --job-name=grainbank-column
#SBATCH --ntasks=64
#SBATCH --cpus-per-task=1
#SBATCH --time=02:00:00
#SBATCH --signal=TERM@120
set -eu
root=${SLURM_SUBMIT_DIR:-$(pwd)}
build=${GRAINBANK_BUILD_DIR:-$root/build}
out=${1:-$root/column_mpi}
mkdir -p "$out"
export OMP_NUM_THREADS=${SLURM_CPUS_PER_TASK:-1}
# The newest restart (a finished, stopped or killed segment's) is where the next segment starts.
n=0
while [ -e "$out/run_$((n + 1))/restart.h5" ]; do n=$((n + 1)); done
set -- "$root/workflows/column_collapse/column.json" --out "$out/run_$((n + 1))" --threads "$OMP_NUM_THREADS"
[ "$n" -gt 0 ] && set -- "$@" --restart "$out/run_$n/restart.h5"
srun "$build/mpm_solver/mpm_solver" "$@"
