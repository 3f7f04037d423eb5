#!/bin/sh
# The paper's benchmark (seed §4): a 2.4 m cohesive snow-like column settling under its own weight,
# then collapsing when both gates are removed at t = 0.5 s. README, "The paper's column collapse".
# Usage: run_column.sh [OUT]   (default: $GRAINBANK_OUT/column, i.e. build/out/column)
# Environment: LAW = live (the paper's method, default) | hybrid | cache; END = end time [s] (default:
#   the scene's 4 s, unless the column comes to rest before: kinetic energy below 1e-3 of its peak
#   after t = 0.6 s, time.stop_at_rest); PPC = material points per grid cell and direction (default: the scene's 2);
#   workflows/env.sh (GRAINBANK_BUILD_DIR, GRAINBANK_OUT, THREADS).
# hybrid and cache first build OUT/lib from paths.json (skipped when already sampled).
# A run stopped by Ctrl-C or SIGTERM has written its restart, and a killed one its last checkpoint (every
# 10 min): the same command again resumes it into the next segment (OUT/run_2, OUT/run_3, …), and the
# figures are drawn over every segment.
# Run time on 2 cores: hours to days (estimate_time.py measures and extrapolates it; do not start a full
# run by accident).
set -eu
here=$(cd "$(dirname "$0")" && pwd)
. "$here/../env.sh"
out=${1:-$outputs/column}
law=${LAW:-live}
mkdir -p "$out"
set -- --law "$law"
if [ "$law" != live ]; then
  "$build/dem_sampler/dem_sampler" prepare "$here/cell_snow_370um.json" --library "$out/lib"
  "$build/dem_sampler/dem_sampler" sample "$here/paths.json" --library "$out/lib" --threads "$threads" 2> "$out/sample.log"
  set -- "$@" --library "$out/lib"
  [ "$law" = hybrid ] && set -- "$@" --material "$(cat "$here/hybrid.json")"
fi
[ -n "${END:-}" ] && set -- "$@" --set "/time/end=$END"
[ -n "${PPC:-}" ] && set -- "$@" --set "/regions/0/points_per_cell=$PPC"  # the scene has one region
"$build/mpm_solver/mpm_solver" scene "$here/column.json" "$@" --out "$out/scene.json"
segment() { if [ "$1" = 1 ]; then echo "$out/run"; else echo "$out/run_$1"; fi; }
# A segment with a restart was interrupted (summary says so) or killed (no summary; its restart is the
# last checkpoint): the next segment resumes from it. One without a restart never reached a checkpoint
# and is run again.
n=1
runs=""
while [ -f "$(segment $n)/restart.h5" ]; do
  runs="$runs $(segment $n)"
  [ -f "$(segment $n)/summary.json" ] && ! grep -q '"interrupted": true' "$(segment $n)/summary.json" && break
  n=$((n + 1))
done
if [ ! -f "$(segment $n)/summary.json" ] || grep -q '"interrupted": true' "$(segment $n)/summary.json"; then
  rm -rf "$(segment $n)"
  set -- "$out/scene.json" --out "$(segment $n)" --threads "$threads"
  if [ "$n" -gt 1 ]; then
    echo "resuming from $(segment $((n - 1)))/restart.h5"
    set -- "$@" --restart "$(segment $((n - 1)))/restart.h5"
  fi
  "$build/mpm_solver/mpm_solver" "$@"
  runs="$runs $(segment $n)"
fi
# shellcheck disable=SC2086  # the segments are separate arguments
"$python" "$here/figures.py" $runs "$out/figures"
