#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-2.0-or-later
"""Benchmark of the report's heaviest step (issue 10 item 7): one snapshot of
500,000 particles and 2,000,000 contacts reduced to ring stresses.

    bench/report/run.py [--particles 500000] [--contacts 2000000] [--repeat 3]
                        [--out bench/report/results.json]

1. Writes a synthetic snapshot in the layout of fix snapshot/hdf5
   (docs/fix_snapshot_hdf5.md) into a temporary folder: grains of one size
   at random in a chamber of the source paper's proportions (pile radius
   R = 18 mm, chamber radius 12 R, height 0.4 m, solid fraction 0.6:
   d = 5.2 mm), 2,000,000 pair contacts between random neighbours (sorted
   by id pair, as the fix writes them) and 20,000 wall contacts.
2. In a fresh Python process for each repeat (so the peak memory is that of
   the reduction alone): reads it (crushpost.snapshot.read_snapshot),
   computes the per-particle stresses with the wall contacts
   (crushpost.snapshot.snapshot_particle_stress), the sphere-ring volumes
   (crushpost.rings.sphere_cell_volumes; rings R wide and 25 mm high, 12 x 16
   rings) and the ring averages (crushpost.rings.ring_fields), timing each
   step; the peak resident memory is the child's ru_maxrss.
3. Writes the times (median and all repeats) and the peak memory to --out
   and prints them. The limits of the issue (LIMITS): 20 s and 2 GB for the
   medians; the script exits 1 when a median is over its limit (the results
   are written first).
"""

import argparse
import json
import math
import os
import platform
import resource
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(REPO, "scripts"))

import numpy as np  # noqa: E402

from crushpost.snapshot import write_snapshot  # noqa: E402

R_PILE = 0.018
R_CH = 12 * R_PILE
H = 0.4
SOLID = 0.6
#: issue 10 item 7: the reduction of one such snapshot within 20 s and 2 GB
LIMITS = {"total_s": 20.0, "peak_rss_MB": 2048.0}


def limit_failures(median, limits=LIMITS):
    """The limits a result misses: one line per median over its limit (or
    missing), none when every one is within."""
    out = []
    for k, lim in limits.items():
        v = median.get(k)
        if v is None or not v <= lim:
            out.append("%s = %s over the limit %g" % (k, v, lim))
    return out


def write_synthetic(path, n, n_contacts, n_walls=20000, seed=2024):
    rng = np.random.default_rng(seed)
    v_grain = SOLID * math.pi * R_CH ** 2 * H / n
    a = (3.0 * v_grain / (4.0 * math.pi)) ** (1.0 / 3.0)
    rho = (R_CH - a) * np.sqrt(rng.uniform(0, 1, n))
    phi = rng.uniform(0, 2 * math.pi, n)
    x = np.column_stack([rho * np.cos(phi), rho * np.sin(phi), rng.uniform(a, H - a, n)])
    radius = a * rng.uniform(0.8, 1.2, n)
    ids = np.arange(1, n + 1, dtype=np.int64)
    # contacts between random neighbours in the id order of a sorted packing
    order = np.lexsort((x[:, 0], x[:, 1], np.floor(x[:, 2] / (4 * a))))
    i = rng.integers(0, n - 40, n_contacts)
    j = i + rng.integers(1, 40, n_contacts)
    pi, pj = ids[order[i]], ids[order[j]]
    lo, hi = np.minimum(pi, pj), np.maximum(pi, pj)
    key = np.unique(lo * (n + 1) + hi)
    while key.size < n_contacts:                     # top up duplicates
        extra = rng.integers(1, n + 1, (n_contacts - key.size, 2))
        extra = extra[extra[:, 0] != extra[:, 1]]
        key = np.unique(np.concatenate([key, extra.min(1) * (n + 1) + extra.max(1)]))
    key = key[:n_contacts]
    pid = np.column_stack([key // (n + 1), key % (n + 1)]).astype(np.int64)
    cp = 0.5 * (x[pid[:, 0] - 1] + x[pid[:, 1] - 1])
    force = rng.normal(0.0, 5.0, (n_contacts, 3))
    # the draws in the order of the former inline writer (same data)
    wid = np.sort(rng.choice(ids, n_walls, replace=False))
    mesh = rng.integers(0, 5, n_walls)
    tri = rng.integers(0, 100, n_walls)
    f_wall = rng.normal(0.0, 5.0, (n_walls, 3))
    write_snapshot(path, {
        "step": 1000, "time": 1e-3, "dt": 1e-7, "trigger": "f_jack[6]", "trigger_old": 0.0,
        "trigger_new": 1.0, "snapshot": 1,
        "particles": {"id": ids, "type": np.ones(n, dtype=np.int32), "x": x,
                      "v": np.zeros((n, 3)), "radius": radius},
        "contacts": {
            "pp": {"id": pid, "contact_point": cp, "force": force, "force_normal": force,
                   "overlap": np.full(n_contacts, 1e-5)},
            "pw": {"id": wid, "mesh": mesh, "triangle": tri,
                   "contact_point": x[wid - 1] + [a, 0, 0], "force": f_wall,
                   "force_normal": f_wall, "overlap": np.full(n_walls, 1e-5),
                   "meshes": ["side", "bottom", "top", "cone", "shaft"], "wall_fix": "walls"}}})
    return a


def reduce_once(path):
    """The timed reduction (run in a child process)."""
    from crushpost.prep import ring_edges
    from crushpost.rings import ring_fields, sphere_cell_volumes
    from crushpost.snapshot import snapshot_particle_stress
    from crushpost.snapshot import read_snapshot

    t = {}
    t0 = time.perf_counter()
    snap = read_snapshot(path)
    t["read_s"] = time.perf_counter() - t0
    t1 = time.perf_counter()
    sig = snapshot_particle_stress(snap)
    t["particle_stress_s"] = time.perf_counter() - t1
    p = snap["particles"]
    r_edges = ring_edges(R_PILE, R_CH)
    z_edges = ring_edges(0.025, H)
    t2 = time.perf_counter()
    trip = sphere_cell_volumes(p["x"], p["radius"], r_edges, z_edges)
    t["ring_volumes_s"] = time.perf_counter() - t2
    t3 = time.perf_counter()
    rf = ring_fields(sig, p["x"], p["radius"], r_edges, z_edges, triplets=trip)
    t["ring_sums_s"] = time.perf_counter() - t3
    t["total_s"] = time.perf_counter() - t0
    t["n_rings"] = int(rf["porosity"].size)
    t["n_triplets"] = int(trip[0].size)
    t["n_cut"] = int(trip[0].size - np.unique(trip[0]).size)
    t["peak_rss_MB"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    t["mean_porosity"] = float(np.mean(rf["porosity"]))
    return t


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--particles", type=int, default=500000)
    ap.add_argument("--contacts", type=int, default=2000000)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--out", default=os.path.join(HERE, "results.json"))
    ap.add_argument("--child", help=argparse.SUPPRESS)
    a = ap.parse_args(argv)
    if a.child:
        print(json.dumps(reduce_once(a.child)))
        return 0
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "jack_1000.h5")
        t = time.time()
        grain_r = write_synthetic(path, a.particles, a.contacts)
        print("synthetic snapshot: %d particles (radius %.3g mm +- 20 %%), %d contacts, %.0f MB, "
              "written in %.1f s" % (a.particles, grain_r * 1e3, a.contacts,
                                     os.path.getsize(path) / 2 ** 20, time.time() - t))
        runs = []
        for k in range(a.repeat):
            out = subprocess.run([sys.executable, os.path.abspath(__file__), "--child", path],
                                 capture_output=True, text=True, check=True)
            runs.append(json.loads(out.stdout))
            print("run %d: %s" % (k + 1, json.dumps(runs[-1])))
    keys = ("read_s", "particle_stress_s", "ring_volumes_s", "ring_sums_s", "total_s",
            "peak_rss_MB")
    med = {k: float(np.median([r[k] for r in runs])) for k in keys}
    res = {"particles": a.particles, "contacts": a.contacts, "repeats": a.repeat,
           "grain_radius_m": grain_r, "rings": runs[0]["n_rings"],
           "sphere_ring_pairs": runs[0]["n_triplets"], "median": med, "runs": runs,
           "limits": dict(LIMITS),
           "machine": {"cpus": os.cpu_count(), "python": platform.python_version(),
                       "numpy": np.__version__, "platform": platform.platform(),
                       "load_avg_1min": os.getloadavg()[0]},
           "date": time.strftime("%Y-%m-%d")}
    with open(a.out, "w") as f:
        json.dump(res, f, indent=2)
    print("median: %s" % json.dumps(med))
    bad = limit_failures(med)
    for line in bad:
        print("LIMIT MISSED: " + line)
    print("within the limits (20 s, 2 GB): %s" % (not bad))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
