#!/usr/bin/env bash
# Installs what is missing and builds the project into build/ (or $SRICS_BUILD_DIR).
# Shared by tests/run.sh, tests/bench.sh and deploy/run.sh. With SRICS_PHASE_TIMES=FILE the
# seconds of each phase are appended to FILE (tests/fresh-debian.sh reports them).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${SRICS_BUILD_DIR:-$root/build}
phase() { [ -n "${SRICS_PHASE_TIMES:-}" ] && echo "$1 seconds: $2" >>"$SRICS_PHASE_TIMES"; return 0; }
t0=$SECONDS
"$root/deploy/install-deps.sh"
phase install $((SECONDS - t0))
export CCACHE_DIR=${CCACHE_DIR:-$HOME/.cache/srics-ccache}
# Paths relative to the checkout, so a fresh clone or a worktree hits the cache of another.
export CCACHE_BASEDIR=${CCACHE_BASEDIR:-$root} CCACHE_NOHASHDIR=${CCACHE_NOHASHDIR:-1}
t0=$SECONDS
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=${SRICS_BUILD_TYPE:-Release} ${SRICS_CMAKE_ARGS:-} >/dev/null
cmake --build "$build" -j "${SRICS_JOBS:-$(nproc)}" "$@"
phase "build ($*)" $((SECONDS - t0))
