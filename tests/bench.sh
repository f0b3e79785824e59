#!/usr/bin/env bash
# ./tests/bench.sh NAME [args]: builds if needed, runs one benchmark or learning run.
# Each prints a readable table and, as its very last line, one JSON object with "bench": NAME.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${SRICS_BUILD_DIR:-$root/build}
if [ $# -lt 1 ]; then
  echo "usage: $0 NAME [args]   (names: $(ls "$root/tests/bench" | grep -v CMakeLists | tr '\n' ' '))" >&2
  exit 2
fi
name=$1; shift
target="bench_${name//-/_}"
# SRICS_BENCH_PLAN=1: print what would be built and run, and stop (tests)
plan() {
  if [ -n "${SRICS_BENCH_PLAN:-}" ]; then
    echo "build: $1"
    shift
    echo "run: $*"
    exit 0
  fi
}
if [ -x "$root/tests/bench/$name/run.sh" ]; then
  # a script with a target of its own (bench_NAME in its CMakeLists.txt) builds just that;
  # the others need the programs (gnn-acceptance's CMakeLists.txt holds only its script's test)
  if grep -qE "add_(executable|custom_target)\\(${target}[ )]" "$root/tests/bench/$name/CMakeLists.txt" 2>/dev/null; then
    plan "$target" "$root/tests/bench/$name/run.sh" "$build" "$@"
    "$root/tests/build.sh" --target "$target" >&2
  else
    plan everything "$root/tests/bench/$name/run.sh" "$build" "$@"
    "$root/tests/build.sh" >&2
  fi
  exec "$root/tests/bench/$name/run.sh" "$build" "$@"
fi
plan "$target" "$build/tests/bench/$name/$target" "$@"
"$root/tests/build.sh" --target "$target" >&2
exec "$build/tests/bench/$name/$target" "$@"
