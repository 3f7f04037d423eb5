#!/bin/sh
# Cache and hybrid against live DEM on the cohesive column collapse (README, "cache and hybrid").
# Usage: run_comparison.sh [OUT]   (default: ./out next to this script)
# Builds nothing: expects mpm_solver and dem_sampler in $GRAINBANK_BUILD_DIR (default ../../build).
set -eu
here=$(cd "$(dirname "$0")" && pwd)
build=${GRAINBANK_BUILD_DIR:-$here/../../build}
out=${1:-$here/out}
threads=${THREADS:-2}
rm -rf "$out"
mkdir -p "$out"
/usr/bin/python3 "$here/cache_vs_live.py" scenes "$here/collapse.json" "$out"
# The 125-sphere snow cell with bonds 20x weaker than workflows/scenes/cell_snow_125.json (that column
# stands): template 1 of a fresh library.
"$build/dem_sampler/dem_sampler" prepare "$here/cell_weak_snow_125.json" --library "$out/lib"
for run in reference live_probe hybrid cache hybrid_skip hybrid_fine cache_fine hybrid_wide; do
  echo "== $run"
  "$build/mpm_solver/mpm_solver" "$out/scenes/$run.json" --out "$out/$run" --threads "$threads" > "$out/$run.log"
done
/usr/bin/python3 "$here/cache_vs_live.py" compare "$out"
