"""Initial grain assemblies: the NE34 grading shape and random loose packings.

The grading of Fontainebleau NE34 (SPEC section 3: d50 = 0.21 mm, coefficient
of uniformity Cu = d60/d10 about 1.47) is represented by a log-normal grading
*by mass* with median d50 and ln-standard deviation
``SIGMA_LN = ln(Cu) / (z60 - z10)``, truncated at +-2 SIGMA_LN. Scaling by N
multiplies d50 and keeps the shape. A log-normal by mass is a log-normal by
number with median ``d50 exp(-3 SIGMA_LN^2)`` and the same SIGMA_LN.
"""

import math

import numpy as np
from scipy.special import ndtri

D50_NE34 = 0.21e-3  # m, real size
CU_NE34 = 1.47
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


def rsa_cylinder(diameters, radius, z_lo, z_hi, rng=None, max_tries=200000):
    """Random sequential addition of spheres (largest first) in a cylinder on the z axis.

    Returns positions (n, 3). Raises RuntimeError if a sphere cannot be placed:
    ask for a lower solid fraction or a larger container.
    """
    def sample(rng, ri):
        rho = (radius - ri) * math.sqrt(rng.random())
        phi = 2.0 * math.pi * rng.random()
        return np.array([rho * math.cos(phi), rho * math.sin(phi),
                         z_lo + ri + (z_hi - z_lo - 2.0 * ri) * rng.random()])
    return _rsa(diameters, sample, rng, max_tries)


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

