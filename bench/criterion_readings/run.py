#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-2.0-or-later
"""Criterion readings: which convention of the breakage criterion puts the
crushing where the paper found it (docs/studies/criterion-readings.md).

    python3 bench/criterion_readings/run.py --list           # pieces and their state
    python3 bench/criterion_readings/run.py [--only NAME ...] [--scene S ...] [--np N]
    python3 bench/criterion_readings/run.py --table          # results_table.md + maps

Each reading (READINGS: keywords of fix crush/particle, docs/fix_crush_particle.md
"Criterion readings") is run on
- the oedometer of the error-vs-runtime study (its reference setting, to
  30 MPa): e against log sigma_v, the stress at which 1 % of the grains have
  broken, Br at 10 and 30 MPa;
- the triaxial example (examples/triaxial/run.py, its defaults): phi_peak, phi_cs;
- the study's reference chamber (crushable, packing seeds 2024 and 2025):
  steady q_c, its ratio to the unbreakable reference of the error-vs-runtime
  study (bench/error_vs_runtime/results.json, pooled over its seeds), events
  by zone (crushpost.pile.break_zones) and Br over the penetrated layers.
The printed reading is run again here (the error-vs-runtime records predate
the zone metrics); the unbreakable chamber reference is that study's
(bench/error_vs_runtime/results.json), whose q_c the ratio divides.

The study is restartable in the same way as bench/error_vs_runtime/run.py,
whose piece runner it uses: each piece's record is appended to
results.json at once; a later call skips the pieces already there. Commit
results.json after each call. Run folders go to results/criterion_readings/.
"""

import argparse
import importlib.util
import json
import math
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(REPO, "scripts"))

import numpy as np  # noqa: E402


def _load_evr():
    spec = importlib.util.spec_from_file_location(
        "evr_run", os.path.join(REPO, "bench", "error_vs_runtime", "run.py"))
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


evr = _load_evr()

#: name -> keywords given to fix crush/particle (the printed reading is the default)
READINGS = {
    "printed": "",
    "peak": "pressure peak",
    "sliding": "force sliding",
    "weibull": "scatter weibull",
    "truncated_0.5": "scatter truncated f_min 0.5",
    "peak_truncated_0.5": "pressure peak scatter truncated f_min 0.5",
    "peak_weibull": "pressure peak scatter weibull",
    "no_N": "size_law no_N",                    # a bracket: F_lim / 27
}
# readings that are options of the chamber driver, not fix keywords: measured
# on the chamber only (name -> what the table's keywords column says)
CHAMBER_READINGS = {
    # crushing on in the preparation's last stage (cpt_demo --crush-in-prep):
    # the grains the prepared state overloads break before jacking
    "prep_crush": "(defaults), --crush-in-prep",
}
# particle dumps of the oedometer: the utilisation at 1, 10 and 30 MPa
# (examples/oedometer/run.py, summary utilisation_at_MPa) needs them
OEDO_DUMP_EVERY = 10000
RESULTS = os.path.join(HERE, "results.json")
CARRY = os.path.join(HERE, "carry")   # killed chamber pieces' resumable state, in git
EVR_RESULTS = os.path.join(REPO, "bench", "error_vs_runtime", "results.json")
ROOT = os.path.join(REPO, "results", "criterion_readings")

# The acceptance of issue "Crushing where the paper found it", item 4
QC_RATIO_RANGE = (1.3, 1.7)
ZONE_FRACTION_MIN = 0.70
OEDO_E_TOL = 0.03          # void ratio at 10 and 30 MPa against the printed reading
OEDO_BR_FACTOR = 2.0       # Br at 30 MPa at most this times the printed reading's
PHI_CS_RANGE = (31.0, 33.5)   # docs/studies/calibration.md (the range quoted in issue 14)


def pieces():
    out = []
    for name, kw in READINGS.items():
        out.append({"name": "oedometer_%s" % name, "scene": "oedometer",
                    "grains": "crushable_ne34", "reading": name,
                    "setting": dict(evr.OEDO_REF, crush_reading=kw, dump_every=OEDO_DUMP_EVERY),
                    "role": "reading"})
        out.append({"name": "triaxial_%s" % name, "scene": "triaxial", "grains": "crushable_ne34",
                    "reading": name, "setting": {"crush_reading": kw}, "role": "reading"})
    # a second packing seed of the triaxial test: one run's phi_cs scatters by
    # about half a degree, as much as the printed reading's distance to the range
    for name, kw in READINGS.items():
        out.append({"name": "triaxial_%s_seed2025" % name, "scene": "triaxial",
                    "grains": "crushable_ne34", "reading": name, "role": "reading",
                    "setting": {"crush_reading": kw, "packing_seed": 2025}})
    # the chamber: every fix-keyword reading, then the driver-option ones
    chamber = ([(name, {"crush_reading": kw}) for name, kw in READINGS.items()] +
               [(name, {"crush_reading": "", "crush_in_prep": True}) for name in CHAMBER_READINGS])
    for name, extra in chamber:
        for seed in (2024, 2025):
            out.append({"name": "chamber_%s_seed%d" % (name, seed), "scene": "chamber",
                        "grains": "crushable_ne34", "reading": name, "role": "reading",
                        "setting": dict(evr.CHAMBER_REF, **extra, packing_seed=seed)})
    # the fragments' velocity rule under density scaling (issue "Nothing
    # changes behind a user's back", item 2): the study's reference chamber
    # with d_scale_ref = 0.55 d50 and the present rule (true momentum), against
    # the error-vs-runtime records of the same setting made with the former
    # rule (fragments at the parent's velocity) and without scaling
    for seed in (2024, 2025):
        out.append({"name": "chamber_dscale_0.55_seed%d" % seed, "scene": "chamber",
                    "grains": "crushable_ne34", "reading": "printed", "role": "density_rule",
                    "setting": dict(evr.CHAMBER_REF, d_scale_ref_d50=0.55, packing_seed=seed)})
    return out


def run_triaxial(p, root, np_):
    out = os.path.join(root, p["name"])
    os.makedirs(out, exist_ok=True)
    cmd = [sys.executable, os.path.join(REPO, "examples", "triaxial", "run.py"), "--out", out,
           "--np", str(np_)]
    if p["setting"]["crush_reading"]:
        cmd += ["--crush-reading", p["setting"]["crush_reading"]]
    if "packing_seed" in p["setting"]:
        cmd += ["--packing-seed", str(p["setting"]["packing_seed"])]
    t0 = time.time()
    with open(os.path.join(out, "driver.txt"), "w") as f:
        rc = subprocess.call(cmd, stdout=f, stderr=subprocess.STDOUT)
    rec = {"name": p["name"], "scene": "triaxial", "grains": p["grains"], "role": p["role"],
           "setting": p["setting"], "command": [c.replace(REPO + os.sep, "") for c in cmd[1:]],
           "exit_status": rc, "wall_s": time.time() - t0, "mpi_ranks": np_,
           "loadavg_1_5_15": list(os.getloadavg())}
    summ = os.path.join(out, "summary.json")
    if rc != 0 or not os.path.exists(summ):
        rec["error"] = "driver exit status %d (see %s)" % (rc, os.path.join(out, "driver.txt"))
        return rec
    with open(summ) as f:
        s = json.load(f)
    rec["metrics"] = {k: s.get(k) for k in ("phi_peak_deg", "phi_peak_smooth_deg", "phi_cs_deg",
                                            "n_break_events", "Br_final", "shear_curve")}
    return rec


def run(p, np_):
    if p["scene"] == "triaxial":
        rec = run_triaxial(p, ROOT, np_)
    else:
        # a piece killed in an earlier session goes on from its carried state
        evr.carry_in(os.path.join(ROOT, p["name"]), p["name"], CARRY)
        rec = evr.run_piece(p, ROOT, np_)
    rec["reading"] = p["reading"]
    rec["crush_reading"] = p["setting"].get("crush_reading", "")
    return rec


def remeasure(p):
    """Replace a done chamber piece's metrics by those of today's `crushpost
    report` of its run folder (a metric added or mended after the run); the
    record says when and at which commit. Returns what happened."""
    out = os.path.join(ROOT, p["name"])
    summ = os.path.join(out, "summary.json")
    if not os.path.exists(summ):
        return "not remeasured: no %s (the run folder is not on this machine)" % summ
    with open(summ) as f:
        metrics, error = evr.chamber_report_metrics(out, json.load(f))
    if error:
        return "not remeasured: %s" % error
    data = load(RESULTS)                  # another call may have added records
    rec = data["runs"][p["name"]]
    rec["metrics"] = metrics
    rec["remeasured"] = {"date": time.strftime("%Y-%m-%dT%H:%M:%S"),
                         "commit": evr.head_commit()}
    evr.save(RESULTS, data)
    return "remeasured"


def load(path=RESULTS):
    return evr.load(path)


def printed_references(evr_data):
    """The printed reading's oedometer and chamber (crushable, both seeds)
    and the unbreakable chamber references, from the error-vs-runtime study."""
    runs = evr_data["runs"]
    out = {}
    for key, names in (("oedometer", ["oedometer_crush_ref", "oedometer_crush_ref_seed2025"]),
                       ("chamber", ["chamber_crush_ref", "chamber_crush_ref_seed2025"]),
                       ("chamber_rigid", ["chamber_rigid_ref", "chamber_rigid_ref_seed2025"])):
        out[key] = [runs[n] for n in names if n in runs and "metrics" in runs[n]]
    return out


def _mean(values):
    v = [x for x in values if x is not None and np.isfinite(x)]
    return float(np.mean(v)) if v else float("nan")


def rows(data, refs):
    """One row per reading: the numbers of item 3 and the verdicts of item 4."""
    runs = data["runs"]
    qc_rigid = _mean([r["metrics"].get("qc_steady_MPa") for r in refs["chamber_rigid"]])
    out = []

    def total(cm, key):
        vals = [m.get(key) for m in cm]
        return sum(vals) if vals and all(v is not None for v in vals) else None

    for name in list(READINGS) + list(CHAMBER_READINGS):
        oed = runs.get("oedometer_%s" % name, {}).get("metrics", {})
        tm = [runs[n]["metrics"] for n in ("triaxial_%s" % name, "triaxial_%s_seed2025" % name)
              if n in runs and "metrics" in runs[n]]
        tri = {k: _mean([m.get(k) for m in tm]) for k in ("phi_peak_deg", "phi_cs_deg")} if tm else {}
        ch = [runs[n] for n in ("chamber_%s_seed2024" % name, "chamber_%s_seed2025" % name)
              if n in runs and "metrics" in runs[n]]
        cm = [c["metrics"] for c in ch]
        qc = _mean([m.get("qc_steady_MPa") for m in cm])
        row = {"reading": name, "keywords": READINGS.get(name, CHAMBER_READINGS.get(name)) or "(defaults)",
               "oed_e_core_10": oed.get("e_core_at_10MPa"), "oed_e_core_30": oed.get("e_core_at_30MPa"),
               "oed_onset_MPa": oed.get("sigma_v_crush_onset_MPa"),
               "oed_Br_10": oed.get("Br_at_10MPa"), "oed_Br_30": oed.get("Br_at_30MPa"),
               "tri_phi_peak": tri.get("phi_peak_deg"), "tri_phi_cs": tri.get("phi_cs_deg"),
               "tri_runs": len(tm),
               "chamber_runs": len(cm), "qc_MPa": qc, "qc_ratio": qc_rigid / qc if qc else float("nan"),
               "fraction_in_zone": _mean([m.get("fraction_in_zone") for m in cm]),
               "along_shaft": total(cm, "events_along_shaft"),
               "beyond_5R": total(cm, "events_beyond_5R_below"),
               "switch_on": total(cm, "events_switch_on"),
               "Br_pen_1_2": _mean([m.get("Br_penetrated_1_2R") for m in cm]),
               "Br_pen_2_3": _mean([m.get("Br_penetrated_2_3R") for m in cm])}
        out.append(row)
    base = out[0]
    for row in out:
        row["verdict"] = verdict(row, base)
    return out


def verdict(row, base):
    """Which of the acceptance criteria a reading meets (None: not measured)."""
    def ok(cond, *vals):
        return None if any(v is None or (isinstance(v, float) and not np.isfinite(v))
                           for v in vals) else bool(cond())
    v = {
        "qc_ratio": ok(lambda: QC_RATIO_RANGE[0] <= row["qc_ratio"] <= QC_RATIO_RANGE[1], row["qc_ratio"]),
        "zone": ok(lambda: row["fraction_in_zone"] >= ZONE_FRACTION_MIN, row["fraction_in_zone"]),
        "shaft": ok(lambda: row["along_shaft"] == 0, row["along_shaft"]),
        "triaxial": ok(lambda: PHI_CS_RANGE[0] <= row["tri_phi_cs"] <= PHI_CS_RANGE[1], row["tri_phi_cs"]),
        "oedometer": ok(lambda: (abs(row["oed_e_core_10"] - base["oed_e_core_10"]) <= OEDO_E_TOL
                                 and abs(row["oed_e_core_30"] - base["oed_e_core_30"]) <= OEDO_E_TOL
                                 and row["oed_Br_30"] <= OEDO_BR_FACTOR * base["oed_Br_30"]),
                        row["oed_e_core_10"], row["oed_e_core_30"], row["oed_Br_30"],
                        base["oed_e_core_10"], base["oed_e_core_30"], base["oed_Br_30"]),
    }
    return v


def _f(v, fmt="%.3g"):
    if v is None or (isinstance(v, float) and not np.isfinite(v)):
        return "-"
    return fmt % v


def write_table(table, path, qc_rigid):
    yn = {True: "yes", False: "**no**", None: "-"}
    lines = [
        "# Criterion readings: results (bench/criterion_readings/run.py --table)",
        "",
        "Oedometer: the error-vs-runtime reference setting (N = 39, 5 d50 x 8 d50 cell, to "
        "30 MPa), core void ratio. Triaxial: examples/triaxial/run.py defaults, mean of the "
        "packing seeds run (column tri n). Chamber: the "
        "error-vs-runtime reference (8 R, quarter sector, 1 m/s, to 0.2 m), crushable, mean of "
        "the packing seeds run (column n), the event counts (shaft, beyond 5R, switch-on) "
        "summed over them; q_c ratio = pooled unbreakable reference / this "
        "reading's q_c (%.2f MPa, bench/error_vs_runtime/results.json). '-': not measured yet "
        "(in zone: also when no break happened during penetration)."
        % qc_rigid,
        "",
        "| reading | keywords | e 10 MPa | e 30 MPa | 1 % broken at (MPa) | Br 10 | Br 30 | "
        "phi_peak | phi_cs | tri n | n | q_c (MPa) | ratio | in zone | shaft | beyond 5R | switch-on | "
        "Br 1-2R | Br 2-3R |",
        "|" + "---|" * 19,
    ]
    for r in table:
        lines.append("| %s | %s | %s | %s | %s | %s | %s | %s | %s | %d | %d | %s | %s | %s | %s | %s | %s | %s | %s |" % (
            r["reading"], r["keywords"], _f(r["oed_e_core_10"], "%.4f"), _f(r["oed_e_core_30"], "%.4f"),
            _f(r["oed_onset_MPa"]), _f(r["oed_Br_10"]), _f(r["oed_Br_30"]),
            _f(r["tri_phi_peak"], "%.1f"), _f(r["tri_phi_cs"], "%.1f"), r["tri_runs"], r["chamber_runs"],
            _f(r["qc_MPa"], "%.2f"), _f(r["qc_ratio"], "%.2f"), _f(r["fraction_in_zone"], "%.2f"),
            _f(r["along_shaft"], "%d"), _f(r["beyond_5R"], "%d"), _f(r["switch_on"], "%d"),
            _f(r["Br_pen_1_2"]), _f(r["Br_pen_2_3"])))
    lines += ["", "Acceptance (issue item 4): q_c ratio in [%g, %g]; at least %d %% of the "
              "penetration events in the zone; none along the shaft; phi_cs in [%g, %g] deg; "
              "oedometer e at 10 and 30 MPa within %g of the printed reading and Br at 30 MPa at "
              "most %g times." % (QC_RATIO_RANGE[0], QC_RATIO_RANGE[1], 100 * ZONE_FRACTION_MIN,
                                  PHI_CS_RANGE[0], PHI_CS_RANGE[1], OEDO_E_TOL, OEDO_BR_FACTOR), "",
              "| reading | q_c ratio | zone | shaft | triaxial | oedometer |", "|---|---|---|---|---|---|"]
    for r in table:
        v = r["verdict"]
        lines.append("| %s | %s | %s | %s | %s | %s |" % (r["reading"], yn[v["qc_ratio"]], yn[v["zone"]],
                                                       yn[v["shaft"]], yn[v["triaxial"]], yn[v["oedometer"]]))
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


#: the chamber pieces' break events, relative to the apex (committed: the
#: maps figure is drawn from it, not from the uncommitted run folders)
EVENTS = os.path.join(HERE, "break_events.json")
MAPS_PNG = os.path.join(REPO, "docs", "img", "criterion_breakage_maps.png")


def collect_events(names, root=ROOT, path=EVENTS):
    """Add to ``path`` the break events of every chamber piece in ``names``
    whose report (root/NAME/report/fields.h5, breakage/events) exists: h/R and
    r/R of the parent relative to the apex at the event and the tip's depth
    (in R), rounded to 1e-3 R. Returns the dict written (piece -> columns)."""
    import h5py
    data = {}
    if os.path.exists(path):
        with open(path) as f:
            data = json.load(f)
    for name in names:
        fields = os.path.join(root, name, "report", "fields.h5")
        if not os.path.exists(fields):
            continue
        with h5py.File(fields, "r") as f:
            if "breakage/events" not in f:
                if "breakage/zones/n_events" in f and int(f["breakage/zones/n_events"][()]) == 0:
                    # crushable grains that never broke: a measured empty map
                    data[name] = {"h_over_R": [], "r_over_R": [], "tip_depth_over_R": []}
                continue
            g = f["breakage/events"]
            tip = g["tip_depth"][()] / _pile_radius(os.path.join(root, name))   # m -> R
            data[name] = {k: [round(float(v), 3) for v in vals] for k, vals in
                          (("h_over_R", g["h_over_R"][()]), ("r_over_R", g["r_over_R"][()]),
                           ("tip_depth_over_R", tip))}
    with open(path, "w") as f:        # one line per piece: small diffs
        f.write("{\n" + ",\n".join("%s: %s" % (json.dumps(k), json.dumps(data[k], sort_keys=True))
                                   for k in sorted(data)) + "\n}\n")
    return data


def _pile_radius(run_dir):
    path = os.path.join(run_dir, "summary.json")
    with open(path) as f:
        R = json.load(f).get("R_pile_m")
    if not R:
        raise KeyError("%s: no R_pile_m" % path)
    return float(R)


def penetration_events(ev):
    """(h/R, r/R) of the events during penetration (tip deeper than
    ZONE_DEPTH_MIN radii: switch-on, preparation and entry events excluded,
    as crushpost.pile.break_zones counts them)."""
    from crushpost.pile import ZONE_DEPTH_MIN
    h, r, d = (np.asarray(ev[k], dtype=float) for k in ("h_over_R", "r_over_R", "tip_depth_over_R"))
    pen = d > ZONE_DEPTH_MIN
    return h[pen], r[pen], int((~pen).sum())


def _pyplot():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def _save(fig, path):
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    _pyplot().close(fig)


def draw_maps(events, path=MAPS_PNG, readings=None):
    """One panel per reading (seeds pooled): the penetration events in the
    (r/R, h/R) plane about the apex, the zone of the acceptance (r < 3R,
    -5R < h < 1.73R) and the pile. Returns the readings drawn."""
    plt = _pyplot()
    from crushpost.pile import ZONE_H_BELOW, ZONE_R_MAX
    names = readings or [n for n in list(READINGS) + list(CHAMBER_READINGS)
                         if any(k.startswith("chamber_%s_seed" % n) for k in events)]
    if not names:
        return []
    fig, axes = plt.subplots(1, len(names), figsize=(2.6 * len(names) + 0.6, 5.2), sharey=True,
                             squeeze=False)
    shoulder = 1.0 / math.tan(math.radians(30.0))
    for ax, name in zip(axes[0], names):
        hs, rs, n_other, seeds = [], [], 0, 0
        for seed in (2024, 2025):
            ev = events.get("chamber_%s_seed%d" % (name, seed))
            if ev is None:
                continue
            h, r, n = penetration_events(ev)
            hs.append(h), rs.append(r)
            n_other += n
            seeds += 1
        h, r = np.concatenate(hs), np.concatenate(rs)
        zone = (r < ZONE_R_MAX) & (h > -ZONE_H_BELOW) & (h < shoulder)
        ax.plot(r[zone], h[zone], ".", ms=3, color="C3")
        ax.plot(r[~zone], h[~zone], ".", ms=3, color="C0")
        ax.add_patch(plt.Rectangle((0.0, -ZONE_H_BELOW), ZONE_R_MAX, ZONE_H_BELOW + shoulder,
                                   fill=False, ls="--", lw=0.8, color="k"))
        ax.fill([0.0, 1.0, 1.0, 0.0], [0.0, shoulder, 8.0, 8.0], color="0.8", lw=0)
        ax.set_xlim(0.0, 8.0)
        ax.set_ylim(-12.0, 8.0)
        ax.set_xlabel("r / R")
        ax.set_title("%s\n%d events, %s in zone\n(%d seed%s; %d before 2R depth)"
                     % (name, h.size, "%.0f %%" % (100.0 * zone.mean()) if h.size else "-",
                        seeds, "" if seeds == 1 else "s", n_other), fontsize=8)
    axes[0][0].set_ylabel("h / R above the apex at the event")
    _save(fig, path)
    return names


OEDO_PNG = os.path.join(REPO, "docs", "img", "criterion_oedometer_curves.png")


def draw_oedometer_curves(data, path=OEDO_PNG):
    """The oedometer pieces' loading curves (crushpost.oedometer.loading_curve,
    kept in each record): core void ratio and Br against log sigma_v, one line
    per reading, the printed reading in black. Returns the readings drawn."""
    plt = _pyplot()
    curves = {name: data["runs"]["oedometer_%s" % name]["metrics"].get("loading_curve")
              for name in READINGS if "oedometer_%s" % name in data["runs"]}
    names = [n for n, c in curves.items() if c and c.get("sigma_v_MPa")]
    if not names:
        return []
    fig, (ax_e, ax_b) = plt.subplots(1, 2, figsize=(10.0, 4.2))
    for k, name in enumerate(names):
        c = curves[name]
        sv = np.asarray(c["sigma_v_MPa"], float)
        style = dict(color="k", lw=2.0) if name == "printed" else dict(color="C%d" % (k % 10), lw=1.2)
        for ax, key in ((ax_e, "e_core"), (ax_b, "Br")):
            y = np.array([np.nan if v is None else v for v in c[key]], float)
            ax.plot(sv, y, label=name, **style)
    for ax, label in ((ax_e, "void ratio of the core"), (ax_b, "Br")):
        ax.set_xscale("log")
        ax.set_xlabel("sigma_v (MPa)")
        ax.set_ylabel(label)
        ax.grid(True, which="both", lw=0.3)
    ax_e.set_ylim(bottom=max(-0.2, ax_e.get_ylim()[0]))
    ax_b.legend(fontsize=7)
    fig.suptitle("oedometer (N = 39, 5 x 8 d50, packing seed 2024), one line per criterion reading",
                 fontsize=9)
    _save(fig, path)
    return names


TRIAX_PNG = os.path.join(REPO, "docs", "img", "criterion_triaxial_curves.png")


def draw_triaxial_curves(data, path=TRIAX_PNG):
    """The triaxial pieces' shearing curves (crushpost.triaxial.shear_curve,
    kept in each record): q/p and eps_v against eps_a, one colour per reading
    (the printed one in black), seed 2024 solid and 2025 dashed. Returns the
    readings drawn."""
    plt = _pyplot()
    drawn = []
    fig, (ax_q, ax_v) = plt.subplots(1, 2, figsize=(10.0, 4.2))
    for k, name in enumerate(READINGS):
        for seed, suffix, ls in ((2024, "", "-"), (2025, "_seed2025", "--")):
            rec = data["runs"].get("triaxial_%s%s" % (name, suffix), {})
            c = rec.get("metrics", {}).get("shear_curve")
            if not c or not c.get("eps_a"):
                continue
            colour = "k" if name == "printed" else "C%d" % (k % 10)
            ea = 100.0 * np.asarray(c["eps_a"], float)
            for ax, key, scale in ((ax_q, "eta", 1.0), (ax_v, "eps_v", 100.0)):
                y = scale * np.array([np.nan if v is None else v for v in c[key]], float)
                ax.plot(ea, y, ls=ls, color=colour, lw=1.2,
                        label="%s, seed %d" % (name, seed))
            if name not in drawn:
                drawn.append(name)
    if not drawn:
        plt.close(fig)
        return []
    ax_q.set_ylabel("q / p")
    ax_v.set_ylabel("eps_v (%, compression positive)")
    for ax in (ax_q, ax_v):
        ax.set_xlabel("eps_a (%)")
        ax.grid(True, lw=0.3)
    ax_q.legend(fontsize=7)
    fig.suptitle("drained triaxial (examples/triaxial/run.py defaults), one colour per criterion "
                 "reading", fontsize=9)
    _save(fig, path)
    return drawn


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--list", action="store_true")
    ap.add_argument("--table", action="store_true")
    ap.add_argument("--only", nargs="+", help="piece names")
    ap.add_argument("--scene", nargs="+", choices=("oedometer", "triaxial", "chamber"))
    ap.add_argument("--reading", nargs="+", choices=sorted(READINGS))
    ap.add_argument("--np", type=int, default=1)
    ap.add_argument("--rerun", action="store_true",
                    help="run the selected pieces again even if done, replacing their records "
                    "(e.g. --rerun --scene oedometer, for records made before a metric existed)")
    ap.add_argument("--remeasure", action="store_true",
                    help="measure the selected done chamber pieces again from their run folders "
                    "(crushpost report, no LIGGGHTS run), replacing only their metrics")
    ap.add_argument("--carry", action="store_true",
                    help="pack every killed chamber piece's resumable state into carry/ (commit it)")
    a = ap.parse_args(argv)
    data = load()
    todo = [p for p in pieces()
            if (not a.only or p["name"] in a.only) and (not a.scene or p["scene"] in a.scene)
            and (not a.reading or p["reading"] in a.reading)]
    if a.list:
        for p in todo:
            state = "done" if p["name"] in data["runs"] else "to run"
            print("%-34s %-10s %s" % (p["name"], state, p["setting"].get("crush_reading") or "(printed)"))
        return 0
    if a.carry:
        for name, step, mb in evr.carry_out(ROOT, [p["name"] for p in pieces()], CARRY):
            print("carried %s at restart step %s (%.1f MB)" % (name, step, mb))
        return 0
    if a.table:
        refs = printed_references(evr.load(EVR_RESULTS))
        table = rows(data, refs)
        write_table(table, os.path.join(HERE, "results_table.md"),
                    _mean([r["metrics"].get("qc_steady_MPa") for r in refs["chamber_rigid"]]))
        with open(os.path.join(HERE, "results_table.json"), "w") as f:
            json.dump(table, f, indent=1)
        print("wrote %s" % os.path.join(HERE, "results_table.md"))
        events = collect_events([p["name"] for p in pieces()
                                 if p["scene"] == "chamber" and p["role"] == "reading"])
        drawn = draw_maps(events)
        if drawn:
            print("wrote %s (%s)" % (MAPS_PNG, ", ".join(drawn)))
        drawn = draw_oedometer_curves(data)
        if drawn:
            print("wrote %s (%s)" % (OEDO_PNG, ", ".join(drawn)))
        drawn = draw_triaxial_curves(data)
        if drawn:
            print("wrote %s (%s)" % (TRIAX_PNG, ", ".join(drawn)))
        return 0
    if a.remeasure:
        for p in todo:
            if p["scene"] == "chamber" and p["name"] in data["runs"]:
                print("criterion readings: %s %s" % (p["name"], remeasure(p)), flush=True)
        return 0
    for p in todo:
        if p["name"] in data["runs"] and not a.rerun:
            continue
        print("criterion readings: running %s" % p["name"], flush=True)
        rec = run(p, a.np)
        data = load()                     # another call may have added records
        data["runs"][p["name"]] = rec
        evr.save(RESULTS, data)
        carried = evr.carry_path(p["name"], CARRY)
        if "error" not in rec and os.path.exists(carried):
            os.remove(carried)            # the record replaces the carried state
        print("criterion readings: %s %s" % (p["name"], rec.get("error") or "done"), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
