#!/usr/bin/env bash
# Debian packages only the test suite needs (tests/run.sh calls this before building):
# - fastddsgen and libfastrtps-dev, for the test that builds a Fast DDS 2.9 subscriber from
#   idl/srics.idl (tests/integration/fastdds/). Cost, measured on Debian 12: 40 packages,
#   ~40 MB download, ~60 MB on disk, ~25 s when a Java runtime is present; without one,
#   fastddsgen also pulls openjdk-17-jre-headless (+44 MB download, +190 MB on disk).
# - chromium, the headless browser of the dashboard test (tests/deploy/dashboard/); without
#   recommends, measured on this Debian 12 host (which had the X and font libraries already):
#   9 packages, ~122 MB download, ~400 MB on disk.
# - ffmpeg, for the render tests that read an MP4 of `srics eval` back frame by frame
#   (tests/actor/env/render/; without it they SKIP): 32 packages without recommends, 12 s to
#   install here from a warm package cache.
# - clang-format-14, for the format check (tests/format/check.sh, the house style).
# Idempotent like deploy/install-deps.sh. SRICS_SKIP_TEST_DEPS=1 skips it (the interop and
# browser tests then SKIP).
set -euo pipefail

[ -n "${SRICS_SKIP_TEST_DEPS:-}" ] && exit 0
packages=(fastddsgen libfastrtps-dev chromium ffmpeg clang-format-14)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "install-test-deps: installing ${missing[*]}"
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
export DEBIAN_FRONTEND=noninteractive
if ! { "${sudo_cmd[@]}" apt-get update -qq &&
       "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"; }; then
  # the rest of the suite does not need them: go on, the interop test will SKIP and say why
  echo "install-test-deps: could not install ${missing[*]}; the Fast DDS interop test, the dashboard's browser test or the MP4 render tests will SKIP" >&2
fi
