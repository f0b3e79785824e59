#!/usr/bin/env bash
# The test suite under AddressSanitizer (leaks included) and UndefinedBehaviorSanitizer: a
# separate build in build-sanitize/ (clang, -O1 with line tables, SRICS_SANITIZE=ON; the normal
# build is untouched). Any sanitizer report aborts the test that caused it, so ctest fails.
#   ./tests/sanitize.sh                 unit and integration tests, the slow ones left out
#   ./tests/sanitize.sh --unit          only the unit tests, and only their targets are built
#                                       (what .ci/run runs after ./tests/run.sh)
#   ./tests/sanitize.sh -R Transport    ctest's own filters instead of the default ones
# SRICS_JOBS (build jobs) and SRICS_TEST_JOBS (ctest jobs) as for ./tests/run.sh.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${SRICS_SANITIZE_BUILD_DIR:-$root/build-sanitize}
target=all
filters=(-L "unit|integration" -LE slow)
if [ "${1:-}" = --unit ]; then
  shift
  target=srics_unit_tests
  filters=(-L unit)
fi
[ $# -gt 0 ] && filters=("$@")
"$root/deploy/install-deps.sh"
"$root/tests/install-test-deps.sh"
# clang and its sanitizer runtimes (the same packages as the fuzz build)
"$root/tests/install-fuzz-deps.sh"
export CCACHE_DIR=${CCACHE_DIR:-$HOME/.cache/srics-ccache}
export CCACHE_BASEDIR=${CCACHE_BASEDIR:-$root} CCACHE_NOHASHDIR=${CCACHE_NOHASHDIR:-1}
t0=$SECONDS
# clang rather than gcc: with both sanitizers over the Eigen code it compiles in about half the
# time; -O1 as the sanitizers' documentation advises, line tables only (enough for the reports)
flags="-O1 -gline-tables-only -DNDEBUG"
CC=clang CXX=clang++ cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="$flags" -DCMAKE_C_FLAGS_RELWITHDEBINFO="$flags" \
  -DSRICS_SANITIZE=ON -DSRICS_BUILD_BENCHMARKS=OFF >/dev/null
cmake --build "$build" --target "$target" -j "${SRICS_JOBS:-$(nproc)}" >/dev/null || {
  cmake --build "$build" --target "$target" -j 1 2>&1 | grep -E "error|Error" | head -30
  exit 2
}
echo "sanitize: build $((SECONDS - t0)) s"
cd "$build"
export TEST_TMPDIR=${TEST_TMPDIR:-$(mktemp -d /tmp/srics-sanitize.XXXXXX)/}
symbolizer=$(command -v llvm-symbolizer || ls /usr/lib/llvm-*/bin/llvm-symbolizer 2>/dev/null | tail -1 || true)
[ -n "$symbolizer" ] && export ASAN_SYMBOLIZER_PATH=$symbolizer
# any report ends the process with a failure; leaks are reported at exit.
# intercept_tls_get_addr=0: the runtime of LLVM <= 16 (Debian 12's clang 14) takes a dynamic
# TLS block that happens to start 16 bytes past a page for a glibc < 2.25 header and reads a
# bogus range from it, and LeakSanitizer's tracer then dies at exit ("Tracer caught signal 11",
# no leak reported): Mesa's dlopened GL driver made render_test fail so in CI once (150 runs
# in a row here did not); tests/sanitizer_runtime/leak_check_test.cc makes it happen every run.
# Our own thread-locals are static TLS, which the leak check still scans.
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1:intercept_tls_get_addr=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
# third-party libraries' own allocations (tests/sanitize.supp says which and why)
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$root/tests/sanitize.supp:print_suppressions=0}
t0=$SECONDS
rc=0
ctest --output-on-failure --timeout 900 -j "${SRICS_TEST_JOBS:-2}" "${filters[@]}" || rc=$?
echo "sanitize: tests $((SECONDS - t0)) s (ctest exit $rc)"
exit $rc
