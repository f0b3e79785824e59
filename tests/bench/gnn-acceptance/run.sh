#!/usr/bin/env bash
# Acceptance of the graph service: learns the interaction graph of every environment preset
# (deploy/configs/env/*.yaml) and of random tables 1..10 (srics learn-graph --random-table N),
# seeds 1..3 each, with the default GraphConfig, one thread per run, and compares each graph
# with the one the table implies by construction (exact match of every edge).
#   ./tests/bench.sh gnn-acceptance [--jobs N] [--tables "a b ..."] [--seeds "1 2 3"] [--set K=V]...
#                                   [--record DIR] [--runs "table:seed ..."] [--held-out]
#                                   [--held-out-range FIRST-LAST] [--dry-run]
#   tests/bench/gnn-acceptance/run.sh BUILD_DIR [same options]
# --runs lists single runs instead of the tables x seeds grid (e.g. "table-4:3 rearrange-1:2").
# --held-out: the held-out acceptance (issue 35): random tables 11-40, graph seeds 1-2, tables
# no setting was ever chosen on; its own OUT (runs/gnn-acceptance-heldout) and record
# (docs/results/gnn-acceptance-heldout) unless given. Run it once with the settings frozen and
# report it as it came out. --held-out-range FIRST-LAST: a further held-out set, random tables
# FIRST..LAST (seeds 1-2; runs/ and docs/results/gnn-acceptance-heldout-FIRST-LAST), for settings
# chosen after the first was reported; it refuses the tables ever tuned on (1-10 and 2001-2080,
# the five-object tie tuning set's range) and the first held-out set (11-40). --dry-run prints the runs, OUT and the record folder, and stops.
# Table names: a preset's file name without .yaml, or table-N for random table N.
# Output in $OUT (default runs/gnn-acceptance, kept across calls): OUT/<table>-s<seed>/ holds
# the run's log, graph.json and pictures and result.txt. Resumable: a run with a result.txt
# is not repeated (delete the folder to redo it), so a stopped acceptance continues where it
# was. --record DIR (relative to the repository root, e.g. docs/results/gnn-acceptance) also
# copies each finished run's result.txt, graph.json and evidence.txt (its log's tie evidence) to
# DIR/<table>-s<seed>/, to be committed:
# runs/ is not kept by a new checkout, DIR is, and a run recorded there is not repeated either
# (the table counts it). Runs are niced; --jobs 2 runs two at a time (one per core: do not benchmark meanwhile).
# Prints a markdown table of every run so far (docs/results/graph-service-history.md keeps those
# of 2026-12-03; graph_service/README.md sums them up) and, as its
# last line, one JSON object {"bench":"gnn-acceptance","exact":..,"runs":..,"max_cpu_s":..}.
set -euo pipefail
root="$(cd "$(dirname "$0")/../../.." && pwd)"
build="${1:-$root/build}"
shift || true
out="${OUT:-}"
jobs=1
held_out=0
held_out_range=""
dry_run=0
tables=""
seeds="1 2 3"
overrides=""  # --set K=V passed to every run (e.g. graph.onset_loss_weight=10); use another OUT
record=""
runs=""
while [[ $# -gt 0 ]]; do
  case "$1" in
    --jobs) jobs="$2"; shift 2 ;;
    --tables) tables="$2"; shift 2 ;;
    --seeds) seeds="$2"; shift 2 ;;
    --set) overrides+="--set $2 "; shift 2 ;;
    --runs) runs="$2"; shift 2 ;;
    --record) record="$2"; [[ $record == /* ]] || record="$root/$record"; shift 2 ;;
    --held-out) held_out=1; shift ;;
    --held-out-range) held_out_range="$2"; shift 2 ;;
    --dry-run) dry_run=1; shift ;;
    *) echo "unknown option $1" >&2; exit 2 ;;
  esac
done
first=11 last=40 suffix=""
if [[ -n $held_out_range ]]; then
  [[ $held_out_range =~ ^([0-9]+)-([0-9]+)$ ]] || { echo "--held-out-range: '$held_out_range' is not FIRST-LAST" >&2; exit 2; }
  first=$((10#${BASH_REMATCH[1]})) last=$((10#${BASH_REMATCH[2]})) suffix="-$first-$last"
  ((first <= last)) || { echo "--held-out-range: $first > $last" >&2; exit 2; }
  # tables a setting was chosen on, or already reported as held out, can never be held out again
  for used in 1-10:tuned 2001-2080:tuned 11-40:"the first held-out set"; do
    lo=${used%%-*} rest=${used#*-} hi=${rest%%:*} what=${used#*:}
    if ((first <= hi && last >= lo)); then
      [[ $what == tuned ]] && what="tuned on"
      echo "--held-out-range $first-$last: tables $lo-$hi are $what; choose tables outside 1-40 and 2001-2080" >&2
      exit 2
    fi
  done
  held_out=1
fi
if [[ $held_out == 1 ]]; then
  [[ -z "$tables" ]] || { echo "--held-out names its own tables ($first-$last): no --tables with it" >&2; exit 2; }
  for n in $(seq "$first" "$last"); do tables+="table-$n "; done
  seeds="1 2"
  out="${out:-$root/runs/gnn-acceptance-heldout$suffix}"
  record="${record:-$root/docs/results/gnn-acceptance-heldout$suffix}"
fi
out="${out:-$root/runs/gnn-acceptance}"
if [[ -z "$tables" ]]; then
  for f in "$root"/deploy/configs/env/*.yaml; do tables+="$(basename "$f" .yaml) "; done
  for n in $(seq 1 10); do tables+="table-$n "; done
fi
pairs=""  # "table seed" lines, checked before anything runs
if [[ -n $runs ]]; then
  for r in $runs; do
    [[ $r =~ ^[A-Za-z0-9_.-]+:[0-9]+$ ]] || { echo "--runs: '$r' is not table:seed" >&2; exit 2; }
    pairs+="${r%%:*} ${r##*:}"$'\n'
  done
else
  for t in $tables; do for s in $seeds; do pairs+="$t $s"$'\n'; done; done
fi
# what every record names, taken once: the commit the binaries are built from (the build
# folder's source tree, which need not be this script's checkout), "+modified" if that tree has
# uncommitted changes
source_dir=$(sed -n 's/^CMAKE_HOME_DIRECTORY:INTERNAL=//p' "$build/CMakeCache.txt" 2>/dev/null)
commit=$(git -C "${source_dir:-$root}" rev-parse --short HEAD 2>/dev/null || echo unknown)
git -C "${source_dir:-$root}" diff --quiet HEAD -- 2>/dev/null || commit+="+modified"
if [[ $dry_run == 1 ]]; then
  printf '%s' "$pairs"
  echo "$(printf '%s' "$pairs" | wc -l) runs; out $out; record ${record:-none}; binaries from $commit"
  exit 0
fi
srics="$build/deploy/launcher/srics"
cmake --build "$build" --target srics -j1 >/dev/null
mkdir -p "$out"
[[ -n $record ]] && mkdir -p "$record"
cpu_model=$(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo | head -1)
# the model string alone may not tell (this machine's says "AMD EPYC"): the vector ISA too
if grep -qw avx512f /proc/cpuinfo; then cpu_model+=" (AVX-512)"
elif grep -qw avx2 /proc/cpuinfo; then cpu_model+=" (AVX2)"; fi

# one run: learns, times, compares; writes result.txt last (its presence = done)
run_one() {
  local table=$1 seed=$2 dir="$out/$1-s$2"
  [[ -n $record && -f "$record/$1-s$2/result.txt" ]] && return 0
  [[ -f "$dir/result.txt" ]] && return 0
  rm -rf "$dir"
  mkdir -p "$dir"
  local source=(--env "$root/deploy/configs/env/$table.yaml")
  [[ $table == table-* ]] && source=(--random-table "${table#table-}")
  local expected
  expected=$("$srics" learn-graph "${source[@]}" --out "$dir" --expected)
  local start=$SECONDS rc=0
  OMP_NUM_THREADS=1 nice /usr/bin/time -f '%U %S' -o "$dir/time.txt" \
    "$srics" learn-graph "${source[@]}" --seed "$seed" --out "$dir" $overrides >"$dir/log.txt" 2>&1 || rc=$?
  local wall=$((SECONDS - start))
  # stopped by a signal (a stopped session, Ctrl-C): no result, so that a rerun does it again
  # (recorded as a miss it would be skipped for good)
  if ((rc >= 128)); then
    echo "$table seed $seed: interrupted (exit $rc), not recorded" >&2
    return 0
  fi
  python3 - "$dir" "$table" "$seed" "$wall" "$expected" "$commit" "$cpu_model" "$overrides" <<'PY'
import json, sys
d, table, seed, wall, expected, commit, cpu_model, overrides = sys.argv[1:]
cpu = sum(float(x) for x in open(d + "/time.txt").read().split()[-2:])
try:
    g = json.load(open(d + "/graph.json"))
    learned, exact = g["edges"], g["edges"] == expected
    n, s, adj = g["num_entities"], g["edge_scores"], g["adjacency"]
    kept = min((s[i][j] for i in range(n) for j in range(n) if adj[i][j]), default=1)
    other = max((s[i][j] for i in range(n) for j in range(n) if i != j and not adj[i][j]), default=0)
    detail = f"weakest kept {kept:.2f}, strongest cut {other:.2f}, {g['updates']} updates"
except Exception as e:
    learned, exact, detail = "no graph", False, str(e)
with open(d + "/result.txt", "w") as f:
    f.write(json.dumps({"table": table, "seed": int(seed), "exact": exact, "learned": learned,
                        "expected": expected, "cpu_s": round(cpu), "wall_s": int(wall),
                        "detail": detail, "commit": commit, "cpu": cpu_model,
                        "overrides": overrides.strip()}) + "\n")
PY
  if [[ -n $record ]]; then
    mkdir -p "$record/$table-s$seed"
    [[ -f "$dir/graph.json" ]] && cp "$dir/graph.json" "$record/$table-s$seed/"
    # the data's tie evidence, which set each object pair's bar (pair_bars.py and tie_evidence.py read it)
    grep -E '^onsets at a distance|while another object moves|^tied by that evidence|^by construction' \
      "$dir/log.txt" >"$record/$table-s$seed/evidence.txt" || true
    cp "$dir/result.txt" "$record/$table-s$seed/"  # last: its presence = recorded
  fi
  echo "$table seed $seed: $(cat "$dir/result.txt")" >&2
}
export -f run_one
export out root srics overrides record commit cpu_model
printf '%s' "$pairs" |
  xargs -P "$jobs" -L 1 bash -c 'run_one "$0" "$1"'

python3 - "$out" "$record" <<'PY'
import glob, json, sys
found = {}  # (table, seed) -> result; a recorded result wins over the run folder's
for folder in sys.argv[1:]:
    for p in glob.glob(folder + "/*/result.txt") if folder else []:
        r = json.loads(open(p).read())
        found[(r["table"], r["seed"])] = r
rows = sorted(found.values(),
              key=lambda r: (r["table"].startswith("table-"), r["table"].split("-")[0],
                             int(r["table"][6:]) if r["table"].startswith("table-") else 0,
                             r["table"], r["seed"]))
print("| table | seed | exact | learned graph | expected (by construction) | CPU s | scores |")
print("|---|---|---|---|---|---|---|")
for r in rows:
    same = r["learned"] == r["expected"]
    print(f"| {r['table']} | {r['seed']} | {'yes' if r['exact'] else '**no**'} | {r['learned']} | "
          f"{'(same)' if same else r['expected']} | {r['cpu_s']} | {r['detail']} |")
exact = sum(r["exact"] for r in rows)
print(f"\n{exact} of {len(rows)} runs exact ({100.0 * exact / max(len(rows), 1):.0f}%), "
      f"largest CPU time {max((r['cpu_s'] for r in rows), default=0)} s")
print(json.dumps({"bench": "gnn-acceptance", "exact": exact, "runs": len(rows),
                  "max_cpu_s": max((r["cpu_s"] for r in rows), default=0)}))
PY
