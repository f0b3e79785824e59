#!/usr/bin/env python3
"""The read-out's bar per object pair, replayed on recorded runs that were read with one threshold.

    tests/bench/gnn-acceptance/pair_bars.py RECORD_DIR... [--tied T] [--untied U] [--evidence DIR]...
                                            [--per-episode R] [--share S] [--episodes N] [--pair-share P]

How graph.tied_pair_threshold (T) and graph.untied_pair_threshold (U) are chosen on tuning records
without training again. For each RECORD_DIR/<run>/ with graph.json and result.txt: the tie evidence
from the run's evidence.txt or log.txt, else from DIR/<run>/log.txt of an --evidence folder (the
first found); the object pairs it names: both ends start moving at a distance at least R * N times,
at least S of those onsets while the other end moves (GnnTrainer::TiedByEvidence). Each object
pair's recorded score (reciprocal; a pair graph.object_pair_share cut reads 0 and stays cut) is
scaled by threshold / T when named and threshold / U when not (CalibrateObjectPairs), a pair
under P of either end's strongest scaled pair is cut (graph.object_pair_share, as the service
does after scaling), then the run's one threshold decides; the arm's edges stay as recorded.
Unlike the service, a pair with a static end is scaled too (its scores are 0 anyway). A run
without evidence keeps its recorded scores (so does the service when it has none: object sets, no
entity sizes), and so does a run whose log says the service already read it with the bars or
counted no evidence ("object pairs' bars:", printed since the bars exist): its scores are final.
Prints per run its verdict against the graph by construction, the weakest kept and strongest cut
edge after scaling and their ratio, the misses, then one JSON line.
"""
import argparse
import glob
import json
import math
import os
import signal
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from margins import expected_edges  # noqa: E402
from tie_evidence import pairs_of  # noqa: E402


# what `srics learn-graph` prints once the service reads object pairs against their bars (or
# says it does not): the record's scores are already final
READ_WITH_BARS = ("object pairs' bars:", "graph.tied_pair_threshold", "graph.untied_pair_threshold")


def evidence_log(run_folder, evidence_dirs, expected):
    """The text holding the run's evidence lines (with the graph by construction), or None."""
    name = os.path.basename(os.path.normpath(run_folder))
    candidates = [os.path.join(run_folder, "evidence.txt"), os.path.join(run_folder, "log.txt")]
    candidates += [os.path.join(d, name, "log.txt") for d in evidence_dirs]
    for path in candidates:
        if os.path.exists(path):
            text = open(path).read()
            if "by construction: " not in text:  # a log cut short: the record knows the graph
                text += f"\nby construction: {expected}\n"
            if pairs_of(text) is not None:
                return text
    return None


def cut_weak_pairs(scores, arm, share):
    """graph.object_pair_share on the scaled scores (CutWeakObjectPairs)."""
    n = len(scores)
    pairs = [(i, j) for i in range(n) for j in range(n) if i != j and arm not in (i, j)]
    strongest = [0.0] * n
    for i, j in pairs:
        strongest[i] = max(strongest[i], scores[i][j])
        strongest[j] = max(strongest[j], scores[i][j])
    return [[0.0 if (i, j) in pairs and scores[i][j] < share * max(strongest[i], strongest[j]) else scores[i][j]
             for j in range(n)] for i in range(n)]


def replay(run_folder, args):
    graph = json.load(open(os.path.join(run_folder, "graph.json")))
    expected = json.load(open(os.path.join(run_folder, "result.txt")))["expected"]
    truth = expected_edges(expected)
    n, arm, threshold = graph["num_entities"], graph["action_entity"], graph["threshold"]
    scores = [row[:] for row in graph["edge_scores"]]
    log = evidence_log(run_folder, args.evidence, expected)
    final = log is not None and any(line in log for line in READ_WITH_BARS)
    named = None
    if log is not None and not final:
        needed = args.per_episode * args.episodes
        named = {(i, j) for i, j, _, count, share in pairs_of(log) if count >= needed and share >= args.share}
        for i in range(n):
            for j in range(n):
                if i != j and arm not in (i, j):
                    bar = args.tied if (min(i, j), max(i, j)) in named else args.untied
                    scores[i][j] = min(1.0, scores[i][j] * threshold / bar)
        scores = cut_weak_pairs(scores, arm, args.pair_share)
    edges = [(i, j) for i in range(n) for j in range(n) if i != j]
    kept = {(i, j) for i, j in edges if scores[i][j] > threshold}
    # the action node's edge is not in the scores; the rest must match the graph by construction
    wrong = sorted((kept - truth) | (truth - kept))
    weakest_kept = min([scores[i][j] for i, j in kept], default=math.inf)
    strongest_cut = max([scores[i][j] for i, j in edges if (i, j) not in kept], default=0.0)
    return {"run": os.path.basename(os.path.normpath(run_folder)), "evidence": named is not None, "final": final,
            "named": sorted(named) if named is not None else None, "exact": not wrong, "wrong": wrong,
            "weakest_kept": weakest_kept, "strongest_cut": strongest_cut,
            "gap": weakest_kept / strongest_cut if strongest_cut > 0 else math.inf,
            # how close the threshold came to deciding otherwise (> 1: neither side touches it)
            "narrowest": min(weakest_kept / threshold, threshold / strongest_cut if strongest_cut > 0 else math.inf)}


def main():
    signal.signal(signal.SIGPIPE, signal.SIG_DFL)  # piped into head: stop quietly
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("records", nargs="+", help="record folders (<run>/graph.json, <run>/result.txt)")
    parser.add_argument("--tied", type=float, default=0.02, help="graph.tied_pair_threshold")
    parser.add_argument("--untied", type=float, default=0.12, help="graph.untied_pair_threshold")
    parser.add_argument("--evidence", action="append", default=[], help="folders of <run>/log.txt with evidence")
    parser.add_argument("--per-episode", type=float, default=0.025, help="graph.tie_evidence_per_episode")
    parser.add_argument("--share", type=float, default=0.5, help="graph.tie_evidence_share")
    parser.add_argument("--episodes", type=int, default=1000, help="graph.episodes of the runs")
    parser.add_argument("--pair-share", type=float, default=0.5, help="graph.object_pair_share")
    args = parser.parse_args()
    if not (0 < args.tied <= args.untied):
        sys.exit("pair_bars.py: --tied must be above 0 and not above --untied")
    folders = sorted(os.path.dirname(p) for r in args.records for p in glob.glob(os.path.join(r, "*", "graph.json"))
                     if os.path.exists(os.path.join(os.path.dirname(p), "result.txt")))
    if not folders:
        sys.exit(f"pair_bars.py: no <run>/graph.json with result.txt under {' '.join(args.records)}")
    runs = [replay(f, args) for f in folders]
    print(f"| run | evidence names | exact | weakest kept | strongest cut | kept / cut | nearer side / threshold |")
    print("|---|---|---|---|---|---|---|")
    for r in sorted(runs, key=lambda r: r["narrowest"]):
        named = ("read by the service" if r["final"] else "no evidence" if r["named"] is None
                 else " ".join(f"{i}-{j}" for i, j in r["named"]) or "none")
        print(f"| {r['run']} | {named} | {'yes' if r['exact'] else 'no: ' + ' '.join(f'{i}->{j}' for i, j in r['wrong'])} "
              f"| {r['weakest_kept']:.4f} | {r['strongest_cut']:.4f} | {r['gap']:.2f} | {r['narrowest']:.2f} |")
    exact = [r for r in runs if r["exact"]]
    print()
    print(f"bars {args.tied:g} (named pairs) and {args.untied:g} (other object pairs): {len(exact)} of {len(runs)} runs "
          f"exact ({sum(not r['evidence'] and not r['final'] for r in runs)} without evidence, read with the one "
          f"threshold; {sum(r['final'] for r in runs)} read by the service itself); of the exact "
          f"runs the smallest kept / cut ratio {min([r['gap'] for r in exact], default=math.nan):.2f}, the nearest edge "
          f"to the threshold {min([r['narrowest'] for r in exact], default=math.nan):.2f}x from it")
    print(json.dumps({"bench": "gnn-pair-bars", "tied": args.tied, "untied": args.untied, "runs": len(runs),
                      "exact": len(exact), "without_evidence": sum(not r["evidence"] and not r["final"] for r in runs),
                      "read_by_the_service": sum(r["final"] for r in runs),
                      "misses": [r["run"] for r in runs if not r["exact"]],
                      "min_exact_gap": round(min([r["gap"] for r in exact], default=math.nan), 3),
                      "min_exact_threshold_ratio": round(min([r["narrowest"] for r in exact], default=math.nan), 3)}))


if __name__ == "__main__":
    main()
