# SPDX-License-Identifier: GPL-2.0-or-later
"""Reader for the HDF5 snapshots of ``fix snapshot/hdf5`` (docs/fix_snapshot_hdf5.md).

One file per snapshot, ``PREFIX_<step>.h5``. :func:`read_snapshot` returns::

    {"path": str, "step": int, "time": float, "dt": float,
     "trigger": str, "trigger_old": float, "trigger_new": float,
     "snapshot": int, "fix": str, "group": str,
     "particles": {"id": (N,) int64, "type": (N,) int32, "x": (N, 3),
                   "v": (N, 3), "radius": (N,),
                   "values": {name as in the deck, e.g. "f_crush[1]": (N,) or (N, k)}},
     "contacts": None (written without contacts) or
        {"pp": {"id": (M, 2) int64 with id[:, 0] < id[:, 1],
                "contact_point": (M, 3), "force": (M, 3) on particle id[:, 0],
                "force_normal": (M, 3) on particle id[:, 0], "overlap": (M,)},
         "pw": None (no mesh walls) or
               {"id": (K,) int64 particle, "mesh": (K,) int32 index into "meshes",
                "triangle": (K,) int64, "contact_point": (K, 3),
                "force": (K, 3) on the particle, "force_normal": (K, 3),
                "overlap": (K,), "meshes": [mesh fix IDs], "wall_fix": str}}}

Particles are sorted by id, pair contacts by (id_i, id_j), wall contacts by
(id, mesh, triangle). SI units (the decks of this project).

:func:`write_snapshot` writes such a dict back in the fix's layout, for
synthetic runs in tests and benchmarks (the fix is the only writer of real
snapshots).
"""

import glob
import re
from pathlib import Path

import numpy as np

from .stress import particle_stress

__all__ = ["read_snapshot", "write_snapshot", "list_snapshots", "read_snapshots", "contact_rows",
           "snapshot_particle_stress"]

_STEP_RE = re.compile(r"_(\d+)\.h5$")


def _h5py():
    try:
        import h5py
    except ImportError as exc:  # pragma: no cover - h5py is a project dependency
        raise ImportError("crushpost.snapshot needs h5py (Debian: python3-h5py)") from exc
    return h5py


def _attr(obj, name, default=None):
    if name not in obj.attrs:
        return default
    v = obj.attrs[name]
    if isinstance(v, bytes):
        return v.decode()
    if isinstance(v, np.ndarray) and v.shape == ():
        v = v[()]
    if isinstance(v, (np.integer,)):
        return int(v)
    if isinstance(v, (np.floating,)):
        return float(v)
    if isinstance(v, np.bytes_):
        return v.decode()
    return v


def _group(g, names):
    return {n: g[n][()] for n in names if n in g}


def read_snapshot(path):
    """Everything in one snapshot file as a dict of numpy arrays (see module doc).

    A missing file raises FileNotFoundError; an empty, truncated or corrupt
    file, or an HDF5 file that is not a snapshot, raises ValueError. Both
    name the file."""
    h5py = _h5py()
    try:
        return _read_snapshot(h5py, path)
    except FileNotFoundError:
        raise FileNotFoundError(2, "no such snapshot file", str(path)) from None
    except IsADirectoryError:
        raise ValueError("%s: is a folder, not a snapshot file" % path) from None
    except (OSError, KeyError) as exc:
        # h5py's message, first line: "Unable to open file (truncated file: eof = ...)"
        why = (str(exc).splitlines() or [type(exc).__name__])[0]
        raise ValueError("%s: not a readable fix snapshot/hdf5 file: empty, truncated or "
                         "corrupt (%s)" % (path, why)) from None


def _read_snapshot(h5py, path):
    with h5py.File(str(path), "r") as f:
        out = {"path": str(path)}
        for a in ("step", "snapshot"):
            out[a] = int(_attr(f, a, -1))
        for a in ("time", "dt", "trigger_old", "trigger_new"):
            out[a] = float(_attr(f, a, np.nan))
        for a in ("trigger", "fix", "group"):
            out[a] = _attr(f, a, "")
        if "particles" not in f:
            raise ValueError("%s: no 'particles' group; not a fix snapshot/hdf5 file" % path)
        g = f["particles"]
        p = _group(g, ("id", "type", "x", "v", "radius"))
        p["values"] = _group(g["values"], list(g["values"].keys())) if "values" in g else {}
        out["particles"] = p
        if "contacts" in f:
            c = f["contacts"]
            names = ("id", "contact_point", "force", "force_normal", "overlap")
            pp = _group(c["pp"], names) if "pp" in c else None
            pw = None
            if "pw" in c:
                pw = _group(c["pw"], names + ("mesh", "triangle"))
                meshes = _attr(c["pw"], "meshes", "")
                pw["meshes"] = meshes.split() if meshes else []
                pw["wall_fix"] = _attr(c["pw"], "wall_fix", "")
            for d in (pp, pw):
                if d is None:
                    continue
                # empty data sets are written 1-D; give them their row shape
                for k in ("contact_point", "force", "force_normal"):
                    if k in d:
                        d[k] = np.asarray(d[k], dtype=float).reshape(-1, 3)
            if pp is not None and "id" in pp:
                pp["id"] = np.asarray(pp["id"], dtype=np.int64).reshape(-1, 2)
            out["contacts"] = {"pp": pp, "pw": pw}
        else:
            out["contacts"] = None
    for k in ("x", "v"):
        if k in p:
            p[k] = np.asarray(p[k], dtype=float).reshape(-1, 3)
    return out


def write_snapshot(path, snap):
    """Write ``snap``, a dict laid out as :func:`read_snapshot` returns it,
    in the layout of fix snapshot/hdf5. Needed: "step" and
    "particles" (id, type, x, v, radius); optional: "time", "dt",
    "trigger", "trigger_old", "trigger_new", "snapshot" (written when
    given), "particles"/"values" and "contacts" (None: none; "pw" None: no
    wall contacts). Returns ``path``."""
    h5py = _h5py()
    with h5py.File(str(path), "w") as f:
        f.attrs["step"] = np.int64(snap["step"])
        for a in ("time", "dt", "trigger_old", "trigger_new"):
            if a in snap:
                f.attrs[a] = float(snap[a])
        if "snapshot" in snap:
            f.attrs["snapshot"] = np.int64(snap["snapshot"])
        for a in ("trigger", "fix", "group"):
            if snap.get(a):
                f.attrs.create(a, np.bytes_(snap[a]))
        g = f.create_group("particles")
        p = snap["particles"]
        for k, dtype in (("id", np.int64), ("type", np.int32), ("x", float), ("v", float),
                         ("radius", float)):
            g[k] = np.asarray(p[k], dtype=dtype)
        if p.get("values"):
            gv = g.create_group("values")
            for k, v in p["values"].items():
                gv[k] = np.asarray(v)
        c = snap.get("contacts")
        if c is None:
            return path
        gc = f.create_group("contacts")
        kinds = (("pp", {"id": np.int64}), ("pw", {"id": np.int64, "mesh": np.int32,
                                                   "triangle": np.int64}))
        for kind, int_types in kinds:
            d = c.get(kind)
            if d is None:
                continue
            gk = gc.create_group(kind)
            for k in ("id", "mesh", "triangle", "contact_point", "force", "force_normal",
                      "overlap"):
                if k in d:
                    gk[k] = np.asarray(d[k], dtype=int_types.get(k, float))
            if kind == "pw":
                gk.attrs.create("meshes", np.bytes_(" ".join(d.get("meshes", []))))
                gk.attrs.create("wall_fix", np.bytes_(d.get("wall_fix", "")))
    return path


def list_snapshots(prefix):
    """``[(step, path), ...]`` of the files ``PREFIX_<step>.h5``, by step."""
    prefix = str(prefix)
    found = []
    for path in glob.glob(glob.escape(prefix) + "_*.h5"):
        m = _STEP_RE.search(path)
        # only PREFIX_<digits>.h5, not PREFIX_other_<digits>.h5
        if m and path[:m.start()] == prefix:
            found.append((int(m.group(1)), Path(path)))
    found.sort()
    return found


def read_snapshots(prefix):
    """All snapshots of a prefix, in step order (list of dicts)."""
    return [read_snapshot(p) for _, p in list_snapshots(prefix)]


def contact_rows(snap, ids):
    """Row indices in ``snap["particles"]`` of particle ``ids`` (ValueError
    for an id that is not in the snapshot)."""
    pid = snap["particles"]["id"]
    ids = np.asarray(ids, dtype=np.int64)
    rows = np.searchsorted(pid, ids)
    rows = np.clip(rows, 0, max(len(pid) - 1, 0))
    if len(ids) and (len(pid) == 0 or np.any(pid[rows] != ids)):
        raise ValueError("snapshot %s: contact ids not among its particles" % snap.get("path"))
    return rows


def snapshot_particle_stress(snap, walls=True, compression_positive=True):
    """Per-particle stress ``sigma_p = (1/V_p) sum_c s^c (x) F^c`` (docs/model.md §4.7)
    from the pair contacts (both sides) and, with ``walls``, the mesh-wall
    contacts of a snapshot written with ``contacts yes``. Returns (N, 3, 3)
    in particle order [Pa]; compression positive by default."""
    if snap["contacts"] is None:
        raise ValueError("%s: written without contacts (contacts yes is needed for the "
                         "particle stresses)" % snap.get("path"))
    p = snap["particles"]
    x = p["x"]
    vol = 4.0 / 3.0 * np.pi * p["radius"] ** 3
    pp = snap["contacts"]["pp"]
    i = contact_rows(snap, pp["id"][:, 0])
    j = contact_rows(snap, pp["id"][:, 1])
    cp, f = pp["contact_point"], pp["force"]
    # both sides of each pair contact: (cp - x_i) (x) F on i, (cp - x_j) (x) (-F)
    # on j; summed side by side, without stacking copies of millions of rows
    sig = particle_stress(i, cp - x[i], f, vol, compression_positive)
    sig -= particle_stress(j, cp - x[j], f, vol, compression_positive)
    pw = snap["contacts"]["pw"]
    if walls and pw is not None and len(pw["id"]):
        iw = contact_rows(snap, pw["id"])
        sig += particle_stress(iw, pw["contact_point"] - x[iw], pw["force"], vol,
                               compression_positive)
    return sig
