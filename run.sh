#!/usr/bin/env bash
# grainbank in two commands:
#   ./run.sh demo   install what is missing, build the tools, build a small cohesive cell library and run
#                   a cohesive column collapse against it (hybrid), with figures and a report (~5 min)
#   ./run.sh test   install what is missing, build, run the test suite (benchmarks as smoke tests), then
#                   the engine's physics tests once more in a portable build (no -march=native)
# Safe to run again: it installs only missing packages and rebuilds only what changed.
# GRAINBANK_BUILD_DIR overrides the build directory (default: build); GRAINBANK_DEMO_OUT the demo's
# output folder (default: demo_out; a second demo reuses its cell library).
set -euo pipefail
export DEBIAN_FRONTEND=noninteractive

cd "$(dirname "$0")"
readonly BUILD_DIR="${GRAINBANK_BUILD_DIR:-build}"
readonly PACKAGES=(cmake g++ make libeigen3-dev libhdf5-dev libsqlite3-dev sqlite3 nlohmann-json3-dev libgtest-dev
                   libnanoflann-dev libcli11-dev libbenchmark-dev libopenmpi-dev hdf5-tools python3-matplotlib)

usage() {
  echo "usage: $0 demo|test" >&2
  exit 2
}

missing_packages() {
  local pkg
  for pkg in "${PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed" || echo "$pkg"
  done
}

ensure_packages() {
  if ! command -v dpkg-query >/dev/null; then
    echo "run.sh: not a Debian system; install the equivalents of: ${PACKAGES[*]}" >&2
    command -v cmake >/dev/null || exit 1
    return
  fi
  local missing
  missing=$(missing_packages | tr '\n' ' ')
  [[ -z "$missing" ]] && return
  if [[ $(id -u) -eq 0 ]] && command -v apt-get >/dev/null; then
    echo "run.sh: installing $missing" >&2
    apt-get update -q
    # shellcheck disable=SC2086  # one word per package
    apt-get install -y -q --no-install-recommends $missing
  else
    echo "run.sh: missing packages; install them with:" >&2
    echo "  sudo apt-get update && sudo apt-get install -y $missing" >&2
    exit 1
  fi
}

# build [TARGET...]: configure, then build the given targets (default: everything).
build() {
  cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release
  cmake --build "$BUILD_DIR" --parallel "$(nproc)" ${1:+--target "$@"}
}

[[ $# -eq 1 ]] || usage
case "$1" in
  demo)
    ensure_packages
    build dem_sampler mpm_solver celldb
    GRAINBANK_BUILD_DIR="$BUILD_DIR" workflows/demo/run_demo.sh "${GRAINBANK_DEMO_OUT:-demo_out}"
    ;;
  test)
    ensure_packages
    build
    ctest --test-dir "$BUILD_DIR" --output-on-failure --parallel "$(nproc)"
    # The engine as a portable build compiles it (no -march=native: SSE2 vectors, no FMA): its
    # physics tests too, since the force loop's vector code differs between the two.
    cmake -S . -B "$BUILD_DIR-portable" -DCMAKE_BUILD_TYPE=Release -DGRAINBANK_NATIVE=OFF
    cmake --build "$BUILD_DIR-portable" --parallel "$(nproc)" --target dem_tests
    ctest --test-dir "$BUILD_DIR-portable" -L dem --output-on-failure --parallel "$(nproc)"
    ;;
  *) usage ;;
esac
