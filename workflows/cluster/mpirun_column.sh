#!/bin/bash
# The paper's live column collapse (workflows/column_collapse/column.json) with plain mpirun: RANKS
# ranks (default 2) of THREADS OpenMP threads each (default 1), on this machine or on the hosts of
# HOSTFILE. Run from anywhere:
#   RANKS=8 HOSTFILE=hosts.txt workflows/cluster/mpirun_column.sh [OUT] [--set /time/end=0.01 ...]
# Ctrl-C stops every rank after the same step and writes OUT/run_<n>/restart.h5; the same command
# again resumes from it into OUT/run_<n+1>.
set -eu
here=$(cd "$(dirname "$0")" && pwd)
. "$here/../env.sh"
out=${1:-$outputs/column_mpi}
[ $# -gt 0 ] && shift
mkdir -p "$out"
# The newest restart (a finished, stopped or killed segment's) is where the next segment starts.
n=0
while [ -e "$out/run_$((n + 1))/restart.h5" ]; do n=$((n + 1)); done
set -- "$root/workflows/column_collapse/column.json" --out "$out/run_$((n + 1))" --threads "${THREADS:-1}" "$@"
[ "$n" -gt 0 ] && set -- "$@" --restart "$out/run_$n/restart.h5"
# Ctrl-C reaches the ranks as SIGTERM; give them two minutes to write the restart before mpirun kills them.
mpi=(mpirun -n "${RANKS:-2}" --mca odls_base_sigkill_timeout 120)
[ -n "${HOSTFILE:-}" ] && mpi+=(--hostfile "$HOSTFILE")
[ "$(id -u)" = 0 ] && mpi+=(--allow-run-as-root)
exec "${mpi[@]}" "$build/mpm_solver/mpm_solver" "$@"
