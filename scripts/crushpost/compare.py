# SPDX-License-Identifier: GPL-2.0-or-later
"""Two chamber runs side by side (``crushpost compare RUN_A RUN_B``): the
q_c ratio and the difference in crushing, e.g. the demo with unbreakable
grains against the demo with crushable ones.

Each run folder holds the demo's ``summary.json`` (examples/cpt_demo/run.py)
and, when ``crushpost report`` has run on it, ``report/fields.h5``, whose
``headline`` attributes add the events by zone and Br per radial band over the
penetrated layers (docs/report.md). Numbers a run lacks are ``None``.
"""

import json
import math
import os

from .formats import FIELDS_H5_HEADLINE, SUMMARY as S
from .inputfile import InputFileError

#: What is compared: (name, where it comes from: summary key or headline name)
COMPARED = (
    ("qc_steady_MPa", "summary", "qc_steady_MPa"),
    ("qc_last3_bands_MPa", "headline", "qc_last3_bands_MPa"),
    ("n_break_events", "summary", "n_break_events"),
    ("events_switch_on", "headline", "events_switch_on"),
    ("events_penetration", "headline", "events_penetration"),
    ("events_in_zone", "headline", "events_in_zone"),
    ("events_along_shaft", "headline", "events_along_shaft"),
    ("events_beyond_5R_below", "headline", "events_beyond_5R_below"),
    ("fraction_in_zone", "headline", "fraction_in_zone"),
    ("Br_penetrated_1_2R", "headline", "Br_penetrated_1_2R"),
    ("Br_penetrated_2_3R", "headline", "Br_penetrated_2_3R"),
    ("fines_mass_fraction", "summary", "fines_mass_fraction"),
)


def read_run(run_dir):
    """``{"summary": dict, "headline": dict}`` of a run folder. The summary is
    required; the report's headline (report/fields.h5) is optional."""
    path = os.path.join(run_dir, "summary.json")
    try:
        with open(path) as f:
            summary = json.load(f)
    except FileNotFoundError:
        raise InputFileError("%s: no such file (a run folder of examples/cpt_demo/run.py "
                             "or scripts/demo holds one)" % path) from None
    except json.JSONDecodeError as exc:
        raise InputFileError("%s: not JSON (%s)" % (path, exc)) from None
    if not isinstance(summary, dict):
        raise InputFileError("%s: expected a JSON object" % path)
    headline = {}
    h5 = os.path.join(run_dir, "report", "fields.h5")
    if os.path.exists(h5):
        import h5py
        try:
            with h5py.File(h5, "r") as f:
                if FIELDS_H5_HEADLINE in f:
                    headline = {k: _plain(v) for k, v in f[FIELDS_H5_HEADLINE].attrs.items()}
        except OSError as exc:
            raise InputFileError("%s: not a readable HDF5 file (%s)" % (h5, exc)) from None
    if S.break_zones in summary and isinstance(summary[S.break_zones], dict):
        for k, v in summary[S.break_zones].items():
            key = k if k == "fraction_in_zone" else "events_" + k
            headline.setdefault(key, v)
    return {"summary": summary, "headline": headline}


def _plain(v):
    try:
        return v.item()
    except AttributeError:
        return v


def _value(run, source, key):
    v = run[source].get(key)
    if v is None or isinstance(v, (bool, str)):
        return None
    v = float(v)
    return v if math.isfinite(v) else None


def compare(run_a, run_b):
    """Rows ``(name, a, b, a/b, a-b)`` for every compared number (None where
    a run lacks it or the ratio is undefined), and the q_c ratio A/B."""
    rows = []
    for name, source, key in COMPARED:
        a, b = _value(run_a, source, key), _value(run_b, source, key)
        ratio = a / b if (a is not None and b not in (None, 0.0)) else None
        diff = a - b if (a is not None and b is not None) else None
        rows.append((name, a, b, ratio, diff))
    qc = {r[0]: r for r in rows}["qc_steady_MPa"]
    return rows, qc[3]


def _fmt(v):
    if v is None:
        return "n/a"
    return "%d" % v if float(v).is_integer() and abs(v) < 1e9 else "%.4g" % v


def format_table(rows, name_a, name_b):
    out = ["%-24s %12s %12s %10s %12s" % ("", "A", "B", "A/B", "A-B"),
           "A: %s" % name_a, "B: %s" % name_b]
    for name, a, b, ratio, diff in rows:
        out.append("%-24s %12s %12s %10s %12s" % (name, _fmt(a), _fmt(b),
                                                  "n/a" if ratio is None else "%.4g" % ratio,
                                                  _fmt(diff)))
    return "\n".join(out)
