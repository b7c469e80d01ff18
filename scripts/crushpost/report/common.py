# SPDX-License-Identifier: GPL-2.0-or-later
"""What every part of the report shares: the settings (ReportOptions), the
error of a bad input (ReportInputError), the collector of a report's
outputs (_Report: figures, fields.h5 groups, headline numbers, problems),
the constants of the analyses and the small drawing helpers."""

import math
import os

import numpy as np

from ..formats import fields_h5_check
from ..inputfile import InputFileError
from ..materials import D_MAX_BR, D_MIN_BR, RHO_GRAIN

#: Calibrated NE34 Br range at real size (docs/model.md §3) [m]; scaled by N.
D_MIN_REAL = D_MIN_BR
D_MAX_REAL = D_MAX_BR
RHO = RHO_GRAIN
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
        fields_h5_check(group, items, "datasets")
        self.h5.setdefault(group, {}).update(items)

    def attrs(self, group, **items):
        fields_h5_check(group, items, "attrs")
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


def _hatch_low(ax, xe, ye, low):
    if not np.any(low):
        return
    ax.pcolor(xe, ye, np.ma.masked_where(~low.T.astype(bool), np.ones_like(low.T, float)),
              hatch="///", alpha=0.0, shading="flat", zorder=2)


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


def _fmt(v):
    if isinstance(v, (int, np.integer)):
        return "%d" % v
    if v is None or not np.isfinite(v):
        return "n/a"
    return "%.4g" % v
