# Sourced by the workflow shell scripts once `here` (their folder) is set: the repository root, the
# build directory (GRAINBANK_BUILD_DIR, relative to the root unless absolute; default build), the
# thread count (THREADS, default all cores) and the Python that has Debian's python3-matplotlib (a
# pyenv python3 may shadow it on PATH).
root=$(cd "$here/../.." && pwd)
build=${GRAINBANK_BUILD_DIR:-$root/build}
case $build in /*) ;; *) build=$root/$build ;; esac
threads=${THREADS:-$(nproc)}
python=/usr/bin/python3
