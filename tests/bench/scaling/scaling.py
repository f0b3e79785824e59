#!/usr/bin/env python3
"""Helpers of tests/bench/scaling/run.sh: read a run folder's CSVs (written by `srics run` from
what the processes publish, one row per process and status period, wall_time in seconds).

  scaling.py warm RUN_DIR ACTORS RATIO GIVE_UP_S   prints the wall time at which the warm-up
                                        ended and why (see warm()), nothing while it has not
  scaling.py window RUN_DIR T0 SECONDS  prints "START END KIND" once the measuring window is
                                        complete (see window()), nothing before
  scaling.py measure RUN_DIR ACTORS T0 T1   one JSON object: the rates between T0 and T1
  scaling.py report OUT_DIR META_JSON   the table and, as the last line, the bench's JSON
"""
import csv
import json
import math
import os
import re
import sys


def rows(path):
    if not os.path.exists(path):
        return []
    with open(path, newline="") as f:
        out = []
        for r in csv.DictReader(f):
            try:
                r["_t"] = float(r["wall_time"])
            except (KeyError, TypeError, ValueError):
                continue  # a row being written
            out.append(r)
        return out


def actor_rows(run_dir):
    by_id = {}
    for r in rows(f"{run_dir}/nodes.csv"):
        if r.get("role") == "actor":
            by_id.setdefault(r["node_id"], []).append(r)
    return by_id


def rate_error_buffer(run_dir):
    """learner.rate_error_buffer of the run (its config.yaml lists the keys set; default 500)."""
    try:
        m = re.search(r"^\s+rate_error_buffer:\s*([0-9.eE+-]+)\s*$", open(f"{run_dir}/config.yaml").read(), re.M)
        return float(m.group(1)) if m else 500.0
    except (OSError, ValueError):
        return 500.0


def warm(run_dir, actors, ratio, give_up_s):
    """(end of the warm-up, why) or None while it goes on. After the learner's first update
    the run is in a transient either way, and the window must start after it:
    - the learner starts with rate_error_buffer updates of credit: at a low ratio it runs
      flat out until it has used it (surplus = updates - ratio x inserted, both counted from
      its first update, at 0.8 buffer or more and grown by at most 1% of the buffer over the
      last 3 reports) and from then on waits for data: 'data-bound';
    - the actors usually explored beyond the learner's warm-up before the first weights
      arrived, and at ratio 1 they wait while the learner works that off (inserts flat): the
      first report with new data after a flat one is 'resumed';
    - or the actors run a buffer ahead and wait for the learner without a visible stop:
      surplus at -buffer/2 or below, new data, and the surplus within 0.2 buffer of its value
      two reports before (not the data in flight at the first update, which drops it by
      hundreds a report): 'learner-bound'.
    If none of these within give_up_s of the first update: 'no steady state'. And every actor
    has reported training or waiting since the first update."""
    learner = rows(f"{run_dir}/learner.csv")
    first = next((k for k, r in enumerate(learner) if int(r["updates"] or 0) > 0), None)
    if first is None:
        return None
    base = learner[first]
    buffer = rate_error_buffer(run_dir)
    inserted = [int(r["transitions_inserted"]) for r in learner]
    found = None
    surpluses = [0.0]
    for k in range(first + 1, len(learner)):
        r = learner[k]
        surplus = (int(r["updates"]) - int(base["updates"])) - ratio * (inserted[k] - inserted[first])
        surpluses.append(surplus)
        new_data = inserted[k] > inserted[k - 1]
        if surplus >= 0.8 * buffer and k - 3 >= first and surplus - surpluses[-4] <= max(2.0, 0.01 * buffer):
            found = (r["_t"], "data-bound")
        elif new_data and k - 2 >= first and inserted[k - 1] == inserted[k - 2]:
            found = (r["_t"], "resumed")
        elif new_data and k >= first + 2 and surplus <= -0.5 * buffer and abs(surplus - surpluses[-3]) <= 0.2 * buffer:
            found = (r["_t"], "learner-bound")
        elif r["_t"] - base["_t"] > give_up_s:
            found = (r["_t"], "no steady state")
        if found:
            break
    if found is None:
        return None
    by_id = actor_rows(run_dir)
    if len(by_id) < actors:
        return None
    end = found[0]
    for rs in by_id.values():
        t = next((r["_t"] for r in rs if r["_t"] >= base["_t"] and r["state"] in ("training", "waiting")), None)
        if t is None:
            return None
        end = max(end, t)
    return end, found[1]


def latest(run_dir):
    ts = [r["_t"] for r in rows(f"{run_dir}/learner.csv")] + [r["_t"] for r in rows(f"{run_dir}/nodes.csv")]
    return max(ts) if ts else 0.0


def span(rs, t0, t1, key):
    """(delta of key, delta of wall time) between the first row at or after t0 and the last row
    at or before t1 (rows every status period: the window is within a period of [t0, t1])."""
    inside = [r for r in rs if t0 <= r["_t"] <= t1]
    if len(inside) < 2:
        return None
    a, b = inside[0], inside[-1]
    return float(b[key]) - float(a[key]), b["_t"] - a["_t"]


def window(run_dir, t0, seconds):
    """The measuring window from t0 on, or None while the run has not covered it yet:
    (start, end, kind). When the actors deliver data in every learner report (kind 'steady')
    it is [t0, t0 + seconds]. When they deliver in bursts (they ran a rate_error_buffer ahead
    and wait for the learner, a cycle of buffer / updates-per-s seconds: a minute with a slow
    learner) a fixed window would cut cycles and be off by up to a burst, so it spans whole
    cycles (kind 'cycles'): from the last report before the first burst after t0 to the last
    report before the first burst that starts at least `seconds` later."""
    learner = [r for r in rows(f"{run_dir}/learner.csv") if r["_t"] >= t0]
    if not learner or learner[-1]["_t"] < t0 + seconds + 1.5:
        return None
    inserted = [int(r["transitions_inserted"]) for r in learner]
    in_nominal = [k for k, r in enumerate(learner) if r["_t"] <= t0 + seconds]
    flat = any(inserted[k] == inserted[k - 1] for k in in_nominal if k > 0)
    if not flat:
        return t0, t0 + seconds, "steady"
    # boundaries: the report before each burst that follows a report with no new data
    bounds = [learner[k - 1]["_t"] for k in range(2, len(learner))
              if inserted[k] > inserted[k - 1] == inserted[k - 2]]
    if not bounds:
        return None
    end = next((t for t in bounds if t >= bounds[0] + seconds), None)
    return (bounds[0], end, "cycles") if end is not None else None


def measure(run_dir, actors, t0, t1):
    """Rates over [t0, t1]. env steps/s: what the learner received (learner.csv
    transitions_inserted: the actors' training steps; exploration ended in the warm-up and
    evaluations are out of the window), so that it lines up with the window's boundaries;
    the actors' own counts (nodes.csv) beside it."""
    nan = float("nan")
    out = {"env_steps_per_s": nan, "updates_per_s": nan, "achieved_ratio": nan,
           "actor_env_steps_per_s": nan, "actor_waiting_fraction": nan, "actors_seen": 0}
    per_actor = []
    states = []
    by_id = actor_rows(run_dir)
    out["actors_seen"] = len(by_id)
    for rs in by_id.values():
        s = span(rs, t0, t1, "env_steps")
        if s and s[1] > 0:
            per_actor.append(s[0] / s[1])
        states += [r["state"] for r in rs if t0 <= r["_t"] <= t1]
    if len(per_actor) == actors:
        out["actor_env_steps_per_s"] = sum(per_actor)
    out["per_actor_env_steps_per_s"] = [round(x, 1) for x in per_actor]
    if states:
        out["actor_waiting_fraction"] = sum(s == "waiting" for s in states) / len(states)
    learner = rows(f"{run_dir}/learner.csv")
    u = span(learner, t0, t1, "updates")
    i = span(learner, t0, t1, "transitions_inserted")
    if u and u[1] > 0:
        out["updates_per_s"] = u[0] / u[1]
    if i and i[1] > 0:
        out["env_steps_per_s"] = i[0] / i[1]
        if i[0] > 0 and u:
            out["achieved_ratio"] = u[0] / i[0]
    out["window_s"] = round(t1 - t0, 1)
    return out


def fmt(x, spec):
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "n/a".rjust(int(re.match(r"\d*", spec).group(0) or 0))
    return format(x, spec)


def times(x):
    return "n/a" if math.isnan(x) else f"{x:.2f}x"


def clean(x):
    if isinstance(x, float):
        return None if math.isnan(x) else round(x, 4 if abs(x) < 10 else 1)
    if isinstance(x, list):
        return [clean(v) for v in x]
    if isinstance(x, dict):
        return {k: clean(v) for k, v in x.items()}
    return x


def report(out_dir, meta):
    results = []
    with open(f"{out_dir}/results.jsonl") as f:
        for line in f:
            if line.strip():
                results.append(json.loads(line))
    base = {}
    for r in results:  # speed-up over the fewest actors measured at the same ratio (1 by default)
        b = base.get(r["updates_per_step"])
        if b is None or r["actors"] < b["actors"]:
            base[r["updates_per_step"]] = r
    nan = float("nan")
    for r in results:
        for k in ("env_steps_per_s", "updates_per_s", "actor_env_steps_per_s", "achieved_ratio", "actor_waiting_fraction"):
            r[k] = nan if r.get(k) is None else r[k]
        b = base[r["updates_per_step"]]
        r["baseline_actors"] = b["actors"]
        r["env_speedup"] = r["env_steps_per_s"] / b["env_steps_per_s"] if b["env_steps_per_s"] > 0 else nan
        r["updates_speedup"] = r["updates_per_s"] / b["updates_per_s"] if b["updates_per_s"] > 0 else nan

    print(f"scaling: {meta['config']}, run.method={meta['method']}, {meta['seconds']} s per configuration "
          f"after warm-up + {meta['settle']} s; {meta['machine']['model_name']}, {meta['machine']['cores']} cores, "
          f"load average {meta['loadavg_start'][0]:.2f} at the start, {meta['loadavg_end'][0]:.2f} at the end")
    head = (f"{'updates/step':>12s} {'actors':>6s} {'env steps/s':>11s} {'updates/s':>9s} {'achieved':>8s} "
            f"{'speed-up env':>12s} {'speed-up upd':>12s} {'actors waiting':>14s} {'window':>7s}  warm-up end / window / status")
    print(head)
    for r in results:
        print(f"{r['updates_per_step']:>12g} {r['actors']:>6d} {fmt(r['env_steps_per_s'], '11.1f')} "
              f"{fmt(r['updates_per_s'], '9.1f')} {fmt(r['achieved_ratio'], '8.3f')} "
              f"{times(r['env_speedup']):>12s} {times(r['updates_speedup']):>12s} "
              f"{fmt(r['actor_waiting_fraction'] * 100, '.0f') + '%':>14s} {fmt(r.get('window_s'), '6.0f') + 's':>7s}"
              f"  {r.get('steady') or '-'} / {r.get('window') or '-'} / {r['status']}")
    print("env steps/s = as the learner received them; achieved = updates / inserted transitions in the window; "
          "speed-up = over the fewest actors at the same ratio; actors waiting = share of the actors' status reports "
          "that said 'waiting for the learner'; warm-up end and window: scaling.py warm, window")

    def top(ratio_pick):
        rs = [r for r in results if ratio_pick(r["updates_per_step"])]
        if not rs:
            return nan
        return max(rs, key=lambda r: r["actors"])["env_speedup"]

    ratios = sorted({r["updates_per_step"] for r in results})
    low, high = ratios[0], ratios[-1]
    summary = {
        "bench": "scaling",
        "config": meta["config"],
        "method": meta["method"],
        "seconds": meta["seconds"],
        "settle_seconds": meta["settle"],
        "machine": meta["machine"],
        "loadavg_start": meta["loadavg_start"],
        "loadavg_end": meta["loadavg_end"],
        "results": [{k: r[k] for k in ("updates_per_step", "actors", "env_steps_per_s", "updates_per_s",
                                       "achieved_ratio", "env_speedup", "updates_speedup", "actor_env_steps_per_s",
                                       "actor_waiting_fraction", "per_actor_env_steps_per_s", "steady", "window",
                                       "window_s", "status")}
                    for r in results],
        # what the most actors buy at the lowest ratio (actor-bound) and at the highest (learner-bound)
        "env_speedup_low_ratio": top(lambda x: x == low),
        "env_speedup_high_ratio": top(lambda x: x == high) if high != low else nan,
    }
    summary["ratio"] = summary["env_speedup_low_ratio"]
    print(json.dumps(clean(summary)))


def main():
    cmd = sys.argv[1]
    if cmd == "warm":
        w = warm(sys.argv[2], int(sys.argv[3]), float(sys.argv[4]), float(sys.argv[5]))
        if w is not None:
            print(f"{w[0]:.3f} {w[1]}")
    elif cmd == "latest":
        print(f"{latest(sys.argv[2]):.3f}")
    elif cmd == "window":
        w = window(sys.argv[2], float(sys.argv[3]), float(sys.argv[4]))
        if w is not None:
            print(f"{w[0]:.3f} {w[1]:.3f} {w[2]}")
    elif cmd == "measure":
        print(json.dumps(measure(sys.argv[2], int(sys.argv[3]), float(sys.argv[4]), float(sys.argv[5]))))
    elif cmd == "report":
        report(sys.argv[2], json.loads(sys.argv[3]))
    else:
        sys.exit(f"unknown command {cmd}")


if __name__ == "__main__":
    main()
