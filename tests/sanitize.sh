#!/usr/bin/env bash
# The suite's unit and integration tests under AddressSanitizer (leaks included) and
# UndefinedBehaviorSanitizer: a separate build in build-sanitize/ (gcc, RelWithDebInfo,
# SRICS_SANITIZE=ON; the normal build is untouched). Called by .ci/run after ./tests/run.sh.
#   ./tests/sanitize.sh                 unit and integration tests, the slow ones left out
#   ./tests/sanitize.sh -R Transport    ctest's own filters instead
# Exits non-zero when a test fails or a sanitizer reports (a report aborts the test).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${SRICS_SANITIZE_BUILD_DIR:-$root/build-sanitize}
"$root/deploy/install-deps.sh"
"$root/tests/install-test-deps.sh"
export CCACHE_DIR=${CCACHE_DIR:-$HOME/.cache/srics-ccache}
export CCACHE_BASEDIR=${CCACHE_BASEDIR:-$root} CCACHE_NOHASHDIR=${CCACHE_NOHASHDIR:-1}
t0=$SECONDS
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSRICS_SANITIZE=ON \
  -DSRICS_BUILD_BENCHMARKS=OFF >/dev/null
cmake --build "$build" -j "${SRICS_JOBS:-$(nproc)}" >/dev/null || {
  cmake --build "$build" -j 1 2>&1 | grep -E "error|Error" | head -30
  exit 2
}
echo "sanitize: build $((SECONDS - t0)) s"
cd "$build"
export TEST_TMPDIR=${TEST_TMPDIR:-$(mktemp -d /tmp/srics-sanitize.XXXXXX)/}
# leaks are reported at exit; symbolised stacks; halt on the first UB report
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
# Cyclone DDS and MuJoCo allocate once per process and keep it (not leaks of ours)
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$root/tests/sanitize.supp:print_suppressions=0}
t0=$SECONDS
filters=("$@")
[ ${#filters[@]} -eq 0 ] && filters=(-L "unit|integration" -LE slow)
rc=0
ctest --output-on-failure --timeout 900 -j "${SRICS_TEST_JOBS:-2}" "${filters[@]}" || rc=$?
echo "sanitize: tests $((SECONDS - t0)) s (ctest exit $rc)"
exit $rc
