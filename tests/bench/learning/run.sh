#!/usr/bin/env bash
# ./tests/bench.sh learning [ENV ...]: SRICS learning runs with the CPU profile, in process
# (srics-train), on Rearrange 1 and Rearrange 2 by default. Each run is limited by its
# config (deploy/configs/<env>-cpu.yaml: env steps and 30 wall-clock minutes) and ends with
# the final evaluation against the passive policy on the same goals.
# Prints a table and, last, one JSON line; "ratio" = SRICS final avg_object_distance /
# passive final avg_object_distance on the first environment (target: < 0.5 on rearrange-1).
set -euo pipefail
build=$1; shift
root=$(cd "$(dirname "$0")/../../.." && pwd)
envs=("$@")
[ ${#envs[@]} -gt 0 ] || envs=(rearrange-1 rearrange-2)
out=${SRICS_BENCH_OUT:-$root/runs/bench-learning-$(date +%Y%m%d-%H%M%S)}
mkdir -p "$out"
json="{\"bench\":\"learning\""
first_ratio=""
printf '%-14s %10s %10s %10s %8s %9s %8s\n' env steps "policy" passive ratio "arm succ" minutes > "$out/table.txt"
for env in "${envs[@]}"; do
  config=$root/deploy/configs/$env-cpu.yaml
  [ -f "$config" ] || { echo "no CPU config $config" >&2; exit 2; }
  "$build/learner/trainer/srics-train" "$config" --out "$out/$env" >&2
  # last row of the curve: env_steps, ..., avg_object_distance (5), passive (9), subgoal_success_0
  read -r steps policy passive minutes arm < <(python3 - "$out/$env/curve.csv" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
r = rows[-1]
print(r["env_steps"], r["avg_object_distance"], r["passive_avg_object_distance"],
      float(r["wall_seconds"]) / 60, r.get("subgoal_success_0", "nan"))
PY
)
  ratio=$(python3 -c "print(f'{$policy / $passive:.3f}')")
  [ -n "$first_ratio" ] || first_ratio=$ratio
  printf '%-14s %10s %10.4f %10.4f %8s %9s %8.1f\n' "$env" "$steps" "$policy" "$passive" "$ratio" "$arm" "$minutes" >> "$out/table.txt"
  key=${env//-/_}
  json+=",\"${key}_env_steps\":$steps,\"${key}_avg_object_distance\":$policy,\"${key}_passive\":$passive,\"${key}_ratio\":$ratio"
done
cat "$out/table.txt"
echo "curves and plots: $out/<env>/curve.csv, curve.png"
echo "$json,\"ratio\":$first_ratio}"
