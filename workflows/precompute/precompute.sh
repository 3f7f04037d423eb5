#!/bin/sh
# Precomputing a cell library (README, "Precomputing a cell library"): prepares the cell of CELL as a
# template of LIB, then samples the paths of PATHS on it (every pending path of the library). Safe to
# run again: the template is found, registered paths are not added twice, and an interrupted sample
# resumes.
# Usage: precompute.sh [LIB]   (default: $GRAINBANK_OUT/precompute/lib, i.e. build/out/precompute/lib)
# Environment: workflows/env.sh (GRAINBANK_BUILD_DIR, GRAINBANK_OUT, THREADS); CELL (default:
#   workflows/demo/cell.json), PATHS (default: paths.json next to this script).
set -eu
here=$(cd "$(dirname "$0")" && pwd)
. "$here/../env.sh"
library=${1:-$outputs/precompute/lib}
cell=${CELL:-$here/../demo/cell.json}
paths=${PATHS:-$here/paths.json}
mkdir -p "$(dirname "$library")"
"$build/dem_sampler/dem_sampler" prepare "$cell" --library "$library"
"$build/dem_sampler/dem_sampler" sample "$paths" --library "$library" --threads "$threads"
"$build/database/celldb" info "$library"
