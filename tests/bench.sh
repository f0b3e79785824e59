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
if [ -x "$root/tests/bench/$name/run.sh" ]; then
  # a script with its own executable builds just that; the others need the programs
  if [ -f "$root/tests/bench/$name/CMakeLists.txt" ]; then
    "$root/tests/build.sh" --target "$target" >&2
  else
    "$root/tests/build.sh" >&2
  fi
  exec "$root/tests/bench/$name/run.sh" "$build" "$@"
fi
"$root/tests/build.sh" --target "$target" >&2
exec "$build/tests/bench/$name/$target" "$@"
