#!/usr/bin/env python3
"""The soak's report (tests/bench/soak/run.sh): reads the soak folder (rss.csv, kills,
launcher.log, injector.log) and its run folder's CSVs, prints the tables and, as the last
line, the JSON with the checks; exit 0 only if every check passes.

    report.py SOAK_DIR LAUNCHER_EXIT_CODE MINUTES
"""
import csv, json, re, sys, yaml
out, code, minutes = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
run = out + "/run"
def rows(name):
    try: return list(csv.DictReader(open(f"{run}/{name}")))
    except FileNotFoundError: return []
rss = list(csv.DictReader(open(f"{out}/rss.csv")))
learner = rows("learner.csv"); nodes = rows("nodes.csv"); evals = rows("eval.csv")
kills = [l.strip() for l in open(f"{out}/kills") if l.strip()]
cfg = yaml.safe_load(open(f"{run}/config.yaml"))
capacity = int(cfg["learner"]["replay_capacity"])
try: outcome = yaml.safe_load(open(f"{run}/outcome.yaml"))
except FileNotFoundError: outcome = {}
t0 = float(learner[0]["wall_time"]) if learner else 0.0
start_wall = None
# --- learner memory over time (one line a minute), per process
print(f"learner RSS (MiB) over time, sampled every ~10 s")
print(f"{'t (s)':>6s} {'pid':>8s} {'RSS':>8s}")
for i, r in enumerate(rss):
    if i % 6 == 0 or i == len(rss) - 1 or (i > 0 and r["pid"] != rss[i - 1]["pid"]):
        print(f"{int(r['t_s']):6d} {r['pid']:>8s} {int(r['rss_kb']) / 1024:8.1f}")
# memory check: the last learner process (it runs from the second learner kill, at 70%, to the
# end), from 30 s after its first sample (its checkpoint restored, training going) to its end:
# the largest RSS within 10% of the RSS then. The replay still filling counts against it (its
# size at both ends is reported, from the process's NodeStatus "replay N").
pids = []
for r in rss:
    if not pids or pids[-1] != r["pid"]: pids.append(r["pid"])
memory = {"flat": False, "why": "no samples"}
if pids:
    last = [r for r in rss if r["pid"] == pids[-1]]
    window = [r for r in last if int(r["t_s"]) >= int(last[0]["t_s"]) + 30]
    replay = [int(m.group(1)) for n in nodes if n["role"] == "learner" and n["pid"] == pids[-1]
              for m in [re.match(r"replay (\d+)", n["detail"])] if m]
    if len(window) < 3:
        memory = {"flat": False, "why": f"only {len(window)} samples of the last learner (pid {pids[-1]})"}
    else:
        base = int(window[0]["rss_kb"]); top = max(int(r["rss_kb"]) for r in window)
        growth = (top - base) / base
        # informative: the floor (lowest RSS) of the window's first and last thirds, which leaves
        # out transient peaks (a checkpoint write holds the serialized state beside the state)
        third = max(1, len(window) // 3)
        floor_first = min(int(r["rss_kb"]) for r in window[:third])
        floor_last = min(int(r["rss_kb"]) for r in window[-third:])
        memory = {"flat": growth <= 0.10, "growth": round(growth, 4), "rss_mib_start": round(base / 1024, 1),
                  "floor_mib_first_third": round(floor_first / 1024, 1), "floor_mib_last_third": round(floor_last / 1024, 1),
                  "rss_mib_max": round(top / 1024, 1), "samples": len(window),
                  "seconds": int(window[-1]["t_s"]) - int(window[0]["t_s"]),
                  "replay_first": replay[0] if replay else None, "replay_last": replay[-1] if replay else None,
                  "replay_capacity": capacity}
    all_kb = [int(r["rss_kb"]) for r in rss]
    memory["rss_mib_all_min"] = round(min(all_kb) / 1024, 1)
    memory["rss_mib_all_max"] = round(max(all_kb) / 1024, 1)
print(f"memory: {memory}")
# --- restarts
restarts = outcome.get("restarts") if isinstance(outcome, dict) else None
# the launcher's last line: "run finished: REASON; restarts N"
found = re.findall(r"^run \w+: .*; restarts (\d+)", open(f"{out}/launcher.log").read(), re.M)
launcher_restarts = int(found[-1]) if found else None
procs = {}
for n in nodes:
    procs.setdefault(n["role"], set()).add(n["pid"])
print(f"\nkills: {len(kills)} ({', '.join(f'{k} {kills.count(k)}' for k in sorted(set(kills)))}); "
      f"launcher restarts: {launcher_restarts}; processes seen per role: "
      + ", ".join(f"{r} {len(p)}" for r, p in sorted(procs.items())))
# --- rejections: each process's last NodeStatus, summed per role and counter
last_row = {}
for n in nodes:
    last_row[(n["role"], n["node_id"], n["pid"])] = n
rejected = {}
for (role, _, _), n in last_row.items():
    m = re.search(r"rejected: (.*)$", n["detail"])
    if not m: continue
    for item in m.group(1).split():
        if "=" not in item: continue
        k, v = item.rsplit("=", 1)
        if v.isdigit(): rejected.setdefault(role, {}).setdefault(k, 0); rejected[role][k] += int(v)
print("\nrejected samples (summed over each process's last status)")
for role, counters in sorted(rejected.items()):
    print(f"  {role:8s} " + ", ".join(f"{k}={v}" for k, v in sorted(counters.items())))
injected = [l for l in open(f"{out}/injector.log")] if __import__("os").path.exists(f"{out}/injector.log") else []
bursts = [l for l in injected if l.startswith("burst")]
print(f"injector: {len(bursts)} bursts" + (f"; last: {bursts[-1].strip()}" if bursts else "") +
      ("" if all(l.startswith("burst") for l in injected) else f"; other output: {[l.strip() for l in injected if not l.startswith('burst')][:3]}"))
# --- versions
def monotone(values):
    back = [(a, b) for a, b in zip(values, values[1:]) if b < a]
    return back
learner_versions = [int(r["policy_version"]) for r in learner]
back_learner = monotone(learner_versions)
# the graph version per learner process (a restarted one has none until the graph arrives)
back_graph = []
for pid in {n["pid"] for n in nodes if n["role"] == "learner"}:
    back_graph += monotone([int(n["graph_version"]) for n in nodes if n["role"] == "learner" and n["pid"] == pid])
back_actor = []
for (role, nid, pid) in {(n["role"], n["node_id"], n["pid"]) for n in nodes if n["role"] == "actor"}:
    mine = [n for n in nodes if n["role"] == role and n["node_id"] == nid and n["pid"] == pid]
    b = monotone([int(n["policy_version"]) for n in mine]) + monotone([int(n["graph_version"]) for n in mine])
    back_actor += [(nid, pid, x) for x in b]
print(f"\nversions: learner.csv policy v{learner_versions[0] if learner_versions else '-'} -> "
      f"v{learner_versions[-1] if learner_versions else '-'}, steps back {len(back_learner)} {back_learner[:5]}; "
      f"learner graph steps back {len(back_graph)} {back_graph[:5]}; actor processes' weights or graph steps back "
      f"{len(back_actor)} {back_actor[:5]}")
# --- episodes
dups = rejected.get("learner", {}).get("episode.duplicate", 0)
accepted = int(learner[-1]["episodes_accepted"]) if learner else 0
print(f"episodes: learner accepted {accepted} (its last stats), duplicates refused {dups}")
# --- evaluation
passive = [r for r in evals if int(r["policy_version"]) == 0]
learned = [r for r in evals if int(r["policy_version"]) > 0]
print("\nevaluations (avg_object_distance; lower is better)")
print(f"{'env steps':>10s} {'policy v':>9s} {'actor':>6s} {'obj dist':>9s} {'success':>8s}")
for r in evals:
    print(f"{int(r['env_steps']):10d} {int(r['policy_version']):9d} {r['actor_id']:>6s} "
          f"{float(r['avg_object_distance']):9.4f} {float(r['success_rate']):8.2f}")
p = float(passive[0]["avg_object_distance"]) if passive else float("nan")
f = float(learned[-1]["avg_object_distance"]) if learned else float("nan")
checks = {
    "memory_flat": bool(memory.get("flat")),
    "versions_monotone": not back_learner and not back_graph and not back_actor and len(learner_versions) > 0,
    "no_episode_twice": dups > 0,
    "restarts": launcher_restarts is not None and launcher_restarts >= len(kills) and len(kills) > 0,
    "better_than_passive": bool(learned and passive and f < p),
    "exit_0": code == 0,
}
print(f"\nfinal evaluation: avg_object_distance {f:.4f} vs passive {p:.4f}"
      + (f" (ratio {f / p:.3f})" if passive and learned else ""))
print("checks: " + ", ".join(f"{k} {'pass' if v else 'FAIL'}" for k, v in checks.items()))
print(json.dumps({"bench": "soak", "minutes": minutes, "launcher_exit": code, "kills": len(kills),
                  "launcher_restarts": launcher_restarts, "memory": memory, "rejected": rejected,
                  "duplicates_refused": dups, "policy_version_final": learner_versions[-1] if learner_versions else None,
                  "final_avg_object_distance": f, "passive_avg_object_distance": p,
                  "ratio": round(f / p, 3) if passive and learned else None,
                  "checks": checks, "pass": all(checks.values())}))
sys.exit(0 if all(checks.values()) else 1)
