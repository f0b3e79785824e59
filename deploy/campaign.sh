#!/usr/bin/env bash
# The campaign's queue (docs/results.md, "The paper's claims"): the runs still to do, one at a
# time, in the order of deploy/configs/campaign/queue.txt. Each is a one-run `srics sweep`
# (in process), so a queue stopped anywhere (Ctrl-C, the end of a session) resumes with the
# same command: a sweep resumes its run from its checkpoint, replay included. A run whose
# curves are already under docs/results/campaign/raw/ is skipped; one that finishes has its
# config.yaml, resolved-config.yaml, eval.csv, train.csv, learner.csv (losses: a frozen learner shows),
# outcome.yaml and graph.json copied there (commit them: the
# sweep folders in runs/ are not kept by a new checkout).
#   deploy/campaign.sh [--dry-run] [--build DIR] [--queue FILE] [--runs DIR]
#     --dry-run  print what each line would do, run nothing
#     --runs DIR where the sweep folders go (default runs/campaign; a relative DIR is taken from
#                the repository root)
# Run it from anywhere; niced (10, as the graph acceptance runs are, so that neither starves the
# other): it is meant to run beside other work, one run per core. To use two cores, start it
# twice: a run being trained holds a lock (flock on DIR/OUT.lock), and a queue that reaches it
# skips to the next run instead of training it a second time.
# Queue lines (blank lines and # comments ignored):
#   OUT GROUP NAME CONFIG METHOD SEED [--set KEY=VALUE ...]
#   OUT     the sweep folder under runs/campaign/
#   GROUP   the raw folder under docs/results/campaign/raw/ (what `srics compare` reads)
#   NAME    the run's name there (NAME-seedSEED): compare groups runs by it, so a variant of a
#           method (another selectivity form) needs its own NAME
#   CONFIG  the campaign config, relative to the repository root
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=$root/build
queue=$root/deploy/configs/campaign/queue.txt
runs=runs/campaign
dry_run=0
while [[ $# -gt 0 ]]; do
  case "$1" in
    --dry-run) dry_run=1; shift ;;
    --build) build=$(cd "$2" && pwd); shift 2 ;;
    --queue) queue=$(cd "$(dirname "$2")" && pwd)/$(basename "$2"); shift 2 ;;
    --runs) runs=${2%/}; shift 2 ;;
    *) echo "deploy/campaign.sh: unknown option '$1' (--dry-run, --build DIR, --queue FILE, --runs DIR)" >&2; exit 2 ;;
  esac
done
[[ -f $queue ]] || { echo "deploy/campaign.sh: no queue file $queue" >&2; exit 2; }
srics=$build/deploy/launcher/srics
[[ $dry_run == 1 || -x $srics ]] || { echo "deploy/campaign.sh: $srics not built (./tests/build.sh)" >&2; exit 2; }
cd "$root"

line_no=0
while IFS= read -r line || [[ -n $line ]]; do
  line_no=$((line_no + 1))
  line=${line%%#*}
  read -r -a f <<<"$line"
  [[ ${#f[@]} -eq 0 ]] && continue
  if [[ ${#f[@]} -lt 6 ]]; then
    echo "deploy/campaign.sh: $queue:$line_no: expected OUT GROUP NAME CONFIG METHOD SEED [--set K=V ...], got '$line'" >&2
    exit 2
  fi
  out=${f[0]} group=${f[1]} name=${f[2]} config=${f[3]} method=${f[4]} seed=${f[5]}
  extra=("${f[@]:6}")
  raw=docs/results/campaign/raw/$group/$name-seed$seed
  if [[ -f $raw/outcome.yaml ]] && grep -q '^state: finished' "$raw/outcome.yaml"; then
    echo "[$(date -u +%H:%M)] $name-seed$seed ($group): finished, curves in $raw"
    continue
  fi
  [[ -f $config ]] || { echo "deploy/campaign.sh: $queue:$line_no: no config file $config" >&2; exit 2; }
  cmd=("$srics" sweep "$config" --methods "$method" --seeds "$seed" --in-process --out "$runs/$out" "${extra[@]}")
  # one queue per core: the lock says another queue is training this run (released when its
  # sweep ends, however it ends)
  busy="[$(date -u +%H:%M)] $name-seed$seed ($group): being trained by another queue ($runs/$out.lock), skipped"
  if [[ $dry_run == 1 ]]; then
    if [[ -e $runs/$out.lock ]] && ! flock -n "$runs/$out.lock" true; then echo "$busy"; continue; fi
    echo "would run: ${cmd[*]}  -> $raw"
    continue
  fi
  mkdir -p "$runs"
  exec {lock}>"$runs/$out.lock"
  if ! flock -n "$lock"; then
    echo "$busy"
    exec {lock}>&-
    continue
  fi
  echo "[$(date -u +%H:%M)] $name-seed$seed ($group): nice -n 10 ${cmd[*]}"
  nice -n 10 "${cmd[@]}" || true  # its outcome.yaml says how it ended
  exec {lock}>&-
  run_dir=$runs/$out/$method-seed$seed
  if ! grep -q '^state: finished' "$run_dir/outcome.yaml" 2>/dev/null; then
    echo "deploy/campaign.sh: $run_dir did not finish (outcome.yaml: $(head -c 200 "$run_dir/outcome.yaml" 2>/dev/null || echo none)); the queue stops here" >&2
    exit 1
  fi
  mkdir -p "$raw"
  for file in config.yaml resolved-config.yaml eval.csv train.csv learner.csv outcome.yaml graph.json; do
    [[ -f $run_dir/$file ]] && cp "$run_dir/$file" "$raw/"
  done
  [[ -f $root/docs/results/campaign/raw/$group/sweep.yaml ]] || cp "$runs/$out/sweep.yaml" "docs/results/campaign/raw/$group/"
  echo "[$(date -u +%H:%M)] $name-seed$seed ($group): finished, curves copied to $raw (commit them)"
done <"$queue"
echo "[$(date -u +%H:%M)] the queue is done"
