#!/usr/bin/env python3
"""Margins of the graph acceptance: how far each run's threshold is from deciding otherwise.

    tests/bench/gnn-acceptance/margins.py [DIR]     (default docs/results/gnn-acceptance)

Reads every DIR/<table>-s<seed>/graph.json (the learned graph with its edge scores, adjacency and
threshold) and prints, per run, the weakest kept edge, the strongest cut one, their ratio (the
run's own gap: how well the scores separate whatever the threshold) and the threshold's distance
from each side as a ratio (how close a fixed threshold came to deciding otherwise); then the
window of thresholds that would have kept every run's decisions (from the strongest cut edge of
any run to the weakest kept edge of any run). Runs sorted by the threshold's narrowest side.
Against the graph by construction (the `expected` of the run's result.txt, when there): the
thresholds that would make each run exact, from its strongest edge that is not in that graph to
its weakest edge that is, and the window shared by every run (none when the two cross: then no
fixed threshold can be right on all of them, however each run ranks its edges).
"""
import glob
import json
import math
import os
import sys


def margins(path):
    graph = json.load(open(path))
    n, scores, adjacency = graph["num_entities"], graph["edge_scores"], graph["adjacency"]
    pairs = [(i, j) for i in range(n) for j in range(n) if i != j]
    kept = [scores[i][j] for i, j in pairs if adjacency[i][j]]
    cut = [scores[i][j] for i, j in pairs if not adjacency[i][j]]
    run = {
        "run": os.path.basename(os.path.dirname(path)),
        "threshold": graph["threshold"],
        "weakest_kept": min(kept) if kept else math.inf,
        "strongest_cut": max(cut) if cut else 0.0,
    }
    result = os.path.join(os.path.dirname(path), "result.txt")
    if os.path.exists(result):
        truth = expected_edges(json.load(open(result))["expected"])
        run["weakest_true"] = min([scores[i][j] for i, j in pairs if (i, j) in truth], default=math.inf)
        run["strongest_false"] = max([scores[i][j] for i, j in pairs if (i, j) not in truth], default=0.0)
    return run


def expected_edges(described):
    """The entity edges of a described graph ("action->0, 0->1, 1->2"; the action node's left out)."""
    edges = set()
    for edge in described.split(", "):
        source, target = edge.split("->")
        if source != "action":
            edges.add((int(source), int(target)))
    return edges


def ratio(a, b):
    return a / b if b > 0 else math.inf


def main():
    folder = sys.argv[1] if len(sys.argv) > 1 else "docs/results/gnn-acceptance"
    runs = [margins(p) for p in sorted(glob.glob(os.path.join(folder, "*", "graph.json")))]
    if not runs:
        sys.exit(f"margins.py: no <run>/graph.json under {folder}")
    for r in runs:
        r["gap"] = ratio(r["weakest_kept"], r["strongest_cut"])
        r["above"] = ratio(r["weakest_kept"], r["threshold"])  # > 1: kept edges clear the threshold
        r["below"] = ratio(r["threshold"], r["strongest_cut"])  # > 1: cut edges stay under it
        r["narrowest"] = min(r["above"], r["below"])
    runs.sort(key=lambda r: r["narrowest"])
    print("| run | threshold | weakest kept | strongest cut | kept / cut | kept / threshold | threshold / cut |")
    print("|---|---|---|---|---|---|---|")
    for r in runs:
        print(f"| {r['run']} | {r['threshold']:g} | {r['weakest_kept']:.4f} | {r['strongest_cut']:.4f} | "
              f"{r['gap']:.1f} | {r['above']:.2f} | {r['below']:.2f} |")
    low = max(r["strongest_cut"] for r in runs)
    high = min(r["weakest_kept"] for r in runs)
    wrong = [r["run"] for r in runs if r["narrowest"] <= 1]
    print()
    print(f"{len(runs)} runs; every run's own gap (weakest kept / strongest cut) at least "
          f"{min(r['gap'] for r in runs):.1f}x; a fixed threshold keeps every run's decisions in "
          f"[{low:.4f}, {high:.4f}] (width {ratio(high, low):.2f}x)"
          + (f"; runs the threshold decides otherwise: {', '.join(wrong)}" if wrong else ""))
    summary = {"bench": "gnn-margins", "runs": len(runs), "min_gap": round(min(r["gap"] for r in runs), 3),
               "window_low": round(low, 5), "window_high": round(high, 5),
               "narrowest_threshold_ratio": round(runs[0]["narrowest"], 4)}
    judged = [r for r in runs if "weakest_true" in r]
    if judged:
        exact_low = max(r["strongest_false"] for r in judged)
        exact_high = min(r["weakest_true"] for r in judged)
        without = sorted(r["run"] for r in judged if r["strongest_false"] >= r["weakest_true"])
        shared = (f"[{exact_low:.4f}, {exact_high:.4f}]" if exact_low < exact_high
                  else f"none (an edge not in its graph scores {exact_low:.4f}, one in its graph {exact_high:.4f})")
        print(f"against the graphs by construction: {len(judged) - len(without)} of {len(judged)} runs have a "
              f"threshold of their own that makes them exact"
              + (f" (not: {', '.join(without)})" if without else "") + f"; a threshold shared by all: {shared}")
        summary.update({"exact_runs_possible": len(judged) - len(without), "exact_window_low": round(exact_low, 5),
                        "exact_window_high": round(exact_high, 5)})
    print(json.dumps(summary))


if __name__ == "__main__":
    main()
