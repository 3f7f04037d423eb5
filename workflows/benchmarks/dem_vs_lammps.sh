#!/usr/bin/env bash
# Side-by-side throughput of the periodic DEM cell against LAMMPS on the standard benchmark cell
# (shared/peers/README.md): 1331 frictional spheres, simple shear at constant volume, one core.
# Usage: workflows/benchmarks/dem_vs_lammps.sh [SHEAR_STEPS] [REPEATS]
# Needs dem_sampler in the build directory of workflows/env.sh and LAMMPS (apt-get install lammps).
set -euo pipefail
steps=${1:-30000}
repeats=${2:-3}
here=$(cd "$(dirname "$0")" && pwd)
. "$here/../env.sh"
dem="$build/dem_sampler/dem_sampler"
peer_script="$here/lammps_shear.in"
command -v lmp >/dev/null || { echo "LAMMPS not found: apt-get install lammps" >&2; exit 1; }
[ -x "$dem" ] || { echo "build dem_sampler first (./run.sh test or cmake --build $build)" >&2; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

lammps_rate() {  # particle-steps/s of the shear phase = timesteps/s of the last run x 1331
  (cd "$work" && OMP_NUM_THREADS=1 lmp -in "$peer_script" -var nshear "$steps" -log none -screen lmp.out >/dev/null)
  awk '/^Performance:/ {rate=$(NF-1)} END {printf "%.4g\n", rate * 1331}' "$work/lmp.out"
}
grainbank_rate() {
  "$dem" bench --steps "$steps" "$@" --json | awk -F': ' '/particle_steps_per_second/ {gsub(",","",$2); print $2}'
}

printf "%-6s %16s %16s %16s %8s\n" run "LAMMPS" "grainbank" "grainbank+bonds" "ratio"
for r in $(seq 1 "$repeats"); do
  l=$(lammps_rate); g=$(grainbank_rate); b=$(grainbank_rate --bonds)
  printf "%-6s %16.4g %16.4g %16.4g %8.3f\n" "$r" "$l" "$g" "$b" "$(awk -v g="$g" -v l="$l" 'BEGIN {print g / l}')"
done
echo "(particle-steps/s over the shear phase, one core; ratio = grainbank / LAMMPS, measured in turn)"
