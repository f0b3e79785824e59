#!/usr/bin/env bash
# The campaign's queue (docs/results.md, "The paper's claims"): the runs still to do, one at a
# time, in the order of deploy/configs/campaign/queue.txt. Each is a one-run `srics sweep`
# (in process), so a queue stopped anywhere (Ctrl-C, the end of a session) resumes with the
# same command: a sweep resumes its run from its checkpoint, replay included. A run whose
# curves are already under docs/results/campaign/raw/ is skipped; one that finishes has its
# config.yaml, resolved-config.yaml, eval.csv, train.csv, learner.csv (losses: a frozen learner shows),
# outcome.yaml and graph.json copied there (commit them: the
# sweep folders in runs/ are not kept by a new checkout), and its last checkpoint evaluated by
# `srics eval` over more episodes than an in-run evaluation: final-eval/ (episodes.csv,
# attempts.csv) on the run's own evaluation goals and its passive policy on them,
# final-eval-passive/ (what `srics compare` reports); final-eval-selection/ and
# final-eval-selection-passive/ on the goals of evaluation seed 1000 + SEED, which no report
# uses: variants are chosen there (`srics compare --final-eval final-eval-selection`), so the
# choice is never made on the goals the results are reported on. A finished run whose raw
# folder lacks them gets them on the next pass while its sweep folder is still there.
#   deploy/campaign.sh [--dry-run] [--build DIR] [--queue FILE] [--runs DIR] [--final-episodes N]
#                      [--final-eval-only]
#     --dry-run  print what each line would do, run nothing
#     --runs DIR where the sweep folders go (default runs/campaign; a relative DIR is taken from
#                the repository root)
#     --final-episodes N  episodes of the final evaluation (default 300: fewer cannot separate methods closer than ~0.01 m; 0: none)
#     --final-eval-only   train nothing: only the final evaluations finished runs lack (beside
#                         two queues already training)
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
# The whole script is one block, read before it runs: bash reads a script as it goes, and an edit
# of this file while a queue trains (hours) used to break that queue when its loop ended.
{
root=$(cd "$(dirname "$0")/.." && pwd)
build=$root/build
queue=$root/deploy/configs/campaign/queue.txt
runs=runs/campaign
dry_run=0
final_episodes=300
final_eval_only=0
while [[ $# -gt 0 ]]; do
  case "$1" in
    --dry-run) dry_run=1; shift ;;
    --build) build=$(cd "$2" && pwd); shift 2 ;;
    --queue) queue=$(cd "$(dirname "$2")" && pwd)/$(basename "$2"); shift 2 ;;
    --runs) runs=${2%/}; shift 2 ;;
    --final-episodes) final_episodes=$2; shift 2 ;;
    --final-eval-only) final_eval_only=1; shift ;;
    *) echo "deploy/campaign.sh: unknown option '$1' (--dry-run, --build DIR, --queue FILE, --runs DIR, --final-episodes N, --final-eval-only)" >&2; exit 2 ;;
  esac
done
[[ -f $queue ]] || { echo "deploy/campaign.sh: no queue file $queue" >&2; exit 2; }
# With autogroup scheduling (Linux's default on Debian), nice only ranks processes within one
# session: a queue started with setsid, or from another terminal, would share the CPU equally
# with a build or a benchmark whatever its nice. So the queue's whole scheduling group is
# niced too (2026-12-05: a run niced to 0 got 56% of its core beside builds niced to 15).
if [[ -w /proc/self/autogroup ]]; then echo 10 >/proc/self/autogroup 2>/dev/null || true; fi
srics=$build/deploy/launcher/srics
[[ $dry_run == 1 || -x $srics ]] || { echo "deploy/campaign.sh: $srics not built (./tests/build.sh)" >&2; exit 2; }
[[ $final_episodes =~ ^[0-9]+$ ]] || { echo "deploy/campaign.sh: --final-episodes takes a count, got '$final_episodes'" >&2; exit 2; }
cd "$root"

# final_eval RUN_DIR RAW SEED: the last checkpoint over $final_episodes episodes on the run's own
# goals (final-eval) and on goals no report uses (final-eval-selection: evaluation seed 1000 +
# SEED), each with the passive policy on the same goals (its yardstick); logs beside them
# Always on the reference's schedule, whatever the run evaluated with, so that one table never
# mixes schedules. Holds LOCK (the run's lock file) so that two queues never evaluate one run.
final_eval() {
  local run_dir=$1 raw=$2 seed=$3 lock_file=$4
  [[ $final_episodes -gt 0 && -f $run_dir/checkpoint.srics ]] || return 0
  [[ $dry_run == 1 ]] && { echo "would evaluate $run_dir's last checkpoint over $final_episodes episodes -> $raw/final-eval*"; return 0; }
  local kind extra fd
  exec {fd}>"$lock_file"
  if ! flock -n "$fd"; then
    echo "[$(date -u +%H:%M)] $(basename "$run_dir"): being evaluated or trained by another queue, skipped"
    exec {fd}>&-
    return 0
  fi
  for kind in final-eval final-eval-passive final-eval-selection final-eval-selection-passive; do
    extra=(--set actors.eval_schedule=reference)
    [[ $kind == *-passive ]] && extra+=(--passive)
    [[ $kind == final-eval-selection* ]] && extra+=(--goal-set $((1000 + seed)))
    rm -rf "$raw/$kind.tmp"
    if nice -n 10 "$srics" eval "$run_dir" --episodes "$final_episodes" --no-video "${extra[@]}" \
         --out "$raw/$kind.tmp" >"$raw/$kind.log" 2>&1 </dev/null; then
      rm -rf "${raw:?}/$kind" && mv "$raw/$kind.tmp" "$raw/$kind"
    else
      echo "deploy/campaign.sh: srics eval of $run_dir failed (see $raw/$kind.log)" >&2
      rm -rf "$raw/$kind.tmp"
      exec {fd}>&-
      return 1
    fi
  done
  exec {fd}>&-
  echo "[$(date -u +%H:%M)] $(basename "$run_dir"): its last checkpoint evaluated over $final_episodes episodes in $raw/final-eval*"
}

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
    [[ -d $raw/final-eval-selection-passive ]] ||
      final_eval "$runs/$out/$method-seed$seed" "$raw" "$seed" "$runs/$out.lock" || true
    continue
  fi
  if [[ $final_eval_only == 1 ]]; then
    echo "[$(date -u +%H:%M)] $name-seed$seed ($group): not finished, left alone (--final-eval-only)"
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
  nice -n 10 "${cmd[@]}" </dev/null || true  # its outcome.yaml says how it ended
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
  final_eval "$run_dir" "$raw" "$seed" "$runs/$out.lock" || true
done <"$queue"
echo "[$(date -u +%H:%M)] the queue is done"
exit 0
}
