# SPDX-License-Identifier: GPL-2.0-or-later
"""Reading the run's files for the report, each failure one line naming the
file (ReportInputError)."""

import json
import os
import re

import numpy as np

from ..dump import read_crush_log
from ..inputfile import read_checked
from ..pile import read_jack
from ..snapshot import read_snapshot
from ..spheres import read_sphere_series
from .common import ReportInputError


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
