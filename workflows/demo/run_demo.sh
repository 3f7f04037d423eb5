#!/bin/sh
# The default demo (README, "The demo"): a small cohesive cell library, a cohesive column collapse
# against it with the state-keyed `surrogate` law, the audit of that run against live cells, PNG figures and a short report.
# Usage: run_demo.sh [OUT]   (default: $GRAINBANK_OUT/demo, i.e. build/out/demo; ./run.sh demo passes demo_out)
# Environment: workflows/env.sh (GRAINBANK_BUILD_DIR, GRAINBANK_OUT, THREADS),
#              DEMO_SCENE and DEMO_PATHS (other inputs, e.g. the tiny ones of the tests).
# A second run reuses OUT/lib: `prepare` finds its template and `sample` finds every path registered
# and done.
set -eu
here=$(cd "$(dirname "$0")" && pwd)
. "$here/../env.sh"
out=${1:-$outputs/demo}
scene=${DEMO_SCENE:-$here/column.json}
paths=${DEMO_PATHS:-$here/paths.json}
mkdir -p "$out"
seconds() { date +%s.%N; }  # timestamps for the report
start=$(seconds)

echo "== cell library $out/lib"
"$build/dem_sampler/dem_sampler" prepare "$here/cell_soft_snow_250.json" --library "$out/lib"
"$build/dem_sampler/dem_sampler" sample "$paths" --library "$out/lib" --threads "$threads" 2> "$out/sample.log"
library_done=$(seconds)

echo "== column collapse -> $out/run"
rm -rf "$out/run"
"$build/mpm_solver/mpm_solver" "$scene" --library "$out/lib" --out "$out/run" --threads "$threads" > /dev/null
"$build/database/celldb" info "$out/lib" --json > "$out/library.json"
run_done=$(seconds)

# The scene records a few points' histories ("audit"): re-run them with live cells and compare, and
# with cells of another packing seed (the audit's noise floor: what two live cells differ by).
echo "== audit of the run against live cells -> $out/run/audit"
"$python" -c 'import json, sys; c = json.load(open(sys.argv[1])); c["preparation"]["seed"] += 1000; json.dump(c, open(sys.argv[2], "w"), indent=2)' \
  "$here/cell_soft_snow_250.json" "$out/floor_cell.json"
"$build/mpm_solver/mpm_solver" audit "$out/run" --threads "$threads" --floor-cell "$out/floor_cell.json" > "$out/run_audit.txt"
"$python" "$here/../audit/plot_run_audit.py" "$out/run/audit" "$out/figures" 2> /dev/null
audit_done=$(seconds)

echo "== figures and report -> $out/figures, $out/report.txt"
"$python" "$here/report.py" "$out" --timestamps "$start" "$library_done" "$run_done" "$audit_done"
