#!/usr/bin/env bash
# Installs the Debian packages SRICS-DDS needs. Idempotent: does nothing when all are present,
# and runs `apt-get update` only when something is missing.
#   deploy/install-deps.sh          what the build, the tests and the runs need
#   deploy/install-deps.sh video    also ffmpeg, for the MP4 and GIF videos of `srics eval`
#                                   (without it, srics eval writes PNG frames)
set -euo pipefail

packages=(
  build-essential cmake ccache pkg-config
  cyclonedds-dev cyclonedds-tools
  libmujoco-dev
  # libmujoco-dev's CMake config asks for OpenGL but the package does not depend on its
  # development files (a minimal Debian 12 root lacks them: tests/fresh-debian.sh)
  libgl-dev libglx-dev libopengl-dev
  libeigen3-dev libyaml-cpp-dev libspdlog-dev libfmt-dev
  libdnnl-dev  # oneDNN: the float matrix products of the networks (common/nn/gemm.h)
  # oneDNN's CMake config requires OpenCL (Debian builds it with the OpenCL GPU runtime), but
  # libdnnl-dev only recommends it, and we install without recommends
  ocl-icd-opencl-dev
  libcli11-dev  # the one argument parser of every program (common/cli)
  libgtest-dev libgmock-dev libbenchmark-dev
  libpng-dev gnuplot-nox graphviz libqhull-dev
  libdeflate-dev  # CRC-32 of the policy weights (PCLMUL: 3x zlib's on 5 MB, checked on each side)
  libcpp-httplib-dev  # the web dashboard's HTTP server (srics run --http, srics-monitor --http)
  # MuJoCo's offscreen renderer without a display (srics eval): EGL with Mesa (llvmpipe)
  libegl-dev libegl-mesa0 libgl1-mesa-dri
  iproute2 procps
  openssl  # the command line that makes DDS Security keystores (deploy/security/, security_test)
  python3 bc time  # the bench and acceptance scripts summarise and time with them
)

# optional: only the command that needs them asks for them
video_packages=(ffmpeg)
case "${1:-}" in
  "") ;;
  video) packages+=("${video_packages[@]}") ;;
  *) echo "install-deps: unknown argument '$1' (expected: video)" >&2; exit 2 ;;
esac

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
