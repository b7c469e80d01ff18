#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-2.0-or-later
"""Error against run time: what each cost saving gives up (docs/studies/error-vs-runtime.md).

    python3 bench/error_vs_runtime/run.py --list            # the pieces and their state
    python3 bench/error_vs_runtime/run.py [--only NAME ...] [--budget-h H] [--np N]
    python3 bench/error_vs_runtime/run.py --table           # table + plot from results.json
    python3 bench/error_vs_runtime/run.py --carry           # pack killed pieces for git
    python3 bench/error_vs_runtime/run.py --smoke           # the whole chain on tiny scenes

One reference setting of the chamber (and of the oedometer) and variants
that change one thing at a time: the particle up-scaling N, the chamber
radius R_ch/R, the sector, the time step (a fraction of the smallest
Rayleigh time), the density-scaling size, the pile (platen) velocity and the
comminution limit, for crushable and unbreakable grains; the reference with
a second packing seed gives the scatter that separates an error from noise.

The study is restartable: each piece (one run) is run by the example drivers
(examples/cpt_demo/run.py, examples/oedometer/run.py), post-processed
(`crushpost report` for the chamber) and appended to
bench/error_vs_runtime/results.json at once, with its cost (wall time,
core-seconds, particle-steps), the machine, the commit and its numbers.
A later call skips the pieces already there (--redo to run them again), so
the study goes on in whatever pieces the time at hand allows (--budget-h
stops starting new pieces after that many hours). Commit results.json
after each call. Run folders go to results/error_vs_runtime/ (ignored by git).
A chamber piece longer than a session writes restart files while jacking;
killed, it goes on from the last one at the next call (crushpost.restart:
the merged series are those of one run; its particle-steps count the lost
work too). The run folders stay on the machine; --carry packs each killed
piece's resumable state into carry/<piece>.tar.xz here, to be committed, so
that a call on a new machine (a fresh clone) unpacks it and goes on from it;
the carry is removed when the piece's record is added. Calls may run side
by side (--np 1 each on a 2-core machine; the drivers' mpirun does not bind
ranks to cores): each takes the next piece no live call has claimed (running.pid in its folder) and adds
its record to results.json as the file is then.
"""

import argparse
import datetime
import json
import math
import os
import platform
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(REPO, "scripts"))

import numpy as np  # noqa: E402

from crushpost import restart as rs  # noqa: E402
from crushpost import study  # noqa: E402
from crushpost.materials import D50, D_COMM_RATIO, rayleigh_time  # noqa: E402
from crushpost.runner import (default_binary, log_errors, process_alive, read_pid,  # noqa: E402
                              remove_tree, snapshot_tree)
from crushpost.thermo import parse_log  # noqa: E402

# NE34 at N = 1 (docs/model.md §3; inputs/materials_ne34.in, crushable_ne34.in)
D50_1 = D50
SMALL_FRAGMENT_RATIO = 0.23         # smallest fragment over its parent (docs/model.md §5)
R_PILE = 0.018                      # pile radius of the demo and the study (m)


def time_step(N, dt_frac, d_comm_ratio=D_COMM_RATIO, d_scale_ref=0.0):
    """dt = dt_frac x the Rayleigh time of the smallest particle that can
    occur: the smallest fragment of a grain just above d_comm, or, under
    density scaling, a particle of size d_scale_ref (its scaled density
    gives every finer particle that Rayleigh time)."""
    r_min = SMALL_FRAGMENT_RATIO * 0.5 * d_comm_ratio * D50_1 * N
    return dt_frac * rayleigh_time(max(r_min, 0.5 * d_scale_ref))


# The reference: the paper's N, a 90-degree sector of a chamber 8 R wide,
# monotonic push at 1 m/s to 0.2 m in a chamber 0.3 m tall, so that b h > 3
# for the b of about 15 1/m that a first, shallower reference measured
# (H 0.2 m, depth 0.12 m: b h = 1.76, docs/studies/error-vs-runtime.md), the
# demo's time step (0.156 of the smallest Rayleigh time), no density scaling,
# the paper's comminution limit.
CHAMBER_REF = {"N": 39.0, "R_ch_over_R": 8.0, "sector": 90, "dt_frac": 0.156, "d_scale_ref_d50": 0.0,
               "v_push": 1.0, "d_comm_ratio": D_COMM_RATIO, "H_ch": 0.3, "depth": 0.2,
               "n_target": 0.385, "packing_seed": 2024}
CHAMBER_VARIANTS = [
    ("N", [30.0, 50.0]),
    ("R_ch_over_R", [6.0, 12.0]),
    ("sector", [180, 360]),
    ("dt_frac", [0.078, 0.2]),
    ("d_scale_ref_d50", [0.55, 1.0]),
    ("v_push", [0.25, 0.5]),
    ("d_comm_ratio", [0.7, 0.85]),
]
OEDO_REF = {"N": 39.0, "R_d50": 5.0, "H_d50": 8.0, "dt_frac": 0.156, "d_scale_ref_d50": 0.0,
            "v_load": 1.0, "d_comm_ratio": D_COMM_RATIO, "sv_max": 30e6, "n_target": 0.385,
            "packing_seed": 2024}
OEDO_VARIANTS = [
    ("N", [30.0, 50.0]),
    ("R_d50", [7.0]),
    ("dt_frac", [0.078, 0.2]),
    ("d_scale_ref_d50", [0.55, 1.0]),
    ("v_load", [0.25, 0.5]),
    ("d_comm_ratio", [0.7, 0.85]),
]
# the grain model does not change these, so unbreakable runs skip them
CRUSH_ONLY = {"d_comm_ratio"}
# tiny scenes only check the chain (small samples cannot reach 0.385: docs/preparation.md)
SMOKE_CHAMBER = {"N": 39.0, "R_ch_over_R": 3.3333333, "sector": 360, "H_ch": 0.1, "depth": 0.004}
SMOKE_OEDO = {"R_d50": 3.0, "H_d50": 4.0, "sv_max": 35e6, "n_target": 0.40}


# planning estimates (--list): grains per m^3 of sample at N = 39, from the
# demo chamber (3,132 grains in pi 0.06^2 0.1 m^3 at core porosity 0.385),
# steps of the preparation (the demo's: about 2e5), and the 2-rank rate of
# this machine (docs/studies/cpt-cost.md: 3.8e6 particle-steps per core-second)
GRAINS_PER_M3_N39 = 3132 / (math.pi * 0.06 ** 2 * 0.1)
PREP_STEPS = 2.0e5
RATE_PER_CORE_S = 3.8e6


def estimate(p):
    """(grains, particle-steps, core-hours) expected for a piece: the grain
    count scales with the sample volume and N^-3; the steps are the
    preparation plus the push (chamber: depth / (v dt)) or the loading
    (oedometer: about 30 % strain of the height at the platen speed)."""
    s = p["setting"]
    N = s["N"]
    d50 = D50_1 * N
    dt = setting_dt(s)
    if p["scene"] == "chamber":
        V = math.pi * (s["R_ch_over_R"] * R_PILE) ** 2 * s["H_ch"] * s["sector"] / 360.0
        steps = PREP_STEPS + s["depth"] / (s["v_push"] * dt)
    else:
        V = math.pi * (s["R_d50"] * d50) ** 2 * s["H_d50"] * d50
        steps = PREP_STEPS + 0.3 * s["H_d50"] * d50 / (s["v_load"] * dt)
    n = GRAINS_PER_M3_N39 * V * (39.0 / N) ** 3
    ps = n * steps
    return n, ps, ps / RATE_PER_CORE_S / 3600.0


def _name(scene, grains, key=None, value=None, seed=None):
    tag = "ref" if key is None else "%s=%g" % (key, value)
    if seed is not None:
        tag += "_seed%d" % seed
    return "%s_%s_%s" % (scene, "crush" if grains == "crushable_ne34" else "rigid", tag)


def pieces(smoke=False):
    """Every run of the study, in the order they are worth running: the
    references and their second seeds first, then the variants cheapest
    first within each scene."""
    out = []
    for scene, ref, variants in (("chamber", CHAMBER_REF, CHAMBER_VARIANTS),
                                 ("oedometer", OEDO_REF, OEDO_VARIANTS)):
        base = dict(ref)
        if smoke:
            base.update(SMOKE_CHAMBER if scene == "chamber" else SMOKE_OEDO)
        for grains in ("crushable_ne34", "unbreakable"):
            out.append({"name": _name(scene, grains), "scene": scene, "grains": grains,
                        "setting": dict(base), "role": "reference"})
            s2 = dict(base, packing_seed=2025)
            out.append({"name": _name(scene, grains, seed=2025), "scene": scene, "grains": grains,
                        "setting": s2, "role": "reference_seed"})
        if smoke:
            continue
        var = []
        for key, values in variants:
            for v in values:
                for grains in ("crushable_ne34", "unbreakable"):
                    if grains == "unbreakable" and key in CRUSH_ONLY:
                        continue
                    var.append({"name": _name(scene, grains, key, v), "scene": scene,
                                "grains": grains, "setting": dict(base, **{key: v}),
                                "role": "variant", "varied": key})
        out += sorted(var, key=lambda p: estimate(p)[1])     # stable: crushable first at a tie
    return out


def setting_dt(s):
    """The time step of a setting (time_step() with its N, dt_frac, d_comm
    and density-scaling size)."""
    return time_step(s["N"], s["dt_frac"], s["d_comm_ratio"], s["d_scale_ref_d50"] * D50_1 * s["N"])


# what a piece runs, copied once per call (crushpost.runner.snapshot_tree)
TREE_PARTS = ("examples/cpt_demo", "examples/oedometer", "inputs", "scripts/crushpost")


def driver_args(p, out, np_, example, tree=REPO):
    """The command line of an example driver for a piece: the options the
    chamber and the oedometer drivers share."""
    s = p["setting"]
    return [sys.executable, os.path.join(tree, "examples", example, "run.py"), "--out", out,
            "--np", str(np_), "--grains", p["grains"], "--N", repr(s["N"]),
            "--dt", repr(setting_dt(s)), "--d-scale-ref", repr(s["d_scale_ref_d50"] * D50_1 * s["N"]),
            "--d-comm-ratio", repr(s["d_comm_ratio"]), "--packing-seed", str(s["packing_seed"]),
            "--n-target", repr(s["n_target"])] + (
                # a criterion reading (bench/criterion_readings): the printed one otherwise
                ["--crush-reading", s["crush_reading"]] if s.get("crush_reading") else [])


def chamber_args(p, out, np_, tree=REPO):
    s = p["setting"]
    return driver_args(p, out, np_, "cpt_demo", tree) + [
        "--mode", "monotonic", "--R-ch", repr(s["R_ch_over_R"] * R_PILE), "--H-ch", repr(s["H_ch"]),
        "--R-pile", repr(R_PILE), "--sector", str(s["sector"]), "--v-push", repr(s["v_push"]),
        "--depth", repr(s["depth"]), "--snapshots", "yes", "--spheres", "no"] + (
            # crushing during the preparation (bench/criterion_readings)
            ["--crush-in-prep"] if s.get("crush_in_prep") else [])


def oedometer_args(p, out, np_, tree=REPO):
    s = p["setting"]
    return driver_args(p, out, np_, "oedometer", tree) + [
        "--R-d50", repr(s["R_d50"]), "--H-d50", repr(s["H_d50"]), "--v-load", repr(s["v_load"]),
        "--sv-max", repr(s["sv_max"]), "--dump-every", str(s.get("dump_every", 0))]


TEST_COLUMNS = ("qc", "e_void")     # thermo columns of the jacking / loading runs


def log_particle_steps(log_path):
    """(all, test) particle-steps of a run: every thermo block, and only the
    blocks of the test itself (jacking or loading, not the preparation,
    which a user can run once and reuse for several settings)."""
    with open(log_path, errors="replace") as f:
        blocks = [b for b in parse_log(f.read()) if "Step" in b and "Atoms" in b]
    every = sum(study.particle_steps(b["Step"], b["Atoms"]) for b in blocks)
    test = sum(study.particle_steps(b["Step"], b["Atoms"]) for b in blocks
               if any(c in b for c in TEST_COLUMNS))
    return every, test


# chamber pieces write a restart file every this many chunks of 10000 steps
# (about 10 minutes of the reference at 2 ranks); a piece whose folder holds
# one and no summary.json goes on from it (crushpost.restart)
RESTART_CHUNKS = 10


def resumable(out):
    return (os.path.exists(os.path.join(out, "restart", "latest.txt"))
            and not os.path.exists(os.path.join(out, "summary.json")))


CLAIM = "running.pid"        # in a piece's folder while a call runs it
CARRY = os.path.join(HERE, "carry")   # killed pieces' resumable state, in git


def carry_path(name, carry_dir=CARRY):
    return os.path.join(carry_dir, name + ".tar.xz")


def carry_out(root, names, carry_dir=CARRY):
    """Pack every killed piece among ``names`` (its folder in ``root`` is
    resumable) into carry/<piece>.tar.xz; [(name, restart step, MB)]."""
    packed = []
    for name in names:
        out = os.path.join(root, name)
        if not resumable(out):
            continue
        path = carry_path(name, carry_dir)
        step = rs.pack_carry(out, path)
        packed.append((name, step, os.path.getsize(path) / 1e6))
    return packed


def carry_in(out, name, carry_dir=CARRY):
    """Lay a carried piece out in ``out`` when the folder has no run of its
    own to go on from; the restart step, or None if nothing was unpacked."""
    path = carry_path(name, carry_dir)
    if not os.path.exists(path) or rs.holds_run(out):
        return None
    return rs.unpack_carry(path, out)


def claim(out):
    """Mark the piece in ``out`` as run by this process; False if a live
    process has it already (two calls side by side take different pieces)."""
    os.makedirs(out, exist_ok=True)
    path = os.path.join(out, CLAIM)
    pid = read_pid(path)             # None: no claim
    if pid is not None and pid != os.getpid() and process_alive(pid):
        return False                 # (a dead process's claim is taken over)
    with open(path, "w") as f:
        f.write("%d\n" % os.getpid())
    return True


def stability_alarm(log):
    """The message of fix check/stability (docs/stability.md) if the run
    stopped on it, else None."""
    alarms = [e for e in log_errors(log) if e.startswith("fix check/stability: unstable")]
    return alarms[-1] if alarms else None


def run_piece(p, root, np_, liggghts=None, tree=REPO):
    out = os.path.join(root, p["name"])
    os.makedirs(out, exist_ok=True)
    cmd = (chamber_args if p["scene"] == "chamber" else oedometer_args)(p, out, np_, tree)
    if p["scene"] == "chamber":
        cmd += ["--restart-every", str(RESTART_CHUNKS)]
        if resumable(out):
            cmd += ["--resume"]
    if liggghts:
        cmd += ["--liggghts", liggghts]
    t0 = time.time()
    with open(os.path.join(out, "driver.txt"), "w") as f:
        rc = subprocess.call(cmd, stdout=f, stderr=subprocess.STDOUT)
    wall = time.time() - t0
    rec = {"name": p["name"], "scene": p["scene"], "grains": p["grains"], "role": p["role"],
           "varied": p.get("varied"), "setting": p["setting"],
           "command": [c.replace(tree + os.sep, "") for c in cmd[1:]],
           "exit_status": rc, "wall_s": wall, "mpi_ranks": np_, "core_s": wall * np_,
           "date": datetime.datetime.now().isoformat(timespec="seconds"),
           # the machine's load at the end: wall times under load are not costs
           "loadavg_1_5_15": list(os.getloadavg()),
           "machine": "%s, %d cores" % (platform.processor() or platform.machine(), os.cpu_count()),
           "commit": head_commit()}
    log = os.path.join(out, "log.liggghts")
    if os.path.exists(log):
        rec["particle_steps"], rec["particle_steps_test"] = log_particle_steps(log)
    summ_path = os.path.join(out, "summary.json")
    unstable = stability_alarm(log) if rc != 0 else None
    if unstable:
        # the setting's own result (the same run stops the same way), not a
        # failure to retry: recorded as done, listed apart in the table
        rec["unstable"] = unstable
        return rec
    if rc != 0 or not os.path.exists(summ_path):
        rec["error"] = "driver exit status %d (see %s)" % (rc, os.path.join(out, "driver.txt"))
        return rec
    with open(summ_path) as f:
        summ = json.load(f)
    if summ.get("parts"):
        # a run in parts: the wall time of all of them (the killed ones until
        # their logs last changed), core-seconds at each part's rank count
        rec["wall_s"] = summ["wall_time_s"]
        rec["core_s"] = summ.get("core_s", summ["wall_time_s"] * np_)
        rec["parts"] = summ["parts"]
    rec["n_particles_initial"] = summ.get("n_particles_initial")
    if p["scene"] == "chamber":
        metrics, error = chamber_report_metrics(out, summ, tree)
        if error:
            rec["error"] = error
            return rec
        rec["metrics"] = metrics
    else:
        rec["metrics"] = study.oedometer_metrics(summ)
    return rec


def head_commit():
    """The short hash of the repository's HEAD, the commit a record was made at."""
    return subprocess.run(["git", "-C", REPO, "rev-parse", "--short", "HEAD"],
                          capture_output=True, text=True).stdout.strip()


def chamber_report_metrics(out, summ, tree=REPO):
    """`crushpost report` of the chamber run in ``out`` (into out/report) and
    the study's numbers from it (crushpost.study.chamber_metrics): (metrics,
    None), or (None, the error) when the report wrote no fields.h5."""
    rep = os.path.join(out, "report")
    rc = subprocess.call([sys.executable, "-m", "crushpost", "report", out, "--out", rep,
                          "--profile-h", "0.5"], stdout=subprocess.DEVNULL,
                         stderr=subprocess.DEVNULL,
                         env=dict(os.environ, PYTHONPATH=os.path.join(tree, "scripts")))
    fields = os.path.join(rep, "fields.h5")
    if not os.path.exists(fields):
        return None, "crushpost report exit status %d, no %s" % (rc, fields)
    return study.chamber_metrics(summ, fields), None


def load(path):
    if os.path.exists(path):
        with open(path) as f:
            return json.load(f)
    return {"runs": {}}


def save(path, data):
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        json.dump(data, f, indent=1)
    os.replace(tmp, path)


CHAMBER_METRICS = ["qc_steady_MPa", "Br_band_1_2", "sigma_r_2R_kPa"]
# the core's void ratio first (the Pareto front's metric): the whole cell's
# depends on the cell's width through its loose fringe at the walls
OEDO_METRICS = ["e_core_at_10MPa", "e_core_at_30MPa", "Br_at_30MPa", "e_at_10MPa", "e_at_30MPa"]


def cost_core_h(run):
    """A run's cost: its particle-steps at the measured rate, in core-hours
    (deterministic; the wall times here carry the load of the shared cores)."""
    return (run.get("particle_steps") or np.nan) / RATE_PER_CORE_S / 3600.0


def levelled_off(run):
    """False for a chamber run whose q_c fit did not level off (b h <= 3 at
    the final depth): its fitted asymptote is not a steady q_c (docs/
    docs/studies/error-vs-runtime.md, "The first, shallower reference"), so its q_c error
    is flagged and kept off the Pareto front. True for everything else."""
    return run["scene"] != "chamber" or run["metrics"].get("qc_levelled_off") is not False


def metric_values(run, metrics):
    """A run's recorded metrics in the given order, NaN where not recorded."""
    return [np.nan if run["metrics"].get(m) is None else run["metrics"][m] for m in metrics]


def table(data):
    """Rows of the study, per scene and grain model: cost, and the error of
    each run against the reference run with the same packing seed (every
    variant uses the reference's seed, so the packing is the same and the
    difference is the setting's), the reference's seed-to-seed scatter,
    noise flags (|error| inside that scatter), and the Pareto front
    (cost against |error| of the scene's first metric)."""
    runs = [r for r in data["runs"].values() if "metrics" in r]
    rows = []
    for scene, metrics in (("chamber", CHAMBER_METRICS), ("oedometer", OEDO_METRICS)):
        for grains in ("crushable_ne34", "unbreakable"):
            sel = [r for r in runs if r["scene"] == scene and r["grains"] == grains]
            refs = [r for r in sel if r["role"] in ("reference", "reference_seed")]
            ref = [r for r in sel if r["role"] == "reference"]
            if not ref:
                continue

            ref_vals = np.array([metric_values(r, metrics) for r in refs], float)
            scatter = study.seed_scatter(ref_vals) if len(refs) > 1 else np.full(len(metrics), np.nan)
            vals = np.array([metric_values(r, metrics) for r in sel], float)
            same_seed = {r["setting"]["packing_seed"]: v for r, v in zip(refs, ref_vals)}
            ref0 = ref_vals[refs.index(ref[0])]
            # a variant against the reference of its own seed; the second
            # seed's reference against the first (that error is the scatter)
            base = np.array([ref0 if r["role"] == "reference_seed" else
                             same_seed.get(r["setting"]["packing_seed"], np.full(len(metrics), np.nan))
                             for r in sel])
            err = study.relative_error(vals, base)
            cost_h = np.array([cost_core_h(r) for r in sel])
            lev = np.array([levelled_off(r) for r in sel])
            on_front = np.array([r["role"] != "reference_seed" for r in sel]) & lev
            front = study.pareto_front(cost_h, np.where(on_front, err[:, 0], np.nan))
            for k, r in enumerate(sel):
                rows.append({"name": r["name"], "scene": scene, "grains": grains, "role": r["role"],
                             "qc_levelled_off": bool(lev[k]),
                             "varied": r.get("varied"), "core_h": cost_h[k],
                             "core_h_measured": r["core_s"] / 3600.0,
                             "particle_steps": r.get("particle_steps"),
                             "particle_steps_test": r.get("particle_steps_test"),
                             "values": dict(zip(metrics, vals[k].tolist())),
                             "error": dict(zip(metrics, err[k].tolist())),
                             "noise": dict(zip(metrics, study.is_noise(err[k], scatter).tolist())),
                             "reference_scatter": dict(zip(metrics, scatter.tolist())),
                             "pareto": bool(front[k])})
    return rows


def qc_ratio(data):
    """The ratio of unbreakable to crushable steady q_c for every chamber
    setting run with both grain models (issue 11), its error against the
    reference's ratio (same packing seed), the scatter of the ratio over the
    reference's two seeds and the noise flags."""
    runs = [r for r in data["runs"].values()
            if "metrics" in r and r["scene"] == "chamber"]

    def side(grains):
        sel = [r for r in runs if r["grains"] == grains]
        return ([r["name"].split("_", 2)[2] for r in sel],
                [np.nan if r["metrics"].get("qc_steady_MPa") is None else r["metrics"]["qc_steady_MPa"]
                 for r in sel])

    keys, ratio = study.paired_ratio(*side("unbreakable"), *side("crushable_ne34"))
    # a ratio of two asymptotes is steady only when both pushes levelled off
    not_levelled = {r["name"].split("_", 2)[2] for r in runs if not levelled_off(r)}
    if "ref" not in keys:
        return []
    ref = ratio[keys.index("ref")]
    seeds = [ratio[keys.index(k)] for k in keys if k == "ref" or k.startswith("ref_seed")]
    scatter = float(study.seed_scatter(np.array(seeds))) if len(seeds) > 1 else float("nan")
    err = study.relative_error(ratio, np.full(ratio.shape, ref))
    noise = study.is_noise(err, np.full(ratio.shape, scatter))
    return [{"setting": k, "ratio": float(ratio[i]), "error": float(err[i]),
             "noise": bool(noise[i]), "reference_scatter": scatter,
             "qc_levelled_off": k not in not_levelled} for i, k in enumerate(keys)]


# chamber runs of the reference setting that repeat its trajectory with a
# perturbation: the second seed, and the time steps 0.078 and 0.2 T_R,
# which land on either side of the reference's 0.156 with no trend in any
# number (docs/studies/error-vs-runtime.md, "Run-to-run spread"). Together they
# measure how far one run lands from another better than two seeds do.
SPREAD_SETTINGS = ("ref", "ref_seed2025", "dt_frac=0.078", "dt_frac=0.2")


def spread(data, settings=SPREAD_SETTINGS):
    """Pooled run-to-run spread of the chamber's reference setting, per
    grain model (mean and relative sample standard deviation of each metric
    over the runs of `settings`) and for the unbreakable/crushable q_c
    ratio; and every chamber run's error against that pooled mean, flagged
    'noise' when inside two standard deviations."""
    runs = [r for r in data["runs"].values() if "metrics" in r and r["scene"] == "chamber"]
    out = {"settings": list(settings), "models": {}, "runs": []}
    for grains in ("crushable_ne34", "unbreakable"):
        sel = [r for r in runs if r["grains"] == grains]
        rep = [r for r in sel if r["name"].split("_", 2)[2] in settings]
        if len(rep) < 2:
            continue
        mean, rel = study.replicate_spread(np.array([metric_values(r, CHAMBER_METRICS) for r in rep], float))
        out["models"][grains] = {"runs": [r["name"] for r in rep],
                                 "mean": dict(zip(CHAMBER_METRICS, mean.tolist())),
                                 "rel_std": dict(zip(CHAMBER_METRICS, rel.tolist()))}
        vals = np.array([metric_values(r, CHAMBER_METRICS) for r in sel], float)
        err = study.relative_error(vals, np.broadcast_to(mean, vals.shape))
        cost_h = np.array([cost_core_h(r) for r in sel])
        # the second seed repeats the reference's setting: not a setting of its own
        lev = np.array([levelled_off(r) for r in sel])
        on_front = np.array([r["role"] != "reference_seed" for r in sel]) & lev
        front = study.pareto_front(cost_h, np.where(on_front, err[:, 0], np.nan))
        for k, r in enumerate(sel):
            out["runs"].append({"name": r["name"], "grains": grains, "core_h": float(cost_h[k]),
                                "qc_levelled_off": bool(lev[k]),
                                "error": dict(zip(CHAMBER_METRICS, err[k].tolist())),
                                "noise": dict(zip(CHAMBER_METRICS,
                                                  study.is_noise(err[k], 2 * rel).tolist())),
                                "pareto": bool(front[k])})
    ratio_rows = qc_ratio(data)
    ratio = {r["setting"]: r["ratio"] for r in ratio_rows}
    rr = [ratio[k] for k in settings if k in ratio]
    if len(rr) >= 2:
        m, s = study.replicate_spread(np.array(rr))
        out["qc_ratio"] = {"settings": [k for k in settings if k in ratio],
                           "mean": float(m), "rel_std": float(s),
                           "error": {k: float(study.relative_error(v, m)) for k, v in ratio.items()},
                           "not_levelled_off": [r["setting"] for r in ratio_rows if not r["qc_levelled_off"]]}
    return out


COLOUR = {"crushable_ne34": "C0", "unbreakable": "C1"}
NOT_LEVELLED = ", not levelled off"


def _plot_panel(ax, points, levels, ylabel, title):
    """|error| against cost on log axes. points: (name, grains, core_h,
    error, on the Pareto front); levels: (grains, |error| to dash, label)."""
    for name, grains, core_h, e, pareto in points:
        if not np.isfinite(e):
            continue
        y = max(abs(e), 1e-4)
        ax.loglog(core_h, y, "o" if pareto else "x", color=COLOUR[grains])
        ax.annotate(name.split("_", 2)[-1], (core_h, y), fontsize=6)
    for grains, y, label in levels:
        if np.isfinite(y):
            ax.axhline(y, color=COLOUR[grains], ls="--", lw=0.8, label=label)
    ax.set_xlabel("cost (core-hours at %.2g particle-steps per core-second)" % RATE_PER_CORE_S)
    ax.set_ylabel(ylabel)
    ax.set_title("%s: o Pareto front, x dominated; blue crushable, orange unbreakable" % title,
                 fontsize=8)
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=7)
    ax.grid(True, which="both", alpha=0.3)


def write_table(rows, path_md, path_png, ratio_rows=(), unstable=(), spread_rows=None):
    lines = []
    for scene, metrics in (("chamber", CHAMBER_METRICS), ("oedometer", OEDO_METRICS)):
        sel = [r for r in rows if r["scene"] == scene]
        if not sel:
            continue
        lines += ["", "%s: value (error against the reference of the same seed, %%; "
                  "'noise': inside the reference's seed scatter)" % scene, "",
                  "| run | core-hours at the measured rate | measured core-hours | particle-steps "
                  "(all / test only) | "
                  + " | ".join(metrics) + " | Pareto |",
                  "|---" * (len(metrics) + 5) + "|"]
        scat = {}
        for r in sel:
            scat[r["grains"]] = r["reference_scatter"]
            cells = []
            for m in metrics:
                v, e = r["values"][m], r["error"][m]
                cells.append("%.4g (%s%s%s)" % (v, "%+.1f" % (100 * e) if np.isfinite(e) else "-",
                                                ", noise" if r["noise"][m] else "",
                                                NOT_LEVELLED if m == "qc_steady_MPa"
                                                and not r.get("qc_levelled_off", True) else ""))
            lines.append("| %s | %.3g | %.3g | %.3g / %.3g | %s | %s |" % (
                r["name"], r["core_h"], r["core_h_measured"], r["particle_steps"] or 0,
                r["particle_steps_test"] or 0,
                " | ".join(cells), "yes" if r["pareto"] else ""))
        for g, sc in scat.items():
            lines.append("")
            lines.append("%s %s reference scatter (half the seed range over the mean): %s" % (
                scene, g, ", ".join("%s %.2g %%" % (m, 100 * v) for m, v in sc.items())))
        if scene == "chamber" and "unbreakable" in scat:
            lines += ["", "Br_band_1_2 of unbreakable runs is the measure's floor, not breakage: the "
                      "band's grains now against those in it at the start, as the pile pushes grains "
                      "from band to band (docs/studies/error-vs-runtime.md); its errors are not read."]
    if unstable:
        lines += ["", "Runs stopped by the blow-up detector (fix check/stability, docs/stability.md):", ""]
        lines += ["* %s: %s" % (name, msg) for name, msg in unstable]
    if ratio_rows:
        lines += ["", "chamber: unbreakable / crushable steady q_c, per setting run with both "
                  "(error against the reference's ratio, %%; 'noise': inside the ratio's seed "
                  "scatter, %.2g %%)" % (100 * ratio_rows[0]["reference_scatter"]), "",
                  "| setting | q_c ratio | error |", "|---|---|---|"]
        for r in ratio_rows:
            lines.append("| %s | %.3f | %s%s%s |" % (
                r["setting"], r["ratio"], "%+.1f" % (100 * r["error"]) if np.isfinite(r["error"]) else "-",
                ", noise" if r["noise"] else "", "" if r.get("qc_levelled_off", True) else NOT_LEVELLED))
    if spread_rows and spread_rows["models"]:
        sp = spread_rows
        lines += ["", "chamber: run-to-run spread of the reference setting, pooled over %s "
                  "(mean, and sample standard deviation over the mean)" % ", ".join(sp["settings"]), "",
                  "| grains | runs | " + " | ".join(CHAMBER_METRICS) + " |",
                  "|---" * (len(CHAMBER_METRICS) + 2) + "|"]
        for g, m in sp["models"].items():
            lines.append("| %s | %d | %s |" % (g, len(m["runs"]), " | ".join(
                "%.4g (%.2g %%)" % (m["mean"][k], 100 * m["rel_std"][k]) for k in CHAMBER_METRICS)))
        if "qc_ratio" in sp:
            q = sp["qc_ratio"]
            lines += ["", "unbreakable / crushable steady q_c over %s: %.3f (%.2g %%)" % (
                ", ".join(q["settings"]), q["mean"], 100 * q["rel_std"])]
        lines += ["", "chamber: every run against the pooled mean (%; 'noise': inside two standard "
                  "deviations; Pareto: cost against |error in q_c|)", "",
                  "| run | " + " | ".join(CHAMBER_METRICS) + " | q_c ratio | Pareto |",
                  "|---" * (len(CHAMBER_METRICS) + 3) + "|"]
        qerr = sp.get("qc_ratio", {}).get("error", {})
        qsd = sp.get("qc_ratio", {}).get("rel_std", np.nan)
        q_unsteady = sp.get("qc_ratio", {}).get("not_levelled_off", [])
        for r in sp["runs"]:
            key = r["name"].split("_", 2)[2]
            qe = qerr.get(key, np.nan) if r["grains"] == "crushable_ne34" else np.nan
            lines.append("| %s | %s | %s | %s |" % (r["name"], " | ".join(
                ("%+.1f%s%s" % (100 * r["error"][k], ", noise" if r["noise"][k] else "",
                                NOT_LEVELLED if k == "qc_steady_MPa" and not r.get("qc_levelled_off", True)
                                else ""))
                if np.isfinite(r["error"][k]) else "-" for k in CHAMBER_METRICS),
                ("%+.1f%s%s" % (100 * qe, ", noise" if abs(qe) <= 2 * qsd else "",
                                NOT_LEVELLED if key in q_unsteady else "")) if np.isfinite(qe) else "",
                "yes" if r["pareto"] else ""))
    with open(path_md, "w") as f:
        f.write("\n".join(lines).lstrip() + "\n")
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    scenes = [s for s in ("chamber", "oedometer") if any(r["scene"] == s for r in rows)]
    fig, axes = plt.subplots(1, len(scenes), figsize=(6.5 * len(scenes), 4.8), squeeze=False)
    for ax, scene in zip(axes[0], scenes):
        sel = [r for r in rows if r["scene"] == scene]
        m0 = (CHAMBER_METRICS if scene == "chamber" else OEDO_METRICS)[0]
        if scene == "chamber" and spread_rows and spread_rows["models"]:
            # the chamber against the pooled mean of the reference setting's runs
            sp = spread_rows
            points = [(r["name"], r["grains"], r["core_h"], r["error"][m0], r["pareto"])
                      for r in sp["runs"]]
            levels = [(g, 2 * m["rel_std"][m0], "%s: 2 sd of the reference setting's %d runs"
                       % (g, len(m["runs"]))) for g, m in sp["models"].items()]
            ylabel = "|error of %s against the pooled mean| (-)" % m0
        else:
            points = [(r["name"], r["grains"], r["core_h"], r["error"][m0], r["pareto"])
                      for r in sel if r["role"] != "reference"]
            scat = {r["grains"]: r["reference_scatter"][m0] for r in sel}
            levels = [(g, v, "%s: reference seed scatter" % g) for g, v in scat.items()]
            ylabel = "|relative error| of %s (-)" % m0
        _plot_panel(ax, points, levels, ylabel, scene)
    fig.tight_layout()
    fig.savefig(path_png, dpi=120)
    plt.close(fig)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--list", action="store_true", help="list the pieces and whether they are done")
    ap.add_argument("--only", nargs="+", default=None, help="run only these pieces (names from --list)")
    ap.add_argument("--redo", action="store_true", help="run pieces again that are in results.json")
    ap.add_argument("--budget-h", type=float, default=None,
                    help="start no new piece after this many hours")
    ap.add_argument("--np", type=int, default=2, help="MPI ranks per run")
    ap.add_argument("--liggghts", default=None, help="LIGGGHTS binary (default build/liggghts)")
    ap.add_argument("--smoke", action="store_true",
                    help="the references on tiny scenes (minutes): checks the chain, writes "
                    "results_smoke.json")
    ap.add_argument("--table", action="store_true",
                    help="write table.md and error_vs_cost.png from the results")
    ap.add_argument("--recost", action="store_true",
                    help="recount the particle-steps of the recorded runs from their logs (if still there)")
    ap.add_argument("--carry", action="store_true",
                    help="pack every killed piece's resumable state into carry/<piece>.tar.xz "
                    "(commit it: a call on a new machine goes on from it)")
    ap.add_argument("--results", default=None, help="results file (default results.json here)")
    ap.add_argument("--work", default=os.path.join(REPO, "results", "error_vs_runtime"))
    a = ap.parse_args(argv)
    path = a.results or os.path.join(HERE, "results_smoke.json" if a.smoke else "results.json")
    data = load(path)
    todo = pieces(smoke=a.smoke)
    if a.list:
        print("%-40s %8s %9s %8s  %s" % ("piece", "grains", "p-steps", "core-h", "state (estimates: see estimate())"))
        tot = 0.0
        for p in todo:
            r = data["runs"].get(p["name"])
            n, ps, ch = estimate(p)
            carried = os.path.exists(carry_path(p["name"]))
            state = (("carried from step %d" % rs.carry_step(carry_path(p["name"])))
                     if r is None and carried else
                     "-" if r is None else "error" if "error" in r else
                     "unstable (fix check/stability)" if "unstable" in r else
                     "done %.2f core-h" % (r["core_s"] / 3600))
            tot += ch if r is None or "error" in r else 0.0
            print("%-40s %8.0f %9.2e %8.2f  %s" % (p["name"], n, ps, ch, state))
        print("left: about %.0f core-hours" % tot)
        return 0
    if a.carry:
        root = a.work + ("_smoke" if a.smoke else "")
        packed = carry_out(root, [p["name"] for p in todo])
        for name, step, mb in packed:
            print("%s: restart step %d -> %s (%.1f MB)" % (name, step, carry_path(name), mb))
        if not packed:
            print("no killed piece with a restart file under %s" % root)
        return 0
    if a.recost:
        for name, r in data["runs"].items():
            log = os.path.join(a.work + ("_smoke" if a.smoke else ""), name, "log.liggghts")
            if os.path.exists(log):
                r["particle_steps"], r["particle_steps_test"] = log_particle_steps(log)
        save(path, data)
    if a.table:
        rows = table(data)
        ratio_rows = qc_ratio(data)
        base = os.path.splitext(path)[0]
        unstable = sorted((n, r["unstable"]) for n, r in data["runs"].items() if "unstable" in r)
        spread_rows = spread(data)
        write_table(rows, base + "_table.md", base + "_error_vs_cost.png", ratio_rows, unstable,
                    spread_rows)
        with open(base + "_table.json", "w") as f:
            json.dump({"runs": rows, "qc_ratio_unbreakable_over_crushable": ratio_rows,
                       "unstable": dict(unstable), "chamber_spread": spread_rows}, f, indent=1)
        print("wrote %s_table.md, _table.json, _error_vs_cost.png (%d runs)" % (base, len(rows)))
        return 0
    if a.only:
        known = {p["name"] for p in todo}
        bad = [n for n in a.only if n not in known]
        if bad:
            ap.error("unknown piece(s) %s; --list shows the names" % ", ".join(bad))
        todo = [p for p in todo if p["name"] in a.only]
    t_start = time.time()
    root = a.work + ("_smoke" if a.smoke else "")
    tree = None
    try:
        for p in todo:
            data = load(path)           # another call may have run it meanwhile
            if p["name"] in data["runs"] and not a.redo and "error" not in data["runs"][p["name"]]:
                continue
            if a.budget_h is not None and time.time() - t_start > a.budget_h * 3600:
                print("budget of %.2f h spent; stopping before %s" % (a.budget_h, p["name"]))
                break
            if not claim(os.path.join(root, p["name"])):
                print("%s: another call is running it; next" % p["name"], flush=True)
                continue
            step = carry_in(os.path.join(root, p["name"]), p["name"])
            if step is not None:
                print("%s: unpacked %s (restart step %d)" % (p["name"], carry_path(p["name"]), step),
                      flush=True)
            print("running %s ..." % p["name"], flush=True)
            if tree is None:
                tree = snapshot_tree(root, TREE_PARTS)
            try:
                rec = run_piece(p, root, a.np, a.liggghts or default_binary(), tree)
            finally:
                os.remove(os.path.join(root, p["name"], CLAIM))
            # read the file again: another call may have added its pieces meanwhile
            data = load(path)
            data["runs"][p["name"]] = rec
            save(path, data)
            print("  %s: %.0f s, %s" % (p["name"], rec["wall_s"], rec.get("error") or rec.get("metrics")),
                  flush=True)
            if "error" not in rec and os.path.exists(carry_path(p["name"])) and not a.smoke:
                # the record holds the result now: the carried state is spent
                os.remove(carry_path(p["name"]))
                print("  removed %s (commit its removal with results.json)" % carry_path(p["name"]),
                      flush=True)
    finally:
        remove_tree(tree)          # the copy served this call only
    return 0


if __name__ == "__main__":
    sys.exit(main())
