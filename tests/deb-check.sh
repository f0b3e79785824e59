#!/usr/bin/env bash
# Builds the portable Debian package and checks that an installed srics works from any folder.
# Not part of the test suite (it builds the programs a second time, without -march=native):
#
#   ./tests/deb-check.sh                  build the .deb, unpack it with dpkg -x into a
#                                         scratch root, run srics --version and a short
#                                         srics run default.yaml from a scratch folder in /tmp
#   sudo ./tests/deb-check.sh --debootstrap
#                                         the same, then apt installs the .deb into a minimal
#                                         Debian 12 root (tests/fresh-debian.sh: its
#                                         dependencies come from Debian) and runs srics there
#
# Environment: SRICS_DEB_BUILD_DIR (default build-deb/), SRICS_JOBS (default: the cores),
# SRICS_DEB_SECONDS (the run's wall-clock limit, default 30). Exit 0 when every check
# passes; the .deb's path is printed.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${SRICS_DEB_BUILD_DIR:-$root/build-deb}
seconds=${SRICS_DEB_SECONDS:-30}
debootstrap=0
case "${1:-}" in
  "") ;;
  --debootstrap) debootstrap=1 ;;
  -h|--help) sed -n '2,17p' "$0"; exit 0 ;;
  *) echo "deb-check: unknown argument '$1' (expected: --debootstrap)" >&2; exit 2 ;;
esac
fail() { echo "deb-check: FAIL: $*" >&2; exit 1; }

# --- the package: a portable Release build of the programs (no tests, no benchmarks) ---
"$root/deploy/install-deps.sh"
export CCACHE_DIR=${CCACHE_DIR:-$HOME/.cache/srics-ccache}
export CCACHE_BASEDIR=${CCACHE_BASEDIR:-$root} CCACHE_NOHASHDIR=${CCACHE_NOHASHDIR:-1}
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release -DSRICS_NATIVE=OFF -DSRICS_BUILD_TESTS=OFF \
  -DSRICS_BUILD_BENCHMARKS=OFF >/dev/null
cmake --build "$build" -j "${SRICS_JOBS:-$(nproc)}"
rm -f "$build"/srics-dds_*.deb
(cd "$build" && cpack -G DEB >/dev/null)
deb=$(ls "$build"/srics-dds_*.deb 2>/dev/null | head -1)
[ -n "$deb" ] || fail "cpack made no .deb in $build"
echo "deb-check: $deb"
dpkg-deb --info "$deb" | sed -n 's/^ \(Package\|Version\|Architecture\|Depends\|Recommends\):/  \1:/p'
contents=$(dpkg-deb --contents "$deb")
for f in srics srics-actor srics-learner srics-graph srics-monitor srics-draw-episode; do
  grep -q "\./usr/bin/$f\$" <<<"$contents" || fail "the package has no /usr/bin/$f"
done
grep -q "\./usr/share/srics-dds/configs/default.yaml\$" <<<"$contents" || fail "the package has no configs"

# --- installed by unpacking: the programs find their configs and each other ---
scratch=$(mktemp -d /tmp/srics-deb-check.XXXXXX)
trap 'rm -rf "$scratch"' EXIT
dpkg -x "$deb" "$scratch/root"
bin=$scratch/root/usr/bin
version=$("$bin/srics" --version)
echo "deb-check: $version"
[ "$version" = "srics $(sed -n 's/^project(srics_dds VERSION \([0-9.]*\).*/\1/p' "$root/CMakeLists.txt")" ] ||
  fail "srics --version says '$version'"
mkdir -p "$scratch/work"
domain=$((100 + $$ % 100))  # not the default domain of a run that may be going on here
echo "deb-check: srics run default.yaml from $scratch/work for ${seconds} s"
status=0
(cd "$scratch/work" && "$bin/srics" run default.yaml --display plain --set transport.domain_id=$domain \
  --set "run.max_wall_minutes=$(awk -v s="$seconds" 'BEGIN { print s / 60 }')" --set run.name=deb-check \
  >"$scratch/run.out" 2>&1) || status=$?
run_dir=$(ls -d "$scratch"/work/runs/deb-check-* 2>/dev/null | head -1)
if [ $status -ne 0 ] || [ -z "$run_dir" ]; then
  tail -n 30 "$scratch/run.out" >&2
  fail "srics run exited with $status"
fi
grep -q "state: finished" "$run_dir/outcome.yaml" || fail "outcome.yaml: $(cat "$run_dir/outcome.yaml")"
# the launcher looks for the role programs beside itself only (and in a build tree's layout,
# which the unpacked root does not have): a role that started is the package's
for role in graph learner actor-0 actor-1; do
  grep -q "started" "$run_dir/logs/$role.out" || fail "$role did not start (logs/$role.out)"
done
# a portable build still multiplies with the host's vector instructions: oneDNN picks them at
# run time (common/nn/gemm.h); the learner names them when it starts
products=$(sed -n "s/.*matrix products on \(.*\)$/\1/p" "$run_dir/logs/learner.out" | head -1)
case "$products" in
  "onednn ("*) echo "deb-check: the learner's matrix products: $products" ;;
  *) fail "the learner does not multiply on oneDNN: '${products:-no line in logs/learner.out}'" ;;
esac
episodes=$("$bin/srics" column "$run_dir/learner.csv" episodes_accepted) || fail "learner.csv: unreadable"
[ "$episodes" -gt 0 ] || fail "the learner accepted no episode (learner.csv)"
echo "deb-check: dpkg -x: srics run from $scratch/work: finished, 4 roles, $episodes episodes accepted"

# --- installed by apt into a minimal Debian root ---
if [ $debootstrap = 1 ]; then
  [ "$(id -u)" -eq 0 ] || fail "--debootstrap needs root"
  # tests/fresh-debian.sh copies the checkout's unignored files into the root: the .deb goes there
  mkdir -p "$root/.deb-check"
  trap 'rm -rf "$scratch" "$root/.deb-check"' EXIT
  cp "$deb" "$root/.deb-check/"
  # (a work folder of its own: another fresh-debian.sh may be using the default one)
  SRICS_FRESH_WORK=${SRICS_FRESH_WORK:-/var/tmp/srics-deb-check} \
    "$root/tests/fresh-debian.sh" "apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq \
    --no-install-recommends ./.deb-check/$(basename "$deb") >/dev/null && mkdir -p /tmp/w && cd /tmp/w && \
    srics --version && srics run default.yaml --display plain --set run.name=deb-check \
    --set transport.domain_id=$domain --set run.max_wall_minutes=$(awk -v s="$seconds" 'BEGIN { print s / 60 }') && \
    grep -q 'state: finished' runs/deb-check-*/outcome.yaml" ||
    fail "apt install or srics run in a minimal Debian root"
  echo "deb-check: apt install into a minimal Debian 12 root: srics run finished"
fi
echo "deb-check: PASS ($deb)"
