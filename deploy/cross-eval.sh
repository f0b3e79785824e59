#!/usr/bin/env bash
# Plays each run's final policy under both evaluation protocols, on the same goals for every
# run: "depth" (the subgoals of the interaction graph in depth order, the arm last, as SRICS is
# evaluated; runs without a graph use the table's graph by construction) and "random" (every
# entity a subgoal, the static ones too, in random order, as SMORL is evaluated). It separates
# what a method's policy can do from what its evaluation protocol adds (docs/results.md).
#
#   deploy/cross-eval.sh --out DIR [--goal-sets "1 2 3"] [--episodes 20] RUN_DIR...
#
# Writes DIR/cross-eval.csv (one row per run, protocol and goal set) and DIR/cross-eval.md (per
# run and protocol the means over goal sets; per method and protocol mean ± sd over its runs).
# Each evaluation's own files stay in DIR/raw/. Needs each run's checkpoint.srics (the final
# policy is the one compared, never best.srics). Exit 2 on bad arguments, 1 when an evaluation fails.
set -euo pipefail

usage() { sed -n '8p' "$0" | sed 's/^#   /usage: /' >&2; exit 2; }
root=$(cd "$(dirname "$0")/.." && pwd)
srics=${SRICS:-$root/build/deploy/launcher/srics}  # SRICS: another build's program (tests)
out="" goal_sets="1 2 3" episodes=20 runs=()
while [ $# -gt 0 ]; do
  case "$1" in
    --out) out=${2:-}; shift 2 || usage ;;
    --goal-sets) goal_sets=${2:-}; shift 2 || usage ;;
    --episodes) episodes=${2:-}; shift 2 || usage ;;
    -h|--help) usage ;;
    -*) echo "cross-eval: unknown option $1" >&2; usage ;;
    *) runs+=("$1"); shift ;;
  esac
done
[ -n "$out" ] && [ ${#runs[@]} -gt 0 ] || usage
[[ "$episodes" =~ ^[1-9][0-9]*$ ]] || { echo "cross-eval: --episodes wants a positive integer, got '$episodes'" >&2; exit 2; }
for s in $goal_sets; do [[ "$s" =~ ^[1-9][0-9]*$ ]] || { echo "cross-eval: --goal-sets wants seeds >= 1, got '$s'" >&2; exit 2; }; done
for r in "${runs[@]}"; do
  [ -f "$r/checkpoint.srics" ] && [ -f "$r/config.yaml" ] || { echo "cross-eval: $r has no checkpoint.srics and config.yaml" >&2; exit 2; }
done
[ -x "$srics" ] || { echo "cross-eval: $srics is not built (./tests/build.sh)" >&2; exit 1; }

mkdir -p "$out/raw"
csv="$out/cross-eval.csv"
echo "run,method,protocol,goal_set,episodes,avg_distance,avg_object_distance,object_attempts,object_reached,objects_solved_before,objects_undone" > "$csv"
total=$(( ${#runs[@]} * 2 * $(echo $goal_sets | wc -w) ))
done_count=0
for r in "${runs[@]}"; do
  name=$(basename "$r")
  method=""  # from srics eval's own report (a config that leaves the method at its default does not name it)
  for protocol in depth random; do
    for s in $goal_sets; do
      dir="$out/raw/$name-$protocol-goals$s"
      done_count=$((done_count + 1))
      echo "[$done_count/$total] $name, protocol $protocol, goals of seed $s" >&2
      "$srics" eval "$r" --protocol "$protocol" --goal-set "$s" --episodes "$episodes" --no-video --out "$dir" > "$dir.log" 2>&1 ||
        { echo "cross-eval: srics eval failed, see $dir.log" >&2; exit 1; }
      [ -n "$method" ] || method=$(awk '$1 == "method" { sub(/,$/, "", $2); print $2; exit }' "$dir.log")
      # the objects that have a subgoal: those of the depth protocol (a static object has none)
      movable=$(awk -F, 'NR > 1 && $3 != 0 { seen[$3] = 1 } END { for (e in seen) printf "%s ", e }' "$out/raw/$name-depth-goals$s/attempts.csv")
      ep=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) col[$i] = i; next }
                   $col["status"] == "ok" { n++; d += $col["avg_distance"]; o += $col["avg_object_distance"] }
                   END { if (n) printf "%d,%.5f,%.5f", n, d / n, o / n; else printf "0,," }' "$dir/episodes.csv")
      at=$(awk -F, -v movable="$movable" 'BEGIN { split(movable, m, " "); for (i in m) ok[m[i]] = 1 }
                   NR > 1 && $4 == 0 && ok[$3] { n++; reached += $7; solved += $8; undone += $9 }
                   END { printf "%d,%.4f,%d,%d", n, n ? reached / n : 0, solved, undone }' "$dir/attempts.csv")
      echo "$name,$method,$protocol,$s,$ep,$at" >> "$csv"
    done
  done
done

# the tables: per run and protocol (means over goal sets), per method and protocol (mean ± sd over runs)
awk -F, -v goal_sets="$goal_sets" -v episodes="$episodes" '
  NR == 1 { next }
  { key = $1 SUBSEP $3
    if (!($1 in runs)) order[++nruns] = $1
    runs[$1] = $2; d[key] += $6; o[key] += $7; a[key] += $8; r[key] += $9 * $8; s[key] += $10; u[key] += $11; g[key]++ }
  END {
    printf "# Cross-evaluation: each final policy under both protocols, on the same goals\n\n"
    printf "Goals of evaluation seeds %s, %d episodes each; distances in metres at the final step. depth: the graph'"'"'s subgoals in depth order (the arm last; runs without a graph use the table'"'"'s graph by construction); random: every entity a subgoal (static ones too), random order. reached: object attempts ending within 0.05 m of their goal; undone: objects solved before an attempt that it left unsolved. Written by deploy/cross-eval.sh.\n\n", goal_sets, episodes
    printf "| run | method | protocol | avg distance (arm incl.) | avg object distance | object attempts reached | solved objects undone |\n|---|---|---|---|---|---|---|\n"
    for (i = 1; i <= nruns; ++i) for (p = 0; p < 2; ++p) {
      name = order[i]; proto = p ? "random" : "depth"; key = name SUBSEP proto
      if (!g[key]) continue
      printf "| %s | %s | %s | %.3f | %.3f | %.2f | %.2f |\n", name, runs[name], proto, d[key] / g[key], o[key] / g[key], a[key] ? r[key] / a[key] : 0, s[key] ? u[key] / s[key] : 0
      m = runs[name] SUBSEP proto
      if (!(m in count)) { morder[++nmethods] = m; count[m] = 0 }
      k = ++count[m]; md[m, k] = d[key] / g[key]; mo[m, k] = o[key] / g[key]
    }
    printf "\n| method | protocol | runs | avg distance (arm incl.) | avg object distance |\n|---|---|---|---|---|\n"
    for (i = 1; i <= nmethods; ++i) {
      m = morder[i]; split(m, parts, SUBSEP); k = count[m]; sd = so = 0; mean_d = mean_o = 0
      for (j = 1; j <= k; ++j) { mean_d += md[m, j] / k; mean_o += mo[m, j] / k }
      for (j = 1; j <= k; ++j) { sd += (md[m, j] - mean_d) ^ 2; so += (mo[m, j] - mean_o) ^ 2 }
      sd = k > 1 ? sqrt(sd / (k - 1)) : 0; so = k > 1 ? sqrt(so / (k - 1)) : 0
      printf "| %s | %s | %d | %.3f ± %.3f | %.3f ± %.3f |\n", parts[1], parts[2], k, mean_d, sd, mean_o, so
    }
  }' "$csv" > "$out/cross-eval.md"
cat "$out/cross-eval.md"
echo "wrote $csv and $out/cross-eval.md" >&2
