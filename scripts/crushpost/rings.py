# SPDX-License-Identifier: GPL-2.0-or-later
"""Ring averages of a chamber in one vectorised pass (issue 10 item 1).

Rings are annuli about the pile axis (the z axis through ``axis_xy``):
column ``i`` spans ``r_edges[i] <= r < r_edges[i + 1]``, layer ``k`` spans
``z_edges[k] <= z < z_edges[k + 1]``; cell (ring) ``c = i * n_z + k``.

Every particle is a sphere; a ring counts the part of each sphere inside it,
the exact sphere-ring intersection volume (not centre binning):

* :func:`sphere_cell_volumes` returns (particle, ring, volume) triplets for
  every ring each sphere touches. Per sphere it finds the ring edges that
  cut it (few: a grain is smaller than a ring) and evaluates
  ``K(rho, z)``, the sphere's volume inside the cylinder of radius ``rho``
  and below the plane ``z``, at every pair of cutting edges; the volume in
  a ring is the 2-D difference of ``K`` over its four corners. ``K`` is
  exact (closed form) when only planes cut the sphere (spherical caps) or
  nothing does; with a cylinder it is a 1-D integral over horizontal slices
  of the exact disc / disc overlap area, by Gauss-Legendre pieces split at
  the slice heights where the integrand has a kink (within 2e-9 of the
  sphere's volume with 16 nodes).
  Spheres are grouped by how many radial and vertical edges cut them; each
  group is one vectorised evaluation (a few groups in all), with no Python
  loop over particles.
* :func:`ring_fields` sums the particle stresses (rotated to the local
  cylindrical basis at each particle's centre), the solid volume and the
  grain counts per ring with :func:`numpy.bincount`.

Lengths in m, stresses in Pa (any consistent units work). Compression
positive (the particle stresses of :mod:`crushpost.snapshot`).
"""

import math

import numpy as np

from .stress import to_cylindrical_tensor

__all__ = ["sphere_cell_volumes", "cylinder_below_volume", "ring_volumes", "ring_fields",
           "ring_edges_from"]

_GL = {}


def _gauss(n):
    if n not in _GL:
        _GL[n] = np.polynomial.legendre.leggauss(n)
    return _GL[n]


def _gauss_sine(n):
    """Gauss-Legendre nodes mapped by t = sin(pi u / 2) (and the weights
    times dt/du): the lens integrand vanishes like (t_end - t)^(3/2) at a
    tangency, which the map turns into a smooth (1 - u)^4 behaviour."""
    key = ("sine", n)
    if key not in _GL:
        u, w = np.polynomial.legendre.leggauss(n)
        _GL[key] = ((np.sin(0.5 * math.pi * u),), w * 0.5 * math.pi * np.cos(0.5 * math.pi * u))
    return _GL[key]


def _cap_below(z, zc, a):
    """Volume of the sphere (centre height zc, radius a) below the plane z."""
    t = np.clip((z - zc) / a, -1.0, 1.0)
    return (math.pi * a ** 3) * (1.0 + t) ** 2 * (2.0 - t) / 3.0


def _lens_area(s, rho, d):
    """Overlap of a disc of radius ``s`` with one of radius ``rho``, centres
    ``d`` apart, where the two circles cross (|rho - d| <= s <= rho + d)."""
    dd = np.maximum(d, 1e-300)
    s2, r2, d2 = s * s, rho * rho, dd * dd
    c1 = (d2 + s2 - r2) / (2.0 * dd * s)
    c2 = (d2 + r2 - s2) / (2.0 * dd * rho)
    np.minimum(np.maximum(c1, -1.0, out=c1), 1.0, out=c1)
    np.minimum(np.maximum(c2, -1.0, out=c2), 1.0, out=c2)
    # 16 x (triangle of sides s, rho, d)^2, Heron
    k = (-dd + s + rho) * (dd + s - rho) * (dd - s + rho) * (dd + s + rho)
    np.maximum(k, 0.0, out=k)
    return s2 * np.arccos(c1) + r2 * np.arccos(c2) - 0.5 * np.sqrt(k)


def _gl_piece(lo, hi, rho_c, a, rho, n_gauss):
    """Integral over t in [lo, hi] of the lens area of the slice of radius
    a cos(t) times a cos(t) (zero where hi <= lo)."""
    nodes, weights = _gauss_sine(n_gauss)
    half = 0.5 * np.maximum(hi - lo, 0.0)
    t = (0.5 * (hi + lo))[..., None] + half[..., None] * nodes[0]
    s = a[..., None] * np.cos(t)
    f = _lens_area(s, rho[..., None], rho_c[..., None]) * s
    return (f @ weights) * half


def cylinder_below_volume(rho_c, zc, a, rho, z=np.inf, n_gauss=16):
    """``K(rho, z)``: volume of spheres (centre at distance ``rho_c`` from the
    axis and height ``zc``, radius ``a``) inside the cylinder ``r < rho``
    and below the plane at height ``z``. Arrays broadcast; ``z = inf`` (the
    default) gives the whole cylinder.

    Horizontal slices at height ``zc + a sin(t)`` are discs of radius
    ``a cos(t)``. Where a slice lies wholly inside or outside the cylinder
    (the polar caps ``|t| > t1``, and for a sphere around the axis the
    middle band ``|t| < t2`` whose slices hold the cylinder's whole
    section) the volume is closed form; the band ``t2 < |t| < t1`` where
    the slice's circle crosses the cylinder is integrated by Gauss-Legendre
    on the exact lens area (``n_gauss`` nodes per piece: the integrand is
    smooth inside, with square-root ends, which a sine map of the nodes
    smooths). Within 2e-9 of the sphere's volume with 16 nodes.
    """
    rho_c, zc, a, rho, z = np.broadcast_arrays(*(np.asarray(v, dtype=float)
                                                 for v in (rho_c, zc, a, rho, z)))
    d = np.abs(rho - rho_c)
    t1 = np.arccos(np.clip(d / a, 0.0, 1.0))
    t2 = np.arccos(np.clip((rho + rho_c) / a, 0.0, 1.0))
    h1, h2 = a * np.sin(t1), a * np.sin(t2)
    out = np.zeros(a.shape)
    # polar caps, inside the cylinder when the centre is
    inside = rho_c < rho
    if np.any(inside):
        zi, zci, h1i = z[inside], zc[inside], h1[inside]
        ai = a[inside]
        out[inside] = (_cap_below(np.minimum(zi, zci - h1i), zci, ai)
                       + np.maximum(0.0, _cap_below(zi, zci, ai) - _cap_below(zci + h1i, zci, ai)))
    # middle band of a sphere around the axis: the cylinder's whole section
    out += math.pi * rho * rho * np.maximum(0.0, np.minimum(z, zc + h2) - (zc - h2))
    whole = bool(np.all(np.isposinf(z)))
    straddle = bool(np.any(t2 > 0.0))
    if whole:
        # symmetric in t: twice the band t2 < t < t1
        out += 2.0 * _gl_piece(t2, t1, rho_c, a, rho, n_gauss)
    else:
        t_top = np.arcsin(np.clip((z - zc) / a, -1.0, 1.0))
        if straddle:
            out += _gl_piece(-t1, np.minimum(-t2, t_top), rho_c, a, rho, n_gauss)
            out += _gl_piece(t2, np.minimum(t1, t_top), rho_c, a, rho, n_gauss)
        else:
            out += _gl_piece(-t1, np.minimum(t1, t_top), rho_c, a, rho, n_gauss)
    return out


def _edge_slices(edges, lo, hi):
    """Index of the cell holding ``lo`` and the number of edges strictly
    between ``lo`` and ``hi`` (the edges that cut each sphere)."""
    i0 = np.searchsorted(edges, lo, side="right") - 1
    i1 = np.searchsorted(edges, hi, side="left") - 1
    return i0, i1 - i0


def sphere_cell_volumes(centres, radii, r_edges, z_edges, axis_xy=(0.0, 0.0), n_gauss=16):
    """Volume of each sphere inside each ring of the grid ``r_edges`` x
    ``z_edges`` it touches.

    Returns ``(particle, cell, volume)``: int64, int64 and float arrays, one
    entry per (sphere, ring) pair with a positive overlap; ``cell = i * n_z
    + k`` for column ``i`` and layer ``k``. Parts of a sphere outside the
    grid are in no ring.
    """
    r_edges = np.asarray(r_edges, dtype=float)
    z_edges = np.asarray(z_edges, dtype=float)
    if r_edges.ndim != 1 or z_edges.ndim != 1 or r_edges.size < 2 or z_edges.size < 2:
        raise ValueError("r_edges and z_edges need at least two edges each")
    if np.any(np.diff(r_edges) <= 0) or np.any(np.diff(z_edges) <= 0) or r_edges[0] < 0:
        raise ValueError("ring edges must increase, and r_edges start at r >= 0")
    c = np.asarray(centres, dtype=float).reshape(-1, 3)
    a = np.broadcast_to(np.asarray(radii, dtype=float), (c.shape[0],))
    n_r, n_z = r_edges.size - 1, z_edges.size - 1
    rho = np.hypot(c[:, 0] - axis_xy[0], c[:, 1] - axis_xy[1])
    zc = c[:, 2]
    ir0, kr = _edge_slices(r_edges, np.maximum(rho - a, 0.0), rho + a)
    iz0, kz = _edge_slices(z_edges, zc - a, zc + a)
    on = (ir0 + kr >= 0) & (ir0 < n_r) & (iz0 + kz >= 0) & (iz0 < n_z)
    parts_p, parts_c, parts_v = [], [], []
    # spheres cut by no edge: whole, in one ring (most of them)
    whole = on & (kr == 0) & (kz == 0)
    idx = np.nonzero(whole)[0]
    parts_p.append(idx)
    parts_c.append(ir0[idx] * n_z + iz0[idx])
    parts_v.append(4.0 / 3.0 * math.pi * a[idx] ** 3)
    cut = on & ~whole
    if np.any(cut):
        groups = kr[cut] * (kz.max() + 1) + kz[cut]
        cut_idx = np.nonzero(cut)[0]
        for g in np.unique(groups):
            sel = cut_idx[groups == g]
            p, cell, vol = _cut_group(sel, rho[sel], zc[sel], a[sel], ir0[sel], iz0[sel],
                                      int(kr[sel[0]]), int(kz[sel[0]]), r_edges, z_edges,
                                      n_gauss)
            parts_p.append(p)
            parts_c.append(cell)
            parts_v.append(vol)
    p = np.concatenate(parts_p).astype(np.int64)
    cell = np.concatenate(parts_c).astype(np.int64)
    vol = np.concatenate(parts_v)
    keep = vol > 0.0
    return p[keep], cell[keep], vol[keep]


def _cut_group(sel, rho, zc, a, ir0, iz0, kr, kz, r_edges, z_edges, n_gauss, chunk=50000):
    """Triplets of the spheres ``sel``, each cut by ``kr`` radial and ``kz``
    vertical edges (the same counts for all)."""
    n_r, n_z = r_edges.size - 1, z_edges.size - 1
    m = sel.size
    v_all = 4.0 / 3.0 * math.pi * a ** 3
    # K at the corners: index 0 = below the sphere (0), kr + 1 / kz + 1 = beyond
    K = np.zeros((m, kr + 2, kz + 2))
    K[:, -1, -1] = v_all
    re = r_edges[np.clip(ir0[:, None] + 1 + np.arange(kr), 0, n_r)] if kr else None
    ze = z_edges[np.clip(iz0[:, None] + 1 + np.arange(kz), 0, n_z)] if kz else None
    if kz:
        K[:, -1, 1:-1] = _cap_below(ze, zc[:, None], a[:, None])
    if kr:
        for s in range(0, m, chunk):
            sl = slice(s, s + chunk)
            K[sl, 1:-1, -1] = cylinder_below_volume(rho[sl, None], zc[sl, None], a[sl, None],
                                                    re[sl], np.inf, n_gauss)
            if kz:
                K[sl, 1:-1, 1:-1] = cylinder_below_volume(
                    rho[sl, None, None], zc[sl, None, None], a[sl, None, None],
                    re[sl, :, None], ze[sl, None, :], n_gauss)
    vol = K[:, 1:, 1:] - K[:, :-1, 1:] - K[:, 1:, :-1] + K[:, :-1, :-1]
    col = ir0[:, None, None] + np.arange(kr + 1)[None, :, None]
    lay = iz0[:, None, None] + np.arange(kz + 1)[None, None, :]
    col, lay = np.broadcast_arrays(col, lay)
    inside = (col >= 0) & (col < n_r) & (lay >= 0) & (lay < n_z)
    p = np.broadcast_to(sel[:, None, None], vol.shape)
    return p[inside], (col * n_z + lay)[inside], vol[inside]


def ring_volumes(r_edges, z_edges, sector=360.0):
    """(n_r, n_z) volumes of the rings of a chamber sector [m^3]."""
    if not 0.0 < sector <= 360.0:
        raise ValueError("sector must be in (0, 360] degrees, got %r" % (sector,))
    r_edges = np.asarray(r_edges, dtype=float)
    z_edges = np.asarray(z_edges, dtype=float)
    area = sector / 360.0 * math.pi * np.diff(r_edges ** 2)
    return area[:, None] * np.diff(z_edges)[None, :]


def ring_edges_from(width, r_max, height, z_lo, z_hi):
    """Ring edges: columns of ``width`` from the axis to ``r_max`` and layers
    of ``height`` from ``z_lo`` to ``z_hi``, remainders as
    :func:`crushpost.prep.ring_edges` (none narrower than half a width)."""
    from .prep import ring_edges

    return ring_edges(width, r_max), ring_edges(height, z_hi - z_lo, z_lo)


def ring_fields(sigma_p, centres, radii, r_edges, z_edges, axis_xy=(0.0, 0.0), sector=360.0,
                triplets=None):
    """Ring averages of one state of a chamber.

    ``sigma_ring = (1/V_ring) sum_p V_p,in sigma_p`` with ``V_p,in`` the
    exact part of particle p in the ring and ``V_ring`` the ring's volume in
    the simulated sector (voids carry no stress, so this is the average over
    the whole ring). The particle tensors are symmetrised and rotated to the
    (r, theta, z) basis at their centres before the sum.

    Parameters
    ----------
    sigma_p : (n, 3, 3) particle stresses [Pa], or None (no stresses).
    centres, radii : (n, 3), (n,) [m].
    r_edges, z_edges : ring edges [m] (see the module doc).
    sector : degrees of the chamber simulated (360, 180, 90).
    triplets : optional output of :func:`sphere_cell_volumes` to reuse.

    Returns
    -------
    dict of (n_r, n_z) arrays: ``sigma`` (n_r, n_z, 3, 3) in (r, theta, z)
    [Pa] (absent when ``sigma_p`` is None), ``V_ring``, ``V_solid`` [m^3],
    ``porosity`` (1 - V_solid / V_ring), ``n_grains`` (grains whose centre
    is in the ring), ``n_equiv`` (sum of the grains' volume fractions in
    the ring).
    """
    r_edges = np.asarray(r_edges, dtype=float)
    z_edges = np.asarray(z_edges, dtype=float)
    c = np.asarray(centres, dtype=float).reshape(-1, 3)
    rad = np.broadcast_to(np.asarray(radii, dtype=float), (c.shape[0],))
    n_r, n_z = r_edges.size - 1, z_edges.size - 1
    n_cells = n_r * n_z
    if triplets is None:
        triplets = sphere_cell_volumes(c, rad, r_edges, z_edges, axis_xy)
    p, cell, w = triplets
    v_ring = ring_volumes(r_edges, z_edges, sector)
    v_solid = np.bincount(cell, weights=w, minlength=n_cells).reshape(n_r, n_z)
    v_p = 4.0 / 3.0 * math.pi * rad ** 3
    n_equiv = np.bincount(cell, weights=w / v_p[p], minlength=n_cells).reshape(n_r, n_z)
    # centre binning, for the count of grains per ring
    rho = np.hypot(c[:, 0] - axis_xy[0], c[:, 1] - axis_xy[1])
    ic = np.searchsorted(r_edges, rho, side="right") - 1
    kc = np.searchsorted(z_edges, c[:, 2], side="right") - 1
    ok = (ic >= 0) & (ic < n_r) & (kc >= 0) & (kc < n_z)
    n_grains = np.bincount(ic[ok] * n_z + kc[ok], minlength=n_cells).reshape(n_r, n_z)
    out = {"V_ring": v_ring, "V_solid": v_solid, "porosity": 1.0 - v_solid / v_ring,
           "n_grains": n_grains, "n_equiv": n_equiv}
    if sigma_p is not None:
        sig = np.asarray(sigma_p, dtype=float)
        sig = 0.5 * (sig + np.swapaxes(sig, -1, -2))
        cyl = to_cylindrical_tensor(sig, c[:, 0], c[:, 1], axis_xy)
        avg = np.empty((n_cells, 3, 3))
        for i in range(3):
            for j in range(i, 3):
                avg[:, i, j] = np.bincount(cell, weights=w * cyl[p, i, j], minlength=n_cells)
                avg[:, j, i] = avg[:, i, j]
        out["sigma"] = avg.reshape(n_r, n_z, 3, 3) / v_ring[..., None, None]
    return out
