#!/usr/bin/env bash
# ./tests/bench.sh soak [MINUTES] [CONFIG]: a real distributed run (`srics run`, default
# rearrange-1-cpu.yaml, MINUTES of wall time, default 20) under faults:
#   - a random actor is killed (SIGKILL) every minute,
#   - the learner is killed twice (at 40% and 70% of the time) and the graph service once (at
#     55%; with graph.ground_truth=false not before it published its graph, at the latest at
#     85%: on a busy 2-core machine learning the graph takes most of a short soak),
#   - a foreign participant (bench_soak, soak_injector.cc) publishes a burst of malformed
#     samples on every topic every minute, from 30 s on,
# on its own DDS domain and run_id. The launcher restarts what was killed. The graph service
# publishes the environment's graph (graph.ground_truth: the graph it learns for Rearrange 1)
# so that the minutes go to the learner; SRICS_SOAK_SET=graph.ground_truth=false learns it.
# Every ~10 s the learner's RSS is sampled (whichever learner process is alive).
# Reports learner memory over time, restarts, rejected counts per node and reason, policy and
# graph versions, duplicates refused, and the final evaluation against the passive policy.
# Checks (the JSON's "checks"; exit 0 only if all pass):
#   memory_flat      the last learner process (from the second learner kill to the end), from
#                    30 s after it started: its largest RSS within 10% of its RSS then; the
#                    replay still filling counts against it (learner.replay_capacity is lowered
#                    to 20000 transitions, ~2 MB on Rearrange 1, so that its growth is small)
#   versions_monotone  learner.csv's policy version never goes back over the whole run (across
#                    learner restarts), nor any learner or actor process's graph and weights
#                    versions (nodes.csv)
#   no_episode_twice the injector replays real episodes of the run every burst; the learner
#                    refused them as duplicates (its NodeStatus counter episode.duplicate > 0;
#                    learner/episode_dedup.h: an (actor, episode id) stored once is refused
#                    after, also across learner restarts)
#   restarts         every kill was followed by a restart (the launcher's count >= kills)
#   better_than_passive  the last evaluation of learned weights has a lower
#                    avg_object_distance than the passive policy's (policy_version 0)
#   exit_0           the launcher ended the run with exit code 0 (the wall-clock limit)
# SRICS_SOAK_SET="k=v k=v" adds config overrides; SRICS_BENCH_OUT sets the output folder.
set -euo pipefail
build=$1; shift
root=$(cd "$(dirname "$0")/../../.." && pwd)
minutes=${1:-20}
config=${2:-$root/deploy/configs/rearrange-1-cpu.yaml}
out=${SRICS_BENCH_OUT:-$root/runs/bench-soak-$(date +%Y%m%d-%H%M%S)}
mkdir -p "$out"
run="$out/run"
# own domain (221..230: below the tests' 20..219, ports stay < 65536) and run id
domain=$((221 + $$ % 10))
run_id="soak-$(date +%s)-$$"
total=$((minutes * 60))
injector="$build/tests/bench/soak/bench_soak"
[ -x "$injector" ] || { echo "no $injector (build the bench_soak target)" >&2; exit 2; }

sets=(--set transport.domain_id=$domain --set transport.run_id=$run_id
      --set run.max_wall_minutes=$minutes --set run.total_env_steps=100000000
      --set learner.replay_capacity=20000 --set graph.ground_truth=true)
for kv in ${SRICS_SOAK_SET:-}; do sets+=(--set "$kv"); done

echo "soak: $minutes min, config $config, domain $domain, run id $run_id, folder $out" >&2
"$build/deploy/launcher/srics" run "$config" --run-dir "$run" --display plain "${sets[@]}" >"$out/launcher.log" 2>&1 &
launcher=$!
start=$(date +%s)
now() { echo $(( $(date +%s) - start )); }
# pid of a role process of this launcher: role srics-learner | srics-graph | srics-actor
role_pids() { ps -o pid=,args= --ppid "$launcher" 2>/dev/null | awk -v p="$1" '$2 ~ p"$" {print $1}'; }
log_event() { echo "$(now) $*" >>"$out/events.log"; echo "[soak $(now)s] $*" >&2; }
kill_role() {
  local pids; pids=($(role_pids "$1"))
  if [ ${#pids[@]} -eq 0 ]; then log_event "no $1 to kill"; return; fi
  local pid=${pids[$((RANDOM % ${#pids[@]}))]}
  kill -KILL "$pid" 2>/dev/null && log_event "killed $1 pid $pid" && echo "$1" >>"$out/kills"
}

: >"$out/rss.csv"; : >"$out/events.log"; : >"$out/kills"
echo "t_s,pid,rss_kb" >"$out/rss.csv"
learner_kills=($((total * 40 / 100 + 20)) $((total * 70 / 100 + 20)))
graph_kill=$((total * 55 / 100 + 40))
next_actor_kill=60 next_sample=0 injector_pid=""
while kill -0 "$launcher" 2>/dev/null; do
  t=$(now)
  if [ -z "$injector_pid" ] && [ "$t" -ge 30 ] && [ -f "$run/config.yaml" ]; then
    "$injector" "$run/config.yaml" $((minutes - 1)) 60 >"$out/injector.log" 2>&1 &
    injector_pid=$!
    log_event "injector started (pid $injector_pid)"
  fi
  if [ "$t" -ge "$next_sample" ]; then
    for pid in $(role_pids srics-learner); do
      rss=$(awk '/^VmRSS:/ {print $2}' /proc/"$pid"/status 2>/dev/null || true)
      [ -n "$rss" ] && echo "$t,$pid,$rss" >>"$out/rss.csv"
    done
    next_sample=$((next_sample + 10))
  fi
  if [ "$t" -ge "$next_actor_kill" ] && [ "$t" -lt $((total - 20)) ]; then
    kill_role srics-actor
    next_actor_kill=$((next_actor_kill + 60))
  fi
  for i in 0 1; do
    if [ "${learner_kills[$i]}" -gt 0 ] && [ "$t" -ge "${learner_kills[$i]}" ]; then
      kill_role srics-learner; learner_kills[$i]=0
    fi
  done
  # the graph service once it published its graph (graph.json; at the latest at 85%)
  if [ "$graph_kill" -gt 0 ] && [ "$t" -ge "$graph_kill" ] && { [ -f "$run/graph.json" ] || [ "$t" -ge $((total * 85 / 100)) ]; }; then
    kill_role srics-graph; graph_kill=0
  fi
  sleep 1
done
set +e
wait "$launcher"; launcher_code=$?
if [ -n "$injector_pid" ]; then kill -TERM "$injector_pid" 2>/dev/null; wait "$injector_pid"; fi
set -e
log_event "launcher exited with $launcher_code"

python3 "$root/tests/bench/soak/report.py" "$out" "$launcher_code" "$minutes"
