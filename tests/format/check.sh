#!/usr/bin/env bash
# Fails on a C++ file of the checkout that clang-format (the house style, .clang-format at the
# root) would change, naming each file and the first lines it would change.
#   tests/format/check.sh [ROOT]          check (a ctest test: format_check_test)
#   tests/format/check.sh --fix [ROOT]    rewrite the files in place
# clang-format-14 comes with tests/install-test-deps.sh; without it the check SKIPs (exit 77).
set -euo pipefail
fix=0
if [ "${1:-}" = "--fix" ]; then fix=1; shift; fi
root=$(cd "${1:-$(dirname "$0")/../..}" && pwd)
# version 14 only: another formats some constructs differently and would fail formatted files
formatter=$(command -v clang-format-14 || true)
if [ -z "$formatter" ] && command -v clang-format > /dev/null &&
  clang-format --version | grep -q 'version 14\.'; then
  formatter=$(command -v clang-format)
fi
if [ -z "$formatter" ]; then
  echo "format check: SKIP, clang-format-14 is not installed (tests/install-test-deps.sh installs it)"
  exit 77
fi
cd "$root"
mapfile -t files < <(find common actor learner graph_service deploy tests \
  \( -name '*.cc' -o -name '*.h' \) -type f | sort)
if [ "$fix" = 1 ]; then
  "$formatter" -i --style=file "${files[@]}"
  echo "format: rewrote ${#files[@]} files as .clang-format says"
  exit 0
fi
bad=0
for f in "${files[@]}"; do
  if ! out=$("$formatter" --style=file "$f" | diff -u "$f" - 2>&1); then
    bad=$((bad + 1))
    echo "not formatted: $f"
    echo "$out" | sed -n '3,12p'
  fi
done
if [ "$bad" -gt 0 ]; then
  echo "format check: $bad of ${#files[@]} files differ from .clang-format; tests/format/check.sh --fix rewrites them"
  exit 1
fi
echo "format check: ${#files[@]} files as .clang-format says"
