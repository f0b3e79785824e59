#!/usr/bin/env bash
# ./tests/bench.sh distributed [CONFIG] [ENV_STEPS]: the distributed system against the same
# loops in one process on the same config, seed and budget.
#  1. `srics run` with one actor over loopback DDS, which also learns the graph;
#  2. `srics run --in-process` with one actor and that learned graph (graph.file).
# Reports both final evaluations against the passive policy, the actor's env steps/s while
# training against the in-process trainer's, and as the last line one JSON object whose
# "ratio" is distributed final avg_object_distance / in-process final avg_object_distance.
set -euo pipefail
build=$1; shift
root=$(cd "$(dirname "$0")/../../.." && pwd)
config=${1:-$root/deploy/configs/rearrange-1-cpu.yaml}
steps=${2:-20000}
out=${SRICS_BENCH_OUT:-$root/runs/bench-distributed-$(date +%Y%m%d-%H%M%S)}
mkdir -p "$out"
common=(--set run.total_env_steps=$steps --set run.max_wall_minutes=0 --set actors.eval_every_env_steps=$((steps / 4)))

start=$(date +%s)
"$build/deploy/launcher/srics" run "$config" --actors 1 --run-dir "$out/distributed" --display plain \
  "${common[@]}" >&2
dist_seconds=$(( $(date +%s) - start ))
start=$(date +%s)
"$build/deploy/launcher/srics" run "$config" --in-process --actors 1 --run-dir "$out/in-process" --display plain \
  --set graph.file="$out/distributed/graph.json" "${common[@]}" >&2
inproc_seconds=$(( $(date +%s) - start ))

python3 - "$out" "$dist_seconds" "$inproc_seconds" <<'PY'
import csv, json, sys
out, dist_s, inproc_s = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
def final(folder):
    evals = list(csv.DictReader(open(f"{out}/{folder}/eval.csv")))
    passive = [r for r in evals if int(r["policy_version"]) == 0]
    return [r for r in evals if int(r["policy_version"]) > 0][-1], passive[0] if passive else None
dist, passive = final("distributed")
inproc, inproc_passive = final("in-process")
# actor env steps/s while training: from its NodeStatus rows (env_steps over uptime)
nodes = [r for r in csv.DictReader(open(f"{out}/distributed/nodes.csv")) if r.get("role") == "actor"]
def rate(rows):
    rows = [r for r in rows if r.get("state") in ("training", "waiting")]
    if len(rows) < 2: return float("nan")
    a, b = rows[0], rows[-1]
    dt = (float(b["uptime_ms"]) - float(a["uptime_ms"])) / 1000
    return (float(b["env_steps"]) - float(a["env_steps"])) / dt if dt > 0 else float("nan")
actor_rate = rate(nodes)
inproc_rate = float(inproc["env_steps"]) / inproc_s
d = float(dist["avg_object_distance"]); i = float(inproc["avg_object_distance"])
print(f"{'':28s} {'distributed':>12s} {'in-process':>12s}")
print(f"{'final avg_object_distance':28s} {d:12.4f} {i:12.4f}")
print(f"{'final avg_distance':28s} {float(dist['avg_distance']):12.4f} {float(inproc['avg_distance']):12.4f}")
nan = float("nan")
print(f"{'passive avg_object_distance':28s} {float(passive['avg_object_distance']) if passive else nan:12.4f} {float(inproc_passive['avg_object_distance']) if inproc_passive else nan:12.4f}")
print(f"{'env steps/s (whole run)':28s} {actor_rate:12.1f} {inproc_rate:12.1f}")
print(f"{'wall seconds':28s} {dist_s:12d} {inproc_s:12d}")
print(json.dumps({"bench": "distributed", "distributed_avg_object_distance": d, "in_process_avg_object_distance": i,
                  "actor_env_steps_per_s": round(actor_rate, 1), "in_process_env_steps_per_s": round(inproc_rate, 1),
                  "ratio": round(d / i, 3)}))
PY
