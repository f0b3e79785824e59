#!/usr/bin/env python3
"""How well the data's tie evidence tells tied object pairs from the others, read from run logs.

    tests/bench/gnn-acceptance/tie_evidence.py FOLDER... [--per-episode R --share S --episodes N]

Each FOLDER is one `srics learn-graph` output folder (its log.txt; `--evidence` runs stop right
after the evidence, acceptance runs train on): the onsets at a distance per object, the same
onsets by the object moving in that step (`i->j`: j starts while i moves) and the graph by
construction. For every pair of objects: its smaller count (the rarer end's onsets at a distance)
and its smaller share (the share of an end's onsets that start while the other end moves).
Prints the range of both for tied and untied pairs, the untied pairs that pass each condition of
graph.tie_evidence_per_episode (R) and graph.tie_evidence_share (S) alone, and the pairs picked
by both against the ties, then one JSON line.
"""
import argparse
import json
import os
import re

PER_OBJECT = re.compile(r"onsets at a distance \(per entity[^)]*\):((?: \d+: \d+)+)")
BY_MOVER = re.compile(r"while another object moves \([^)]*\):((?: \d+->\d+: \d+)+| none)")
EXPECTED = re.compile(r"by construction: ([^(\n]*)")


def pairs_of(log):
    """[(i, j, tied, count, share)] for the object pairs i < j of one log, or None without evidence."""
    per_object, by_mover, expected = PER_OBJECT.search(log), BY_MOVER.search(log), EXPECTED.search(log)
    if not (per_object and by_mover and expected):
        return None
    onsets = {int(k): int(v) for k, v in re.findall(r"(\d+): (\d+)", per_object.group(1))}
    moving = {(int(i), int(j)): int(c) for i, j, c in re.findall(r"(\d+)->(\d+): (\d+)", by_mover.group(1))}
    ties = set()
    for edge in expected.group(1).strip().split(", "):
        a, b = edge.split("->")
        if a not in ("action", "0") and b != "0":
            ties.add(tuple(sorted((int(a), int(b)))))
    objects = sorted(k for k in onsets if k != 0)  # the arm is entity 0
    out = []
    for i in objects:
        for j in objects:
            if i < j:
                share_i = moving.get((j, i), 0) / onsets[i] if onsets[i] else 0.0
                share_j = moving.get((i, j), 0) / onsets[j] if onsets[j] else 0.0
                out.append((i, j, (i, j) in ties, min(onsets[i], onsets[j]), min(share_i, share_j)))
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folders", nargs="+", help="srics learn-graph output folders (FOLDER/log.txt)")
    parser.add_argument("--per-episode", type=float, default=0.025, help="graph.tie_evidence_per_episode")
    parser.add_argument("--share", type=float, default=0.5, help="graph.tie_evidence_share")
    parser.add_argument("--episodes", type=int, default=1000, help="graph.episodes of the runs")
    args = parser.parse_args()
    needed = args.per_episode * args.episodes
    tied, untied, picked_wrong, missed = [], [], [], []
    for folder in args.folders:
        path = os.path.join(folder, "log.txt")
        pairs = pairs_of(open(path).read()) if os.path.exists(path) else None
        if pairs is None:
            continue
        name = os.path.basename(os.path.normpath(folder))
        for i, j, is_tie, count, share in pairs:
            row = (name, i, j, count, share)
            (tied if is_tie else untied).append(row)
            picked = count >= needed and share >= args.share
            if picked and not is_tie:
                picked_wrong.append(row)
            if is_tie and not picked:
                missed.append(row)

    def describe(rows, title):
        if not rows:
            print(f"{title}: none")
            return
        counts, shares = [r[3] for r in rows], [r[4] for r in rows]
        print(f"{title}: {len(rows)}, count {min(counts)}-{max(counts)}, share {min(shares):.2f}-{max(shares):.2f}")

    describe(tied, "tied pairs")
    describe(untied, "untied pairs")
    describe([r for r in untied if r[3] >= needed], f"untied pairs with a count of at least {needed:g}")
    describe([r for r in untied if r[4] >= args.share], f"untied pairs with a share of at least {args.share:g}")
    for name, i, j, count, share in picked_wrong:
        print(f"picked but untied: {name} {i}-{j} (count {count}, share {share:.2f})")
    for name, i, j, count, share in missed:
        print(f"tied but not picked: {name} {i}-{j} (count {count}, share {share:.2f})")
    print(json.dumps({"tied": len(tied), "untied": len(untied), "picked_untied": len(picked_wrong),
                      "missed_ties": len(missed)}))


if __name__ == "__main__":
    main()
