#!/usr/bin/env python3
"""Times benchmark programs of two commits in turn (A B A B ...) and prints pair-by-pair ratios.

    tests/bench_pair.py BASE [NEW] [--bench sac-update nn gnn] [--repeats 3] [--keys K ...]

Builds each commit's bench programs (bench_<name> of tests/bench/<name>/) in one worktree
(default ~/.cache/srics-bench-pair; the build shares the project's ccache), copies them out,
then runs BASE and NEW alternately, `repeats` pairs per bench, each program without arguments.
Every bench prints one JSON object as its last line; for each numeric key both have, the
table shows the medians and the median of the per-pair ratios NEW / BASE (a key is a time or
a rate: read its direction from its name). NEW defaults to HEAD. Nothing else should run
meanwhile: the ratios say what the two commits cost on this machine in this hour, no more.
"""
import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def last_json(text):
    """The last line of a bench's output that parses as a JSON object, or None."""
    for line in reversed(text.splitlines()):
        line = line.strip()
        if line.startswith("{"):
            try:
                value = json.loads(line)
            except json.JSONDecodeError:
                continue
            if isinstance(value, dict):
                return value
    return None


def pair_ratios(base_runs, new_runs, keys=None):
    """Per numeric key present in every run: (median base, median new, ratios new/base per pair,
    median ratio). Pairs are matched by position; a base value of 0 gives no ratio."""
    if len(base_runs) != len(new_runs) or not base_runs:
        raise ValueError("pair_ratios: need the same number of base and new runs, at least one")
    numeric = lambda run: {k for k, v in run.items() if isinstance(v, (int, float)) and not isinstance(v, bool)}
    common = set.intersection(*(numeric(r) for r in base_runs + new_runs))
    wanted = [k for k in (keys or sorted(common)) if k in common]
    table = {}
    for k in wanted:
        ratios = [n[k] / b[k] for b, n in zip(base_runs, new_runs) if b[k] != 0]
        table[k] = (statistics.median(r[k] for r in base_runs), statistics.median(r[k] for r in new_runs), ratios,
                    statistics.median(ratios) if ratios else float("nan"))
    return table


def run(cmd, **kw):
    return subprocess.run(cmd, check=True, text=True, **kw)


def resolve(commit):
    return run(["git", "-C", ROOT, "rev-parse", "--short", commit + "^{commit}"], capture_output=True).stdout.strip()


def build_benches(commit, benches, work):
    """Builds bench_<name> for each name at `commit` in the pair's worktree; returns their paths."""
    tree = os.path.join(work, "tree")
    if not os.path.isdir(tree):
        run(["git", "-C", ROOT, "worktree", "add", "--detach", tree, commit], stdout=subprocess.DEVNULL)
    run(["git", "-C", tree, "checkout", "--quiet", "--detach", commit])
    env = dict(os.environ, SRICS_BUILD_DIR=os.path.join(work, "build"))
    targets = ["bench_" + b.replace("-", "_") for b in benches]
    print(f"bench_pair: building {' '.join(targets)} at {commit}", file=sys.stderr, flush=True)
    build = subprocess.run([os.path.join(tree, "tests", "build.sh"), "--target", *targets], env=env, text=True,
                           stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    if build.returncode != 0:  # the compiler's output only when it failed
        sys.exit(f"{build.stdout[-4000:]}\nbench_pair: the build of {commit} failed")
    out = os.path.join(work, "bin", commit)
    os.makedirs(out, exist_ok=True)
    paths = {}
    for b, t in zip(benches, targets):
        built = os.path.join(work, "build", "tests", "bench", b, t)
        if not os.path.exists(built):
            sys.exit(f"bench_pair: {commit} has no {t} (tests/bench/{b}/)")
        paths[b] = shutil.copy2(built, os.path.join(out, t))
    return paths


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("base")
    parser.add_argument("new", nargs="?", default="HEAD")
    parser.add_argument("--bench", nargs="+", default=["sac-update", "nn", "gnn"])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--keys", nargs="+", help="only these JSON keys (default: every numeric one)")
    parser.add_argument("--work", default=os.path.expanduser("~/.cache/srics-bench-pair"))
    args = parser.parse_args()
    if args.repeats < 1:
        parser.error("--repeats must be at least 1")
    base, new = resolve(args.base), resolve(args.new)
    os.makedirs(args.work, exist_ok=True)
    programs = {c: build_benches(c, args.bench, args.work) for c in (base, new)}
    results = {(c, b): [] for c in (base, new) for b in args.bench}
    for i in range(args.repeats):
        for b in args.bench:
            for c in (base, new):
                print(f"bench_pair: pair {i + 1}/{args.repeats} {b} {c}", file=sys.stderr, flush=True)
                out = run([programs[c][b]], capture_output=True).stdout
                value = last_json(out)
                if value is None:
                    sys.exit(f"bench_pair: bench_{b} of {c} printed no JSON line")
                results[(c, b)].append(value)
    summary = {"bench": "pair", "base": base, "new": new, "repeats": args.repeats}
    for b in args.bench:
        table = pair_ratios(results[(base, b)], results[(new, b)], args.keys)
        print(f"\n{b}: {new} / {base}, {args.repeats} pairs in turn")
        print(f"  {'key':40} {'base':>10} {'new':>10} {'ratio':>7}  pairs")
        for k, (mb, mn, ratios, mr) in table.items():
            print(f"  {k:40} {mb:10.4g} {mn:10.4g} {mr:7.3f}  {' '.join(f'{r:.3f}' for r in ratios)}")
            summary[f"{b}.{k}"] = round(mr, 4)
    print(json.dumps(summary))


if __name__ == "__main__":
    main()
