#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-2.0-or-later
"""Cone pile jacked into crushable sand in a reduced calibration chamber.

    examples/cpt_demo/run.py --out results/demo [--np 2] [--mode cyclic|monotonic]
    examples/cpt_demo/run.py --out results/demo --resume     # after --restart-every K

Builds the loose packing and the meshes, runs LIGGGHTS (preparation: radius
expansion to the core porosity --n-target at 5 kPa, 1-D compression to 150 kPa,
radial servo to 76 kPa, docs/preparation.md; then jacking with the lateral wall
held), and writes into --out: summary.json (with the prepared state in
"prep"), qc_depth.png (q_c against depth with the trend q_c = a (1 - exp(-b h))
fitted to virgin penetration), breakage_map.png and breakage_map.txt (breakage
events in (h/R, r/R) relative to the tip), jack.txt, breakage_events.txt,
outside_grains.txt, log.liggghts, snapshots/prep_<step>.h5 and
snapshots/jack_<step>.h5. While LIGGGHTS runs it prints a line per preparation
stage and per phase of the pile (depth, q_c, breaks so far, elapsed time, an
estimate of the time left; crushpost.progress), and at the end the folder it
wrote into (--json: also summary.json on stdout). With --restart-every K it
writes a restart file every K chunks of jacking; --resume goes on from the
last one with the first start's options (args.json) and merges the parts'
series (crushpost.restart; docs/cpt.md "Restarting a run"). With --crush-in-prep
crushing is on from the preparation's radial servo stage (at --dt), so the
grains the prepared state overloads break before jacking; those breaks are
counted apart (summary.json n_break_events_prep, break_zones "prep"; docs/cpt.md
"Crushing during preparation"). The full analyses of the
run: crushpost report OUT (docs/report.md; scripts/demo runs it).

Exit status 1 (reasons on stderr and in summary.json "failed_checks") when a
grain is outside the chamber at the end, the mass balance is off by more
than 1e-12, the grain count differs from the count at the start of jacking
plus 13 per break while jacking, or a breakage event lies inside the pile; LIGGGHTS' own
exit status when it stops (e.g. lost atoms, or a preparation stage that
missed its target).
"""

import argparse
import json
import math
import os
import re
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(REPO, "scripts"))

import numpy as np  # noqa: E402

from crushpost.dump import read_crush_log  # noqa: E402
from crushpost.breakage import (CRUSH_READING_PRINTED, GRAIN_MODELS,  # noqa: E402
                                effective_reading, grain_model_reading)
from crushpost.chamber import hole_radius, write_chamber  # noqa: E402
from crushpost.materials import D_COMM_RATIO, RHO_GRAIN  # noqa: E402
from crushpost.meshes import PILE_APEX_ANGLE_DEG  # noqa: E402
from crushpost.packing import D50_NE34  # noqa: E402
from crushpost.pile import PHASE_PUSH, events_by_zone, inside_pile, read_jack  # noqa: E402
from crushpost.prep import (PAPER_PREPARED, prep_chunk_for, prep_cost, prep_time_step,  # noqa: E402
                            read_prep_report, snapshot_prep_summary)
from crushpost.progress import ChamberProgress, run_watched  # noqa: E402
from crushpost import restart as rs  # noqa: E402
from crushpost.runner import run_liggghts  # noqa: E402
from crushpost.snapshot import list_snapshots, read_snapshot  # noqa: E402
from crushpost.spheres import (chamber_sphere_centres, check_chamber_spheres,  # noqa: E402
                               read_sphere_series, write_sphere_block)
from crushpost.thermo import parse_log  # noqa: E402
from crushpost.trend import fit_qc_trend, qc_trend, virgin_mask  # noqa: E402

RHO = RHO_GRAIN
OUTPUT_BLOCK = {"none": "none", "particles": "vtk_dumps", "contacts": "vtk_dumps_contacts"}
SPHERE_RADIUS_D50 = 1.5            # measurement-sphere radius in d50


def build(a, out):
    c = write_chamber(out, a.N, a.R_ch, a.H_ch, a.R_pile, a.depth, n_target=a.n_target,
                      shrink=a.shrink, sector=a.sector, rng=a.packing_seed, fast=False)
    return c["n"], c["tip_z0"]


SPHERE_R_OVER_R = (2.0,)          # measurement spheres at r = 2 R from the axis ...
SPHERE_DEPTHS_R = (1.0, 2.5)       # ... at these depths below the initial apex, in R (default)


def sphere_centres(a, tip_z0):
    """Measurement-sphere centres (n, 3) beside the pile path, on a radius
    inside the simulated sector."""
    azimuth = {360: 0.0, 180: 90.0, 90: 45.0}[a.sector]
    return chamber_sphere_centres(SPHERE_R_OVER_R, [d * a.R_pile for d in a.sphere_depths],
                                  a.R_pile, tip_z0, azimuth_deg=azimuth)


def sphere_radius(a):
    return SPHERE_RADIUS_D50 * D50_NE34 * a.N


# Where the walls can be while the spheres report (jacking), as fractions of
# the chamber's height and radius: by the end of the servo phase the top wall
# had settled 0.2 % and the lateral wall closed in 0.06 % in the chamber of
# tests/integration/test_chamber_small.py (docs/measurement_spheres.md); the
# margins leave room for looser packings and longer servo phases.
TOP_SETTLE, SIDE_CLOSE = 0.03, 0.02


def check_spheres(a, tip_z0):
    """Raise ValueError if a measurement sphere would not lie wholly in the
    sand during jacking (crushpost.spheres.check_chamber_spheres); returns the
    smallest clearance (m). Spheres may touch walls and the pile: the block
    counts their contacts."""
    return check_chamber_spheres(sphere_centres(a, tip_z0), sphere_radius(a),
                                 R_side=(1.0 - SIDE_CLOSE) * a.R_ch, z_bottom=0.0,
                                 z_top=(1.0 - TOP_SETTLE) * a.H_ch, R_pile=a.R_pile,
                                 sector=a.sector)


def write_spheres(a, out, tip_z0, part=0):
    """The measurement-sphere block (docs/measurement_spheres.md); returns its
    path. Part k > 0 of a run (crushpost.restart) writes spheres.part<k>.txt."""
    check_spheres(a, tip_z0)
    name = "spheres.in" if not part else rs.part_name("spheres.in", part)
    path = os.path.join(out, name)
    write_sphere_block(path, sphere_centres(a, tip_z0), sphere_radius(a), a.jack_every * 10,
                       rs.part_files(part)["spheres"])
    return path


def run_deck(a, out, tip_z0, progress=None, part=0, restart_file=None):
    """Run the deck; part k > 0 goes on jacking from ``restart_file`` and
    writes its own series and log (crushpost.restart). Returns the wall time."""
    if a.mode == "cyclic":
        jack = ("mode cyclic v %g stroke %g v_unload %g pause %g depth %g zero_tol %g"
                % (a.v_push, a.stroke, a.v_unload, a.pause, a.depth, a.zero_tol))
    else:
        jack = "mode monotonic v %g depth %g" % (a.v_push, a.depth)
    dt_prep = a.dt_prep or prep_time_step(os.path.join(out, "grains.data"))
    v = {"inputs": os.path.join(REPO, "inputs"), "N": a.N, "R_ch": a.R_ch, "H_ch": a.H_ch,
         "R_pile": a.R_pile, "R_hole": hole_radius(a.R_pile), "sector": a.sector,
         "grain_model": a.grains, "seed": a.seed, "proc_grid": a.proc_grid,
         "dt": a.dt, "dt_prep": dt_prep, "servo_loops": a.servo_loops, "jack_args": jack,
         "n_expand_max": a.prep_loops, "n_target": a.n_target, "s_prep": a.s_prep,
         "prep_chunk": prep_chunk_for(a.R_ch, a.H_ch),
         "thermo_every": a.thermo_every,
         "jack_every": a.jack_every, "output_block": OUTPUT_BLOCK[a.vtk], "vtk_every": a.vtk_every}
    if a.d_scale_ref > 0:
        v["d_scale_ref"] = a.d_scale_ref
    if a.d_comm_ratio != D_COMM_RATIO:
        v["d_comm_ratio"] = a.d_comm_ratio
    reading = grain_model_reading(a.grains, a.crush_reading)
    if reading is not None:
        v["crush_reading"] = reading
    if a.prep_only:
        v["jacking_block"] = "none"
    if getattr(a, "crush_in_prep", False):
        # the grain model from the radial servo stage on (inputs/chamber_servo.in)
        v["crush_in_prep"] = 1
    if a.snapshots == "yes":
        v["snapshot_block"] = "snapshots_hdf5"
        v["prep_snapshot_block"] = "snapshot_prep"
    if a.restart_every > 0:
        v["restart_chunks"] = a.restart_every
    files = rs.part_files(part)
    if part:
        v.update({"resume": 1, "restart_file": restart_file, "jack_file": files["jack"],
                  "crush_events": files["events"]})
    log = files["log"]
    if a.spheres == "yes":
        v["spheres_file"] = write_spheres(a, out, tip_z0, part)
    if a.snapshots == "no" and a.spheres == "no" and a.vtk == "none":
        # nothing reads the contact computes: a scene pays only for what it uses
        v["contacts_block"] = "none"
    if progress is not None:
        # a line per preparation stage and per phase of the pile while it runs
        return run_watched(os.path.join(HERE, "in.cpt"), out, v, progress, np=a.np,
                           binary=a.liggghts, name="cpt_demo", log=log)
    return run_liggghts(os.path.join(HERE, "in.cpt"), out, v, np=a.np, binary=a.liggghts,
                        name="cpt", log=log)


# The demo stops with a non-zero exit when any of these fails (issue 5 item 6).
MASS_BALANCE_TOL = 1e-12          # relative: (M_grains + fines - M0) / M0
_OUTSIDE = re.compile(r"CHAMBER outside (\d+) grains")


def grains_outside(log_text):
    """The count printed by inputs/chamber_outside.in at the end of the run
    (grains whose centre is outside the chamber), or None."""
    found = _OUTSIDE.findall(log_text)
    return int(found[-1]) if found else None


def failed_checks(summary):
    """Messages for every check the run fails: grains outside the chamber,
    the mass balance, the atom count against the breaks, breakage events
    inside the pile."""
    bad = []
    n_out = summary.get("n_grains_outside")
    if n_out is None:
        bad.append("log.liggghts: no 'CHAMBER outside' line (inputs/chamber_outside.in did "
                   "not run): the grains outside the chamber were not counted")
    elif n_out > 0:
        bad.append("summary.json n_grains_outside = %d: grains left the chamber (their ids "
                   "and positions: outside_grains.txt)" % n_out)
    err = summary["mass_balance_rel_error"]
    if not err <= MASS_BALANCE_TOL:
        bad.append("summary.json mass_balance_rel_error = %.3g > %g: grain mass + fines "
                   "differ from the mass at the start of jacking" % (err, MASS_BALANCE_TOL))
    if summary["n_particles_final"] != summary["n_particles_expected"]:
        bad.append("summary.json n_particles_final = %d, but the start of jacking (%d) plus "
                   "13 per breakage event while jacking (%d) gives %d: atoms were lost or created"
                   % (summary["n_particles_final"], summary["n_particles_jacking_start"],
                      summary["n_break_events"] - summary.get("n_break_events_prep", 0),
                      summary["n_particles_expected"]))
    if summary.get("n_events_inside_pile", 0) > 0:
        bad.append("summary.json n_events_inside_pile = %d: breakage events with the parent's "
                   "centre inside the pile (breakage_events.txt)" % summary["n_events_inside_pile"])
    return bad


def _pile_outline(ax, h_max):
    # the pile in the (r/R, h/R) plane: 60 degree cone, shaft above
    h_cone = 1.0 / math.tan(math.radians(0.5 * PILE_APEX_ANGLE_DEG))
    top = max(h_max, h_cone) + 0.5
    ax.fill([0.0, 1.0, 1.0, 0.0], [0.0, h_cone, top, top], color="0.85", lw=0, zorder=0,
            label="pile")
    ax.plot([0.0, 1.0, 1.0], [0.0, h_cone, top], color="k", lw=0.8, zorder=1)


def prep_summary(a, out):
    """The prepared state (summary.json "prep"): porosity of the core and of
    the whole sample, [mean, sd] of the ring-averaged sigma_z, sigma_r,
    sigma_theta [kPa] and the coordination number from the snapshot of the
    prepared sample (crushpost.prep; without --snapshots the deck's own
    porosities only), the boundary stresses and the other numbers the deck
    printed, the LIGGGHTS time and steps the preparation took, and the
    source paper's values."""
    log = os.path.join(out, "log.liggghts")
    rep = read_prep_report(log)
    seconds, steps = prep_cost(log)
    done = rep.get("prepared", {})
    prep = {"prepared": "prepared" in rep, "n_target": a.n_target,
            "deck": rep, "liggghts_time_s": seconds, "steps": steps, "paper": PAPER_PREPARED}
    if done:
        prep["sv_boundary_kPa"] = done["sv"] / 1e3
        prep["sr_boundary_kPa"] = done["sr"] / 1e3
        prep["porosity_core"] = done["porosity_core"]
        prep["porosity_all"] = done["porosity_all"]
        prep["coordination"] = done["coordination"]
    snaps = list_snapshots(os.path.join(out, "snapshots", "prep"))
    if snaps and done:
        snap = read_snapshot(snaps[-1][1])
        d50 = D50_NE34 * a.N
        prep.update(snapshot_prep_summary(snap, a.R_pile, done["R"], done["H"], d50, a.sector))
        prep["snapshot"] = os.path.relpath(str(snaps[-1][1]), out)
    return prep


def postprocess(a, out, wall, n0, tip_z0, parts=None, core_s=None):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    jack = read_jack(os.path.join(out, "jack.txt"))
    if jack["z_ref"] is None:
        raise SystemExit("cpt_demo: %s has no '# z_ref' header line (a LIGGGHTS binary "
                         "built before fix jack/pile wrote it): the tip position is unknown"
                         % os.path.join(out, "jack.txt"))
    z_ref = jack["z_ref"]                 # the sand surface at the start of jacking
    depth, phase = jack["depth"], jack["phase"]
    area = math.pi * a.R_pile ** 2
    qc = jack["F_cone"] / area
    push = phase == PHASE_PUSH
    # steady state from virgin penetration only: a re-push after an unload
    # enters once it passes the previous deepest point
    virgin = virgin_mask(depth, phase) & (depth > 0)
    # over a shallow push q_c has not levelled off: bound b so that a stays a
    # finite (lower) estimate of the plateau, and say whether it levelled off
    h_max = depth[virgin].max()
    fit = fit_qc_trend(depth[virgin], qc[virgin], b_min=1.0 / h_max)
    levelled_off = bool(fit.b * h_max > 3.0)

    log_path = os.path.join(out, "log.liggghts")
    with open(log_path) as f:
        log_text = f.read()
    blocks = [b for b in parse_log(log_text) if "qc" in b]
    last = blocks[-1]
    # the fix's counters are cumulative since it was defined: with
    # --crush-in-prep the preparation's breaks and fines are in them at the
    # start of jacking (0 otherwise), and the sample's mass is the grains' at
    # the start of jacking plus those fines
    M0 = blocks[0]["M_grains"][0] + blocks[0]["fines"][0]
    n_jack0 = int(blocks[0]["Atoms"][0])
    n_prep = int(blocks[0]["n_break"][0])
    fines = last["fines"][-1]
    mass_err = abs(last["M_grains"][-1] + fines - M0) / M0
    n_events = int(last["n_break"][-1])

    fig, ax = plt.subplots(figsize=(5.5, 4.5))
    ax.plot(qc / 1e6, depth * 1e3, "-", lw=0.8, color="0.6", label="all phases")
    ax.plot(qc[push & ~virgin] / 1e6, depth[push & ~virgin] * 1e3, "x", ms=3, color="C1",
            label="re-push after an unload (not fitted)")
    ax.plot(qc[virgin] / 1e6, depth[virgin] * 1e3, ".", ms=2, color="C0",
            label="virgin penetration (fitted)")
    h = np.linspace(0, depth.max(), 200)
    ax.plot(qc_trend(h, fit.a, fit.b) / 1e6, h * 1e3, "k--",
            label="a (1 - exp(-b h)): a = %.2f MPa, b = %.3g 1/m" % (fit.a / 1e6, fit.b))
    ax.invert_yaxis()
    ax.set_xlabel("tip resistance q_c (MPa)")
    ax.set_ylabel("tip depth below the sand surface (mm)")
    ax.set_title("cone pile, %s jacking, %s" % (a.mode, a.grains))
    ax.legend(fontsize=7)
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "qc_depth.png"), dpi=120)
    plt.close(fig)

    plots = ["qc_depth.png"]
    n_inside = 0
    zones = None
    ev_path = os.path.join(out, "breakage_events.txt")
    events = read_crush_log(ev_path) if os.path.exists(ev_path) else None
    if events is not None:
        # where the events are (crushpost.pile.events_by_zone): preparation
        # (--crush-in-prep: up to the step jacking starts at), switch-on
        # (first step of jacking, when crushing is switched on there), entry,
        # the crushing zone at the cone, the shaft, beyond 5R below the tip;
        # an empty log counts 0 everywhere
        first_step = int(blocks[0]["Step"][0]) + 1 if "Step" in blocks[0] else None
        zones, hh, r, z_tip = events_by_zone(events, jack["step"], depth, z_ref, a.R_pile,
                                             first_step, getattr(a, "crush_in_prep", False))
        if not math.isfinite(zones["fraction_in_zone"]):
            zones["fraction_in_zone"] = None       # no penetration event: undefined
    if events is not None and len(events["step"]):
        inside = inside_pile(hh, r)
        n_inside = int(inside.sum())
        ev_depth = (z_ref - z_tip) * 1e3
        np.savetxt(os.path.join(out, "breakage_map.txt"),
                   np.column_stack([events["step"], hh, r, ev_depth, inside]),
                   fmt=["%d", "%.10g", "%.10g", "%.10g", "%d"],
                   header="breakage events relative to the tip (R = %g m, sand surface z_ref = "
                   "%.10g m): step h/R r/R tip_depth_mm inside_pile" % (a.R_pile, z_ref))
        fig, ax = plt.subplots(figsize=(5.2, 5))
        _pile_outline(ax, float(hh.max()))
        sc = ax.scatter(r, hh, s=8, c=ev_depth, cmap="viridis", zorder=2)
        if n_inside:
            ax.plot(r[inside], hh[inside], "rx", ms=6, zorder=3, label="inside the pile (error)")
            ax.legend(fontsize=7)
        fig.colorbar(sc, ax=ax, label="tip depth at the event (mm)")
        ax.axhline(0.0, color="k", lw=0.6, ls=":")
        ax.set_xlim(0.0, max(2.0, float(r.max()) * 1.05))
        ax.set_xlabel("r / R, distance from the pile axis (-)")
        ax.set_ylabel("h / R, height above the cone apex (-)")
        ax.set_title("%d breakage events around the tip (R = %g mm)" % (len(r), a.R_pile * 1e3))
        ax.grid(True, alpha=0.3)
        fig.tight_layout()
        fig.savefig(os.path.join(out, "breakage_map.png"), dpi=120)
        plt.close(fig)
        plots.append("breakage_map.png")

    summary = {
        "qc_steady_MPa": fit.a / 1e6, "qc_fit_b": fit.b, "qc_fit_a_err_MPa": fit.a_err / 1e6,
        "qc_fit_b_err": fit.b_err, "qc_levelled_off": levelled_off, "n_break_events": n_events,
        "fines_mass_fraction": float(fines / M0), "mass_balance_rel_error": float(mass_err),
        "n_particles_initial": int(n0), "n_particles_final": int(last["Atoms"][-1]),
        "n_break_events_prep": n_prep, "crush_in_prep": bool(getattr(a, "crush_in_prep", False)),
        "n_particles_jacking_start": n_jack0, "n_particles_expected": n_jack0 + 13 * (n_events - n_prep),
        "n_grains_outside": grains_outside(log_text), "n_events_inside_pile": n_inside,
        "qc_fit_points": int(virgin.sum()), "qc_fit_excluded_repush_points": int((push & ~virgin).sum()),
        "sand_surface_z_m": z_ref,
        "final_depth_m": float(jack["depth"].max()), "cycles": int(jack["cycle"].max()) if "cycle" in jack else 0,
        "wall_time_s": wall, "mpi_ranks": a.np,
        # a run in parts may change its rank count between them
        "core_s": wall * a.np if core_s is None else core_s, "mode": a.mode, "grains": a.grains, "N": a.N,
        "R_pile_m": a.R_pile, "R_chamber_m": a.R_ch, "H_chamber_m": a.H_ch, "sector_deg": a.sector,
        "plots": plots,
        "crush_reading": effective_reading(a.grains, getattr(a, "crush_reading", CRUSH_READING_PRINTED)),
    }
    if zones is not None:
        summary["break_zones"] = zones
    snaps = list_snapshots(os.path.join(out, "snapshots", "jack"))
    if snaps:
        summary["snapshots"] = [os.path.relpath(path, out) for _, path in snaps]
    sph = os.path.join(out, "spheres.txt")
    if os.path.exists(sph):
        centres = sphere_centres(a, tip_z0)
        steps, sigma = read_sphere_series(sph, len(centres))
        summary["spheres"] = {
            "file": "spheres.txt", "radius_m": sphere_radius(a),
            "centres_m": centres.tolist(),
            "final_step": int(steps[-1]),
            "final_mean_stress_kPa": [float(np.trace(sg) / 3e3) for sg in sigma[-1]],
            "final_sigma_zz_kPa": [float(sg[2, 2] / 1e3) for sg in sigma[-1]],
        }
    if parts:
        # a run in parts (crushpost.restart): the steps each part went on from
        summary["parts"] = [{"part": p["part"], "restart_step": p["step"],
                             "restart_file": p["restart_file"], "mpi_ranks": p.get("mpi_ranks")}
                            for p in parts]
    summary["prep"] = prep_summary(a, out)
    summary["failed_checks"] = failed_checks(summary)
    with open(os.path.join(out, "summary.json"), "w") as f:
        json.dump(summary, f, indent=2)
    return summary


ARGS_FILE = "args.json"      # the options of the first start (--resume reads them)
SCENE_FILE = "scene.json"    # grains placed, initial apex z, start time
RESUME_OWN = ("np", "proc_grid", "liggghts", "json", "resume", "out")


def resume(a):
    """Go on with the run in a.out from its last complete restart file as the
    next part (crushpost.restart); when it ends, merge the parts' series and
    post-process the whole run."""
    out = a.out
    try:
        with open(os.path.join(out, ARGS_FILE)) as f:
            first = json.load(f)
        with open(os.path.join(out, SCENE_FILE)) as f:
            scene = json.load(f)
    except (OSError, ValueError) as exc:
        raise SystemExit("cpt_demo: --resume: %s: %s (the folder of a run started by this driver "
                         "is needed)" % (out, exc))
    if os.path.exists(os.path.join(out, "summary.json")):
        raise SystemExit("cpt_demo: --resume: %s exists: the run is complete"
                         % os.path.join(out, "summary.json"))
    for key, value in first.items():
        if key not in RESUME_OWN:
            setattr(a, key, value)
    if a.prep_only:
        raise SystemExit("cpt_demo: --resume: the run in %s was started with --prep-only; only "
                         "jacking runs go on from restart files" % out)
    try:
        step, path = rs.latest_restart(out)
        parts = rs.read_parts(out)
    except rs.RestartError as exc:
        raise SystemExit("cpt_demo: --resume: %s" % exc)
    k = len(parts) + 1
    if k == 1:
        # the first run's series become part 0 (merged into the usual names at the end)
        for name in rs.SERIES + (rs.LOG,):
            if os.path.exists(os.path.join(out, name)):
                os.replace(os.path.join(out, name), os.path.join(out, rs.part_name(name, 0)))
    for stale in rs.stale_snapshots(list_snapshots(os.path.join(out, "snapshots", "jack")), step):
        os.remove(str(stale))
    parts.append({"part": k, "restart_file": os.path.relpath(path, out), "step": step,
                  "started": time.time(), "wall_s": None, "mpi_ranks": a.np})
    rs.write_parts(out, parts)
    files = rs.part_files(k)
    log = os.path.join(out, files["log"])
    print("cpt_demo: part %d of the run in %s goes on from %s (step %d); LIGGGHTS on %d MPI "
          "ranks (log: %s)" % (k, out, path, step, a.np, log), flush=True)
    progress = ChamberProgress(out, a.depth, a.R_pile, files=files)
    parts[-1]["wall_s"] = run_deck(a, out, scene["tip_z0"], progress, part=k, restart_file=path)
    rs.write_parts(out, parts)
    rs.merge_parts(out)
    # the first run (part 0) was killed: its wall time ends when its log last changed
    first_run = {"part": 0, "started": scene["started"], "wall_s": None}
    walls = rs.part_walls(out, [first_run] + parts)
    # core-seconds at each part's own rank count (the first run's from args.json)
    ranks = [first.get("np", a.np)] + [p.get("mpi_ranks") or a.np for p in parts]
    core_s = float(sum(w * n for w, n in zip(walls, ranks)))
    return finish(a, sum(walls), scene["n_particles_initial"], scene["tip_z0"], parts, core_s)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", default=os.path.join(REPO, "results", "cpt_demo"))
    p.add_argument("--np", type=int, default=2)
    p.add_argument("--mode", default="cyclic", choices=["cyclic", "monotonic"])
    p.add_argument("--grains", default="crushable_ne34", choices=list(GRAIN_MODELS),
                   help="grain model (inputs/<name>.in, docs/grain_models.md): the printed "
                   "crushable model, the same read with the peak contact pressure, or grains "
                   "that do not break")
    p.add_argument("--N", type=float, default=39.0)
    p.add_argument("--R-ch", type=float, default=0.06, help="chamber radius (m)")
    p.add_argument("--H-ch", type=float, default=0.1, help="chamber height (m)")
    p.add_argument("--R-pile", type=float, default=0.018, help="pile radius (m)")
    p.add_argument("--sector", type=int, default=360, choices=[360, 180, 90],
                   help="simulated sector of the chamber (degrees), bounded by frictionless symmetry planes")
    p.add_argument("--proc-grid", default="* * 1",
                   help="MPI processor grid (LIGGGHTS processors command), e.g. '* * 1'")
    p.add_argument("--n-target", type=float, default=0.385,
                   help="core porosity at the end of the radius expansion")
    p.add_argument("--shrink", type=float, default=0.75)
    p.add_argument("--prep-loops", type=int, default=150,
                   help="at most this many radius-expansion chunks (fast phase) and growth cycles")
    p.add_argument("--s-prep", type=float, default=5e3, help="radius-expansion stress (Pa)")
    p.add_argument("--servo-loops", type=int, default=40,
                   help="at most this many chunks of 2000 steps in each servo stage")
    p.add_argument("--servo-steps", type=int, default=None,
                   help="(old option) at most this many steps in each servo stage")
    p.add_argument("--dt-prep", type=float, default=None,
                   help="time step of the preparation (default 0.15 Rayleigh times of the smallest grain as placed)")
    p.add_argument("--prep-only", action="store_true",
                   help="stop after the preparation (no jacking); summary.json holds the prep object")
    p.add_argument("--v-push", type=float, default=1.0)
    p.add_argument("--stroke", type=float, default=0.01)
    p.add_argument("--v-unload", type=float, default=0.5)
    p.add_argument("--pause", type=float, default=5e-4)
    p.add_argument("--depth", type=float, default=0.03)
    p.add_argument("--zero-tol", type=float, default=1.0)
    p.add_argument("--dt", type=float, default=1.5e-7)
    p.add_argument("--thermo-every", type=int, default=1000)
    p.add_argument("--jack-every", type=int, default=200)
    p.add_argument("--seed", type=int, default=15485863)
    p.add_argument("--d-scale-ref", type=float, default=0.0,
                   help="density scaling of particles finer than this (m; fix crush/particle "
                   "density_scale, docs/fix_crush_particle.md); 0 = off. The time step --dt "
                   "stays as given")
    p.add_argument("--d-comm-ratio", type=float, default=D_COMM_RATIO,
                   help="comminution limit d_comm / d50 (docs/model.md §3: 0.55); grains finer than "
                   "d_comm do not break (a grain breaks when d >= d_comm)")
    p.add_argument("--crush-reading", default=CRUSH_READING_PRINTED,
                   help="keywords of the criterion reading given to fix crush/particle "
                   "(docs/fix_crush_particle.md, Criterion readings), e.g. 'pressure peak "
                   "scatter truncated f_min 0.5'; default: the printed model")
    p.add_argument("--crush-in-prep", action="store_true",
                   help="crushing (--grains) on from the preparation's radial servo stage, at "
                   "--dt, so that the grains the prepared state overloads break before jacking "
                   "(docs/cpt.md 'Crushing during preparation'); default: from the jacking on")
    p.add_argument("--packing-seed", type=int, default=2024)
    p.add_argument("--liggghts", default=None)
    p.add_argument("--snapshots", default="yes", choices=["yes", "no"],
                   help="HDF5 snapshot of particles and contacts at the end of every push and pause")
    p.add_argument("--spheres", default="yes", choices=["yes", "no"],
                   help="measurement spheres beside the pile path (spheres.txt)")
    p.add_argument("--sphere-depths", type=float, nargs="+", default=list(SPHERE_DEPTHS_R),
                   metavar="H_OVER_R",
                   help="depths of the measurement spheres below the initial cone apex, in pile "
                   "radii (default 1 2.5); each sphere must lie wholly in the sand")
    p.add_argument("--vtk", default="none", choices=["none", "particles", "contacts"],
                   help="VTK dumps for ParaView in post/: particles and meshes, or also the contact "
                        "network (crushpost report then draws them with ParaView: paraview.png)")
    p.add_argument("--vtk-every", type=int, default=20000, help="steps between VTK dumps")
    p.add_argument("--json", action="store_true",
                   help="print summary.json on stdout at the end (default: a few lines)")
    p.add_argument("--restart-every", type=int, default=0, metavar="CHUNKS",
                   help="while jacking, write a restart file every CHUNKS chunks of 10000 steps "
                   "(restart/; docs/cpt.md 'Restarting a run'); 0 = none")
    p.add_argument("--resume", action="store_true",
                   help="go on with the run in --out from its last restart file, with the "
                   "options of its first start (args.json) but --np, --proc-grid, --liggghts, --json")
    a = p.parse_args(argv)
    try:
        grain_model_reading(a.grains, a.crush_reading)
    except ValueError as e:
        p.error(str(e))
    if a.servo_steps is not None:
        a.servo_loops = max(1, -(-a.servo_steps // 2000))
    a.out = os.path.abspath(a.out)          # LIGGGHTS runs in --out: paths given to it are absolute
    if a.resume:
        return resume(a)
    os.makedirs(a.out, exist_ok=True)
    rs.clear_parts(a.out)       # an earlier run's restart files are not this run's
    print("cpt_demo: writing into %s" % a.out, flush=True)
    started = time.time()
    n0, tip_z0 = build(a, a.out)
    with open(os.path.join(a.out, ARGS_FILE), "w") as f:
        json.dump(vars(a), f, indent=2)
    with open(os.path.join(a.out, SCENE_FILE), "w") as f:
        json.dump({"n_particles_initial": int(n0), "tip_z0": float(tip_z0), "started": started}, f)
    print("cpt_demo: %d grains placed; LIGGGHTS on %d MPI ranks (log: %s)"
          % (n0, a.np, os.path.join(a.out, "log.liggghts")), flush=True)
    progress = ChamberProgress(a.out, 0.0 if a.prep_only else a.depth, a.R_pile)
    wall = run_deck(a, a.out, tip_z0, progress)
    if a.prep_only:
        summary = {"prep": prep_summary(a, a.out), "wall_time_s": wall, "mpi_ranks": a.np,
                   "crush_in_prep": bool(a.crush_in_prep),
                   "n_particles_initial": int(n0), "N": a.N, "R_chamber_m": a.R_ch,
                   "H_chamber_m": a.H_ch, "sector_deg": a.sector, "packing_seed": a.packing_seed}
        ev_path = os.path.join(a.out, "breakage_events.txt")
        if a.crush_in_prep and os.path.exists(ev_path):
            summary["n_break_events_prep"] = int(len(read_crush_log(ev_path)["step"]))
        with open(os.path.join(a.out, "summary.json"), "w") as f:
            json.dump(summary, f, indent=2)
        if a.json:
            print(json.dumps(summary, indent=2))
        print("cpt_demo: prepared sample in %s (summary.json)" % a.out)
        return 0
    return finish(a, wall, n0, tip_z0)


def finish(a, wall, n0, tip_z0, parts=None, core_s=None):
    """Post-process a run that got to its end; the exit status."""
    summary = postprocess(a, a.out, wall, n0, tip_z0, parts, core_s)
    if a.json:
        print(json.dumps(summary, indent=2))
    print("cpt_demo: q_c trend a = %.3g +- %.2g MPa (%s), %d breaks, mass balance %.2g, "
          "LIGGGHTS %.0f s" % (summary["qc_steady_MPa"], summary["qc_fit_a_err_MPa"],
                               "levelled off" if summary["qc_levelled_off"] else
                               "not levelled off: a lower estimate", summary["n_break_events"],
                               summary["mass_balance_rel_error"], wall))
    print("cpt_demo: results in %s (summary.json, %s)" % (a.out, ", ".join(summary["plots"])))
    for msg in summary["failed_checks"]:
        sys.stderr.write("cpt_demo: FAILED: %s\n" % msg)
    return 1 if summary["failed_checks"] else 0


if __name__ == "__main__":
    sys.exit(main())
