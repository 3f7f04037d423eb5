# The one environment of the workflow scripts, sourced by each once `here` (its folder,
# workflows/<job>/) is set; workflows/plotting/environment.py reads the same variables for the Python
# scripts. Sets:
#   root     the repository root
#   build    the build directory: GRAINBANK_BUILD_DIR (relative to the root unless absolute; default build)
#   outputs  where runs write by default: GRAINBANK_OUT (relative to the root unless absolute; default
#            $build/out), never the source tree
#   threads  THREADS (default: all cores)
#   python   the Python that has Debian's python3-matplotlib (a pyenv python3 may shadow it on PATH)
root=$(cd "$here/../.." && pwd)
build=${GRAINBANK_BUILD_DIR:-build}
case $build in /*) ;; *) build=$root/$build ;; esac
outputs=${GRAINBANK_OUT:-$build/out}
case $outputs in /*) ;; *) outputs=$root/$outputs ;; esac
threads=${THREADS:-$(nproc)}
python=/usr/bin/python3
