# SPDX-License-Identifier: GPL-2.0-or-later
"""Initial grain assemblies: the NE34 grading shape and random loose packings.

The grading of Fontainebleau NE34 (docs/model.md §3: d50 = 0.21 mm, coefficient
of uniformity Cu = d60/d10 about 1.47) is represented by a log-normal grading
*by mass* with median d50 and ln-standard deviation
``SIGMA_LN = ln(Cu) / (z60 - z10)``, truncated at +-2.5 SIGMA_LN about the
median (``TRUNCATE``, in the mass-weighted variable). Scaling by N
multiplies d50 and keeps the shape. A log-normal by mass is a log-normal by
number with median ``d50 exp(-3 SIGMA_LN^2)`` and the same SIGMA_LN.
"""

import math

import numpy as np
from scipy.special import ndtri

from .materials import CU, D50

D50_NE34 = D50  # m, real size (crushpost.materials)
CU_NE34 = CU
SIGMA_LN = math.log(CU_NE34) / (ndtri(0.60) - ndtri(0.10))
TRUNCATE = 2.5


def ne34_diameters(n, N=1.0, rng=None, d50=None):
    """n diameters [m] with the NE34 grading shape scaled by N (number-weighted draws)."""
    rng = np.random.default_rng(rng)
    d50 = D50_NE34 * N if d50 is None else d50
    median_number = d50 * math.exp(-3.0 * SIGMA_LN ** 2)
    out = np.empty(0)
    while out.size < n:
        z = rng.standard_normal(2 * n)
        z = z[np.abs(z - 3.0 * SIGMA_LN) <= TRUNCATE]  # truncate in the mass-weighted variable
        out = np.concatenate([out, median_number * np.exp(SIGMA_LN * z)])
    return out[:n]


def _in_sector(x, y, r, sector_deg):
    """True where a sphere of radius r at (x, y) clears the symmetry planes of
    a sector 0 <= azimuth <= sector_deg (no planes for a full circle)."""
    if sector_deg >= 360.0:
        return np.ones(np.shape(x), dtype=bool)
    t = math.radians(sector_deg)
    # distance to the plane at azimuth 0 (y = 0) and to the one at azimuth t
    ok = (y >= r) & (x * math.sin(t) - y * math.cos(t) >= r)
    if sector_deg > 180.0:
        raise ValueError("sector_deg must be <= 180 or 360, got %g" % sector_deg)
    return ok


def _cylinder_sample(radius, z_lo, z_hi, sector_deg):
    t = math.radians(min(sector_deg, 360.0))

    def sample(rng, ri):
        while True:
            rho = (radius - ri) * math.sqrt(rng.random())
            phi = t * rng.random()
            x, y = rho * math.cos(phi), rho * math.sin(phi)
            if _in_sector(x, y, ri, sector_deg):
                return np.array([x, y, z_lo + ri + (z_hi - z_lo - 2.0 * ri) * rng.random()])
    return sample


def rsa_cylinder(diameters, radius, z_lo, z_hi, rng=None, max_tries=200000, sector_deg=360.0):
    """Random sequential addition of spheres (largest first) in a cylinder on the z axis.

    ``sector_deg`` < 360 (at most 180): only the sector 0 <= azimuth <= sector_deg,
    every sphere clear of its two bounding planes through the axis.
    Returns positions (n, 3). Raises RuntimeError if a sphere cannot be placed:
    ask for a lower solid fraction or a larger container.
    """
    return _rsa(diameters, _cylinder_sample(radius, z_lo, z_hi, sector_deg), rng, max_tries)


def rsa_cylinder_fast(diameters, radius, z_lo, z_hi, rng=None, sector_deg=360.0, batch=40000,
                      tries=8, max_rounds=100000):
    """Random sequential addition in a cylinder (sector), vectorised for large n.

    The same placement rule as :func:`rsa_cylinder` (largest first, a random
    point accepted when it overlaps no placed sphere and lies wholly inside),
    done in rounds: the largest spheres not yet placed (a 200th of all, at
    most ``batch // tries``) get
    ``tries`` random candidates each (more when few are left); the first
    candidate of each sphere that overlaps no placed sphere (k-d tree of the
    placed ones) is kept unless it overlaps the kept candidate of a larger
    sphere of the same round; the others are tried again in the next round. For
    several hundred thousand grains (the paper chamber) it takes minutes where
    the sphere-by-sphere loop takes hours. Returns positions (n, 3).
    """
    from scipy.spatial import cKDTree
    rng = np.random.default_rng(rng)
    d = np.asarray(diameters, dtype=float)
    r = 0.5 * d
    order = np.argsort(-d, kind="stable")
    pos = np.full((d.size, 3), np.nan)
    t = math.radians(min(sector_deg, 360.0))
    placed = np.zeros(0, dtype=int)
    pending = order.copy()
    r_max = r.max()
    tree = None
    for _ in range(max_rounds):
        if pending.size == 0:
            return pos
        # the next (largest) spheres, several tries each, so that a sphere that
        # fails is placed before much smaller ones fill its space
        head = pending[:max(16, min(batch // tries, d.size // 200))]
        idx = np.repeat(head, max(tries, batch // (tries * head.size)))
        ri = r[idx]
        n = idx.size
        rho = (radius - ri) * np.sqrt(rng.random(n))
        phi = t * rng.random(n)
        p = np.column_stack([rho * np.cos(phi), rho * np.sin(phi),
                             z_lo + ri + (z_hi - z_lo - 2.0 * ri) * rng.random(n)])
        ok = _in_sector(p[:, 0], p[:, 1], ri, sector_deg)
        if tree is not None:
            # any placed sphere within ri + r_max; k nearest, and a conservative
            # rejection if all k lie within that range (there may be more)
            k = 64
            dist, nb = tree.query(p, k=k, distance_upper_bound=(ri + r_max)[:, None].max())
            valid = nb < placed.size
            nbc = np.where(valid, nb, 0)
            overl = valid & (dist < ri[:, None] + r[placed[nbc]])
            ok &= ~overl.any(axis=1)
            ok &= ~valid[:, -1]
        # one candidate per sphere: the first that fits
        first = np.zeros(n, dtype=bool)
        okc = np.flatnonzero(ok)
        _, first_pos = np.unique(idx[okc], return_index=True)
        first[okc[first_pos]] = True
        ok = first
        # conflicts inside the batch: a later (smaller or equal) candidate yields
        cand = np.flatnonzero(ok)
        if cand.size > 1:
            bt = cKDTree(p[cand])
            pairs = bt.query_pairs(2.0 * ri[cand].max(), output_type="ndarray")
            if pairs.size:
                a, b = cand[pairs[:, 0]], cand[pairs[:, 1]]
                hit = np.sum((p[a] - p[b]) ** 2, axis=1) < (ri[a] + ri[b]) ** 2
                lose = np.where(a[hit] > b[hit], a[hit], b[hit])
                ok[lose] = False
        pos[idx[ok]] = p[ok]
        placed = np.concatenate([placed, idx[ok]])
        done = np.zeros(d.size, dtype=bool)
        done[idx[ok]] = True
        pending = np.concatenate([head[~done[head]], pending[head.size:]])
        tree = cKDTree(pos[placed])
    raise RuntimeError("rsa_cylinder_fast: %d spheres not placed after %d rounds; lower the "
                       "solid fraction" % (pending.size, max_rounds))


def rsa_box(diameters, lo, hi, rng=None, max_tries=200000):
    """Random sequential addition of spheres (largest first) in the box lo <= x <= hi.

    lo, hi: 3-vectors of the box corners; every sphere lies wholly inside.
    Returns positions (n, 3). Raises RuntimeError if a sphere cannot be placed.
    """
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    if np.any(hi - lo < np.max(diameters)):
        raise RuntimeError("rsa_box: the largest sphere (d = %g) does not fit in the box"
                           % np.max(diameters))

    def sample(rng, ri):
        return lo + ri + (hi - lo - 2.0 * ri) * rng.random(3)
    return _rsa(diameters, sample, rng, max_tries)


def _rsa(diameters, sample, rng, max_tries):
    rng = np.random.default_rng(rng)
    d = np.asarray(diameters, dtype=float)
    order = np.argsort(-d)
    r = 0.5 * d
    pos = np.full((d.size, 3), np.nan)
    cell = 2.0 * r.max()
    grid = {}

    def key(p):
        return tuple((p // cell).astype(int))

    for idx in order:
        ri = r[idx]
        for _ in range(max_tries):
            p = sample(rng, ri)
            k = key(p)
            ok = True
            for dx in (-1, 0, 1):
                for dy in (-1, 0, 1):
                    for dz in (-1, 0, 1):
                        for j in grid.get((k[0] + dx, k[1] + dy, k[2] + dz), ()):
                            if np.sum((pos[j] - p) ** 2) < (ri + r[j]) ** 2:
                                ok = False
                                break
                        if not ok:
                            break
                    if not ok:
                        break
                if not ok:
                    break
            if ok:
                pos[idx] = p
                grid.setdefault(k, []).append(idx)
                break
        else:
            raise RuntimeError("random sequential addition: could not place sphere %d of %d; lower the "
                               "solid fraction" % (idx, d.size))
    return pos


def write_lammps_data(path, positions, diameters, density, box, ntypes=1, atom_type=1):
    """LAMMPS data file for atom_style granular (id type diameter density x y z)."""
    with open(path, "w") as f:
        f.write("LIGGGHTS data file written by crushpost.packing\n\n")
        f.write("%d atoms\n%d atom types\n\n" % (len(diameters), ntypes))
        f.write("%.12g %.12g xlo xhi\n%.12g %.12g ylo yhi\n%.12g %.12g zlo zhi\n\n" % tuple(box))
        f.write("Atoms\n\n")
        for i, (p, d) in enumerate(zip(positions, diameters)):
            f.write("%d %d %.12g %.12g %.12g %.12g %.12g\n" % (i + 1, atom_type, d, density,
                                                                p[0], p[1], p[2]))

