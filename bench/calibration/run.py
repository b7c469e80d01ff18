#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-2.0-or-later
"""Calibration study (issue 14): triaxial element tests at the target density,
specimen size against seed-to-seed scatter, and the candidates that could put
the DEM response off the published NE34 one.

    /usr/bin/python3 bench/calibration/run.py --list
    /usr/bin/python3 bench/calibration/run.py CASE [CASE ...] [--np 2] [--work /tmp/calib_work]
    /usr/bin/python3 bench/calibration/run.py --table        # summary of every result

Each case runs examples/triaxial/run.py (or examples/oedometer/run.py) in
WORK/CASE and writes bench/calibration/results/CASE.json: the options, the
wall time, the measured numbers (summary.json of the driver, plus a peak
from the curve smoothed over 1 % axial strain) and the curves thinned to
0.25 % axial strain, for the plots of docs/studies/calibration.md. A case whose
result exists is skipped (--force runs it again), so the study runs in
restartable pieces and is committed as it comes. docs/studies/calibration.md
explains the cases and the results.
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
RESULTS = os.path.join(HERE, "results")
TRIAXIAL = os.path.join(REPO, "examples", "triaxial", "run.py")
OEDOMETER = os.path.join(REPO, "examples", "oedometer", "run.py")
sys.path.insert(0, os.path.join(REPO, "scripts"))


def _triax(W, seed, *extra, grains="unbreakable", cell="walls"):
    args = ["--grains", grains, "--W-d50", str(W), "--H-d50", str(W),
            "--packing-seed", str(seed), "--cell", cell] + list(extra)
    return {"driver": "triaxial", "args": args}


CASES = {}
# -- size study, rigid frictionless plates (the scene as it was) --
for W in (8, 12, 16):
    for s in (2024, 2025, 2026):
        CASES["walls_W%d_s%d" % (W, s)] = _triax(W, s)
# -- size study, periodic cell (no walls) --
for W in (6, 8, 10, 12, 16):
    for s in (2024, 2025, 2026, 2027, 2028):
        CASES["per_W%d_s%d" % (W, s)] = _triax(W, s, cell="periodic")


from crushpost.runner import default_binary, remove_tree  # noqa: E402


def snapshot_tree(work):
    """The drivers, decks, blocks and scripts copied into WORK/_tree_<time>_<random>
    (crushpost.runner.snapshot_tree)."""
    from crushpost.runner import snapshot_tree as copy_tree

    return copy_tree(work, ("examples/triaxial", "examples/oedometer", "inputs", "scripts/crushpost"))


# -- candidates of issue 14 item 4, on the periodic 8 d50 specimen of seed 2024
# (the same prepared specimen: each setting acts from consolidation on) --
CASES["cand_W8_s2024_rate2.5"] = _triax(8, 2024, "--rate", "2.5", cell="periodic")
CASES["cand_W8_s2024_rate10"] = _triax(8, 2024, "--rate", "10", cell="periodic")
CASES["cand_W8_s2024_D0.01"] = _triax(8, 2024, "--D-loc", "0.01", cell="periodic")
CASES["cand_W8_s2024_D0.2"] = _triax(8, 2024, "--D-loc", "0.2", cell="periodic")
CASES["cand_W8_s2024_rotation"] = _triax(8, 2024, "--rotation", cell="periodic")
CASES["cand_W8_s2024_crushable"] = _triax(8, 2024, grains="crushable_ne34", cell="periodic")
CASES["cand_W8_s2024_eps40"] = _triax(8, 2024, "--eps-a-max", "0.4", cell="periodic")
# the contact law on the reference specimen: tangential incremental from
# consolidation on (the preparation with history, as per_W8_s*; run at
# 1 rank like them, so the prepared specimen is the same)
for s in (2024, 2025, 2026):
    CASES["cand_W8_s%d_incremental" % s] = _triax(8, s, "--incremental-shear", cell="periodic")
# control: the per_W8_s* case again with the build that has the option
# (its history path is not bit-identical to the earlier binary's: the
# difference of the two is the noise floor of the comparison)
for s in (2024, 2025, 2026):
    CASES["ctl_W8_s%d" % s] = _triax(8, s, cell="periodic")
# and at the default size (per_W12_s* were run at 2 ranks: run these at 2)
CASES["cand_W12_s2024_incremental"] = _triax(12, 2024, "--incremental-shear", cell="periodic")
# the contact law: PFC's incremental tangential force instead of LIGGGHTS'
# tangential history, for the whole run (preparation included: the pair
# style cannot be swapped with its contact history at consolidation), so
# compared over seeds with the per_W* cases of the same size and seed
for W in (8, 12):
    for s in (2024, 2025, 2026):
        CASES["tinc_W%d_s%d" % (W, s)] = _triax(W, s, "--tangential-model", "incremental",
                                                cell="periodic")
# the default triaxial run (examples/triaxial/run.py with no size option:
# periodic, crushable, 12 d50, seed 2024)
CASES["default_W12_s2024_crushable"] = _triax(12, 2024, grains="crushable_ne34", cell="periodic")

# critical state: the periodic specimens of the size study sheared to 40 %
# (at 25 % they still dilate), at the default size and the largest
for W in (12, 16):
    for s in (2024, 2025, 2026):
        CASES["cs40_W%d_s%d" % (W, s)] = _triax(W, s, "--eps-a-max", "0.4", cell="periodic")

# -- oedometer (default cell R 5 d50, H 8 d50, to 30 MPa) --
for s in (2024, 2025):
    CASES["oed_crush_s%d" % s] = {"driver": "oedometer",
                                  "args": ["--packing-seed", str(s)]}
# the oedometer integration test's cell (tests/integration/test_oedometer_small.py):
# R 3.5 d50, H 6 d50, core porosity 0.40, to 5 MPa at 1.25 m/s, 1 rank
for s in (2024, 2025, 2026, 2027, 2028, 2029, 2030, 2031):
    CASES["oedsmall_crush_s%d" % s] = {"driver": "oedometer", "args": [
        "--packing-seed", str(s), "--R-d50", "3.5", "--H-d50", "6", "--n-target", "0.40",
        "--sv-max", "5e6", "--v-load", "1.25", "--thermo-every", "250", "--dump-every", "0"]}
CASES["oed_unb_s2024"] = {"driver": "oedometer",
                          "args": ["--packing-seed", "2024", "--grains", "unbreakable"]}
# a wider cell (R 7 d50, same height): does the core's void ratio depend on the cell?
for g, tag in (("crushable_ne34", "crush"), ("unbreakable", "unb")):
    CASES["oed_R7_%s_s2024" % tag] = {"driver": "oedometer",
                                      "args": ["--packing-seed", "2024", "--grains", g, "--R-d50", "7"]}


def run_case(name, np_ranks, work, binary, tree):
    spec = CASES[name]
    out = os.path.join(work, name)
    os.makedirs(out, exist_ok=True)
    driver = os.path.join(tree, os.path.relpath(TRIAXIAL if spec["driver"] == "triaxial" else OEDOMETER, REPO))
    cmd = [sys.executable, driver, "--out", out, "--np", str(np_ranks)] + spec["args"]
    if binary:
        cmd += ["--liggghts", binary]
    t0 = time.time()
    with open(os.path.join(out, "driver.txt"), "w") as f:
        rc = subprocess.call(cmd, stdout=f, stderr=subprocess.STDOUT)
    wall = time.time() - t0
    res = {"case": name, "command": " ".join(cmd[1:]).replace(tree + "/", ""),
           "driver": spec["driver"], "args": spec["args"], "np": np_ranks,
           "wall_time_s": round(wall, 1), "exit_code": rc,
           "load_average_end": os.getloadavg()}
    if rc == 0:
        with open(os.path.join(out, "summary.json")) as f:
            res["summary"] = json.load(f)
        if spec["driver"] == "triaxial":
            res.update(triaxial_extras(out))
        else:
            res.update(oedometer_extras(out))
    os.makedirs(RESULTS, exist_ok=True)
    with open(os.path.join(RESULTS, name + ".json"), "w") as f:
        json.dump(res, f, indent=1)
    return res


def smoothed_peak(ea, eta, window=0.01):
    """Largest running mean of eta over `window` of axial strain (a peak
    that a single stick-slip spike cannot make) and where it is."""
    ea, eta = np.asarray(ea, float), np.asarray(eta, float)
    best, at = -np.inf, float("nan")
    for i in range(len(ea)):
        m = (ea >= ea[i] - window / 2) & (ea <= ea[i] + window / 2)
        if ea[i] - window / 2 < ea[0] or ea[i] + window / 2 > ea[-1]:
            continue
        v = float(eta[m].mean())
        if v > best:
            best, at = v, float(ea[i])
    return best, at


def triaxial_extras(out):
    import h5py
    from crushpost import triaxial
    with h5py.File(os.path.join(out, "triaxial.h5"), "r") as h:
        g = h["shear"]
        ea, ev, eta, p = (g[k][()] for k in ("eps_a", "eps_v", "eta", "p"))
    pk, at = smoothed_peak(ea, eta)
    grid = np.arange(0.0, ea.max() + 1e-12, 0.0025)
    idx = np.searchsorted(ea, grid).clip(0, len(ea) - 1)
    return {"eta_peak_smooth": pk, "eps_a_peak_smooth": at,
            "phi_peak_smooth_deg": float(triaxial.friction_angle(pk)),
            "curve": {"eps_a": ea[idx].round(5).tolist(), "eta": eta[idx].round(4).tolist(),
                      "eps_v": ev[idx].round(5).tolist(), "p": p[idx].round(1).tolist()}}


def oedometer_extras(out):
    """The loading-unloading path thinned to 0.02 in log10(sigma_v), with
    breakage events, Br and the fraction of grains broken."""
    import h5py
    with h5py.File(os.path.join(out, "oedometer.h5"), "r") as h:
        g = h["path"]
        # e_core: the core's void ratio (decks since 2026-12-01; older logs lack it)
        cols = {k: g[k][()] for k in ("sv", "e_void", "e_core", "phase", "n_break", "Br", "Atoms")
                if k in g}
        psd = None
        if "psd" in h:
            psd = {k: h["psd"][k][()].tolist() for k in h["psd"].keys()}
    # the first row of each 0.02 step of log10(sigma_v) per phase, and the last row
    band = np.round(np.log10(np.maximum(cols["sv"], 1.0)) / 0.02)
    new = np.ones(band.size, bool)
    new[1:] = (band[1:] != band[:-1]) | (cols["phase"][1:] != cols["phase"][:-1])
    keep = np.append(np.flatnonzero(new), band.size - 1)
    from crushpost.oedometer import crushing_onset
    n0 = int(cols["Atoms"][0])
    onset = {}
    for frac in (0.01, 0.02, 0.05):
        on, first = crushing_onset(cols, n0, frac)
        onset["sv_onset_%g_MPa" % (100 * frac)] = on / 1e6
        onset["sv_first_break_MPa"] = first / 1e6
    return {"path": {k: np.asarray(v)[keep].tolist() for k, v in cols.items()}, "psd": psd,
            "crushing_onset": onset}


def table():
    rows = []
    for fn in sorted(os.listdir(RESULTS)):
        if not fn.endswith(".json"):
            continue
        with open(os.path.join(RESULTS, fn)) as f:
            r = json.load(f)
        s = r.get("summary", {})
        prep = s.get("prep", {})
        if r["driver"] != "triaxial":
            rows.append("%-28s n0 %5s  n_core %6s  n_all %6s  Z %5s  e0 %.3f e_min %.3f breaks %s Br %.3f "
                        "onset(1%%) %.2f MPa first %.2f MPa  wall %6.0f s"
                        % (r["case"], s.get("n_particles_initial"), _f(prep.get("porosity_core")),
                           _f(prep.get("porosity_all")), _f(prep.get("coordination"), 2),
                           s.get("e_start", np.nan), s.get("e_min", np.nan), s.get("n_break_events"),
                           s.get("Br_final", np.nan),
                           r.get("crushing_onset", {}).get("sv_onset_1_MPa", np.nan),
                           r.get("crushing_onset", {}).get("sv_first_break_MPa", np.nan),
                           r["wall_time_s"]))
            continue
        rows.append("%-28s n0 %5s  n_core %6s  n_all %6s  Z %5s  eta_pk %5.3f (%4.1f%%) phi_pk %4.1f  "
                    "eta_cs %5.3f phi_cs %4.1f  ev_end %6.3f  wall %6.0f s"
                    % (r["case"], s.get("n_particles_initial"), _f(prep.get("porosity_core")),
                       _f(prep.get("porosity_all")), _f(prep.get("coordination"), 2),
                       r.get("eta_peak_smooth", np.nan), 100 * r.get("eps_a_peak_smooth", np.nan),
                       r.get("phi_peak_smooth_deg", np.nan), s.get("eta_cs", np.nan),
                       s.get("phi_cs_deg", np.nan), s.get("eps_v_final", np.nan), r["wall_time_s"]))
    print("\n".join(rows))


def _f(x, nd=4):
    return "-" if x is None else ("%.*f" % (nd, x))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("cases", nargs="*")
    ap.add_argument("--np", type=int, default=2)
    ap.add_argument("--work", default="/tmp/calib_work")
    ap.add_argument("--liggghts", default=None)
    ap.add_argument("--force", action="store_true")
    ap.add_argument("--list", action="store_true")
    ap.add_argument("--table", action="store_true")
    ap.add_argument("--refresh", action="store_true",
                    help="recompute the measured numbers of the given cases from WORK/CASE "
                    "(no run)")
    a = ap.parse_args(argv)
    if a.list:
        for k, v in CASES.items():
            print(k, " ".join(v["args"]))
        return 0
    if a.table:
        table()
        return 0
    for name in a.cases:
        if name not in CASES:
            sys.exit("unknown case %s (--list)" % name)
    if a.refresh:
        for name in a.cases:
            fn = os.path.join(RESULTS, name + ".json")
            with open(fn) as f:
                r = json.load(f)
            out = os.path.join(a.work, name)
            r.update(triaxial_extras(out) if r["driver"] == "triaxial" else oedometer_extras(out))
            with open(fn, "w") as f:
                json.dump(r, f, indent=1)
            print("%s: refreshed" % name)
        return 0
    tree = None
    try:
        for name in a.cases:
            if os.path.exists(os.path.join(RESULTS, name + ".json")) and not a.force:
                print("%s: done already" % name)
                continue
            if tree is None:
                tree = snapshot_tree(a.work)
            # the binary of this checkout (the copied tree has no build/)
            r = run_case(name, a.np, a.work, a.liggghts or default_binary(), tree)
            print("%s: exit %d, %.0f s" % (name, r["exit_code"], r["wall_time_s"]), flush=True)
    finally:
        remove_tree(tree)          # the copy served this call only
    return 0


if __name__ == "__main__":
    sys.exit(main())
