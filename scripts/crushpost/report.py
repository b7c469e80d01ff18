# SPDX-License-Identifier: GPL-2.0-or-later
"""The analyses of a chamber run from one command (issue 10):

    crushpost report RUN_DIR [--out DIR] [--reference FILE]

reads what examples/cpt_demo/run.py (or a deck like it) leaves in RUN_DIR:
jack.txt (fix jack/pile), breakage_events.txt (fix crush/particle),
snapshots/prep_<step>.h5 and snapshots/jack_<step>.h5 (fix snapshot/hdf5 at
the prepared state and at the end of every push and pause), spheres.in and
spheres.txt (measurement spheres), log.liggghts, summary.json and the VTK
series post/grains_<step>.vtk and post/meshes_<step>.vtk (--vtk particles),
and writes into DIR (default RUN_DIR/report): the figures (PNG), fields.h5
(the numbers behind every figure; layout in docs/report.md), report.html,
and, where there is a VTK series, ParaView's picture of its last step
(paraview.png; crushpost/paraview_state.py run by scripts/pvbatch) and
ParaView's state (paraview.pvsm).

Each part runs on the inputs it needs; a part whose input is missing is
skipped and said so (in report.html and one line on stderr), so a run
without snapshots still gets the q_c trend, the breakage map and the
spheres. A missing, truncated or corrupt input gives one line naming the
file and what is wrong.

Conventions: compression positive; lengths in m, stresses in Pa in
fields.h5 (figures in kPa or normalised); ``R`` the pile radius; ``h`` the
height above the cone's apex at the time of the state, ``r`` the distance
from the pile axis; the sand surface ``z_ref`` is jack.txt's depth
reference (tip z = z_ref - depth).
"""

import html
import json
import math
import os
import re
import subprocess
import sys
import time

import numpy as np

from .breakage import W_FRACTAL, break_fines, fractal_psd, psd_curve, sphere_mass
from .dump import read_crush_log
from .inputfile import InputFileError, read_checked, reason
from .fields import (binned_mean, cell_breakage, event_density, interp_columns, interp_radius,
                     qc_reference, qc_trend_band, radial_increments, stress_quantities)
from .pile import (PHASE_PAUSE, PHASE_PUSH, UTILISATION_ZONES, ZONE_DEPTH_MIN, ZONE_H_BELOW,
                   ZONE_R_MAX, break_zones, event_phases, inside_pile, read_jack, relative_to_tip, tip_z_at,
                   utilisation_by_zone)
from .prep import ring_edges
from .rings import ring_fields, sphere_cell_volumes
from .rotation import axis_rotation, unwrap_axis
from .snapshot import list_snapshots, read_snapshot, snapshot_particle_stress
from .spheres import read_sphere_series
from .stress import invariants
from .study import STUDY_TABLE, STUDY_TABLE_NAME, qc_run_scatter, qc_uncertainty
from .thermo import parse_log
from .trend import fit_qc_trend, mean_of_last_bands, qc_band_means, virgin_mask

__all__ = ["ReportInputError", "ReportOptions", "make_report", "read_reference",
           "HEADLINE_NAMES", "STATE_KINDS"]

#: Calibrated NE34 Br range at real size (docs/model.md §3) [m]; scaled by N.
D_MIN_REAL = 0.01e-3
D_MAX_REAL = 0.27e-3
RHO = 2600.0
#: kinds of the states (snapshots) in fields.h5 /states/kind
STATE_KINDS = ("initial", "push_end", "pause_end", "other")
COMPONENTS = ("sigma_r", "sigma_theta", "sigma_z")
LABEL = {"sigma_r": r"$\sigma_r$", "sigma_theta": r"$\sigma_\theta$", "sigma_z": r"$\sigma_z$",
         "tau_rz": r"$\tau_{rz}$"}

#: headline numbers (names the --reference file may use) and their units
HEADLINE_NAMES = {
    "qc_steady_MPa": "MPa", "qc_steady_err_MPa": "MPa", "qc_fit_b_per_m": "1/m",
    "qc_last3_bands_MPa": "MPa", "qc_run_scatter_MPa": "MPa",
    "final_depth_mm": "mm", "n_break_events": "-", "n_break_events_first_step": "-",
    "n_break_events_prep": "-",
    "Br_sample": "-",
    "events_switch_on": "-", "events_entry": "-", "events_penetration": "-",
    "events_in_zone": "-", "events_along_shaft": "-", "events_beyond_5R_below": "-",
    "events_elsewhere": "-", "fraction_in_zone": "-",
    "Br_penetrated_1_2R": "-", "Br_penetrated_2_3R": "-",
    "peak_q_over_p": "-", "max_rotation_deg": "deg", "mass_balance_rel_error": "-",
    "lost_atoms": "-", "porosity_initial": "-", "sigma_r_initial_kPa": "kPa",
    "sigma_theta_initial_kPa": "kPa", "sigma_z_initial_kPa": "kPa",
}


class ReportInputError(InputFileError):
    """An input of the report is missing, truncated or not what it should
    be; the message is one line that names the file."""


class ReportOptions:
    """Settings of a report (the command line's options; lengths in m)."""

    def __init__(self, ring_width=None, ring_height=0.025, min_grains=65,
                 profile_h=(-2.0, 0.0, 2.0, 5.0), history_r=(3.0, 5.0, 8.0), band_width=1.0,
                 qc_norm="push", pile_radius=None, N=None, sector=None, density=RHO,
                 reference=None, dpi=110):
        self.ring_width = ring_width          # None: the pile radius R
        self.ring_height = ring_height
        self.min_grains = min_grains
        self.profile_h = tuple(profile_h)
        self.history_r = tuple(history_r)
        self.band_width = band_width
        self.qc_norm = qc_norm
        self.pile_radius = pile_radius
        self.N = N
        self.sector = sector
        self.density = density
        self.reference = reference
        self.dpi = dpi

    def check(self):
        for name in ("ring_height", "band_width", "density"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and v > 0):
                raise ReportInputError("--%s must be > 0, got %r" % (name.replace("_", "-"), v))
        if self.ring_width is not None and not self.ring_width > 0:
            raise ReportInputError("--ring-width must be > 0 m, got %r" % self.ring_width)
        if self.min_grains < 0:
            raise ReportInputError("--min-grains must be >= 0, got %r" % self.min_grains)
        if self.qc_norm not in ("push", "steady"):
            raise ReportInputError("--qc-norm must be 'push' or 'steady', got %r" % self.qc_norm)
        if self.sector is not None and self.sector not in (360, 180, 90):
            raise ReportInputError("--sector must be 360, 180 or 90 degrees, got %r" % self.sector)


# ---------------------------------------------------------------------------
# reading, each failure one line naming the file
# ---------------------------------------------------------------------------

def _guard(path, what, reader):
    """``reader()`` with every read failure turned into ReportInputError
    naming ``path`` (``what``: what the file should be)."""
    return read_checked(path, what, reader, error=ReportInputError)


def _optional(rep, name, reader, part, what=None):
    """``reader`` of the run's file ``name``, or None: a missing file skips
    ``part`` of the report (``what``: what the file would have been), a bad
    one is an error of the report; neither stops it."""
    path = rep.path(name)
    if not os.path.exists(path):
        rep.skip(part, "%s: no such file%s" % (path, " (%s)" % what if what else ""))
        return None
    try:
        return reader(path)
    except ReportInputError as exc:
        rep.error(str(exc))
        return None


def read_summary(path):
    """summary.json of the driver, or None when there is none."""
    if not os.path.exists(path):
        return None

    def rd():
        with open(path) as f:
            data = json.load(f)
        if not isinstance(data, dict):
            raise ValueError("the top level is not an object")
        return data
    return _guard(path, "a JSON summary of the driver", rd)


def read_jack_checked(path):
    """jack.txt with the columns the report needs (phase, forces) and its
    z_ref header."""
    def rd():
        with open(path, "rb") as f:
            if not f.read(4096).strip():
                raise ReportInputError("%s: empty file; expected the time series of fix "
                                       "jack/pile" % path)
        return read_jack(path)
    jack = _guard(path, "a fix jack/pile time series", rd)
    if "phase" not in jack or "F_cone" not in jack:
        raise ReportInputError("%s: %d columns; a fix jack/pile series has 9 (step time depth "
                               "F_cone F_shaft F_head phase cycle v_next)"
                               % (path, len([k for k in jack if k != "z_ref"])))
    if jack["step"].size < 2:
        raise ReportInputError("%s: %d row(s); need at least 2" % (path, jack["step"].size))
    if np.any(np.diff(jack["step"]) < 0):
        raise ReportInputError("%s: steps do not increase (two runs appended to one file?)"
                               % path)
    if jack["z_ref"] is None:
        raise ReportInputError("%s: no '# z_ref' header line: the tip position is unknown "
                               "(written by a fix jack/pile older than the one that writes it)"
                               % path)
    return jack


def read_events_checked(path):
    return _guard(path, "an event log of fix crush/particle", lambda: read_crush_log(path))


_REGION = re.compile(r"^region\s+(\S+)_reg\s+sphere\s+(\S+)\s+(\S+)\s+(\S+)\s+(\S+)")


def read_spheres_checked(block, series):
    """Centres (n, 3), radius and the stress series (steps, sigma (m, n, 3, 3))
    of the measurement spheres from the deck block (spheres.in) and its
    output (spheres.txt)."""
    def rd_block():
        centres, radii = [], []
        with open(block) as f:
            for line in f:
                m = _REGION.match(line.strip())
                if m:
                    centres.append([float(m.group(k)) for k in (2, 3, 4)])
                    radii.append(float(m.group(5)))
        if not centres:
            raise ValueError("no 'region ..._reg sphere x y z r' line")
        return np.array(centres), float(radii[0])
    centres, radius = _guard(block, "a measurement-sphere block (crushpost.spheres)", rd_block)

    def rd_series():
        steps, sigma = read_sphere_series(series, len(centres))
        if steps.size == 0:
            raise ValueError("no output line")
        return steps, sigma
    steps, sigma = _guard(series, "the output of %d measurement spheres (step and 6 "
                          "components each)" % len(centres), rd_series)
    return centres, radius, steps, sigma


def read_log_checked(path):
    def rd():
        with open(path, errors="replace") as f:
            text = f.read()
        if not text.strip():
            raise ValueError("empty file")
        return text
    return _guard(path, "a LIGGGHTS log", rd)


def read_snapshot_checked(path, need_contacts=True):
    snap = _guard(path, "a fix snapshot/hdf5 file", lambda: read_snapshot(path))
    p = snap["particles"]
    for key in ("id", "x", "radius"):
        if key not in p:
            raise ReportInputError("%s: no particles/%s data set" % (path, key))
    if need_contacts and snap["contacts"] is None:
        raise ReportInputError("%s: written without contacts (the deck's fix needs "
                               "'contacts yes' for the particle stresses)" % path)
    return snap


def read_reference(path):
    """The user's reference values: JSON ``{name: {"value": v, "source": s,
    "unit": u}}`` (or ``{name: v}``, or a list of such objects with a
    "name"), or CSV with a header ``name,value[,unit],source``. Returns
    ``{name: {"value": float, "source": str, "unit": str}}``."""
    def rd():
        with open(path) as f:
            text = f.read()
        if not text.strip():
            raise ValueError("empty file")
        out = {}
        if path.lower().endswith(".json") or text.lstrip()[:1] in "{[":
            data = json.loads(text)
            items = data if isinstance(data, list) else [
                dict(v, name=k) if isinstance(v, dict) else {"name": k, "value": v}
                for k, v in data.items()]
            for it in items:
                if not isinstance(it, dict) or "name" not in it or "value" not in it:
                    raise ValueError("each entry needs a name and a value")
                out[str(it["name"])] = {"value": float(it["value"]),
                                        "source": str(it.get("source", "")),
                                        "unit": str(it.get("unit", ""))}
        else:
            import csv
            rows = list(csv.reader(line for line in text.splitlines()
                                   if line.strip() and not line.lstrip().startswith("#")))
            head = [h.strip().lower() for h in rows[0]]
            if "name" not in head or "value" not in head:
                raise ValueError("the CSV header must name the columns 'name' and 'value' "
                                 "(and 'source', 'unit')")
            for k, row in enumerate(rows[1:], 2):
                rec = dict(zip(head, (c.strip() for c in row)))
                try:
                    val = float(rec.get("value", ""))
                except ValueError:
                    raise ValueError("row %d: value %r is not a number"
                                     % (k, rec.get("value"))) from None
                out[rec["name"]] = {"value": val, "source": rec.get("source", ""),
                                    "unit": rec.get("unit", "")}
        if not out:
            raise ValueError("no value")
        return out
    return _guard(path, "a reference file (JSON or CSV of named values)", rd)


# ---------------------------------------------------------------------------
# the report
# ---------------------------------------------------------------------------

class _Report:
    def __init__(self, run_dir, out_dir, opt, say):
        self.run = run_dir
        self.out = out_dir
        self.opt = opt
        self.say = say
        self.problems = []            # (kind, message): "error" (bad input) or "skipped"
        self.figures = []             # (file, title, caption)
        self.h5 = {}                  # group -> {name: array or scalar}
        self.h5_attrs = {}            # group -> {attr: value}
        self.head = {}                # headline name -> value
        self.head_notes = {}          # headline name -> how it was measured
        self.settings = []            # (name, value)

    def path(self, *parts):
        return os.path.join(self.run, *parts)

    def error(self, msg):
        self.problems.append(("error", msg))
        self.say("error: " + msg)

    def skip(self, part, why):
        msg = "%s skipped: %s" % (part, why)
        self.problems.append(("skipped", msg))
        self.say(msg)

    def put(self, group, **items):
        self.h5.setdefault(group, {}).update(items)

    def attrs(self, group, **items):
        self.h5_attrs.setdefault(group, {}).update(items)

    def figure(self, fig, name, title, caption):
        fig.savefig(os.path.join(self.out, name), dpi=self.opt.dpi)
        import matplotlib.pyplot as plt
        plt.close(fig)
        self.figures.append((name, title, caption))


def _plt():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def _pile_outline(ax, h_top, R=1.0):
    # the pile in the (r/R, h/R) plane: 60 degree cone, shaft above
    h_cone = 1.0 / math.tan(math.radians(30.0))
    top = max(h_top, h_cone) + 0.5
    ax.fill([0.0, 1.0, 1.0, 0.0], [0.0, h_cone, top, top], color="0.8", lw=0, zorder=3)
    ax.plot([0.0, 1.0, 1.0], [0.0, h_cone, top], color="k", lw=0.8, zorder=4)


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
    R = opt.pile_radius or summary.get("R_pile_m")
    if not R:
        raise ReportInputError("%s: no R_pile_m; give the pile radius with --pile-radius R (m)"
                               % rep.path("summary.json"))
    N = opt.N or summary.get("N")
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


# ---------------------------------------------------------------------------
# settings, q_c, log
# ---------------------------------------------------------------------------

def _settings(rep, ctx):
    s, R = ctx["summary"], ctx["R"]
    rows = [("run folder", os.path.abspath(rep.run)), ("pile radius R", "%.4g mm" % (R * 1e3))]
    names = [("mode", "jacking mode", "%s"), ("grains", "grain model", "%s"),
             ("N", "up-scaling factor N", "%g"), ("R_chamber_m", "chamber radius", "%.4g m"),
             ("H_chamber_m", "chamber height", "%.4g m"), ("sector_deg", "sector", "%d deg"),
             ("mpi_ranks", "MPI ranks", "%d"), ("wall_time_s", "LIGGGHTS wall time", "%.0f s"),
             ("n_particles_initial", "grains placed", "%d")]
    for key, label, fmt in names:
        if key in s:
            rows.append((label, fmt % s[key]))
    prep = s.get("prep") or {}
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


def _qc(rep, ctx):
    jack, R = ctx["jack"], ctx["R"]
    if jack is None:
        return
    plt = _plt()
    depth, phase = jack["depth"], jack["phase"]
    qc = jack["F_cone"] / (math.pi * R ** 2)
    ctx["qc_series"] = qc
    virgin = virgin_mask(depth, phase) & (depth > 0)
    rep.put("qc", step=jack["step"], time=jack["time"], depth=depth, qc=qc, phase=phase,
            virgin=virgin.astype(np.int8))
    rep.head["final_depth_mm"] = float(depth.max() * 1e3)
    # band means: a plateau read that assumes no shape of q_c(h), on the
    # layers of the rings (the fit below can run away when q_c has not
    # levelled off; the bands cannot)
    dz = rep.opt.ring_height
    if virgin.any():
        bottom, mean, count = qc_band_means(depth[virgin], qc[virgin], dz)
        rep.put("qc", band_bottom=bottom, band_mean=mean, band_count=count)
        rep.attrs("qc", band_height=dz)
        last3 = mean_of_last_bands(mean, count, 3)
        if last3 is not None:
            rep.head["qc_last3_bands_MPa"] = last3 / 1e6
            rep.head_notes["qc_last3_bands_MPa"] = (
                "mean q_c of virgin penetration over the last three %g mm bands, %g-%g mm"
                % (dz * 1e3, (bottom[-1] - 3 * dz) * 1e3, bottom[-1] * 1e3))
    if virgin.sum() < 3:
        rep.skip("q_c trend fit", "%s: %d points of virgin penetration; need 3"
                 % (rep.path("jack.txt"), int(virgin.sum())))
        return
    h_max = float(depth[virgin].max())
    try:
        fit = fit_qc_trend(depth[virgin], qc[virgin], b_min=1.0 / h_max)
    except (ValueError, RuntimeError) as exc:
        rep.skip("q_c trend fit", "%s: the fit failed (%s)" % (rep.path("jack.txt"), exc))
        return
    ctx["fit"] = fit
    h = np.linspace(0.0, float(depth.max()), 200)
    band, cov = qc_trend_band(h, depth[virgin], qc[virgin], fit.a, fit.b)
    levelled = bool(fit.b * h_max > 3.0)
    rep.put("qc", fit_h=h, fit_qc=fit.a * -np.expm1(-fit.b * h), fit_qc_std=band, fit_cov=cov)
    rep.attrs("qc", a=fit.a, b=fit.b, a_err=fit.a_err, b_err=fit.b_err,
              levelled_off=int(levelled), R=R,
              model="q_c = a (1 - exp(-b h)) on virgin penetration; b >= 1 / max depth")
    rep.head["qc_steady_MPa"] = fit.a / 1e6
    rep.head["qc_steady_err_MPa"] = fit.a_err / 1e6
    rep.head["qc_fit_b_per_m"] = fit.b
    rep.head_notes["qc_steady_MPa"] = (
        "a of q_c = a (1 - exp(-b h)) fitted to %d points of virgin penetration; %s"
        % (int(virgin.sum()), "levelled off (b h_max = %.1f > 3)" % (fit.b * h_max) if levelled
           else "NOT levelled off (b h_max = %.2f): a lower estimate of the plateau"
           % (fit.b * h_max)))
    rep.head_notes["qc_steady_err_MPa"] = "standard error of a from the fit's covariance"
    _qc_scatter(rep, ctx, fit)
    fig, ax = plt.subplots(figsize=(5.5, 4.6))
    push = phase == PHASE_PUSH
    ax.plot(qc / 1e6, depth * 1e3, "-", lw=0.7, color="0.65", label="all phases")
    ax.plot(qc[push & ~virgin] / 1e6, depth[push & ~virgin] * 1e3, "x", ms=3, color="C1",
            label="re-push after an unload (not fitted)")
    ax.plot(qc[virgin] / 1e6, depth[virgin] * 1e3, ".", ms=2, color="C0",
            label="virgin penetration (fitted)")
    trend = fit.a * -np.expm1(-fit.b * h)
    ax.fill_betweenx(h * 1e3, (trend - band) / 1e6, (trend + band) / 1e6, color="k", alpha=0.15,
                     lw=0, label="trend +- 1 s.d. (fit covariance)")
    ax.plot(trend / 1e6, h * 1e3, "k--", lw=1.0,
            label="a (1 - exp(-b h)): a = %.3g +- %.2g MPa" % (fit.a / 1e6, fit.a_err / 1e6))
    ax.invert_yaxis()
    ax.set_xlabel("tip resistance q_c (MPa)")
    ax.set_ylabel("tip depth below the sand surface (mm)")
    ax.legend(fontsize=7, loc="lower left")
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    rep.figure(fig, "qc_depth.png", "Tip resistance against depth",
               "q_c = F_cone / (pi R^2) from jack.txt; the trend is fitted to virgin "
               "penetration only (pushing, tip at its deepest so far); the band is one standard "
               "deviation of the trend from the fit's covariance. %s"
               % rep.head_notes["qc_steady_MPa"])


def _qc_scatter(rep, ctx, fit):
    """The run-to-run scatter of steady q_c measured by the error-vs-runtime
    study (pooled over the runs of its reference setting, read from its
    committed results table) next to the fit's standard error, and which of
    the two dominates."""
    grains = ctx["summary"].get("grains")
    if grains is None:
        rep.skip("q_c run-to-run scatter", "%s names no grain model ('grains')"
                 % rep.path("summary.json"))
        return
    sc = qc_run_scatter(grains)
    if sc is None:
        rep.skip("q_c run-to-run scatter", "no pooled spread of steady q_c for grains %r in %s"
                 % (grains, STUDY_TABLE))
        return
    scatter, dominates = qc_uncertainty(fit.a, fit.a_err, sc["rel_sd"])
    which = "run-to-run scatter" if dominates else "fit standard error"
    rep.head["qc_run_scatter_MPa"] = float(scatter) / 1e6
    rep.head_notes["qc_run_scatter_MPa"] = (
        "one run's standard deviation of steady q_c between packings of the same setting, "
        "%.1f %% of q_c (%s grains: sample sd over the %d runs of the error-vs-runtime study's "
        "reference chamber, two packing seeds and two time steps; %s, chamber_spread); against "
        "the fit's standard error %.3g MPa the %s dominates"
        % (100.0 * sc["rel_sd"], grains, len(sc["runs"]),
           STUDY_TABLE_NAME if sc["source"] == STUDY_TABLE else sc["source"],
           fit.a_err / 1e6, which))
    rep.attrs("qc", run_scatter_rel=sc["rel_sd"], run_scatter=float(scatter),
              uncertainty_dominated_by=which)


def _log_numbers(rep, ctx):
    text = ctx["log"]
    if text is None:
        return
    blocks = [b for b in parse_log(text) if "qc" in b and "Atoms" in b]
    lost = re.findall(r"^ERROR.*Lost atoms: original (\d+) current (\d+)", text, re.M)
    if lost:
        rep.head["lost_atoms"] = int(lost[-1][0]) - int(lost[-1][1])
        rep.head_notes["lost_atoms"] = "the run stopped: LIGGGHTS' 'Lost atoms' error in the log"
    if not blocks:
        rep.skip("mass balance", "%s: no thermo block of the jacking (columns qc, Atoms)"
                 % rep.path("log.liggghts"))
        return
    first, last = blocks[0], blocks[-1]
    if "M_grains" in first and "fines" in last:
        # with crushing on in the preparation (cpt_demo --crush-in-prep) the
        # fix's fines start the jacking above 0: M_0 is grains + fines then
        m0 = first["M_grains"][0] + (first["fines"][0] if "fines" in first else 0.0)
        err = abs(last["M_grains"][-1] + last["fines"][-1] - m0) / m0
        rep.head["mass_balance_rel_error"] = float(err)
        rep.head_notes["mass_balance_rel_error"] = (
            "|M_grains + fines - M_0| / M_0 from the log's thermo output (M_0 = M_grains + "
            "fines at the start of jacking)")
        ctx["M0"] = float(m0)
    if "n_break" in last:
        n_break = int(last["n_break"][-1])
        rep.head["n_break_events"] = n_break
        # breaks before jacking (crushing on in the preparation) are in the
        # fix's count at the jacking's first row, and their fragments in Atoms
        n_break0 = int(first["n_break"][0]) if "n_break" in first else 0
        if "lost_atoms" not in rep.head:
            expected = int(first["Atoms"][0]) + 13 * (n_break - n_break0)
            rep.head["lost_atoms"] = expected - int(last["Atoms"][-1])
            rep.head_notes["lost_atoms"] = (
                "atoms at the start of jacking + 13 per break - atoms at the end (log)")
        events = ctx["events"]
        if events is not None and "Step" in first:
            # crushing is switched on with the jacking: the weakest grains of
            # the strength scatter (f_p far below 1, F_lim ~ f_p^3) are already
            # loaded past their limit by the prepared state and break at the
            # first step, wherever they are, not because of the pile
            start = int(first["Step"][0])
            ctx["jack_first_step"] = start + 1
            rep.head["n_break_events_first_step"] = int(np.count_nonzero(events["step"] == start + 1))
            rep.head_notes["n_break_events_first_step"] = (
                "break events at the first step of jacking (step %d), when crushing is switched "
                "on: grains the prepared state already loads past their limit, not the pile's; "
                "counted in n_break_events and in Br" % (start + 1))
            n_prep = int(np.count_nonzero(events["step"] <= start))
            if n_prep:
                rep.head["n_break_events_prep"] = n_prep
                rep.head_notes["n_break_events_prep"] = (
                    "break events before jacking (step <= %d): crushing on in the preparation "
                    "(cpt_demo --crush-in-prep); counted in n_break_events and in Br" % start)
    if "Br" in last:
        rep.head["Br_sample"] = float(last["Br"][-1])
        rep.head_notes["Br_sample"] = "the fix's bounded Br of the whole sample at the end (log)"


# ---------------------------------------------------------------------------
# the snapshots: rings, rotation, Br bands, PSD, increments
# ---------------------------------------------------------------------------

def _state_info(snap, kind_hint, jack, z_ref):
    step = snap["step"]
    info = {"step": step, "time": snap["time"], "file": os.path.basename(snap["path"])}
    if kind_hint == "initial":
        info["kind"] = "initial"
    else:
        old = snap.get("trigger_old")
        info["kind"] = ("push_end" if old == PHASE_PUSH else
                        "pause_end" if old == PHASE_PAUSE else "other")
    if jack is not None:
        if kind_hint == "initial":
            info["depth"] = 0.0
            info["cycle"] = 0
        else:
            info["depth"] = float(np.interp(step, jack["step"], jack["depth"]))
            # the row before the snapshot's step: a row at the step itself is
            # written after the phase change (the next cycle's number)
            k = max(int(np.searchsorted(jack["step"], step, side="left")) - 1, 0)
            info["cycle"] = int(jack["cycle"][k]) if "cycle" in jack else 0
        info["z_tip"] = z_ref - info["depth"]
    return info


def _grid(rep, ctx, snap0):
    s = ctx["summary"]
    x, rad = snap0["particles"]["x"], snap0["particles"]["radius"]
    rho = np.hypot(x[:, 0], x[:, 1])
    r_max = s.get("R_chamber_m") or float(np.max(rho + rad))
    z_ref = ctx["z_ref"]
    if z_ref is None:
        z_ref = float(np.max(x[:, 2] + rad))
        ctx["z_ref_note"] = "the top of the highest grain of the first snapshot (no jack.txt)"
        ctx["z_ref"] = z_ref
    z_bot = min(0.0, float(np.min(x[:, 2] - rad)))
    r_edges = ring_edges(ctx["ring_width"], r_max)
    # layers from the sand surface down, the remainder at the bottom
    z_edges = z_ref - ring_edges(rep.opt.ring_height, z_ref - z_bot)[::-1]
    sector = rep.opt.sector or s.get("sector_deg")
    if not sector:
        # a sector's grains lie on one side of its symmetry planes
        tol = 1e-9
        sector = 90 if (x[:, 0].min() > -tol and x[:, 1].min() > -tol) else \
            180 if x[:, 1].min() > -tol else 360
    return r_edges, z_edges, int(sector)


def _states(rep, ctx):
    prep = list_snapshots(rep.path("snapshots", "prep"))
    jacks = list_snapshots(rep.path("snapshots", "jack"))
    if not prep and not jacks:
        rep.skip("ring fields, rotation, Br bands, PSD, displacement increments",
                 "no snapshots (%s_<step>.h5 or %s_<step>.h5)"
                 % (rep.path("snapshots", "prep"), rep.path("snapshots", "jack")))
        return
    if not prep:
        rep.skip("initial state", "no prepared-state snapshot %s_<step>.h5: rotations and Br "
                 "are relative to the first push end" % rep.path("snapshots", "prep"))
    files = [(str(p), "initial") for _, p in prep[-1:]] + [(str(p), "jack") for _, p in jacks]
    R, jack = ctx["R"], ctx["jack"]
    opt = rep.opt
    grid = None
    states, prev, first = [], None, None
    arrays = {}
    band_rows = []
    psd_rows = []
    incr = []
    N = ctx["N"]
    if N:
        d_min, d_max = D_MIN_REAL * N, D_MAX_REAL * N
        sizes = np.geomspace(d_min, d_max, 60)
        ctx["psd_sizes"] = sizes
    else:
        rep.skip("Br in bands, PSD", "the up-scaling factor N is unknown (no summary.json): "
                 "give --N")
    events = ctx["events"]
    if N and events is None:
        rep.skip("fines in Br and the PSD", "no event log: Br in bands and the PSD count the "
                 "grains only (right for unbreakable grains)")
    t_read = t_stress = t_rings = 0.0
    for path, hint in files:
        t = time.time()
        try:
            snap = read_snapshot_checked(path)
        except ReportInputError as exc:
            rep.error(str(exc))
            continue
        t_read += time.time() - t
        if grid is None:
            grid = _grid(rep, ctx, snap)
            r_edges, z_edges, sector = grid
            ctx["sector"] = sector
            n_z = z_edges.size - 1
        info = _state_info(snap, hint, jack, ctx["z_ref"])
        p = snap["particles"]
        x, rad, ids = p["x"], p["radius"], p["id"]
        t = time.time()
        try:
            sig = snapshot_particle_stress(snap)
        except ValueError as exc:
            rep.error("%s: %s" % (path, reason(exc, path)))
            continue
        t_stress += time.time() - t
        t = time.time()
        trip = sphere_cell_volumes(x, rad, r_edges, z_edges)
        rf = ring_fields(sig, x, rad, r_edges, z_edges, sector=sector, triplets=trip)
        t_rings += time.time() - t
        q = stress_quantities(rf["sigma"])
        for k, v in q.items():
            arrays.setdefault(k, []).append(v)
        for k in ("porosity", "n_grains", "n_equiv"):
            arrays.setdefault(k, []).append(rf[k])
        states.append(info)
        # utilisation of the grains by zone around the tip (compute crush/atom
        # through the decks' v_utilisation), at the ends of pushes
        u = p.get("values", {}).get("v_utilisation")
        if u is not None and info.get("z_tip") is not None and info.get("kind") == "push_end":
            hh_u, rr_u = relative_to_tip(x[:, 0], x[:, 1], x[:, 2], info["z_tip"], R)
            ctx.setdefault("utilisation", []).append(
                (info, utilisation_by_zone(hh_u, rr_u, np.ravel(u))))
        # Br in radial bands x layers, and the PSD of the whole sample
        if N:
            b_edges = _band_edges(r_edges[-1] / R, opt.band_width)
            rr = np.hypot(x[:, 0], x[:, 1]) / R
            cell = _band_cell(rr, x[:, 2], b_edges, z_edges)
            if first is None:
                first = {"cell": cell, "d": 2 * rad, "ids": ids, "step": info["step"], "z": x[:, 2]}
            fines = None
            if events is not None:
                # the breaks since the first state (earlier ones are in its grains)
                ev_sel = (events["step"] > first["step"]) & (events["step"] <= info["step"])
                erho = np.hypot(events["x"][ev_sel], events["y"][ev_sel]) / R
                ev_cell = _band_cell(erho, events["z"][ev_sel], b_edges, z_edges)
                pd = events["parent_diameter"][ev_sel]
                fines = break_fines(pd, density=opt.density) if pd.size else None
            else:
                ev_cell, pd = None, None
            n_cells = (b_edges.size - 1) * n_z
            br, M, M0 = cell_breakage(cell, 2 * rad, first["cell"], first["d"], n_cells, d_min,
                                      d_max, ev_cell, pd, density=opt.density)
            # whole bands over the full height: a second pass with one layer
            cb = np.where(cell >= 0, cell // n_z, -1)
            cb0 = np.where(first["cell"] >= 0, first["cell"] // n_z, -1)
            evb = None if ev_cell is None else np.where(ev_cell >= 0, ev_cell // n_z, -1)
            br_b, _, _ = cell_breakage(cb, 2 * rad, cb0, first["d"], b_edges.size - 1, d_min,
                                       d_max, evb, pd, density=opt.density)
            # whole bands over the layers the tip has passed (z_tip < z < z_ref):
            # the penetrated height, not the untouched sand below the tip
            br_p = np.full(b_edges.size - 1, np.nan)
            z_tip = info.get("z_tip")
            if z_tip is not None and z_tip < ctx["z_ref"]:
                def passed(zz):
                    return (zz > z_tip) & (zz < ctx["z_ref"])
                cp = np.where(passed(x[:, 2]), cb, -1)
                cp0 = np.where(passed(first["z"]), cb0, -1)
                evp = None if evb is None else np.where(passed(events["z"][ev_sel]), evb, -1)
                br_p, _, _ = cell_breakage(cp, 2 * rad, cp0, first["d"], b_edges.size - 1, d_min,
                                           d_max, evp, pd, density=opt.density)
            band_rows.append((br.reshape(-1, n_z), br_b, br_p))
            ctx["band_edges"] = b_edges
            m = sphere_mass(2 * rad, opt.density)
            psd_rows.append(psd_curve(2 * rad, m, 0.0, sizes, fines=fines, d_min=d_min))
        # radial displacement increments since the previous state
        if prev is not None:
            inc = radial_increments(prev["ids"], prev["x"], ids, x)
            x0 = prev["x"][inc["rows0"]]
            r0 = np.hypot(x0[:, 0], x0[:, 1])
            mean, cnt = binned_mean(r0, x0[:, 2], inc["dr"], r_edges, z_edges)
            z_tip = info.get("z_tip")
            incr.append({"from": prev["info"], "to": info, "r0": r0, "z0": x0[:, 2],
                         "dr": inc["dr"], "mean": mean, "count": cnt, "z_tip": z_tip,
                         "n_matched": inc["n_matched"], "n_only0": inc["n_only0"],
                         "n_only1": inc["n_only1"]})
        prev = {"ids": ids, "x": x, "info": info}
    if not states:
        return
    rep.say("snapshots: %d states read in %.1f s, particle stresses %.1f s, rings %.1f s"
            % (len(states), t_read, t_stress, t_rings))
    A = {k: np.array(v) for k, v in arrays.items()}
    A["rotation"] = axis_rotation(A["psi"], axis=0)
    A["psi_unwrapped"] = unwrap_axis(A["psi"], axis=0)
    A["low_count"] = (A["n_grains"] < opt.min_grains).astype(np.int8)
    ctx.update(states=states, A=A, r_edges=r_edges, z_edges=z_edges, incr=incr)
    r_mid = 0.5 * (r_edges[1:] + r_edges[:-1])
    z_mid = 0.5 * (z_edges[1:] + z_edges[:-1])
    ctx["r_mid"], ctx["z_mid"] = r_mid, z_mid
    _store_states(rep, ctx)
    if band_rows:
        ctx["Br_cells"] = np.array([b for b, _, _ in band_rows])
        ctx["Br_bands"] = np.array([b for _, b, _ in band_rows])
        ctx["Br_bands_penetrated"] = np.array([b for _, _, b in band_rows])
        last_pen = ctx["Br_bands_penetrated"][-1]
        b_edges = ctx["band_edges"]
        for lo, key in ((1.0, "Br_penetrated_1_2R"), (2.0, "Br_penetrated_2_3R")):
            k = np.flatnonzero(np.isclose(b_edges[:-1], lo) & np.isclose(b_edges[1:], lo + 1.0))
            if k.size and np.isfinite(last_pen[k[0]]):
                rep.head[key] = float(last_pen[k[0]])
                rep.head_notes[key] = (
                    "Br of the band %g < r/R < %g over the layers the tip has passed (between the "
                    "tip and the sand surface) at the last snapshot" % (lo, lo + 1))
        ctx["psd"] = np.array(psd_rows)
    _fig_initial(rep, ctx)
    _fig_contours(rep, ctx)
    _fig_profiles(rep, ctx)
    _fig_histories(rep, ctx)
    _fig_rotation(rep, ctx)
    _fig_bands(rep, ctx)
    _fig_psd(rep, ctx)
    _fig_increments(rep, ctx)
    _fig_utilisation(rep, ctx)


def _fig_utilisation(rep, ctx):
    """How far the grains' contacts stand from their limits, by zone, at the
    last end of a push (steady penetration)."""
    rows = ctx.get("utilisation")
    if not rows:
        rep.skip("utilisation by zone", "the snapshots carry no v_utilisation (decks before "
                 "compute crush/atom, or unbreakable grains)")
        return
    info, zones = rows[-1]
    names = [z[0] for z in UTILISATION_ZONES]
    for z in names:
        for stat in ("median", "p90", "max"):
            rep.head["utilisation_%s_%s" % (z, stat)] = zones[z][stat]
    rep.head_notes["utilisation_below_tip_max"] = (
        "utilisation = the largest F_n / F_lim over a grain's contacts (compute crush/atom), "
        "at the last end of a push (step %d); zones in R around the apex: %s"
        % (info["step"], "; ".join("%s %g<=r<%g, %g<=h<%g" % z for z in UTILISATION_ZONES)))
    rep.put("utilisation", step=np.array([i["step"] for i, _ in rows]),
            **{"%s_%s" % (z, st): np.array([zz[z][st] for _, zz in rows])
               for z in names for st in ("n", "median", "p90", "max")})
    plt = _plt()
    fig, ax = plt.subplots(figsize=(5.6, 4.2))
    for z in names:
        v = np.sort(zones["values"][z])
        v = v[v > 0]
        if v.size:
            ax.step(v, np.arange(1, v.size + 1) / v.size, where="post",
                    label="%s (%d grains in contact)" % (z.replace("_", " "), v.size))
    ax.axvline(1.0, color="k", lw=0.8, ls=":")
    ax.set_xscale("log")
    ax.set_xlabel("utilisation: largest F_n / F_lim of the grain's contacts (-)")
    ax.set_ylabel("fraction of the zone's grains below (-)")
    ax.set_title("contacts against their limits, step %d" % info["step"], fontsize=9)
    ax.legend(fontsize=7)
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    rep.figure(fig, "utilisation.png", "Contacts against their limits",
               "Distribution of each grain's utilisation (its largest F_n / F_lim, with the run's "
               "criterion reading) by zone around the tip at the last end of a push; 1 (dotted) "
               "breaks the grain.")


def _band_edges(r_max, width):
    """Band edges in r/R from 1 (the shaft) to r_max by ``width``; the last
    band ends at r_max (one narrower than width/4 joins the band before)."""
    edges = list(np.arange(1.0, r_max, width))
    if r_max - edges[-1] < 0.25 * width and len(edges) > 1:
        edges[-1] = r_max
    else:
        edges.append(r_max)
    return np.array(edges)


def _band_cell(r_over_R, z, b_edges, z_edges):
    """Cell index band * n_z + layer of points (-1 outside)."""
    n_b, n_z = b_edges.size - 1, z_edges.size - 1
    i = np.searchsorted(b_edges, r_over_R, side="right") - 1
    k = np.searchsorted(z_edges, z, side="right") - 1
    ok = (i >= 0) & (i < n_b) & (k >= 0) & (k < n_z)
    return np.where(ok, i * n_z + k, -1)


def _qc_norm(rep, ctx):
    """q_c that normalises each state's stresses (NaN for the initial state)."""
    states = ctx["states"]
    steps = np.array([s["step"] for s in states])
    if rep.opt.qc_norm == "steady" and "fit" in ctx:
        out = np.full(steps.shape, ctx["fit"].a)
    elif rep.opt.qc_norm == "steady":
        rep.skip("--qc-norm steady", "no trend fit of q_c; the stresses are over q_c at the "
                 "end of the last push")
        out = _qc_norm_push(ctx, steps)
    else:
        out = _qc_norm_push(ctx, steps)
    kinds = np.array([s["kind"] for s in states])
    return np.where(kinds == "initial", np.nan, out)


def _qc_norm_push(ctx, steps):
    if ctx["jack"] is None:
        return np.full(steps.shape, np.nan)
    return qc_reference(steps, ctx["jack"]["step"], ctx["qc_series"], ctx["jack"]["phase"])


def _store_states(rep, ctx):
    states, A, R = ctx["states"], ctx["A"], ctx["R"]
    qn = _qc_norm(rep, ctx)
    ctx["qc_norm"] = qn
    st = {"step": np.array([s["step"] for s in states], dtype=np.int64),
          "time": np.array([s["time"] for s in states]),
          "kind": np.array([s["kind"] for s in states], dtype="S"),
          "file": np.array([s["file"] for s in states], dtype="S"),
          "qc_norm": qn}
    if "z_tip" in states[0]:
        st["depth"] = np.array([s["depth"] for s in states])
        st["z_tip"] = np.array([s["z_tip"] for s in states])
        st["cycle"] = np.array([s["cycle"] for s in states], dtype=np.int64)
        ctx["h_over_R"] = (ctx["z_mid"][None, :] - st["z_tip"][:, None]) / R
        rep.put("rings", h_over_R=ctx["h_over_R"])
    rep.put("states", **st)
    rep.put("rings", r_edges=ctx["r_edges"], z_edges=ctx["z_edges"], r_mid=ctx["r_mid"],
            z_mid=ctx["z_mid"], r_over_R=ctx["r_mid"] / R, **A)
    rep.attrs("rings", sector=ctx["sector"], ring_width=ctx["ring_width"],
              ring_height=rep.opt.ring_height, min_grains=rep.opt.min_grains,
              z_ref=ctx["z_ref"], R=R)
    ok = A["low_count"] == 0
    rot = np.where(ok, np.abs(A["rotation"]), np.nan)
    if np.any(np.isfinite(rot)):
        k = np.unravel_index(np.nanargmax(rot), rot.shape)
        rep.head["max_rotation_deg"] = float(A["rotation"][k])
        rep.head_notes["max_rotation_deg"] = (
            "largest |rotation| of the (r, z) major principal axis since the first state, over "
            "the rings with at least %d grains: ring r/R = %.2f, z = %.4g m, at the state of "
            "step %d" % (rep.opt.min_grains, ctx["r_mid"][k[1]] / R, ctx["z_mid"][k[2]],
                         states[k[0]]["step"]))
    if states[0]["kind"] == "initial":
        okr = ok[0]
        rep.head["porosity_initial"] = float(np.mean(A["porosity"][0][okr])) if okr.any() \
            else float(np.mean(A["porosity"][0]))
        for c in COMPONENTS:
            v = A[c][0][okr] if okr.any() else A[c][0].ravel()
            rep.head[c + "_initial_kPa"] = float(np.mean(v) / 1e3)
        note = ("mean over the rings of the prepared state with at least %d grains"
                % rep.opt.min_grains if okr.any() else "mean over all rings of the prepared "
                "state (none has %d grains)" % rep.opt.min_grains)
        for name in ("porosity_initial",) + tuple(c + "_initial_kPa" for c in COMPONENTS):
            rep.head_notes[name] = note


def _state_label(s):
    lab = {"initial": "prepared state", "push_end": "end of push", "pause_end": "end of pause",
           "other": "state"}[s["kind"]]
    if s["kind"] in ("push_end", "pause_end") and "cycle" in s:
        lab += " %d" % s["cycle"]
    if "depth" in s:
        lab += ", tip %.3g mm" % (s["depth"] * 1e3)
    return lab


def _short_label(s):
    if s["kind"] == "initial":
        return "prepared"
    return "%s %s" % ({"push_end": "push", "pause_end": "pause"}.get(s["kind"], "state"),
                      s.get("cycle", ""))


def _fig_initial(rep, ctx):
    states, A, R = ctx["states"], ctx["A"], ctx["R"]
    if states[0]["kind"] != "initial":
        return
    plt = _plt()
    z_ref = ctx["z_ref"]
    re_ = ctx["r_edges"] / R
    de = (ctx["z_edges"] - z_ref) / R
    fig, axes = plt.subplots(1, 4, figsize=(12, 3.8), sharey=True)
    panels = [("porosity", A["porosity"][0], "porosity (-)", 1.0)] + [
        (c, A[c][0] / 1e3, LABEL[c] + " (kPa)", 1.0) for c in COMPONENTS]
    low = A["low_count"][0]
    for ax, (name, v, lab, _) in zip(axes, panels):
        m = ax.pcolormesh(re_, de, v.T, shading="flat", cmap="viridis")
        _hatch_low(ax, re_, de, low)
        fig.colorbar(m, ax=ax, label=lab, shrink=0.85)
        ax.set_xlabel("r / R (-)")
        ax.set_title(lab.split(" (")[0])
    axes[0].set_ylabel("(z - z_ref) / R, height above the sand surface (-)")
    fig.suptitle("prepared state (step %d): ring averages" % states[0]["step"], fontsize=10)
    fig.tight_layout()
    rep.figure(fig, "initial_state.png", "Initial state",
               "Ring averages of the prepared state (snapshots/prep_<step>.h5): porosity "
               "(1 - solid volume / ring volume, exact sphere-ring intersections) and the "
               "cylindrical stresses. Hatched rings hold fewer than %d grains (centres)."
               % rep.opt.min_grains)


def _hatch_low(ax, xe, ye, low):
    if not np.any(low):
        return
    ax.pcolor(xe, ye, np.ma.masked_where(~low.T.astype(bool), np.ones_like(low.T, float)),
              hatch="///", alpha=0.0, shading="flat", zorder=2)


def _fig_contours(rep, ctx):
    states, A, R = ctx["states"], ctx["A"], ctx["R"]
    if "h_over_R" not in ctx:
        rep.skip("stress contours", "no tip position (jack.txt)")
        return
    plt = _plt()
    qn = ctx["qc_norm"]
    re_ = ctx["r_edges"] / R
    names = []
    for k, s in enumerate(states):
        if s["kind"] == "initial":
            continue
        if not qn[k] > 0:
            rep.skip("stresses over q_c at the %s" % _state_label(s),
                     "q_c at the end of the last push is %s (the cone touched no grain; "
                     "--qc-norm steady normalises by the trend's plateau)" % _fmt(qn[k]))
            continue
        he = (ctx["z_edges"] - s["z_tip"]) / R
        fig, axes = plt.subplots(1, 3, figsize=(12, 4.2), sharey=True)
        for ax, c in zip(axes, COMPONENTS):
            v = A[c][k] / qn[k]
            m = ax.pcolormesh(re_, he, v.T, shading="flat", cmap="magma_r")
            finite = np.isfinite(v)
            # contour lines only on grids fine enough to draw them
            if finite.all() and min(v.shape) >= 4:
                rc = 0.5 * (re_[1:] + re_[:-1])
                hc = 0.5 * (he[1:] + he[:-1])
                try:
                    cs = ax.contour(rc, hc, v.T, colors="w", linewidths=0.6, levels=6)
                    ax.clabel(cs, fontsize=6, fmt="%.2g")
                except (ValueError, TypeError):
                    pass
            _hatch_low(ax, re_, he, A["low_count"][k])
            _pile_outline(ax, he[-1])
            fig.colorbar(m, ax=ax, label=LABEL[c] + " / q_c (-)", shrink=0.85)
            ax.set_xlabel("r / R (-)")
            ax.set_xlim(0, re_[-1])
            ax.set_ylim(he[0], he[-1])
        axes[0].set_ylabel("h / R, height above the cone apex (-)")
        fig.suptitle("%s: stresses over q_c = %.3g MPa" % (_state_label(s), qn[k] / 1e6),
                     fontsize=10)
        fig.tight_layout()
        name = "stress_%s%s.png" % ({"push_end": "push", "pause_end": "pause"}.get(
            s["kind"], "state"), s.get("cycle", ""))
        if name in names:
            name = name[:-4] + "_step%d.png" % s["step"]
        rep.figure(fig, name, "Stresses around the pile, %s" % _state_label(s),
                   "Ring averages of sigma_r, sigma_theta, sigma_z over q_c (%s) in (r/R, h/R); "
                   "h is the height above the cone apex at this state. Hatched: fewer than %d "
                   "grains in the ring."
                   % ("q_c at the end of the last push" if rep.opt.qc_norm == "push"
                      else "steady q_c", rep.opt.min_grains))
        names.append(name)


def _fig_profiles(rep, ctx):
    states, A, R = ctx["states"], ctx["A"], ctx["R"]
    if "h_over_R" not in ctx:
        return
    plt = _plt()
    qn = ctx["qc_norm"]
    hs = np.array(rep.opt.profile_h, dtype=float)
    rmid = ctx["r_mid"] / R
    ks = [k for k, s in enumerate(states) if s["kind"] != "initial" and qn[k] > 0]
    if not ks:
        return
    prof = np.full((len(states), hs.size, rmid.size, 3), np.nan)
    for k in ks:
        zt = states[k]["z_tip"] + hs * R
        for j, c in enumerate(COMPONENTS):
            prof[k, :, :, j] = interp_columns(A[c][k], ctx["z_mid"], zt) / qn[k]
    rep.put("profiles", h_over_R=hs, r_over_R=rmid, values=prof)
    rep.attrs("profiles", layout="values[state, h, ring column, component]; components "
              "sigma_r, sigma_theta, sigma_z over q_c; linear in z between layer centres, "
              "NaN outside them")
    fig, axes = plt.subplots(hs.size, 3, figsize=(11, 2.6 * hs.size), squeeze=False,
                             sharex=True)
    cmap = plt.get_cmap("viridis")
    for i, h in enumerate(hs):
        for j, c in enumerate(COMPONENTS):
            ax = axes[i, j]
            for n, k in enumerate(ks):
                ls = "-" if states[k]["kind"] == "push_end" else ":"
                ax.plot(rmid, prof[k, i, :, j], ls, marker=".", color=cmap(n / max(len(ks) - 1, 1)),
                        label=_state_label(states[k]) if i == 0 and j == 0 else None)
            ax.set_title("%s / q_c at h/R = %g" % (LABEL[c], h), fontsize=9)
            ax.grid(True, alpha=0.3)
            if i == hs.size - 1:
                ax.set_xlabel("r / R (-)")
    axes[0, 0].legend(fontsize=6)
    fig.tight_layout()
    rep.figure(fig, "radial_profiles.png", "Radial profiles",
               "Ring-averaged stresses over q_c against r/R at chosen heights h/R above the "
               "apex (--profile-h), linear in z between layer centres; solid: ends of pushes, "
               "dotted: ends of pauses. Gaps: the height is outside the sample.")


def _fig_histories(rep, ctx):
    states, A, R = ctx["states"], ctx["A"], ctx["R"]
    if "h_over_R" not in ctx:
        return
    plt = _plt()
    qn = ctx["qc_norm"]
    ks = [k for k, s in enumerate(states) if s["kind"] != "initial" and qn[k] > 0]
    re_ = ctx["r_edges"] / R
    rm = ctx["r_mid"] / R
    lines = []
    for r in rep.opt.history_r:
        if not re_[0] <= r <= re_[-1]:
            rep.skip("stress history at r/R = %g" % r, "outside this chamber (r/R <= %.3g)"
                     % re_[-1])
            continue
        lines.append(r)
    if not lines or not ks:
        return
    fig, axes = plt.subplots(len(lines), 3, figsize=(11, 2.8 * len(lines)), squeeze=False)
    n_z = ctx["z_mid"].size
    cmap = plt.get_cmap("plasma")
    hr = ctx["h_over_R"][ks]                           # (n_k, n_z)
    for a, r in enumerate(lines):
        grp = "histories/r_over_R_%g" % r
        # linear in r between the centres of the two ring columns around r
        vals = {c: interp_radius(A[c][ks], rm, r, axis=1) / qn[ks][:, None] for c in COMPONENTS}
        rep.put(grp, state=np.array(ks), h_over_R=hr, **vals)
        rep.attrs(grp, r_over_R=r)
        for j, c in enumerate(COMPONENTS):
            ax = axes[a, j]
            for z in range(n_z):
                ax.plot(vals[c][:, z], hr[:, z], "-o", ms=2.5, lw=0.8,
                        color=cmap(z / max(n_z - 1, 1)),
                        label="layer z = %.3g m" % ctx["z_mid"][z] if a == 0 and j == 0 else None)
            ax.axhline(0.0, color="k", lw=0.5, ls=":")
            ax.set_title("%s / q_c at r/R = %g" % (LABEL[c], r), fontsize=9)
            ax.set_ylabel("h / R (-)")
            ax.grid(True, alpha=0.3)
    axes[0, 0].legend(fontsize=6)
    fig.tight_layout()
    rep.figure(fig, "stress_history.png", "Stress histories along r/R lines",
               "Each curve follows one fixed point (a layer's centre height on the line r/R, "
               "linear in r between the two ring columns around it) through the states (ends "
               "of pushes and pauses): its stress over q_c against its height h/R above the "
               "apex, which rises as the tip goes down past it.")


def _fig_rotation(rep, ctx):
    states, A, R = ctx["states"], ctx["A"], ctx["R"]
    if len(states) < 2:
        return
    plt = _plt()
    last = len(states) - 1
    re_ = ctx["r_edges"] / R
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    if "h_over_R" in ctx:
        ye = (ctx["z_edges"] - states[last]["z_tip"]) / R
        ylab = "h / R at the last state (-)"
    else:
        ye = (ctx["z_edges"] - ctx["z_ref"]) / R
        ylab = "(z - z_ref) / R (-)"
    rot = A["rotation"][last]
    lim = max(90.0, float(np.nanmax(np.abs(rot))) if np.any(np.isfinite(rot)) else 90.0)
    m = axes[0].pcolormesh(re_, ye, rot.T, cmap="RdBu_r", vmin=-lim, vmax=lim, shading="flat")
    _hatch_low(axes[0], re_, ye, A["low_count"][last])
    if "h_over_R" in ctx:
        _pile_outline(axes[0], ye[-1])
        axes[0].set_ylim(ye[0], ye[-1])
    fig.colorbar(m, ax=axes[0], label="rotation since the first state (deg)")
    axes[0].set_xlabel("r / R (-)")
    axes[0].set_ylabel(ylab)
    axes[0].set_title(_state_label(states[last]), fontsize=9)
    ok = A["low_count"] == 0
    steps = np.arange(len(states))
    cand = np.where(ok.all(axis=0), np.nanmax(np.abs(A["rotation"]), axis=0), -1.0)
    top = np.argsort(cand.ravel())[::-1][:6]
    for f in top:
        i, z = np.unravel_index(f, cand.shape)
        if cand[i, z] < 0:
            continue
        axes[1].plot(steps, A["rotation"][:, i, z], "-o", ms=3,
                     label="r/R = %.2f, z = %.3g m" % (ctx["r_mid"][i] / R, ctx["z_mid"][z]))
    axes[1].set_xticks(steps)
    axes[1].set_xticklabels([_short_label(s) for s in states], fontsize=7, rotation=90)
    axes[1].set_ylabel("rotation of the major axis (deg)")
    axes[1].set_title("the rings that turned most", fontsize=9)
    axes[1].grid(True, alpha=0.3)
    axes[1].legend(fontsize=6)
    fig.tight_layout()
    rep.figure(fig, "rotation.png", "Rotation of the principal axes",
               "Angle of the major principal direction of the (sigma_r, tau_rz; tau_rz, "
               "sigma_z) ring average from the vertical, unwrapped through the states (each "
               "step the smallest change modulo 180 deg) and taken relative to the first state, "
               "at fixed rings. Needs states close enough that the axis turns < 90 deg between "
               "two (docs/report.md).")


def _fig_bands(rep, ctx):
    if "Br_cells" not in ctx:
        return
    plt = _plt()
    states = ctx["states"]
    b_edges = ctx["band_edges"]
    br = ctx["Br_cells"]                  # (n_state, n_band, n_z)
    brb = ctx["Br_bands"]                 # (n_state, n_band)
    rep.put("breakage/bands", band_edges_over_R=b_edges, z_edges=ctx["z_edges"], Br=br,
            Br_band=brb, Br_band_penetrated=ctx["Br_bands_penetrated"])
    rep.attrs("breakage/bands", definition=(
        "bounded Einav Br of the grains whose centre is in band x layer now, plus the fines of "
        "the breaks whose parent was in it (fractal), against the grains in it in the first "
        "state; Br_band: the whole height; Br_band_penetrated: the layers between the tip and "
        "the sand surface (NaN for the prepared state)"))
    last = len(states) - 1
    z_tip = states[last].get("z_tip")
    bands = ["%.3g<r/R<%.3g" % (b_edges[i], b_edges[i + 1]) for i in range(b_edges.size - 1)]
    if z_tip is not None:
        k = int(np.clip(np.searchsorted(ctx["z_edges"], z_tip, side="right") - 1, 0,
                        ctx["z_mid"].size - 1))
        for i, b in enumerate(bands):
            name = "Br_band_%.3g_%.3g" % (b_edges[i], b_edges[i + 1])
            rep.head[name] = float(br[last, i, k])
            rep.head_notes[name] = (
                "Br of band %s in the layer that holds the final tip (%.4g < z < %.4g m)"
                % (b, ctx["z_edges"][k], ctx["z_edges"][k + 1]))
    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    bm = 0.5 * (b_edges[1:] + b_edges[:-1])
    cmap = plt.get_cmap("viridis")
    nz = ctx["z_mid"].size
    for z in range(nz):
        depth = (ctx["z_ref"] - ctx["z_mid"][z]) * 1e3
        axes[0].plot(bm, br[last, :, z], "-o", ms=3, color=cmap(z / max(nz - 1, 1)),
                     label="depth %.3g mm" % depth)
    axes[0].set_xlabel("band centre r / R (-)")
    axes[0].set_ylabel("Br (-)")
    axes[0].set_title(_state_label(states[last]), fontsize=9)
    axes[0].legend(fontsize=6)
    axes[0].grid(True, alpha=0.3)
    for i, b in enumerate(bands):
        axes[1].plot(np.arange(len(states)), brb[:, i], "-o", ms=3, label=b)
    axes[1].set_xticks(np.arange(len(states)))
    axes[1].set_xticklabels([_short_label(s) for s in states], fontsize=7, rotation=90)
    axes[1].set_ylabel("Br over the whole height (-)")
    axes[1].legend(fontsize=6)
    axes[1].grid(True, alpha=0.3)
    fig.tight_layout()
    rep.figure(fig, "br_bands.png", "Breakage in radial bands",
               "Bounded Br (Einav) per radial band and layer (depth of the layer centre below "
               "the sand surface) at the last state, and per band over the whole height "
               "through the states. A band's grading: its grains now (by centre) plus the fines "
               "of the breaks whose parent was in it, against its grains at the first state.")


def _fig_psd(rep, ctx):
    if "psd" not in ctx:
        return
    plt = _plt()
    sizes, F, states, N = ctx["psd_sizes"], ctx["psd"], ctx["states"], ctx["N"]
    lim = fractal_psd(sizes, sizes[0], sizes[-1], W_FRACTAL)
    rep.put("psd", sizes=sizes, F=F, F_limit=lim)
    rep.attrs("psd", d_min=sizes[0], d_max=sizes[-1], N=N, fines="fractal (as the fix)")
    fig, ax = plt.subplots(figsize=(5.5, 4.2))
    cmap = plt.get_cmap("viridis")
    for k, s in enumerate(states):
        ax.semilogx(sizes * 1e3, F[k], color=cmap(k / max(len(states) - 1, 1)), lw=1,
                    label=_state_label(s) if k in (0, len(states) - 1) else None)
    ax.semilogx(sizes * 1e3, lim, "k--", lw=1, label="limit grading (w = %g)" % W_FRACTAL)
    ax.set_xlabel("particle size d (mm)")
    ax.set_ylabel("mass fraction finer (-)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    rep.figure(fig, "psd.png", "Particle-size distribution",
               "Grading of the whole sample at every state, the fines of the breaks so far "
               "spread like the limit grading below their parent's smallest fragment (the "
               "fix's 'fractal' convention); d_min = %.3g mm, d_max = %.3g mm (N = %g)."
               % (sizes[0] * 1e3, sizes[-1] * 1e3, N))


def _fig_increments(rep, ctx):
    incr, R = ctx["incr"], ctx["R"]
    if not incr:
        return
    plt = _plt()
    n = len(incr)
    cols = min(n, 4)
    rows = int(math.ceil(n / cols))
    fig, axes = plt.subplots(rows, cols, figsize=(3.3 * cols, 3.6 * rows), squeeze=False)
    d_all = np.concatenate([c["dr"] for c in incr])
    lim = float(np.percentile(np.abs(d_all), 98)) / R if d_all.size else 1.0
    lim = lim or 1e-6
    for k, c in enumerate(incr):
        ax = axes[k // cols, k % cols]
        grp = "increments/%02d" % k
        rep.put(grp, dr_mean=c["mean"], count=c["count"])
        rep.attrs(grp, from_step=c["from"]["step"], to_step=c["to"]["step"],
                  from_kind=c["from"]["kind"], to_kind=c["to"]["kind"],
                  n_matched=c["n_matched"], n_gone=c["n_only0"], n_new=c["n_only1"])
        ref = c["z_tip"] if c["z_tip"] is not None else ctx["z_ref"]
        sc = ax.scatter(c["r0"] / R, (c["z0"] - ref) / R, c=c["dr"] / R, s=3, cmap="RdBu_r",
                        vmin=-lim, vmax=lim, rasterized=True, lw=0)
        if c["z_tip"] is not None:
            _pile_outline(ax, float(np.max((c["z0"] - ref) / R)) if c["z0"].size else 1.0)
        what = "push" if c["to"]["kind"] == "push_end" else \
            "unload + pause" if c["to"]["kind"] == "pause_end" else "increment"
        ax.set_title("%s %s (%d grains)" % (what, c["to"].get("cycle", ""), c["n_matched"]),
                     fontsize=8)
        ax.set_xlabel("r / R at the start (-)", fontsize=8)
        if k % cols == 0:
            ax.set_ylabel("h / R, above the apex at the end (-)" if c["z_tip"] is not None
                          else "(z - z_ref) / R (-)", fontsize=8)
    for k in range(n, rows * cols):
        axes[k // cols, k % cols].axis("off")
    fig.colorbar(sc, ax=axes.ravel().tolist(), label="radial increment dr / R (-)", shrink=0.8)
    rep.figure(fig, "radial_increments.png", "Radial displacement increments",
               "dr = r_end - r_start of each grain present in both states (matched by id: "
               "grains that broke in between and their fragments are left out), over every "
               "push and every unload + pause; colour scale clipped at the 98th percentile "
               "of |dr|. fields.h5 holds the ring means.")


# ---------------------------------------------------------------------------
# breakage events, spheres
# ---------------------------------------------------------------------------

def _breakage_map(rep, ctx):
    events, jack, R = ctx["events"], ctx["jack"], ctx["R"]
    if events is None:
        return
    if jack is None:
        rep.skip("breakage density map", "no tip position (jack.txt)")
        return
    if events["step"].size == 0:
        rep.skip("breakage density map", "%s: no breakage event" % rep.path("breakage_events.txt"))
        return
    plt = _plt()
    z_tip = tip_z_at(events["step"], jack["step"], jack["depth"], ctx["z_ref"])
    hh, rr = relative_to_tip(events["x"], events["y"], events["z"], z_tip, R)
    inside = inside_pile(hh, rr)
    sector = ctx.get("sector") or rep.opt.sector or ctx["summary"].get("sector_deg") or 360
    r_edges = np.arange(0.0, max(2.0, float(rr.max())) + 0.25, 0.25)
    h_lo = math.floor(float(hh.min()) * 2) / 2
    h_hi = math.ceil(float(hh.max()) * 2) / 2 + 0.5
    h_edges = np.arange(h_lo, h_hi + 1e-9, 0.25)
    dens, cnt = event_density(hh, rr, h_edges, r_edges, sector)
    # events by zone (crushpost.pile.break_zones): switch-on, entry, the
    # crushing zone at the cone, along the shaft, beyond 5R below the tip
    first_step = ctx.get("jack_first_step")
    # crushing on before jacking (cpt_demo --crush-in-prep, or events before
    # the first step): no switch-on
    on_before = bool(ctx["summary"].get("crush_in_prep")) or (
        first_step is not None and bool(np.any(events["step"] < first_step)))
    prep, switch_on = event_phases(events["step"], first_step, on_before)
    zones = break_zones(hh, rr, (ctx["z_ref"] - z_tip) / R, switch_on, prep=prep)
    for k in ("switch_on", "entry", "penetration", "in_zone", "along_shaft", "beyond_5R_below",
              "elsewhere"):
        rep.head["events_" + k] = zones[k]
    rep.head["fraction_in_zone"] = zones["fraction_in_zone"]
    rep.head_notes["events_in_zone"] = (
        "break events during penetration (after the first step, tip deeper than %gR) within "
        "r < %gR and -%gR < h < 1.73R (the cone's shoulder); crushpost.pile.break_zones"
        % (ZONE_DEPTH_MIN, ZONE_R_MAX, ZONE_H_BELOW))
    rep.put("breakage/zones", **{k: np.asarray(v) for k, v in zones.items()})
    rep.put("breakage/events", step=events["step"], h_over_R=hh, r_over_R=rr,
            tip_depth=ctx["z_ref"] - z_tip, inside_pile=inside.astype(np.int8),
            parent_diameter=events["parent_diameter"], generation=events["generation"])
    rep.put("breakage/density", r_edges_over_R=r_edges, h_edges_over_R=h_edges, count=cnt,
            density_per_R3=dens)
    rep.attrs("breakage/density", definition="events per unit volume (R^3) of each (r/R, h/R) "
              "cell, a ring about the axis in the simulated sector of %d deg" % sector)
    fig, ax = plt.subplots(figsize=(5.2, 5))
    with np.errstate(divide="ignore"):
        m = ax.pcolormesh(r_edges, h_edges, np.ma.masked_equal(dens, 0).T, cmap="inferno_r",
                          shading="flat")
    fig.colorbar(m, ax=ax, label="breakage events per R^3")
    _pile_outline(ax, h_edges[-1])
    ax.axhline(0.0, color="k", lw=0.5, ls=":")
    ax.set_xlabel("r / R, distance from the pile axis (-)")
    ax.set_ylabel("h / R, height above the cone apex at the event (-)")
    ax.set_title("%d breakage events%s" % (hh.size, " (%d inside the pile!)" % inside.sum()
                                            if inside.any() else ""), fontsize=9)
    ax.set_ylim(h_edges[0], h_edges[-1])
    fig.tight_layout()
    rep.figure(fig, "breakage_density.png", "Where grains break",
               "Breakage events (breakage_events.txt: the parent's centre at the event) "
               "relative to the tip at the event's step, per unit volume of each ring-shaped "
               "(r/R, h/R) cell of 0.25 R x 0.25 R.")


def _spheres(rep, ctx):
    block, series = rep.path("spheres.in"), rep.path("spheres.txt")
    if not os.path.exists(block) or not os.path.exists(series):
        missing = block if not os.path.exists(block) else series
        rep.skip("measurement spheres", "%s: no such file" % missing)
        return
    try:
        centres, radius, steps, sigma = read_spheres_checked(block, series)
    except ReportInputError as exc:
        rep.error(str(exc))
        return
    inv = invariants(sigma)
    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = np.where(inv.p > 0, inv.q / inv.p, np.nan)
    grp = {"step": steps, "centres": centres, "p": inv.p, "q": inv.q, "q_over_p": ratio}
    jack, R = ctx["jack"], ctx["R"]
    plt = _plt()
    fig, ax = plt.subplots(figsize=(5.2, 4.4))
    if jack is not None:
        z_tip = tip_z_at(steps, jack["step"], jack["depth"], ctx["z_ref"])
        hr = (centres[None, :, 2] - z_tip[:, None]) / R
        grp["h_over_R"] = hr
        for s in range(centres.shape[0]):
            ax.plot(ratio[:, s], hr[:, s], "-", lw=1,
                    label="sphere %d: r/R = %.2f, z = %.3g m"
                    % (s + 1, math.hypot(centres[s, 0], centres[s, 1]) / R, centres[s, 2]))
        ax.set_ylabel("h / R, sphere centre above the apex (-)")
        ax.axhline(0.0, color="k", lw=0.5, ls=":")
    else:
        for s in range(centres.shape[0]):
            ax.plot(steps, ratio[:, s], "-", lw=1, label="sphere %d" % (s + 1))
        ax.set_ylabel("step")
    ax.set_xlabel("q / p' (-)")
    ax.legend(fontsize=7)
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    rep.put("spheres", **grp)
    rep.attrs("spheres", radius=radius)
    if np.any(np.isfinite(ratio)):
        k = np.unravel_index(np.nanargmax(ratio), ratio.shape)
        rep.head["peak_q_over_p"] = float(ratio[k])
        rep.head_notes["peak_q_over_p"] = (
            "largest q/p' of the measurement spheres (sphere %d, step %d); q = sqrt(3 J2)"
            % (k[1] + 1, steps[k[0]]))
    rep.figure(fig, "spheres_q_over_p.png", "q/p' at the measurement spheres",
               "Stress ratio q/p' (q = sqrt(3 J2), p' = tr/3) of each measurement sphere "
               "(spheres.txt; radius %.3g mm) against its height above the apex." % (radius * 1e3))


def _paraview(rep, ctx):
    # the run's VTK series (--vtk particles) drawn by ParaView itself:
    # paraview_state.py under scripts/pvbatch (docs/report.md, "ParaView")
    from . import paraview_state
    grains = paraview_state.grain_files(rep.run)
    if not grains:
        rep.skip("ParaView picture", "no %s (run with --vtk particles)"
                 % os.path.join(rep.run, paraview_state.GRAINS_GLOB))
        return
    wrapper = paraview_state.wrapper()
    if not os.path.isfile(wrapper):
        rep.skip("ParaView picture", "%s: no such file (ParaView's wrapper, docs/install.md)"
                 % wrapper)
        return
    name = "paraview.png"
    png = os.path.join(rep.out, name)
    if os.path.exists(png):
        os.remove(png)
    t0 = time.time()
    try:
        res = paraview_state.render(rep.run, png=png, state=os.path.join(rep.out, "paraview.pvsm"))
    except (OSError, subprocess.TimeoutExpired) as exc:
        rep.skip("ParaView picture", "%s: %s" % (wrapper, exc))
        return
    if res.returncode != 0 or not os.path.isfile(png):
        last = [line for line in (res.stderr or "").splitlines() if line.strip()][-1:]
        rep.skip("ParaView picture", "%s exited %d%s" % (wrapper, res.returncode,
                                                         (": " + last[0]) if last else ""))
        return
    rep.settings.append(("ParaView picture", "%d VTK steps, %.1f s" % (len(grains),
                                                                       time.time() - t0)))
    step = os.path.basename(grains[-1])
    rep.figures.append((name, "The grains in ParaView",
                        "The last VTK step (%s) drawn by ParaView (crushpost/paraview_state.py "
                        "under scripts/pvbatch): the whole grains of the half y >= 0 seen from -y, "
                        "i.e. cut by the plane y = 0 through the pile axis, coloured by the mean stress p = tr/3 "
                        "(kPa, compression positive), the strength sigma_lim (MPa) and the "
                        "generation; the meshes coloured by their normal stress. The ParaView "
                        "state is paraview.pvsm (File > Load State)." % step))


# ---------------------------------------------------------------------------
# fields.h5 and report.html
# ---------------------------------------------------------------------------

def _write_h5(rep, ctx):
    import h5py
    path = os.path.join(rep.out, "fields.h5")
    with h5py.File(path, "w") as f:
        f.attrs["run_dir"] = os.path.abspath(rep.run)
        f.attrs["R"] = ctx["R"]
        if ctx.get("z_ref") is not None:
            f.attrs["z_ref"] = ctx["z_ref"]
        f.attrs["units"] = "SI (m, Pa, s); angles in degrees; compression positive"
        for group, items in rep.h5.items():
            g = f.require_group(group)
            for k, v in items.items():
                g.create_dataset(k, data=np.asarray(v))
        for group, items in rep.h5_attrs.items():
            g = f.require_group(group)
            for k, v in items.items():
                g.attrs[k] = v
        h = f.require_group("headline")
        for k, v in rep.head.items():
            h.attrs[k] = v
        f.attrs["problems"] = "\n".join(m for _, m in rep.problems)


def _fmt(v):
    if isinstance(v, (int, np.integer)):
        return "%d" % v
    if v is None or not np.isfinite(v):
        return "n/a"
    return "%.4g" % v


def _write_html(rep, ctx, reference):
    e = html.escape
    rows = []
    ref = dict(reference or {})
    names = list(rep.head.keys())
    for name in names:
        v = rep.head[name]
        unit = HEADLINE_NAMES.get(name, "-")
        r = ref.pop(name, None)
        if r is not None:
            dv = ("%+.1f %%" % (100.0 * (v - r["value"]) / r["value"])
                  if r["value"] not in (0, 0.0) and np.isfinite(v) else "")
            rcell = "%s %s" % (_fmt(r["value"]), e(r["unit"]))
            rsrc = e(r["source"])
        else:
            dv, rcell, rsrc = "", "", ""
        val = _fmt(v)
        if name == "qc_steady_MPa" and "qc_steady_err_MPa" in rep.head:
            val += " &plusmn; %s (fit s.e.)" % _fmt(rep.head["qc_steady_err_MPa"])
            if "qc_run_scatter_MPa" in rep.head:
                val += " &plusmn; %s (run to run)" % _fmt(rep.head["qc_run_scatter_MPa"])
        rows.append("<tr><td>%s</td><td>%s</td><td>%s</td><td>%s</td><td>%s</td><td>%s</td>"
                    "<td class=note>%s</td></tr>"
                    % (e(name), val, e(unit), rcell, dv, rsrc, e(rep.head_notes.get(name, ""))))
    for name, r in ref.items():
        rows.append("<tr><td>%s</td><td>not in this report</td><td></td><td>%s %s</td><td></td>"
                    "<td>%s</td><td></td></tr>" % (e(name), _fmt(r["value"]), e(r["unit"]),
                                                   e(r["source"])))
    settings = "".join("<tr><td>%s</td><td>%s</td></tr>" % (e(k), e(str(v)))
                       for k, v in rep.settings)
    probs = "".join("<li class=%s>%s</li>" % (k, e(m)) for k, m in rep.problems) or \
        "<li>none</li>"
    figs = "".join("<figure><h3>%s</h3><img src=\"%s\" alt=\"%s\"><figcaption>%s</figcaption>"
                   "</figure>" % (e(t), e(f), e(t), e(c)) for f, t, c in rep.figures)
    doc = """<!DOCTYPE html>
<html><head><meta charset="utf-8"><title>Chamber run report: %(run)s</title>
<style>body{font-family:sans-serif;max-width:1200px;margin:1em auto;font-size:14px}
table{border-collapse:collapse}td,th{border:1px solid #bbb;padding:2px 6px;vertical-align:top}
td.note{font-size:12px;color:#444}li.error{color:#a00}img{max-width:100%%}
figure{margin:1em 0;border-top:1px solid #ddd}figcaption{font-size:12px;color:#333}</style>
</head><body>
<h1>Chamber run report</h1>
<p>Made by <code>crushpost report</code>; the numbers behind every figure are in
<a href="fields.h5">fields.h5</a> (layout: docs/report.md).</p>
<h2>Settings</h2><table>%(settings)s</table>
<h2>Headline numbers</h2>
<table><tr><th>name</th><th>this run</th><th>unit</th><th>reference</th><th>run vs reference</th>
<th>reference source</th><th>how it was measured</th></tr>%(rows)s</table>
<h2>Inputs missing or bad</h2><ul>%(probs)s</ul>
<h2>Figures</h2>%(figs)s
</body></html>
""" % {"run": e(os.path.abspath(rep.run)), "settings": settings, "rows": "".join(rows),
       "probs": probs, "figs": figs}
    with open(os.path.join(rep.out, "report.html"), "w") as f:
        f.write(doc)


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
