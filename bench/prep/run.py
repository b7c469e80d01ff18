#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-2.0-or-later
"""Preparation study (docs/studies/preparation.md; summary in
docs/preparation.md): how close the chamber preparation
gets to the paper's initial state, and what it costs.

    /usr/bin/python3 bench/prep/run.py --work /tmp/prep_study [--np 2] [--cases NAME ...] [--force]

Each case prepares a chamber with examples/cpt_demo/run.py --prep-only (radius
expansion to the core porosity 0.385 at 5 kPa, 1-D compression to 150 kPa,
radial servo to 76 kPa; the deck stops with an error if a stage misses its
target) and reads its summary.json:

  demo_2024, demo_2025   the demo chamber (R 60 mm, H 100 mm, full circle,
                         N = 39, 3132 grains), two packing seeds;
  paper_R216_q           a chamber of the paper's radius (R 216 mm = 12 pile
                         radii) as a 90-degree sector, 100 mm high (about
                         10,000 grains; the paper's 1 m would be 100,000 in
                         the sector, hours here).

Writes bench/prep/results.json (or --results): per case the grain count,
core and whole porosity (crushpost.prep from the snapshot of the prepared
sample, and the deck's own), boundary stresses against their targets,
ring-averaged sigma_z, sigma_r, sigma_theta [mean, sd] over all rings and
over the rings that touch no wall, the expansion's end state (static stress,
friction reached, cycles), K0 of the 1-D compression, coordination number,
LIGGGHTS time, steps and wall time; and the paper's values.

Restartable: a case whose summary.json is in --work is read, not run again
(--force runs it again). Cases run one after the other.
"""

import argparse
import json
import os
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(REPO, "scripts"))

from crushpost.prep import PAPER_PREPARED  # noqa: E402

CASES = {
    "demo_2024": {"R_ch": 0.06, "H_ch": 0.1, "sector": 360, "packing_seed": 2024},
    "demo_2025": {"R_ch": 0.06, "H_ch": 0.1, "sector": 360, "packing_seed": 2025},
    "paper_R216_q": {"R_ch": 0.216, "H_ch": 0.1, "sector": 90, "packing_seed": 2024},
}
TARGETS = {"n_target": 0.385, "s_prep_kPa": 5.0, "sv_kPa": 150.0, "sr_kPa": 76.0}


def run_case(name, spec, work, np_, liggghts, force):
    out = os.path.join(work, name)
    summary = os.path.join(out, "summary.json")
    if force or not os.path.exists(summary):
        cmd = [sys.executable, os.path.join(REPO, "examples", "cpt_demo", "run.py"), "--out", out,
               "--np", str(np_), "--prep-only", "--R-ch", str(spec["R_ch"]), "--H-ch", str(spec["H_ch"]),
               "--sector", str(spec["sector"]), "--packing-seed", str(spec["packing_seed"])]
        if liggghts:
            cmd += ["--liggghts", liggghts]
        t0 = time.time()
        rc = subprocess.call(cmd, stdout=subprocess.DEVNULL)
        # wall times on a shared machine depend on the other jobs: keep the load
        with open(os.path.join(out, "machine_load.json"), "w") as f:
            json.dump({"cpus": os.cpu_count(), "load_average_1_5_15": os.getloadavg()}, f)
        if rc != 0:
            return {"case": name, "spec": spec, "failed": True, "exit_code": rc,
                    "wall_time_s": time.time() - t0, "log": os.path.join(out, "log.liggghts")}
    with open(summary) as f:
        s = json.load(f)
    r = condense(name, spec, s)
    load = os.path.join(out, "machine_load.json")
    if os.path.exists(load):
        with open(load) as f:
            r["machine_at_end"] = json.load(f)
    return r


def condense(name, spec, s):
    p = s["prep"]
    deck = p["deck"]
    exp, comp, done = deck.get("expanded", {}), deck.get("compressed", {}), deck.get("prepared", {})
    rel = lambda x, t: x / t - 1.0
    out = {"case": name, "spec": spec, "n_grains": s["n_particles_initial"], "mpi_ranks": s["mpi_ranks"],
           "prepared": p["prepared"], "wall_time_s": s["wall_time_s"],
           "liggghts_time_s": p["liggghts_time_s"], "steps": p["steps"]}
    if p["prepared"]:
        out.update({
            "porosity_core": p["porosity_core"], "porosity_all": p["porosity_all"],
            "porosity_core_deck": done["porosity_core"],
            "sv_kPa": done["sv"] / 1e3, "sr_kPa": done["sr"] / 1e3,
            "sv_rel_error": rel(done["sv"] / 1e3, TARGETS["sv_kPa"]),
            "sr_rel_error": rel(done["sr"] / 1e3, TARGETS["sr_kPa"]),
            "ring_stats_kPa": {k: p[k] for k in ("sigma_z_kPa", "sigma_r_kPa", "sigma_theta_kPa")},
            "ring_stats_interior_kPa": p["rings"].get("interior"),
            # equilibrium check: the volume-weighted mean of the ring stresses is
            # the sample's average stress, which the boundary forces fix
            "ring_volume_weighted_kPa": volume_weighted(p["rings"]),
            "rings": {"n_r": p["rings"]["n_r"], "n_z": p["rings"]["n_z"],
                      "wall_contacts": p["rings"]["wall_contacts"]},
            "coordination": p["coordination"],
            "expanded": {"porosity_core": exp.get("porosity_core"), "p_static_kPa": exp.get("p", 0) / 1e3,
                         "mu_prep_final": exp.get("mu_prep"), "cycles": exp.get("cycles"),
                         "coordination": exp.get("coordination")},
            "compressed": {"K0": comp.get("K0"), "porosity_core": comp.get("porosity_core")},
        })
    return out


def volume_weighted(rings):
    """Volume-weighted means of the ring stresses [kPa] (ring volumes from the
    edges; a sector's rings all have the same angular fraction)."""
    r, z = np.asarray(rings["r_edges_m"]), np.asarray(rings["z_edges_m"])
    vol = np.outer(np.diff(r ** 2), np.diff(z))
    out = {k: float(np.sum(vol * np.asarray(rings[k])) / vol.sum())
           for k in ("sigma_z_kPa", "sigma_r_kPa", "sigma_theta_kPa")}
    # the lateral wall fixes the mean of the two horizontal components
    out["horizontal_mean_kPa"] = 0.5 * (out["sigma_r_kPa"] + out["sigma_theta_kPa"])
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--work", required=True, help="folder for the runs")
    ap.add_argument("--np", type=int, default=2)
    ap.add_argument("--cases", nargs="+", default=list(CASES), choices=list(CASES))
    ap.add_argument("--force", action="store_true", help="run cases again even if done")
    ap.add_argument("--liggghts", default=None)
    ap.add_argument("--results", default=os.path.join(HERE, "results.json"))
    a = ap.parse_args(argv)
    os.makedirs(a.work, exist_ok=True)
    results = []
    for name in a.cases:
        r = run_case(name, CASES[name], a.work, a.np, a.liggghts, a.force)
        print(json.dumps(r, indent=1), flush=True)
        results.append(r)
    doc = {"targets": TARGETS, "paper": PAPER_PREPARED,
           "how": "bench/prep/run.py --work WORK --np %d (examples/cpt_demo/run.py --prep-only per case)" % a.np,
           "cases": results}
    with open(a.results, "w") as f:
        json.dump(doc, f, indent=2)
    return 0


if __name__ == "__main__":
    sys.exit(main())
