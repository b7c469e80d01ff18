# SPDX-License-Identifier: GPL-2.0-or-later
"""Fields of a chamber run that the report draws (issue 10 items 2-3): stress
quantities of ring-averaged tensors, profiles at chosen heights above the
tip, radial displacement increments, the density of breakage events
around the tip, Br in radial bands, and the uncertainty band of the q_c
trend. Pure, vectorised functions of numpy arrays.

Lengths in m, stresses in Pa; compression positive. ``R`` is the pile
radius, ``h`` the height above the cone's apex (``z - z_tip``), ``r`` the
distance from the pile axis.
"""

import math

import numpy as np
from scipy import sparse

from .breakage import (N_BINS, W_FRACTAL, _fractal_P, break_fines, cell_particle_bins,
                       limit_bin_integrals, sphere_mass)
from .materials import RHO_GRAIN
from .rotation import major_axis_angle
from .trend import qc_trend

__all__ = ["stress_quantities", "interp_columns", "interp_radius", "radial_increments",
           "binned_mean",
           "event_density", "cell_breakage", "qc_trend_band", "qc_reference"]


def stress_quantities(sigma_cyl):
    """Quantities of (..., 3, 3) tensors in the (r, theta, z) basis.

    Returns a dict of (...) arrays [Pa unless said]: sigma_r, sigma_theta,
    sigma_z, tau_rz; p (mean stress tr/3, the effective p' of a dry
    sample); q (sqrt(3 J2), sigma_1 - sigma_3 in triaxial states);
    sigma_1 >= sigma_2 >= sigma_3 (principal stresses of the whole
    tensor); psi [deg], the angle of the major principal direction of the
    (r, z) sub-tensor from the vertical (:mod:`crushpost.rotation`).
    Tensors with a NaN (no stress) give NaN throughout.
    """
    sig = np.asarray(sigma_cyl, dtype=float)
    sig = 0.5 * (sig + np.swapaxes(sig, -1, -2))
    bad = ~np.all(np.isfinite(sig), axis=(-2, -1))
    safe = np.where(bad[..., None, None], 0.0, sig)
    p = np.trace(safe, axis1=-2, axis2=-1) / 3.0
    dev = safe - p[..., None, None] * np.eye(3)
    q = np.sqrt(1.5 * np.sum(dev * dev, axis=(-2, -1)))
    vals = np.linalg.eigvalsh(safe)[..., ::-1]
    out = {"sigma_r": safe[..., 0, 0], "sigma_theta": safe[..., 1, 1], "sigma_z": safe[..., 2, 2],
           "tau_rz": safe[..., 0, 2], "p": p, "q": q, "sigma_1": vals[..., 0],
           "sigma_2": vals[..., 1], "sigma_3": vals[..., 2],
           "psi": major_axis_angle(safe[..., 0, 0], safe[..., 2, 2], safe[..., 0, 2])}
    return {k: np.where(bad, np.nan, v) for k, v in out.items()}


def interp_columns(values, z_mid, z_targets):
    """Values of every column of a ring grid at heights ``z_targets``,
    linear in z between layer centres ``z_mid`` (NaN outside their range).

    values: (n_r, n_z); z_mid: (n_z,) increasing; z_targets: (n_h,).
    Returns (n_h, n_r)."""
    v = np.asarray(values, dtype=float)
    z = np.asarray(z_mid, dtype=float)
    t = np.atleast_1d(np.asarray(z_targets, dtype=float))
    k = np.clip(np.searchsorted(z, t) - 1, 0, max(z.size - 2, 0))
    if z.size == 1:
        out = np.where(np.isclose(t, z[0])[:, None], v[:, 0][None, :], np.nan)
        return out
    f = (t - z[k]) / (z[k + 1] - z[k])
    out = v[:, k].T * (1.0 - f)[:, None] + v[:, k + 1].T * f[:, None]
    outside = (t < z[0]) | (t > z[-1])
    out[outside] = np.nan
    return out


def interp_radius(values, r_mid, r, axis=-2):
    """Values of a ring grid on the line at radius ``r``: linear in r between
    the centres ``r_mid`` of the two columns around it, the nearest column's
    value beyond the first or last centre. ``values`` has the columns along
    ``axis`` (default -2, as (..., n_r, n_z)); that axis is removed."""
    v = np.moveaxis(np.asarray(values, dtype=float), axis, 0)
    rm = np.asarray(r_mid, dtype=float)
    if rm.size == 1:
        return v[0]
    i = int(np.clip(np.searchsorted(rm, r) - 1, 0, rm.size - 2))
    f = float(np.clip((r - rm[i]) / (rm[i + 1] - rm[i]), 0.0, 1.0))
    return v[i] * (1.0 - f) + v[i + 1] * f


def radial_increments(id0, x0, id1, x1, axis_xy=(0.0, 0.0)):
    """Radial displacement increments of the particles present in two
    states (matched by id; a broken grain's fragments have new ids, so
    grains that broke in between, and their fragments, are not counted).

    Returns a dict: rows0, rows1 (indices of the matched particles in each
    state), dr (r1 - r0 [m], r the distance from the pile axis), n_matched,
    n_only0 (gone: broke, or lost), n_only1 (new: fragments)."""
    id0 = np.asarray(id0, dtype=np.int64)
    id1 = np.asarray(id1, dtype=np.int64)
    common, rows0, rows1 = np.intersect1d(id0, id1, assume_unique=True, return_indices=True)
    x0 = np.asarray(x0, dtype=float).reshape(-1, 3)[rows0]
    x1 = np.asarray(x1, dtype=float).reshape(-1, 3)[rows1]
    r0 = np.hypot(x0[:, 0] - axis_xy[0], x0[:, 1] - axis_xy[1])
    r1 = np.hypot(x1[:, 0] - axis_xy[0], x1[:, 1] - axis_xy[1])
    return {"rows0": rows0, "rows1": rows1, "dr": r1 - r0, "n_matched": int(common.size),
            "n_only0": int(id0.size - common.size), "n_only1": int(id1.size - common.size)}


def binned_mean(x, y, values, x_edges, y_edges):
    """Mean of ``values`` over the points (x, y) in each cell of a 2-D grid
    (one bincount pass). Returns (mean (nx, ny) with NaN in empty cells,
    count (nx, ny))."""
    x_edges = np.asarray(x_edges, dtype=float)
    y_edges = np.asarray(y_edges, dtype=float)
    nx, ny = x_edges.size - 1, y_edges.size - 1
    i = np.searchsorted(x_edges, x, side="right") - 1
    j = np.searchsorted(y_edges, y, side="right") - 1
    ok = (i >= 0) & (i < nx) & (j >= 0) & (j < ny)
    key = i[ok] * ny + j[ok]
    cnt = np.bincount(key, minlength=nx * ny).reshape(nx, ny)
    tot = np.bincount(key, weights=np.asarray(values, dtype=float)[ok],
                      minlength=nx * ny).reshape(nx, ny)
    with np.errstate(invalid="ignore", divide="ignore"):
        mean = np.where(cnt > 0, tot / np.maximum(cnt, 1), np.nan)
    return mean, cnt


def event_density(h_over_R, r_over_R, h_edges, r_edges, sector=360.0):
    """Breakage events per unit volume around the tip, in 1/R^3: the count
    in each cell of the (r/R, h/R) grid over the cell's volume in the
    simulated sector, (sector/360) pi (r_hi^2 - r_lo^2) (h_hi - h_lo) in R^3
    units (a cell is a ring about the pile axis).

    Returns (density (n_r, n_h), count (n_r, n_h))."""
    r_edges = np.asarray(r_edges, dtype=float)
    h_edges = np.asarray(h_edges, dtype=float)
    count, _, _ = np.histogram2d(np.asarray(r_over_R, dtype=float),
                                 np.asarray(h_over_R, dtype=float), bins=[r_edges, h_edges])
    vol = sector / 360.0 * math.pi * np.diff(r_edges ** 2)[:, None] * np.diff(h_edges)[None, :]
    return count / vol, count.astype(np.int64)


def _cell_fractal_bins(cell, m, d_f, d_min, d_max, w, n_cells, n, chunk=4096):
    """(n_cells, n) bin integrals of masses m spread like the limit grading
    over [d_min, d_f], summed per cell (a sparse product per chunk)."""
    L = math.log(d_max / d_min)
    h = L / n
    out = np.zeros((n_cells, n))
    k = 3.0 - w
    low = d_f <= d_min
    out += (np.bincount(cell[low], weights=m[low], minlength=n_cells) * h)[:, None]
    cell, m, U = cell[~low], m[~low], np.log(d_f[~low] / d_min)
    edges = np.arange(n + 1) * h
    for s in range(0, m.size, chunk):
        P = np.diff(_fractal_P(edges[None, :], U[s:s + chunk, None], k), axis=1)
        sel = sparse.csr_matrix((m[s:s + chunk], (cell[s:s + chunk], np.arange(P.shape[0]))),
                                shape=(n_cells, P.shape[0]))
        out += sel @ P
    return out


def cell_breakage(cell, d, cell0, d0, n_cells, d_min, d_max, ev_cell=None, ev_parent_d=None,
                  density=RHO_GRAIN, w=W_FRACTAL, n=N_BINS, d_frag_min=0.0):
    """Bounded Einav breakage index Br of many cells at once (bands, layers).

    Each cell's current grading is its grains now (``cell``: cell index of
    each grain, -1 for none; ``d`` diameters) plus the fines of the breaks
    whose parent's centre was in it (``ev_cell``, ``ev_parent_d``: the event
    log), spread like the limit grading (the fix's and
    :func:`crushpost.breakage.breakage`'s 'fractal' convention); its
    initial grading is its grains in the initial state (``cell0``, ``d0``).
    Masses are spheres of ``density``. The result equals
    :func:`crushpost.breakage.breakage` of each cell's grains on its own.

    Returns (Br (n_cells,), NaN where a cell holds no grain initially;
    M (n_cells,) current mass incl. fines; M0 (n_cells,) initial mass).
    """
    cell = np.asarray(cell, dtype=np.int64)
    d = np.asarray(d, dtype=float)
    cell0 = np.asarray(cell0, dtype=np.int64)
    d0 = np.asarray(d0, dtype=float)
    if not 0 < d_min < d_max:
        raise ValueError("need 0 < d_min < d_max")
    sel = (cell >= 0) & (cell < n_cells)
    J, M = cell_particle_bins(cell[sel], d[sel], sphere_mass(d[sel], density), d_min, d_max,
                               n_cells, n)
    sel0 = (cell0 >= 0) & (cell0 < n_cells)
    J0, M0 = cell_particle_bins(cell0[sel0], d0[sel0], sphere_mass(d0[sel0], density), d_min,
                                 d_max, n_cells, n)
    if ev_cell is not None and len(ev_cell):
        ev_cell = np.asarray(ev_cell, dtype=np.int64)
        pd = np.asarray(ev_parent_d, dtype=float)
        ok = (ev_cell >= 0) & (ev_cell < n_cells)
        ev_cell, pd = ev_cell[ok], pd[ok]
        if pd.size:
            fines = break_fines(pd, density=density, d_frag_min=d_frag_min)
            J = J + _cell_fractal_bins(ev_cell, fines.lost, fines.d_small, d_min, d_max, w,
                                       n_cells, n)
            M = M + np.bincount(ev_cell, weights=fines.lost, minlength=n_cells)
            if fines.dropped_m.size:
                # fragments not created, one entry per group (6 large, 8 small)
                r = 0.5 * pd
                from .breakage import R1_RATIO, R2_RATIO
                drop1 = 2.0 * R1_RATIO * r < d_frag_min
                drop2 = 2.0 * R2_RATIO * r < d_frag_min
                dc = np.concatenate([ev_cell[drop1], ev_cell[drop2]])
                Jd, Md = cell_particle_bins(dc, fines.dropped_d, fines.dropped_m, d_min, d_max,
                                             n_cells, n)
                J, M = J + Jd, M + Md
    with np.errstate(invalid="ignore", divide="ignore"):
        Jn = J / M[:, None]
        J0n = J0 / M0[:, None]
    U = limit_bin_integrals(d_min, d_max, w, n)[None, :]
    top = np.maximum(U, J0n)
    num = (np.minimum(np.maximum(Jn, J0n), top) - J0n).sum(axis=1)
    den = (top - J0n).sum(axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        br = np.where((M0 > 0) & (M > 0), np.where(den > 0, num / np.where(den > 0, den, 1.0),
                                                   0.0), np.nan)
    return br, M, M0


def qc_trend_band(h, h_data, q_data, a, b):
    """One-sigma band of the trend ``a (1 - exp(-b h))`` at depths ``h``
    from the linearised covariance of the least-squares fit to
    (``h_data``, ``q_data``): ``s^2 (J^T J)^-1`` with ``s^2`` the residual
    variance (n - 2 degrees of freedom), as scipy's curve_fit reports it
    (its square-root diagonal is :class:`crushpost.trend.QcFit`'s a_err,
    b_err). Returns (std (len(h),), covariance (2, 2))."""
    hd = np.asarray(h_data, dtype=float)
    qd = np.asarray(q_data, dtype=float)
    e = np.exp(-b * hd)
    jac = np.column_stack([1.0 - e, a * hd * e])
    res = qd - qc_trend(hd, a, b)
    dof = max(hd.size - 2, 1)
    s2 = float(res @ res) / dof
    cov = s2 * np.linalg.pinv(jac.T @ jac)
    h = np.asarray(h, dtype=float)
    eh = np.exp(-b * h)
    g = np.column_stack([1.0 - eh, a * h * eh])
    var = np.einsum("ni,ij,nj->n", g, cov, g)
    return np.sqrt(np.maximum(var, 0.0)), cov


def qc_reference(steps, jack_step, jack_qc, jack_phase, push_phase=0):
    """q_c to normalise the stresses of states at ``steps``: the tip
    resistance of the latest row of the pile series that was pushing before
    each step (the end of the last push, also for the end of a pause, whose
    own q_c is near zero). A row at the state's own step is left out: its
    phase is the one after that step's change (a pause that ended there
    shows the next push, with no load yet). NaN before the first push."""
    js = np.asarray(jack_step)
    push = np.asarray(jack_phase) == push_phase
    ps, pq = js[push], np.asarray(jack_qc, dtype=float)[push]
    k = np.searchsorted(ps, np.asarray(steps), side="left") - 1
    return np.where(k >= 0, pq[np.clip(k, 0, max(ps.size - 1, 0))] if ps.size else np.nan,
                    np.nan)
