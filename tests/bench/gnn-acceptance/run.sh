#!/usr/bin/env bash
# Acceptance of the graph service (issue 6): learns the interaction graph of rearrange-3 and
# relational-4 from 1000 random-action episodes for seeds 1..3 with the default GraphConfig,
# one run at a time on one thread, and prints per run: graph, wall and CPU time, held-out
# loss, updates, and the mean weights of the kept edges (full matrices in OUT/<env>-<seed>/).
#   ./tests/bench.sh gnn-acceptance [SEEDS...]              (build dir: SRICS_BUILD_DIR or build)
#   tests/bench/gnn-acceptance/run.sh BUILD_DIR [SEEDS...]    (output: $OUT or /tmp/gnn-acceptance,
#                                                             environments: $ENVS)
# The last line is one JSON object: {"bench":"gnn-acceptance","passed":..,"runs":..,"max_cpu_s":..}.
set -euo pipefail
root="$(cd "$(dirname "$0")/../../.." && pwd)"
build="${1:-$root/build}"
shift || true
out="${OUT:-/tmp/gnn-acceptance}"
if [[ $# -gt 0 ]]; then seeds=("$@"); else seeds=(1 2 3); fi
cmake --build "$build" --target srics -j1 >/dev/null
declare -A expected=(
  [rearrange-3]="action->0, 0->1, 0->2, 0->3"
  [relational-4]="action->0, 0->2, 0->3, 0->4, 2->3|action->0, 0->2, 0->3, 0->4, 3->2|action->0, 0->2, 0->3, 0->4, 2->3, 3->2"
)
mkdir -p "$out"
printf '%-13s %-5s %-7s %-7s %-7s %-10s %s\n' env seed ok wall_s cpu_s updates "graph (mean weights of kept edges)"
for env in ${ENVS:-rearrange-3 relational-4}; do
  for seed in "${seeds[@]}"; do
    dir="$out/$env-$seed"
    rm -rf "$dir"
    mkdir -p "$dir"
    start=$(date +%s.%N)
    OMP_NUM_THREADS=1 /usr/bin/time -f '%U %S' -o "$dir/time.txt" \
      "$build/deploy/launcher/srics" learn-graph --env "$root/deploy/configs/env/$env.yaml" \
      --seed "$seed" --out "$dir" >"$dir/log.txt" 2>&1 || true
    wall=$(echo "$(date +%s.%N) - $start" | bc)
    cpu=$(awk '{print $1 + $2}' "$dir/time.txt")
    python3 - "$dir/graph.json" "$env" "$seed" "$wall" "$cpu" "${expected[$env]}" <<'PY'
import json, sys
path, env, seed, wall, cpu, expected = sys.argv[1:]
try:
    g = json.load(open(path))
except Exception as e:
    open(path + ".ok", "w").write(f"NO {cpu}\n")
    print(f"{env:<13} {seed:<5} {'NO':<7} {float(wall):<7.0f} {float(cpu):<7.0f} -          no graph ({e})")
    sys.exit(0)
n, w, adj = g["num_entities"], g["mean_weights"], g["adjacency"]
kept = ", ".join(f"{i}->{j} {w[i][j]:.3f}" for i in range(n) for j in range(n) if adj[i][j])
rest = max((w[i][j] for i in range(n) for j in range(n) if i != j and not adj[i][j]), default=0)
ok = "yes" if g["edges"] in expected.split("|") else "NO"
open(path + ".ok", "w").write(f"{ok} {cpu}\n")
print(f"{env:<13} {seed:<5} {ok:<7} {float(wall):<7.0f} {float(cpu):<7.0f} {g['updates']:<10} "
      f"{g['edges']}  [{kept}; largest other {rest:.3f}; held-out {g['held_out_loss']:.3g}]")
PY
  done
done
python3 - "$out" <<'PY'
import glob, json, sys
rows = [open(p).read().split() for p in glob.glob(sys.argv[1] + "/*/graph.json.ok")]
print(json.dumps({"bench": "gnn-acceptance", "passed": sum(r[0] == "yes" for r in rows),
                  "runs": len(rows), "max_cpu_s": max((float(r[1]) for r in rows), default=0)}))
PY
