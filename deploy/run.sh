#!/usr/bin/env bash
# The main job: installs what is missing (Debian packages), builds, and runs one SRICS training
# run on this machine (graph service, learner and actors as separate processes over loopback
# DDS) with a live progress display. Leaves runs/<name>-<timestamp>/ with config.yaml, logs/,
# eval.csv, learner.csv, nodes.csv, curve.png, subgoal_success.png, graph.json/graph.png,
# checkpoint.srics and summary.txt.
#
#   ./deploy/run.sh                               the default config (deploy/configs/default.yaml)
#   ./deploy/run.sh CONFIG [srics run options]    e.g. --actors 3 --set run.seed=2
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${SRICS_BUILD_DIR:-$root/build}
config=${1:-$root/deploy/configs/default.yaml}
[ $# -gt 0 ] && shift
"$root/tests/build.sh" --target srics srics-graph srics-learner srics-actor srics-monitor
cd "$root"
exec "$build/deploy/launcher/srics" run "$config" "$@"
