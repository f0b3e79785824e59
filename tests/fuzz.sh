#!/usr/bin/env bash
# Builds the libFuzzer harnesses of tests/fuzz into build-fuzz/ (clang, ASan + UBSan; the
# normal build is untouched) and runs each for SECONDS (default 60) from its seed corpus
# tests/fuzz/corpus/<harness>/. New inputs go to build-fuzz/corpus/<harness>/, findings to
# build-fuzz/findings/<harness>/. Prints runs, coverage and findings per harness; exits 1 on a
# finding. ./tests/fuzz.sh --seeds rewrites the committed seed corpora from the generators.
set -uo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${SRICS_FUZZ_BUILD_DIR:-$root/build-fuzz}
harnesses=(topics config checkpoint graph_json)
seconds=${1:-60}

"$root/deploy/install-deps.sh" || exit 2
"$root/tests/install-fuzz-deps.sh" || exit 2
export CCACHE_DIR=${CCACHE_DIR:-$HOME/.cache/srics-ccache}
export CCACHE_BASEDIR=${CCACHE_BASEDIR:-$root} CCACHE_NOHASHDIR=${CCACHE_NOHASHDIR:-1}
CC=clang CXX=clang++ cmake -S "$root" -B "$build" -DSRICS_FUZZ=ON -DSRICS_BUILD_TESTS=OFF \
  -DSRICS_BUILD_BENCHMARKS=OFF -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null || exit 2
cmake --build "$build" --target fuzz -j "${SRICS_JOBS:-$(nproc)}" >/dev/null || {
  cmake --build "$build" --target fuzz -j 1 2>&1 | tail -30
  exit 2
}

if [ "$seconds" = --seeds ]; then
  for h in "${harnesses[@]}"; do
    SRICS_FUZZ_WRITE_SEEDS="$root/tests/fuzz/corpus/$h" "$build/tests/fuzz/fuzz_$h" || exit 1
  done
  echo "seed corpora written to tests/fuzz/corpus/"
  exit 0
fi

export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
status=0
printf '%-12s %10s %8s %8s %s\n' harness runs cov ft findings
for h in "${harnesses[@]}"; do
  corpus="$build/corpus/$h" findings="$build/findings/$h" log="$build/fuzz_$h.log"
  rm -rf "$findings"
  mkdir -p "$corpus" "$findings"
  "$build/tests/fuzz/fuzz_$h" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=65536 \
    -print_final_stats=1 -artifact_prefix="$findings/" "$corpus" "$root/tests/fuzz/corpus/$h" >"$log" 2>&1
  rc=$?
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | tail -1 | grep -o '[0-9]*$')
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 | grep -o '[0-9]*')
  ft=$(grep -o 'ft: [0-9]*' "$log" | tail -1 | grep -o '[0-9]*')
  found=$(ls -1 "$findings" | wc -l)
  printf '%-12s %10s %8s %8s %s\n' "$h" "${runs:-?}" "${cov:-?}" "${ft:-?}" "$found"
  if [ "$rc" -ne 0 ] || [ "$found" -gt 0 ]; then
    status=1
    echo "  $h: exit $rc; log $log; inputs in $findings:"
    ls -1 "$findings" | sed 's/^/    /'
    grep -m1 -E 'ERROR|runtime error|terminate called|deadly signal' "$log" | sed 's/^/    /'
  fi
done
exit $status
