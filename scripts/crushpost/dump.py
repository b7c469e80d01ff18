# SPDX-License-Identifier: GPL-2.0-or-later
"""Readers for LAMMPS/LIGGGHTS text dumps and for the crush event log.

Dump snapshots are dicts::

    {"timestep": int, "n_atoms": int,
     "box": (3, 2) lo/hi array, or (3, 3) lo/hi/tilt for a triclinic box,
     "boundary": e.g. ["pp", "pp", "ff"],
     "atoms": {column name: (n_atoms,) array}}

Columns ``id``, ``type``, ``mol`` and ``proc`` are int64, the rest float64.
Rows are kept in file order (per-rank order in parallel runs); sort by
``atoms["id"]`` where order matters. Files ending in ``.gz`` are read with gzip.
Units are those of the run (SI in this project's decks).
"""

import gzip
import itertools
from pathlib import Path

import numpy as np

from .formats import (EVENT_LOG_COLUMNS, EVENT_LOG_ENERGY_COLUMNS, EVENT_LOG_INT_COLUMNS,
                      EVENT_LOG_PARTNERS, event_log_columns)

__all__ = ["iter_dump", "read_dump", "CRUSH_LOG_COLUMNS", "read_crush_log"]

_INT_COLUMNS = {"id", "type", "mol", "proc"}


def _open(path):
    path = Path(path)
    if path.suffix == ".gz":
        return gzip.open(path, "rt")
    return open(path, "r")


def _next_item(fh, expect, path):
    line = fh.readline()
    if not line.startswith("ITEM: " + expect):
        raise ValueError("%s: expected 'ITEM: %s', got %r" % (path, expect, line.strip()))
    return line


def iter_dump(path):
    """Yield the snapshots of a text dump one at a time (see module doc)."""
    with _open(path) as fh:
        while True:
            line = fh.readline()
            if not line:
                return
            if not line.strip():
                continue
            if not line.startswith("ITEM: TIMESTEP"):
                raise ValueError("%s: expected 'ITEM: TIMESTEP', got %r" % (path, line.strip()))
            timestep = int(fh.readline().split()[0])
            _next_item(fh, "NUMBER OF ATOMS", path)
            n_atoms = int(fh.readline().split()[0])
            header = _next_item(fh, "BOX BOUNDS", path).split()[3:]
            triclinic = len(header) >= 3 and header[:3] == ["xy", "xz", "yz"]
            boundary = header[3:] if triclinic else header
            box = np.array([[float(v) for v in fh.readline().split()] for _ in range(3)])
            columns = _next_item(fh, "ATOMS", path).split()[2:]
            lines = list(itertools.islice(fh, n_atoms))
            if len(lines) < n_atoms:
                raise ValueError("%s: snapshot at step %d is truncated (%d of %d atoms)"
                                 % (path, timestep, len(lines), n_atoms))
            flat = np.array("".join(lines).split(), dtype=float)
            if flat.size != n_atoms * len(columns):
                raise ValueError("%s: step %d: %d values for %d atoms x %d columns"
                                 % (path, timestep, flat.size, n_atoms, len(columns)))
            data = flat.reshape(n_atoms, len(columns))
            atoms = {}
            for k, name in enumerate(columns):
                col = data[:, k]
                atoms[name] = col.astype(np.int64) if name in _INT_COLUMNS else col.copy()
            yield {"timestep": timestep, "n_atoms": n_atoms, "box": box,
                   "boundary": boundary, "atoms": atoms}


def read_dump(path):
    """All snapshots of a text dump as a list (see module doc)."""
    return list(iter_dump(path))


#: Per-atom columns that hold the true mass (without density scaling): the
#: decks' atom variable (inputs/crushable_ne34.in, unbreakable.in) and
#: column 3 of compute crush/atom, as a dump names them.
TRUE_MASS_COLUMNS = ("v_mass_true", "c_crush_atom[3]", "mass_true")


def true_mass(atoms, density, path="dump"):
    """Mass of every particle without density scaling, (N,) kg.

    ``atoms``: the per-atom columns of a dump snapshot (dict of arrays). A
    true-mass column (TRUE_MASS_COLUMNS) is used when present; otherwise the
    sphere mass ``density pi d^3 / 6`` from the radius (or diameter). The
    dump's ``mass`` column is never used: ``fix crush/particle
    density_scale`` raises the mass of fine particles, so it is not the
    grains' mass (docs/fix_crush_particle.md, "Density scaling")."""
    for name in TRUE_MASS_COLUMNS:
        if name in atoms:
            return np.asarray(atoms[name], dtype=float)
    if "radius" in atoms:
        d = 2.0 * np.asarray(atoms["radius"], dtype=float)
    elif "diameter" in atoms:
        d = np.asarray(atoms["diameter"], dtype=float)
    else:
        raise KeyError("%s: no true-mass column (%s) and neither a radius nor a diameter column"
                       % (path, ", ".join(TRUE_MASS_COLUMNS)))
    return density * np.pi / 6.0 * d ** 3


#: Columns of the crush event log written by the breakage fix, in file order,
#: and those that follow with ``energy yes``: defined in crushpost.formats.
CRUSH_LOG_COLUMNS = EVENT_LOG_COLUMNS
CRUSH_LOG_ENERGY_COLUMNS = EVENT_LOG_ENERGY_COLUMNS
_PARTNER = EVENT_LOG_COLUMNS.index("partner")

def read_crush_log(path):
    """Read a crush event log: one breakage event per line.

    Columns (whitespace separated): step, time [s], parent_tag,
    parent_diameter [m], x y z of the parent centre [m], F_n (the normal
    force that broke it) [N], F_lim [N], partner (``particle`` or ``wall``),
    generation (0 for an original grain). Files written with the fix's
    ``energy yes`` have 7 more columns (CRUSH_LOG_ENERGY_COLUMNS: elastic
    energy before and after [J], kinetic energy of the parent and of the
    fragments at insertion [J], the fragments' kinetic gain [J], their
    largest speed [m/s], steps watched); they are returned too. Every line
    of a file has the same number of columns. Lines starting with ``#`` and
    blank lines are skipped.

    Returns a dict of (n_events,) arrays keyed by the column names plus
    ``partner_is_wall`` (bool). ``step``, ``parent_tag`` and ``generation``
    are int64, ``partner`` is a str array. Events are sorted by step (stable),
    since ranks may append their events in any order.
    """
    rows = []
    columns = None
    with _open(path) as fh:
        for lineno, line in enumerate(fh, 1):
            s = line.strip()
            if not s or s.startswith("#"):
                continue
            words = s.split()
            if columns is None:
                columns = event_log_columns(len(words))
            if len(words) != len(columns):
                raise ValueError("%s:%d: expected %d columns, got %d"
                                 % (path, lineno, len(columns), len(words)))
            partner = words[_PARTNER]
            if partner not in EVENT_LOG_PARTNERS:
                raise ValueError("%s:%d: partner must be %s, got %r"
                                 % (path, lineno, " or ".join("'%s'" % w for w in EVENT_LOG_PARTNERS),
                                    partner))
            rows.append(words)
    out = {}
    for k, name in enumerate(columns or CRUSH_LOG_COLUMNS):
        vals = [r[k] for r in rows]
        if name == "partner":
            out[name] = np.array(vals, dtype=str)
        elif name in EVENT_LOG_INT_COLUMNS:
            out[name] = np.array(vals, dtype=np.int64)
        else:
            out[name] = np.array(vals, dtype=float)
    order = np.argsort(out["step"], kind="stable")
    out = {k: v[order] for k, v in out.items()}
    out["partner_is_wall"] = out["partner"] == EVENT_LOG_PARTNERS[1]
    return out
