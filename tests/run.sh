#!/usr/bin/env bash
# The whole test suite: installs what is missing, builds, runs every test with ctest.
#   ./tests/run.sh                 everything
#   ./tests/run.sh -L unit         only tests labelled unit (labels: unit, integration, slow, fastdds;
#                                  a test may carry two, joined: integration-slow)
#   ./tests/run.sh -LE slow        everything but the slow tests
#   ./tests/run.sh -R Transport    ctest's own filters pass through
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${SRICS_BUILD_DIR:-$root/build}
# test-only packages (Fast DDS for the interop test), before cmake looks for them
t0=$SECONDS
"$root/tests/install-test-deps.sh"
[ -n "${SRICS_PHASE_TIMES:-}" ] && echo "test-deps seconds: $((SECONDS - t0))" >>"$SRICS_PHASE_TIMES"
"$root/tests/build.sh"
cd "$build"
t0=$SECONDS
rc=0
# tests that write under ::testing::TempDir() get a folder of their own per suite run, so two
# checkouts (or two suites) running at once do not share /tmp paths
export TEST_TMPDIR=${TEST_TMPDIR:-$(mktemp -d /tmp/srics-tests.XXXXXX)/}
ctest --output-on-failure --timeout 600 -j "${SRICS_TEST_JOBS:-2}" "$@" || rc=$?
[ -n "${SRICS_PHASE_TIMES:-}" ] && echo "tests seconds: $((SECONDS - t0)) (ctest exit $rc)" >>"$SRICS_PHASE_TIMES"
exit $rc
