#!/usr/bin/env bash
# Installs what is missing and builds the project into build/ (or $SRICS_BUILD_DIR).
# Shared by tests/run.sh, tests/bench.sh and deploy/run.sh.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${SRICS_BUILD_DIR:-$root/build}
"$root/deploy/install-deps.sh"
export CCACHE_DIR=${CCACHE_DIR:-$HOME/.cache/srics-ccache}
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=${SRICS_BUILD_TYPE:-Release} ${SRICS_CMAKE_ARGS:-} >/dev/null
cmake --build "$build" -j "${SRICS_JOBS:-$(nproc)}" "$@"
