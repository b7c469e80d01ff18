# SPDX-License-Identifier: GPL-2.0-or-later
"""The snapshots: each state read once, its ring fields, and the steps of
the parts that follow the states (Br in bands, PSD, utilisation,
displacement increments), then the figures of the states."""

import os
import time

import numpy as np

from ..formats import SUMMARY as S
from ..pile import PHASE_PAUSE, PHASE_PUSH
from ..prep import ring_edges
from ..rings import ring_fields, sphere_cell_volumes
from ..rotation import axis_rotation, unwrap_axis
from ..snapshot import list_snapshots, snapshot_particle_stress
from ..inputfile import reason
from ..fields import stress_quantities
from .common import ReportInputError
from .inputs import read_snapshot_checked
from .stresses import _store_states, _fig_initial, _fig_contours, _fig_profiles, _fig_histories
from .rotation import _fig_rotation
from .bands import _bands_finish, _bands_start, _bands_step, _fig_bands, _fig_utilisation, _utilisation_step
from .psd import _fig_psd, _psd_step
from .increments import _fig_increments, _increment_step


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
    r_max = s.get(S.R_chamber_m) or float(np.max(rho + rad))
    z_ref = ctx["z_ref"]
    if z_ref is None:
        z_ref = float(np.max(x[:, 2] + rad))
        ctx["z_ref_note"] = "the top of the highest grain of the first snapshot (no jack.txt)"
        ctx["z_ref"] = z_ref
    z_bot = min(0.0, float(np.min(x[:, 2] - rad)))
    r_edges = ring_edges(ctx["ring_width"], r_max)
    # layers from the sand surface down, the remainder at the bottom
    z_edges = z_ref - ring_edges(rep.opt.ring_height, z_ref - z_bot)[::-1]
    sector = rep.opt.sector or s.get(S.sector_deg)
    if not sector:
        # a sector's grains lie on one side of its symmetry planes
        tol = 1e-9
        sector = 90 if (x[:, 0].min() > -tol and x[:, 1].min() > -tol) else \
            180 if x[:, 1].min() > -tol else 360
    return r_edges, z_edges, int(sector)


def _snapshot_files(rep):
    """(path, "initial" or "jack") of the snapshots to read, the prepared
    state first; None (said) when there is none."""
    prep = list_snapshots(rep.path("snapshots", "prep"))
    jacks = list_snapshots(rep.path("snapshots", "jack"))
    if not prep and not jacks:
        rep.skip("ring fields, rotation, Br bands, PSD, displacement increments",
                 "no snapshots (%s_<step>.h5 or %s_<step>.h5)"
                 % (rep.path("snapshots", "prep"), rep.path("snapshots", "jack")))
        return None
    if not prep:
        rep.skip("initial state", "no prepared-state snapshot %s_<step>.h5: rotations and Br "
                 "are relative to the first push end" % rep.path("snapshots", "prep"))
    return [(str(p), "initial") for _, p in prep[-1:]] + [(str(p), "jack") for _, p in jacks]


def _read_state(rep, ctx, loop, path, hint):
    """The snapshot at ``path``, its state info and particle stresses, or
    None (the error said); the grid from the first snapshot read."""
    t = time.time()
    try:
        snap = read_snapshot_checked(path)
    except ReportInputError as exc:
        rep.error(str(exc))
        return None
    loop["t_read"] += time.time() - t
    if loop["grid"] is None:
        loop["grid"] = _grid(rep, ctx, snap)
        ctx["sector"] = loop["grid"][2]
    info = _state_info(snap, hint, ctx["jack"], ctx["z_ref"])
    t = time.time()
    try:
        sig = snapshot_particle_stress(snap)
    except ValueError as exc:
        rep.error("%s: %s" % (path, reason(exc, path)))
        return None
    loop["t_stress"] += time.time() - t
    return snap, info, sig


def _ring_step(loop, sig, x, rad):
    """The state's ring averages and stress quantities into loop["arrays"]."""
    r_edges, z_edges, sector = loop["grid"]
    t = time.time()
    trip = sphere_cell_volumes(x, rad, r_edges, z_edges)
    rf = ring_fields(sig, x, rad, r_edges, z_edges, sector=sector, triplets=trip)
    loop["t_rings"] += time.time() - t
    arrays = loop["arrays"]
    q = stress_quantities(rf["sigma"])
    for k, v in q.items():
        arrays.setdefault(k, []).append(v)
    for k in ("porosity", "n_grains", "n_equiv"):
        arrays.setdefault(k, []).append(rf[k])


def _read_states(rep, ctx, files, bands):
    """Each state read once and handed to the per-state steps of the rings,
    utilisation, Br bands, PSD and increments. Returns the loop's record."""
    loop = {"grid": None, "states": [], "arrays": {}, "incr": [], "prev": None,
            "t_read": 0.0, "t_stress": 0.0, "t_rings": 0.0}
    for path, hint in files:
        got = _read_state(rep, ctx, loop, path, hint)
        if got is None:
            continue
        snap, info, sig = got
        p = snap["particles"]
        x, rad, ids = p["x"], p["radius"], p["id"]
        _ring_step(loop, sig, x, rad)
        loop["states"].append(info)
        _utilisation_step(ctx, info, p, x)
        r_edges, z_edges, _ = loop["grid"]
        if bands is not None:
            fines = _bands_step(ctx, bands, info, x, rad, ids, r_edges, z_edges)
            _psd_step(bands, rad, fines, rep.opt.density)
        loop["prev"] = _increment_step(loop["incr"], loop["prev"], info, ids, x, r_edges,
                                       z_edges)
    return loop


def _states(rep, ctx):
    files = _snapshot_files(rep)
    if files is None:
        return
    bands = _bands_start(rep, ctx)
    loop = _read_states(rep, ctx, files, bands)
    states = loop["states"]
    if not states:
        return
    rep.say("snapshots: %d states read in %.1f s, particle stresses %.1f s, rings %.1f s"
            % (len(states), loop["t_read"], loop["t_stress"], loop["t_rings"]))
    A = {k: np.array(v) for k, v in loop["arrays"].items()}
    A["rotation"] = axis_rotation(A["psi"], axis=0)
    A["psi_unwrapped"] = unwrap_axis(A["psi"], axis=0)
    A["low_count"] = (A["n_grains"] < rep.opt.min_grains).astype(np.int8)
    r_edges, z_edges, _ = loop["grid"]
    ctx.update(states=states, A=A, r_edges=r_edges, z_edges=z_edges, incr=loop["incr"])
    r_mid = 0.5 * (r_edges[1:] + r_edges[:-1])
    z_mid = 0.5 * (z_edges[1:] + z_edges[:-1])
    ctx["r_mid"], ctx["z_mid"] = r_mid, z_mid
    _store_states(rep, ctx)
    if bands is not None and bands["rows"]:
        _bands_finish(rep, ctx, bands)
        ctx["psd"] = np.array(bands["psd_rows"])
    _fig_initial(rep, ctx)
    _fig_contours(rep, ctx)
    _fig_profiles(rep, ctx)
    _fig_histories(rep, ctx)
    _fig_rotation(rep, ctx)
    _fig_bands(rep, ctx)
    _fig_psd(rep, ctx)
    _fig_increments(rep, ctx)
    _fig_utilisation(rep, ctx)
