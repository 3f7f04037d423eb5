#!/usr/bin/env bash
# Side-by-side throughput of the periodic DEM cell against the peer codes on the standard benchmark
# cell (shared/peers/README.md): 1331 frictional spheres, simple shear at constant volume, one core.
# The peers run from their own scripts, copied here unchanged: LAMMPS (lammps_shear.in, SHEAR_STEPS
# of shear) and YADE (yade_shear.py, its fixed 20000 steps). A peer that is not installed is skipped
# with the line that installs it; the machine is shared, so each repeat runs every code in turn and
# only ratios from the same repeat mean anything.
# Usage: workflows/benchmarks/dem_vs_peers.sh [SHEAR_STEPS] [REPEATS]
# Needs dem_sampler in the build directory of workflows/env.sh.
set -euo pipefail
shopt -s inherit_errexit  # a peer that fails inside $(...) stops the script
steps=${1:-30000}
repeats=${2:-3}
here=$(cd "$(dirname "$0")" && pwd)
. "$here/../env.sh"
dem="$build/dem_sampler/dem_sampler"
[ -x "$dem" ] || { echo "build dem_sampler first (./run.sh test or cmake --build $build)" >&2; exit 1; }
have_lammps=0; command -v lmp >/dev/null && have_lammps=1 || echo "LAMMPS skipped: apt-get install lammps" >&2
have_yade=0; command -v yade >/dev/null && have_yade=1 || echo "YADE skipped: apt-get install yade" >&2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

lammps_rate() {  # particle-steps/s of the shear phase = timesteps/s of the last run x 1331
  (cd "$work" && OMP_NUM_THREADS=1 lmp -in "$here/lammps_shear.in" -var nshear "$steps" -log none -screen lmp.out >/dev/null)
  awk '/^Performance:/ {rate=$(NF-1)} END {printf "%.4g\n", rate * 1331}' "$work/lmp.out"
}
yade_rate() {  # its script prints "shear: N steps T s -> R steps/s, P particle-steps/s, ..."
  (cd "$work" && OMP_NUM_THREADS=1 yade -j1 -n -x "$here/yade_shear.py" > yade.out 2>&1)
  awk '/^shear:/ {for (k = 1; k <= NF; ++k) if ($k == "particle-steps/s,") rate = $(k-1)} END {printf "%.4g\n", rate}' "$work/yade.out"
}
grainbank_rate() {
  "$dem" bench --steps "$steps" "$@" --json | awk -F': ' '/particle_steps_per_second/ {gsub(",","",$2); print $2}'
}
# A rate that is not a positive number means the code ran but printed no figure: stop, naming it.
positive() { awk -v r="$2" 'BEGIN {exit !(r + 0 > 0)}' || { echo "$1 gave no particle-steps/s figure" >&2; exit 1; }; echo "$2"; }
ratio() { [ "$2" = - ] && echo - || awk -v g="$1" -v p="$2" 'BEGIN {printf "%.3f", g / p}'; }

printf "%-4s %12s %12s %12s %16s %14s %12s\n" run grainbank "+bonds" LAMMPS "grainbank/LAMMPS" YADE "grainbank/YADE"
for r in $(seq 1 "$repeats"); do
  l=-; y=-
  if [ $have_lammps = 1 ]; then l=$(positive LAMMPS "$(lammps_rate)"); fi
  g=$(positive grainbank "$(grainbank_rate)"); b=$(positive grainbank "$(grainbank_rate --bonds)")
  if [ $have_yade = 1 ]; then y=$(positive YADE "$(yade_rate)"); fi
  printf "%-4s %12.4g %12.4g %12s %16s %14s %12s\n" "$r" "$g" "$b" "$l" "$(ratio "$g" "$l")" "$y" "$(ratio "$g" "$y")"
done
echo "(particle-steps/s over the shear phase, one core; ratios of the unbonded cell, measured in turn)"
