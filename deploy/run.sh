#!/usr/bin/env bash
# The main job: installs what is missing (Debian packages), builds, and runs one SRICS training
# run on this machine (graph service, learner and actors as separate processes over loopback
# DDS) with a live progress display. Leaves runs/<name>-<timestamp>/ with config.yaml, logs/,
# eval.csv, learner.csv, nodes.csv, curve.png, subgoal_success.png, graph.json/graph.png,
# checkpoint.srics and summary.txt.
#
#   ./deploy/run.sh                               the default config (deploy/configs/default.yaml)
#   ./deploy/run.sh [CONFIG] [srics run options]  e.g. --actors 3 --set run.seed=2; without a
#                                                 CONFIG (the first argument an option) the default
# SRICS_NO_BUILD=1 runs the build that is there as it is (no package check, no build).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${SRICS_BUILD_DIR:-$root/build}
config=$root/deploy/configs/default.yaml
if [[ $# -gt 0 && $1 != -* ]]; then
  config=$1
  shift
fi
if [[ ${SRICS_NO_BUILD:-0} != 1 ]]; then
  echo "deploy/run.sh: checking packages and building (the first time about 10 minutes)"
  # the compile lines show progress; the "Built target" lines of up-to-date targets do not
  "$root/tests/build.sh" --target srics srics-graph srics-learner srics-actor srics-monitor |
    { grep --line-buffered -v '^\[[ 0-9]*%\] Built target ' || true; }  # nothing left: up to date
fi
cd "$root"
exec "$build/deploy/launcher/srics" run "$config" "$@"
