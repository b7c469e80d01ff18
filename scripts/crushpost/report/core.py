# SPDX-License-Identifier: GPL-2.0-or-later
"""The report's core: reads the run's inputs once (summary.json, jack.txt,
log.liggghts, breakage_events.txt) into one context and hands it to the
parts in turn (q_c, log numbers, the snapshots' fields, the breakage map,
the spheres, ParaView), then writes fields.h5 and report.html."""

import os
import sys
import time

from ..formats import SUMMARY as S
from .bands import _breakage_map
from .common import ReportInputError, ReportOptions, _Report
from .fields_h5 import _write_h5
from .inputs import (_optional, read_events_checked, read_jack_checked, read_log_checked,
                     read_reference, read_summary)
from .log_numbers import _log_numbers
from .page import _write_html
from .paraview import _paraview
from .qc import _qc
from .states import _states
from .stresses import _spheres


def make_report(run_dir, out_dir=None, opt=None, say=None):
    """Write the report of the run in ``run_dir`` into ``out_dir`` (default
    ``run_dir/report``). Returns a dict: out, figures, problems (list of
    (kind, message)), headline. Raises ReportInputError when nothing can be
    reported (no run folder, no pile radius, a bad --reference file)."""
    opt = opt or ReportOptions()
    opt.check()
    say = say or (lambda msg: None)
    if not os.path.isdir(run_dir):
        raise ReportInputError("%s: no such run folder" % run_dir)
    out_dir = out_dir or os.path.join(run_dir, "report")
    os.makedirs(out_dir, exist_ok=True)
    reference = read_reference(opt.reference) if opt.reference else None
    rep = _Report(run_dir, out_dir, opt, say)
    t0 = time.time()

    # -- the run's settings ------------------------------------------------
    summary = None
    try:
        summary = read_summary(rep.path("summary.json"))
    except ReportInputError as exc:
        rep.error(str(exc))
    summary = summary or {}
    R = opt.pile_radius or summary.get(S.R_pile_m)
    if not R:
        raise ReportInputError("%s: no %s; give the pile radius with --pile-radius R (m)"
                               % (rep.path("summary.json"), S.R_pile_m))
    N = opt.N or summary.get(S.N)
    jack = _optional(rep, "jack.txt", read_jack_checked, "q_c, tip-relative fields",
                     "the pile's time series")
    log_text = _optional(rep, "log.liggghts", read_log_checked, "mass balance and lost atoms")
    events = _optional(rep, "breakage_events.txt", read_events_checked, "breakage map",
                       "unbreakable grains, or the fix's events keyword off")

    ctx = {"R": float(R), "N": N, "summary": summary, "jack": jack, "events": events,
           "log": log_text, "z_ref": jack["z_ref"] if jack is not None else None}
    _settings(rep, ctx)
    _qc(rep, ctx)
    _log_numbers(rep, ctx)
    _states(rep, ctx)
    _breakage_map(rep, ctx)
    _spheres(rep, ctx)
    _paraview(rep, ctx)
    _write_h5(rep, ctx)
    rep.settings.append(("report time", "%.1f s" % (time.time() - t0)))
    _write_html(rep, ctx, reference)
    return {"out": out_dir, "figures": [f for f, _, _ in rep.figures], "problems": rep.problems,
            "headline": rep.head}


def _settings(rep, ctx):
    s, R = ctx["summary"], ctx["R"]
    rows = [("run folder", os.path.abspath(rep.run)), ("pile radius R", "%.4g mm" % (R * 1e3))]
    names = [(S.mode, "jacking mode", "%s"), (S.grains, "grain model", "%s"),
             (S.N, "up-scaling factor N", "%g"), (S.R_chamber_m, "chamber radius", "%.4g m"),
             (S.H_chamber_m, "chamber height", "%.4g m"), (S.sector_deg, "sector", "%d deg"),
             (S.mpi_ranks, "MPI ranks", "%d"), (S.wall_time_s, "LIGGGHTS wall time", "%.0f s"),
             (S.n_particles_initial, "grains placed", "%d")]
    for key, label, fmt in names:
        if key in s:
            rows.append((label, fmt % s[key]))
    prep = s.get(S.prep) or {}
    if "n_target" in prep:
        rows.append(("target core porosity", "%.4g" % prep["n_target"]))
    if ctx["jack"] is not None:
        try:
            with open(rep.path("jack.txt")) as f:
                first = f.readline().strip().lstrip("# ")
            rows.append(("fix jack/pile", first))
        except OSError:
            pass
        rows.append(("sand surface z_ref", "%.6g m" % ctx["z_ref"]))
    o = rep.opt
    width = o.ring_width or R
    rows += [("rings", "width %.4g mm (%.3g R), height %.4g mm" % (width * 1e3, width / R,
                                                                    o.ring_height * 1e3)),
             ("minimum grains per ring", "%d (rings below are flagged)" % o.min_grains),
             ("stress normalisation", "q_c at the end of the last push" if o.qc_norm == "push"
              else "steady q_c of the trend fit")]
    rep.settings.extend(rows)
    ctx["ring_width"] = width


def main_report(args, stderr=sys.stderr):
    """The ``report`` subcommand (crushpost.cli); returns the exit status:
    0, or 1 when an input was bad (the rest of the report is still
    written) or nothing could be reported."""
    opt = ReportOptions(ring_width=args.ring_width, ring_height=args.ring_height,
                        min_grains=args.min_grains, profile_h=args.profile_h,
                        history_r=args.history_r, band_width=args.band_width,
                        qc_norm=args.qc_norm, pile_radius=args.pile_radius, N=args.N,
                        sector=args.sector, reference=args.reference)

    def say(msg):
        if not args.quiet or msg.startswith("error"):
            stderr.write("crushpost report: %s\n" % msg)
    try:
        res = make_report(args.run_dir, args.out, opt, say)
    except ReportInputError as exc:
        stderr.write("crushpost report: error: %s\n" % exc)
        return 1
    stderr.write("crushpost report: %d figures, fields.h5 and report.html in %s\n"
                 % (len(res["figures"]), res["out"]))
    return 1 if any(k == "error" for k, _ in res["problems"]) else 0
