#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-2.0-or-later
"""Markdown tables of docs/studies/performance.md ("Instruction counts") from the
JSON files of bench/icount/run.py.

    /usr/bin/python3 bench/icount/tables.py [--scaling bench/icount/results_scaling.json]
                                            [--features bench/icount/results_features.json]
                                            [--rebuild bench/icount/results_scaling_rebuild2.json]
"""

import argparse
import json
import os

HERE = os.path.dirname(os.path.abspath(__file__))


def m(x):
    return "%.2f" % (x / 1e6)


def scaling_tables(res):
    rows = res["summary"]
    print("| ranks | grains per rank (mean) | work per rank per step, mean / max (M instr.) | imbalance max/mean "
          "| replicated work per rank per step (M) | bound on efficiency W_1/(P max W_P) "
          "| MPI calls per rank per step (MPI_Wtime not counted) | MPI instr. per rank per step, mean (M; busy waiting) |")
    print("|---|---|---|---|---|---|---|---|")
    for r, run in zip(rows, res["runs"]):
        W = r["work_per_step_per_rank"]
        calls = [sum(v for k, v in rk["mpi_calls"].items() if "Wtime" not in k) / run["steps"]
                 for rk in run["ranks"]]
        mpi = r["mpi_per_step_per_rank"]
        print("| %d | %.0f | %s / %s | %.3f | %s | %.3f | %.0f | %s |"
              % (r["np"], r["grains_per_rank"], m(sum(W) / len(W)), m(max(W)), r["imbalance_max_over_mean"],
                 m(r.get("replicated_work_per_rank_per_step", 0.0)), r.get("efficiency_bound", float("nan")),
                 sum(calls) / len(calls), m(sum(mpi) / len(mpi))))
    print()
    names = list(rows[0]["components_per_step"])
    names = sorted({n for r in rows for n in r["components_per_step"]},
                   key=lambda n: -rows[0]["components_per_step"].get(n, {"mean": 0})["mean"])
    print("| component (MPI excluded) | " + " | ".join("P = %d: mean / max (M), share" % r["np"] for r in rows) + " |")
    print("|---|" + "---|" * len(rows))
    for n in names:
        cells = []
        for r in rows:
            c = r["components_per_step"].get(n)
            cells.append("%s / %s, %.1f %%" % (m(c["mean"]), m(c["max"]), 100 * c["share_of_mean_work"])
                         if c else "-")
        print("| %s | %s |" % (n, " | ".join(cells)))
    print()
    # replicated work by component: (sum over ranks - the 1-rank count) / P
    one = rows[0]["components_per_step"]
    print("| component | " + " | ".join("replicated per rank, P = %d (M)" % r["np"] for r in rows[1:]) + " |")
    print("|---|" + "---|" * (len(rows) - 1))
    for n in names:
        cells = []
        for r in rows[1:]:
            c = r["components_per_step"].get(n, {"mean": 0.0})
            cells.append("%.3f" % ((r["np"] * c["mean"] - one.get(n, {"mean": 0.0})["mean"]) / r["np"] / 1e6))
        print("| %s | %s |" % (n, " | ".join(cells)))
    print()
    # MPI calls by site at the largest rank count, rank 0
    run = res["runs"][-1]
    rk = run["ranks"][0]
    print("MPI calls per step at P = %d (first rank):" % run["np"])
    for k, v in list(rk["mpi_calls"].items())[:15]:
        print("  %.1f  %s" % (v / run["steps"], k[:160]))


def rebuild_table(static, rebuild):
    """The cost of one neighbour-list rebuild per rank: the runs with a
    rebuild every k steps less the static runs, over the rebuilds."""
    print("| ranks | per rebuild per rank, mean (M) | in static steps | " + "components (mean, M) |")
    print("|---|---|---|---|")
    for rs, rr in zip(static["runs"], rebuild["runs"]):
        assert rs["np"] == rr["np"] and rs["steps"] == rr["steps"]
        n = rr["neighbor_builds_timed_run"]
        d = [(b["work"] - a["work"]) / n for a, b in zip(rs["ranks"], rr["ranks"])]
        mean_static = sum(a["work"] for a in rs["ranks"]) / len(rs["ranks"]) / rs["steps"]
        comp = {}
        for a, b in zip(rs["ranks"], rr["ranks"]):
            for k in set(a["components"]) | set(b["components"]):
                va = a["components"].get(k, 0) - a["components_mpi"].get(k, 0)
                vb = b["components"].get(k, 0) - b["components_mpi"].get(k, 0)
                comp[k] = comp.get(k, 0.0) + (vb - va) / n / len(rs["ranks"])
        parts = ", ".join("%s %.1f" % (k, v / 1e6) for k, v in sorted(comp.items(), key=lambda kv: -kv[1])
                          if abs(v) > 5e4)
        print("| %d | %s | %.2f | %s |" % (rs["np"], m(sum(d) / len(d)), sum(d) / len(d) / mean_static, parts))


def feature_table(res):
    print("| variant | what | instructions per step (M) | extra per step | extra |")
    print("|---|---|---|---|---|")
    for r in res["rows"]:
        print("| %s | %s | %.4f | %+.0f | %+.2f %% |" % (r["variant"], r["what"], r["per_step"] / 1e6,
                                                       r["extra_per_step"], r["extra_percent"]))


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--scaling", default=os.path.join(HERE, "results_scaling.json"))
    p.add_argument("--features", default=os.path.join(HERE, "results_features.json"))
    p.add_argument("--rebuild", default=os.path.join(HERE, "results_scaling_rebuild2.json"))
    a = p.parse_args()
    if os.path.exists(a.scaling) and os.path.exists(a.rebuild):
        rebuild_table(json.load(open(a.scaling)), json.load(open(a.rebuild)))
        print()
    if os.path.exists(a.scaling):
        scaling_tables(json.load(open(a.scaling)))
        print()
    if os.path.exists(a.features):
        feature_table(json.load(open(a.features)))


if __name__ == "__main__":
    main()
