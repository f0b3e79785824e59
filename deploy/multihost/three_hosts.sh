#!/usr/bin/env bash
# Three "hosts" on this machine: network namespaces joined by veth pairs to a bridge (in a
# fourth namespace, so the machine's own network is left alone). Each host runs `srics run
# --roles` for its share of the run, with the launcher's supervisor, restarts and display:
# host A `--roles learner,graph`, hosts B and C `--roles actor --ids 0` and `--ids 1`, all with
# the Cyclone profile `unicast` whose peers are the three veth addresses (each namespace has
# its own loopback: 127.0.0.1 is never a peer). srics-monitor runs on host C, i.e. it watches
# A's learner from another host.
#
# It checks, within a time limit, that
#   1. episodes flow:   the learner accepted episodes from the actors on B and C
#   2. the graph arrives on B and C (the actors' NodeStatus carries graph_version >= 1)
#   3. weights arrive on B and C   (the actors' NodeStatus carries policy_version >= 1)
#   4. learning proceeds: SAC updates grow and newer weights are published (policy v >= 2)
# and exits 0 when all hold, 1 when not (printing the tail of every log), 2 on bad usage.
#
#   sudo deploy/multihost/three_hosts.sh [CONFIG] [--time-limit SECONDS] [--keep] [--secure] [--set key=value ...]
#                                        [--installed]
#
# --secure: DDS Security on every host: a keystore made by deploy/security/make-keystore.sh
# in the run folder, transport.security.keystore set for every process (each uses its own
# identity: launcher, graph, learner, actor-0, actor-1, monitor).
#
# CONFIG defaults to deploy/configs/default.yaml (rearrange-1-cpu.yaml if that does not exist).
# Needs root (ip netns), iproute2, and the built programs in ${SRICS_BUILD_DIR:-build}/ (it
# builds them with tests/build.sh when missing); with --installed, the programs of the
# installed package (srics and srics-monitor on the PATH, e.g. /usr/bin from the .deb) and
# CONFIG by default its share/srics-dds/configs/default.yaml. Everything it creates is removed
# on exit (trap), except the run folder (a subfolder per host: the launcher's run folder with
# logs and CSV files), whose path it prints.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${SRICS_BUILD_DIR:-$root/build}
config=""
time_limit=600
keep=0
secure=0
installed=0
sets=()
while [ $# -gt 0 ]; do
  case "$1" in
    --time-limit) time_limit=$2; shift 2 ;;
    --keep) keep=1; shift ;;
    --secure) secure=1; shift ;;
    --set) sets+=(--set "$2"); shift 2 ;;
    --installed) installed=1; shift ;;
    -h|--help) sed -n '2,30p' "$0"; exit 0 ;;
    -*) echo "three_hosts.sh: unknown option $1" >&2; exit 2 ;;
    *) config=$1; shift ;;
  esac
done
[ "$(id -u)" = 0 ] || { echo "three_hosts.sh: needs root for ip netns (sudo $0)" >&2; exit 2; }
command -v ip >/dev/null || { echo "three_hosts.sh: needs iproute2 (ip)" >&2; exit 2; }

if [ $installed = 1 ]; then
  srics=$(command -v srics) || { echo "three_hosts.sh: --installed: no srics on the PATH" >&2; exit 2; }
  monitor=$(command -v srics-monitor) || { echo "three_hosts.sh: --installed: no srics-monitor on the PATH" >&2; exit 2; }
  share=$(cd "$(dirname "$srics")/../share/srics-dds" && pwd)
  [ -n "$config" ] || config=$share/configs/default.yaml
else
  srics=$build/deploy/launcher/srics
  monitor=$build/deploy/monitor/srics-monitor
  for b in "$srics" "$build/graph_service/srics-graph" "$build/learner/srics-learner" "$build/actor/srics-actor" \
           "$monitor"; do
    if [ ! -x "$b" ]; then
      "$root/tests/build.sh" --target srics srics-graph srics-learner srics-actor srics-monitor
      break
    fi
  done
fi
if [ -z "$config" ]; then
  config=$root/deploy/configs/default.yaml
  [ -f "$config" ] || config=$root/deploy/configs/rearrange-1-cpu.yaml
fi

tag=s$$                      # unique names: several copies may run at once
ns_a=$tag-a ns_b=$tag-b ns_c=$tag-c ns_br=$tag-br
subnet=10.$((($$ >> 8) % 200 + 20)).$(($$ % 250)).   # a /24 of our own
addr_a=${subnet}1 addr_b=${subnet}2 addr_c=${subnet}3
run=$(mktemp -d /tmp/srics-three-hosts.XXXXXX)
pids=()

cleanup() {
  local status=$?
  trap - EXIT INT TERM
  # SIGINT to every process (a launcher stops its roles: the learner checkpoints), a grace
  # period, then SIGKILL (a launcher's roles then get SIGTERM from the parent-death signal)
  for pid in "${pids[@]}"; do kill -INT "$pid" 2>/dev/null || true; done
  for _ in $(seq 250); do
    local alive=0
    for pid in "${pids[@]}"; do kill -0 "$pid" 2>/dev/null && alive=1; done
    [ $alive = 0 ] && break
    sleep 0.1
  done
  for pid in "${pids[@]}"; do kill -KILL "$pid" 2>/dev/null || true; done
  wait 2>/dev/null || true
  for ns in "$ns_a" "$ns_b" "$ns_c" "$ns_br"; do ip netns del "$ns" 2>/dev/null || true; done
  echo "run folder: $run"
  exit $status
}
trap cleanup EXIT
trap 'exit 130' INT TERM

# --- the network: a bridge in its own namespace, one veth pair per host, named eth0 inside ---
ip netns add "$ns_br"
ip -n "$ns_br" link add br0 type bridge
ip -n "$ns_br" link set br0 up
ip -n "$ns_br" link set lo up
for host in a b c; do
  ns=$tag-$host
  eval addr=\$addr_$host
  ip netns add "$ns"
  ip link add "$tag$host" type veth peer name "$tag${host}br"
  ip link set "$tag$host" netns "$ns"
  ip link set "$tag${host}br" netns "$ns_br"
  ip -n "$ns" link set "$tag$host" name eth0
  ip -n "$ns" addr add "$addr/24" dev eth0
  ip -n "$ns" link set eth0 up
  ip -n "$ns" link set lo up
  ip -n "$ns_br" link set "$tag${host}br" master br0
  ip -n "$ns_br" link set "$tag${host}br" up
done
if command -v ping >/dev/null; then  # (ping is optional: DDS discovery below is the real test)
  for ns in "$ns_b" "$ns_c"; do
    ip netns exec "$ns" ping -c 1 -W 2 "$addr_a" >/dev/null || { echo "three_hosts.sh: $ns cannot reach A" >&2; exit 1; }
  done
fi
echo "hosts: A $addr_a (graph, learner)  B $addr_b (actor 0)  C $addr_c (actor 1, monitor)"

# --- the same configuration everywhere: unicast discovery between the three addresses ---
if [ "$secure" = 1 ]; then
  "$root/deploy/security/make-keystore.sh" "$run/keystore" --actors 2 >"$run/keystore.log"
  sets+=(--set "transport.security.keystore=$run/keystore")
fi
common=("$config" --set transport.profile=unicast --set "transport.peers=$addr_a,$addr_b,$addr_c"
        --set transport.network_interface=eth0 --set "transport.run_id=three-hosts-$$" "${sets[@]}")
mkdir -p "$run"/monitor
start() {  # start HOST ROLES...: `srics run` with this host's share, its run folder $run/HOST
  local host=$1
  shift
  ip netns exec "$tag-$host" "$srics" run "${common[@]}" --run-dir "$run/$host" --display plain --stop-timeout 15 \
    --roles "$@" >"$run/$host.out" 2>&1 &
  pids+=($!)
}
start a learner,graph
start b actor --ids 0
start c actor --ids 1
ip netns exec "$ns_c" "$monitor" "${common[@]}" --csv "$run/monitor" --no-weights --for "$time_limit" \
  >"$run/monitor/monitor.out" 2>&1 &
pids+=($!)

# --- the checks, on what the monitor on host C wrote ---
# the largest value of a column of the monitor's files, by name (srics column: the run folder's
# one CSV reader; 0 until a matching row has one)
actor_max() {  # actor_max ID COLUMN: the largest value of COLUMN in that actor's rows of nodes.csv
  "$srics" column "$run/monitor/nodes.csv" "$2" --where role=actor --where node_id="$1" 2>/dev/null || echo 0
}
learner_max() {  # learner_max COLUMN: of learner.csv
  "$srics" column "$run/monitor/learner.csv" "$1" 2>/dev/null || echo 0
}
first_updates=""
deadline=$((SECONDS + time_limit))
ok=0
while [ $SECONDS -lt $deadline ]; do
  sleep 3
  for pid in "${pids[@]:0:3}"; do
    kill -0 "$pid" 2>/dev/null || { echo "a host's srics run exited early (pid $pid)"; break 2; }
  done
  episodes=$(learner_max episodes_accepted); updates=$(learner_max updates); policy=$(learner_max policy_version)
  [ -z "$first_updates" ] && [ "$updates" -gt 0 ] && first_updates=$updates
  g0=$(actor_max 0 graph_version); g1=$(actor_max 1 graph_version)
  w0=$(actor_max 0 policy_version); w1=$(actor_max 1 policy_version)
  s0=$(actor_max 0 env_steps); s1=$(actor_max 1 env_steps)
  printf '[%4ds] episodes %s  env steps B %s C %s  graph B v%s C v%s  weights B v%s C v%s  updates %s  policy v%s\n' \
    "$SECONDS" "$episodes" "$s0" "$s1" "$g0" "$g1" "$w0" "$w1" "$updates" "$policy"
  if [ "$episodes" -gt 0 ] && [ "$s0" -gt 0 ] && [ "$s1" -gt 0 ] && [ "$g0" -ge 1 ] && [ "$g1" -ge 1 ] &&
     [ "$w0" -ge 1 ] && [ "$w1" -ge 1 ] && [ "$policy" -ge 2 ] && [ -n "$first_updates" ] &&
     [ "$updates" -gt "$first_updates" ]; then
    ok=1
    break
  fi
done

if [ $ok = 1 ]; then
  echo "PASS: episodes flow from B and C to A, the graph and weights arrive on B and C, learning proceeds"
  echo "      (updates $first_updates -> $updates, policy v$policy), seen by srics-monitor on host C"
  [ $keep = 1 ] && { echo "--keep: running until Ctrl-C"; wait; }
  exit 0
fi
echo "FAIL: not all checks passed within ${time_limit}s" >&2
for f in "$run"/*.out "$run"/a/logs/*.out "$run"/b/logs/*.out "$run"/c/logs/*.out "$run"/monitor/monitor.out; do
  echo "--- $f" >&2
  tail -n 15 "$f" >&2 || true
done
exit 1
