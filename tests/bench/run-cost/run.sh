#!/usr/bin/env bash
# ./tests/bench.sh run-cost [CONFIG] [ENV_STEPS] [ENV_STEPS_2048]: what a 750k-step run costs, by
# phase. A real in-process run of CONFIG (default: the paper-budget campaign's Relational
# Rearrange 4, SRICS, the one-way graph given so that it starts at once) for ENV_STEPS (default
# 40,000) with SRICS_PHASES set: the run writes its CPU time by phase every 1,000 env steps
# (common/profile/phase_clock.h). The slice from 5,000 steps after the warm-up to the end is
# steady (SRICS_RUN_COST_SETTLE=N: from N steps after it); its CPU seconds per 1,000 env steps, by phase, give the projection for 750k env steps
# (the paper's budget) at batch 256. Then the same for batch 2048 over ENV_STEPS_2048 (default
# warm-up + 11,000). A config that learns its graph adds its graph phase once (measured in the
# first run; 0 with a given graph). Prints a table and, last, one JSON object with
# cpu_min_750k_batch256, cpu_min_750k_batch2048 and share_<phase> for each phase (batch 256).
# SRICS_RUN_COST_SET="key=value ..." adds those settings to both runs (e.g. learner.precision=bf16).
set -euo pipefail
build=$1; shift
root=$(cd "$(dirname "$0")/../../.." && pwd)
config=${1:-$root/deploy/configs/campaign/relational-4-750k.yaml}
steps=${2:-40000}
out=${SRICS_BENCH_OUT:-$root/runs/bench-run-cost-$(date +%Y%m%d-%H%M%S)}
mkdir -p "$out"
extra=()
if [[ -z ${1:-} ]]; then
  extra=(--set run.method=srics --set graph.file="$root/deploy/configs/campaign/graphs/relational-4-one-way.json")
fi
for kv in ${SRICS_RUN_COST_SET:-}; do extra+=(--set "$kv"); done
srics=$build/deploy/launcher/srics
budget=750000  # the paper's budget, which the projection is for
run() {  # NAME STEPS [--set ...]
  local name=$1 n=$2; shift 2
  rm -rf "$out/$name"
  echo "run-cost: $name, $n env steps ..." >&2
  SRICS_PHASES="$out/$name.phases.csv" "$srics" run "$config" --in-process --run-dir "$out/$name" --display plain \
    --set run.total_env_steps="$n" --set run.max_wall_minutes=0 "${extra[@]}" "$@" >"$out/$name.log" 2>&1
}
run batch256 "$steps"
warmup=$(awk '/^  warmup_steps:/{print $2; exit}' "$out/batch256/resolved-config.yaml")
warmup=${warmup:-2000}
run batch2048 "${3:-$((warmup + 11000))}" --set agent.sac.batch_size=2048

python3 - "$out" "$((warmup + ${SRICS_RUN_COST_SETTLE:-5000}))" "$budget" "$config" "$(uname -m) $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)" <<'PY'
import csv, json, sys
out, steady_from, budget, config, machine = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4], sys.argv[5]
def slice_of(name):
    rows = [{k: float(v) for k, v in r.items()} for r in csv.DictReader(open(f"{out}/{name}.phases.csv"))]
    start = next((r for r in rows if r["env_steps"] >= steady_from), None)
    end = rows[-1]
    if start is None or end["env_steps"] - start["env_steps"] < 1000:
        sys.exit(f"run-cost: {name}: too few env steps after the warm-up ({end['env_steps']:.0f})")
    phases = [k for k in rows[0] if k not in ("env_steps", "cpu_s")]
    kilo = (end["env_steps"] - start["env_steps"]) / 1000
    per = {p: (end[p] - start[p]) / kilo for p in phases}
    total = (end["cpu_s"] - start["cpu_s"]) / kilo
    per["other"] = total - sum(per.values())
    # the graph phase, once: what the graph service had spent when training began
    graph_phase = next((r["graph"] for r in rows if r["env_steps"] > 0), 0.0)
    return per, total, graph_phase, kilo
result = {"bench": "run-cost", "config": config, "machine": machine, "budget_env_steps": budget}
for name in ("batch256", "batch2048"):
    per, total, graph_phase, kilo = slice_of(name)
    minutes = (total * budget / 1000 + graph_phase) / 60
    print(f"{name}: {kilo * 1000:.0f} steady env steps; CPU s per 1,000 env steps {total:.2f}; "
          f"projection for {budget:,} env steps {minutes:.0f} CPU min")
    for p, v in sorted(per.items(), key=lambda kv: -kv[1]):
        print(f"  {p:16s} {v:7.3f} s  {100 * v / total:5.1f}%")
    result[f"cpu_min_750k_{name}"] = round(minutes, 1)
    result[f"cpu_s_per_1000_steps_{name}"] = round(total, 3)
    if name == "batch256":
        for p, v in per.items():
            result[f"share_{p}"] = round(v / total, 4)
print(json.dumps(result))
PY
