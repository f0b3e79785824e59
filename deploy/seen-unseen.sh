#!/usr/bin/env bash
# The paper's generalization claim ("on an unseen combination of objects SRICS performs like on
# the seen ones"), measured: each run's final policy plays every object combination, the ones it
# trained on and the held-out one, on the run's own evaluation goals, and so does the passive
# baseline (`srics eval --passive`, the hand never moves) on the same goals; the figure is the
# policy's final object distance over the passive one's, per combination (docs/results.md).
#
#   deploy/seen-unseen.sh --out DIR [--seen "1,2,3 1,2,4 1,3,4"] [--unseen "2,3,4"] [--episodes 50] RUN_DIR...
#
# Combinations are catalogue ids of the present objects (env.object_sets' `present`); the
# defaults are those of deploy/configs/env/rearrange-4-unseen.yaml. Writes DIR/seen-unseen.csv
# (one row per run and combination) and DIR/seen-unseen.md (per run: the mean ratio over the
# seen combinations and the unseen one; over runs: mean ± sd of both and of their paired
# difference). Each evaluation's own files stay in DIR/raw/. Needs each run's checkpoint.srics
# (the final policy, never best.srics). Exit 2 on bad arguments, 1 when an evaluation fails.
set -euo pipefail

usage() { sed -n '8p' "$0" | sed 's/^#   /usage: /' >&2; exit 2; }
root=$(cd "$(dirname "$0")/.." && pwd)
srics=${SRICS:-$root/build/deploy/launcher/srics}  # SRICS: another build's program (tests)
out="" seen="1,2,3 1,2,4 1,3,4" unseen="2,3,4" episodes=50 runs=()
while [ $# -gt 0 ]; do
  case "$1" in
    --out) out=${2:-}; shift 2 || usage ;;
    --seen) seen=${2:-}; shift 2 || usage ;;
    --unseen) unseen=${2:-}; shift 2 || usage ;;
    --episodes) episodes=${2:-}; shift 2 || usage ;;
    -h|--help) usage ;;
    -*) echo "seen-unseen: unknown option $1" >&2; usage ;;
    *) runs+=("$1"); shift ;;
  esac
done
[ -n "$out" ] && [ ${#runs[@]} -gt 0 ] || usage
[[ "$episodes" =~ ^[1-9][0-9]*$ ]] || { echo "seen-unseen: --episodes wants a positive integer, got '$episodes'" >&2; exit 2; }
for c in $seen $unseen; do
  [[ "$c" =~ ^[1-9][0-9]*(,[1-9][0-9]*)*$ ]] || { echo "seen-unseen: a combination is catalogue ids joined by commas (1,2,3), got '$c'" >&2; exit 2; }
done
[ "$(echo $unseen | wc -w)" -eq 1 ] || { echo "seen-unseen: --unseen wants one combination, got '$unseen'" >&2; exit 2; }
for r in "${runs[@]}"; do
  [ -f "$r/checkpoint.srics" ] && [ -f "$r/config.yaml" ] || { echo "seen-unseen: $r has no checkpoint.srics and config.yaml" >&2; exit 2; }
done
[ -x "$srics" ] || { echo "seen-unseen: $srics is not built (./tests/build.sh)" >&2; exit 1; }

# mean final object distance over the episodes that stayed stable ("n,mean")
object_distance() {
  awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) col[$i] = i; next }
           $col["status"] == "ok" { n++; o += $col["avg_object_distance"] }
           END { if (n) printf "%d,%.5f", n, o / n; else printf "0," }' "$1"
}

mkdir -p "$out/raw"
csv="$out/seen-unseen.csv"
echo "run,combination,kind,episodes,object_distance,passive_episodes,passive_object_distance,ratio" > "$csv"
combinations="$seen $unseen"
total=$(( ${#runs[@]} * $(echo $combinations | wc -w) ))
done_count=0
for r in "${runs[@]}"; do
  name=$(basename "$r")
  for c in $combinations; do
    kind=seen; [ "$c" = "$unseen" ] && kind=unseen
    set_objects="env.eval_object_sets=[{present: [$c]}]"
    tag="$name-objects${c//,/-}"
    done_count=$((done_count + 1))
    echo "[$done_count/$total] $name, objects $c ($kind)" >&2
    for who in policy passive; do
      dir="$out/raw/$tag-$who"
      flag=(); [ $who = passive ] && flag=(--passive)
      "$srics" eval "$r" "${flag[@]}" --set "$set_objects" --episodes "$episodes" --no-video --out "$dir" > "$dir.log" 2>&1 ||
        { echo "seen-unseen: srics eval failed, see $dir.log" >&2; exit 1; }
    done
    policy=$(object_distance "$out/raw/$tag-policy/episodes.csv")
    passive=$(object_distance "$out/raw/$tag-passive/episodes.csv")
    ratio=$(awk -v a="${policy#*,}" -v b="${passive#*,}" 'BEGIN { if (a != "" && b > 0) printf "%.4f", a / b }')
    echo "$name,${c//,/ },$kind,$policy,$passive,$ratio" >> "$csv"
  done
done

awk -F, -v episodes="$episodes" -v seen="$seen" -v unseen="$unseen" '
  NR == 1 { next }
  { if (!($1 in known)) { known[$1] = 1; order[++nruns] = $1 }
    if ($3 == "seen") { s[$1] += $8; ns[$1]++ } else u[$1] = $8
    row[++nrows] = $0 }
  END {
    printf "# Seen and unseen object combinations: final object distance over the passive baseline\n\n"
    printf "Each run'"'"'s final policy and the passive baseline (the hand never moves) on the run'"'"'s evaluation goals, %d episodes per combination; combinations are the catalogue ids of the present pucks (seen: %s; unseen: %s). Lower is better, 1 is the passive level. Written by deploy/seen-unseen.sh.\n\n", episodes, seen, unseen
    printf "| run | objects | kind | object distance | passive | ratio |\n|---|---|---|---|---|---|\n"
    for (i = 1; i <= nrows; ++i) { split(row[i], f, ","); printf "| %s | %s | %s | %.4f | %.4f | %.3f |\n", f[1], f[2], f[3], f[5], f[7], f[8] }
    printf "\n| run | seen (mean over combinations) | unseen | unseen - seen |\n|---|---|---|---|\n"
    for (i = 1; i <= nruns; ++i) {
      r = order[i]; ms[i] = s[r] / ns[r]; mu[i] = u[r]; d[i] = mu[i] - ms[i]
      printf "| %s | %.3f | %.3f | %+.3f |\n", r, ms[i], mu[i], d[i]
    }
    for (i = 1; i <= nruns; ++i) { as += ms[i] / nruns; au += mu[i] / nruns; ad += d[i] / nruns }
    for (i = 1; i <= nruns; ++i) { vs += (ms[i] - as) ^ 2; vu += (mu[i] - au) ^ 2; vd += (d[i] - ad) ^ 2 }
    k = nruns > 1 ? nruns - 1 : 1
    printf "| mean ± sd over %d runs | %.3f ± %.3f | %.3f ± %.3f | %+.3f ± %.3f |\n", nruns, as, sqrt(vs / k), au, sqrt(vu / k), ad, sqrt(vd / k)
  }' "$csv" > "$out/seen-unseen.md"
cat "$out/seen-unseen.md"
echo "wrote $csv and $out/seen-unseen.md" >&2
