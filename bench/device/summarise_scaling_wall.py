#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-2.0-or-later
"""Merge the JSON files of bench/device/scaling_wall.sh (one folder per call,
each holding the `results.tgz` it returned, unpacked) into one results file
with the medians per rank count and grid (docs/studies/performance.md "Wall-clock
rates at 16 ranks").

    /usr/bin/python3 bench/device/summarise_scaling_wall.py DIR [DIR ...] \
        --results bench/icount/results_scaling_wall_16core.json

Each DIR holds the `json/` folder of one call. Runs with a break or a
neighbour-list build in the timed steps other than those forced by
`--rebuild-every` are left out of the medians (their work is not the static
packing's) and counted.
"""
import argparse
import glob
import json
import os
import statistics
import sys


def intended_builds(r):
    """True when the timed run rebuilt its neighbour lists only where asked
    to (`run.py --rebuild-every K`: steps / K builds; else none)."""
    every = r["vars"].get("rebuild_every", 0)
    return r["neighbor_builds_timed_run"] == (r["steps"] // every if every else 0)


def load_runs(dirs):
    runs = []
    for call, d in enumerate(dirs, 1):
        files = sorted(glob.glob(os.path.join(d, "json", "*.json")))
        if not files:
            raise SystemExit("%s: no json/*.json (unpack the call's results.tgz there)" % d)
        for f in files:
            with open(f) as fh:
                res = json.load(fh)
            name = os.path.basename(f)[:-5]
            for i, r in enumerate(res["runs"]):
                # at 1 rank balance/grains does nothing: one 1-rank group
                balanced = bool(r["vars"].get("balance_cmd")) and r["np"] > 1
                runs.append({"call": call, "file": name, "order": i, "np": r["np"],
                             "proc_grid": r["proc_grid"], "balanced": balanced,
                             "atoms": r["atoms"], "steps": r["steps"], "loop_s": r["loop_s"],
                             "rebuild_every": r["vars"].get("rebuild_every", 0),
                             "neighbor_builds": r["neighbor_builds_timed_run"], "n_break": r["n_break"],
                             "static": intended_builds(r) and not r["n_break"],
                             "particle_steps_per_core_s": r["particle_steps_per_core_s"]})
    return runs


def summarise(runs):
    """Median rate per (ranks, grid, balanced) over the static runs, and the
    parallel efficiency against the median 1-rank rate."""
    static = [r for r in runs if r["static"]]
    groups = {}
    for r in static:
        key = (r["np"], r["proc_grid"], r["balanced"])
        groups.setdefault(key, []).append(r["particle_steps_per_core_s"])
    one = groups.get((1, "1 1 1", False), [])
    rate_1 = statistics.median(one) if one else None
    rows = []
    for (P, grid, bal), rates in sorted(groups.items()):
        med = statistics.median(rates)
        rows.append({"np": P, "proc_grid": grid, "balance_grains": bal, "n_runs": len(rates),
                     "rate_median": med, "rate_min": min(rates), "rate_max": max(rates),
                     "efficiency_vs_1_rank": med / rate_1 if rate_1 else None})
    return {"rate_1_rank_median": rate_1, "rows": rows,
            "runs_not_static": len(runs) - len(static)}


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("dirs", nargs="+")
    p.add_argument("--results", required=True)
    p.add_argument("--note", default="")
    a = p.parse_args(argv)
    runs = load_runs(a.dirs)
    out = {"what": "wall-clock particle-steps per core-second of bench/icount's chamber slice "
                   "(bench/device/scaling_wall.sh), medians over repeated static runs",
           "note": a.note, "summary": summarise(runs), "runs": runs}
    machine = os.path.join(a.dirs[0], "json", "machine.txt")
    if os.path.exists(machine):
        with open(machine) as fh:
            out["machine"] = fh.read()
    with open(a.results, "w") as fh:
        json.dump(out, fh, indent=1)
    for row in out["summary"]["rows"]:
        print("%2d %-6s bal=%d n=%2d median %.3g (%.3g-%.3g) eff %.2f"
              % (row["np"], row["proc_grid"], row["balance_grains"], row["n_runs"], row["rate_median"],
                 row["rate_min"], row["rate_max"], row["efficiency_vs_1_rank"] or 0))
    print("wrote", a.results)
    return 0


if __name__ == "__main__":
    sys.exit(main())
