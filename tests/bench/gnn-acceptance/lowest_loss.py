#!/usr/bin/env python3
"""What `graph.publish: lowest_held_out_loss` would have published, replayed from run logs.

    tests/bench/gnn-acceptance/lowest_loss.py DIR [--settled UPDATES]   (default 3000)

The option changes only which evaluation the graph service publishes (the training is the same),
so each acceptance run's log.txt (`srics learn-graph` output) tells both outcomes, whichever
of the two the run published: the last evaluation's graph (what `last` publishes: 110 of 110
logs of 2026-12-07) and the graph of the settled evaluation (after `--settled` updates: the
defaults' warm-up 1,500 plus KL ramp 1,500) whose held-out loss was the lowest. Prints the runs
whose outcome differs and a count of exact graphs each way, then one JSON line.
"""
import argparse
import glob
import json
import os
import re

EVALUATION = re.compile(r"^\[.*\] training\s+episodes .* updates (\d+) held-out (\S+) .*stable \d+  (.*)$")


def outcomes(log, settled):
    """(expected, last, lowest) graphs of one run's log, or None for a run without a published graph
    or a settled evaluation."""
    expected = re.search(r"by construction: ([^(\n]*)", log)
    published = re.search(r"published graph version 1: (.*)", log)
    evaluations = [(int(m.group(1)), float(m.group(2)), m.group(3).strip())
                   for m in map(EVALUATION.match, log.splitlines()) if m]
    settled_ones = [e for e in evaluations if e[0] > settled]
    if not (expected and published and settled_ones):
        return None
    lowest = min(settled_ones, key=lambda e: e[1])  # the first of equal losses, as the service keeps it
    # not the published line: a run that published the lowest loss's graph has it there
    return expected.group(1).strip(), evaluations[-1][2], lowest[2]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("dir", help="an acceptance's OUT folder (DIR/<table>-s<seed>/log.txt)")
    parser.add_argument("--settled", type=int, default=3000)
    args = parser.parse_args()
    runs = exact_last = exact_lowest = 0
    for folder in sorted(glob.glob(os.path.join(args.dir, "*-s*"))):
        try:
            log = open(os.path.join(folder, "log.txt")).read()
        except OSError:
            continue
        result = outcomes(log, args.settled)
        if result is None:
            continue
        expected, last, lowest = result
        runs += 1
        exact_last += last == expected
        exact_lowest += lowest == expected
        if lowest != last:
            say = lambda g: "exact" if g == expected else "miss: " + g
            print(f"{os.path.basename(folder)}: last {say(last)} | lowest loss {say(lowest)}")
    print(f"{runs} runs: the last evaluation exact {exact_last}, the lowest held-out loss exact {exact_lowest}")
    print(json.dumps({"runs": runs, "exact_last": exact_last, "exact_lowest_loss": exact_lowest}))


if __name__ == "__main__":
    main()
