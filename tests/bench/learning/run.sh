#!/usr/bin/env bash
# ./tests/bench.sh learning [ENV ...]: SRICS learning runs with the CPU profile, in process
# (`srics run --in-process`: the distributed run's loops wired in memory) with the preset's
# ground-truth graph (graph.ground_truth: this bench measures the RL part), on Rearrange 1
# and Rearrange 2 by default. Each run is limited by its config
# (deploy/configs/<env>-cpu.yaml: env steps and 30 wall-clock minutes) and ends with the
# final evaluation against the passive policy on the same goals.
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
  start=$(date +%s)
  "$build/deploy/launcher/srics" run "$config" --in-process --display plain --run-dir "$out/$env" \
    --set graph.ground_truth=true >&2
  minutes=$(python3 -c "print(($(date +%s) - $start) / 60)")
  # the last evaluation of the trained policy and the passive one (policy_version 0)
  read -r steps policy passive arm < <(python3 - "$out/$env/eval.csv" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
passive = [r for r in rows if int(r["policy_version"]) == 0][0]
r = [r for r in rows if int(r["policy_version"]) > 0][-1]
print(r["env_steps"], r["avg_object_distance"], passive["avg_object_distance"], r["subgoal_success"].split(";")[0])
PY
)
  ratio=$(python3 -c "print(f'{$policy / $passive:.3f}')")
  [ -n "$first_ratio" ] || first_ratio=$ratio
  printf '%-14s %10s %10.4f %10.4f %8s %9s %8.1f\n' "$env" "$steps" "$policy" "$passive" "$ratio" "$arm" "$minutes" >> "$out/table.txt"
  key=${env//-/_}
  json+=",\"${key}_env_steps\":$steps,\"${key}_avg_object_distance\":$policy,\"${key}_passive\":$passive,\"${key}_ratio\":$ratio"
done
cat "$out/table.txt"
echo "run folders (eval.csv, curve.png, ...): $out/<env>"
echo "$json,\"ratio\":$first_ratio}"
