"""Input files of the calibration chamber decks (examples/cpt_demo,
examples/cpt_paper): the loose packing and the meshes read by
inputs/chamber_walls.in, for the full chamber or a sector of it.

A sector of ``sector`` degrees (180: y >= 0, 90: x >= 0 and y >= 0) is bounded
by frictionless symmetry planes through the pile axis (the primitive walls of
inputs/chamber_sym_<sector>.in). Its chamber meshes (lateral wall, top wall,
bottom) cover the sector plus one strip of margin on each side, the pile
meshes are whole, and the simulation box holds the sector and the pile.
"""

import math
import os

import numpy as np

from .meshes import annulus_triangles, cylinder_triangles, plate_triangles, write_pile_stl, write_stl
from .packing import D50_NE34, ne34_diameters, rsa_cylinder, rsa_cylinder_fast, write_lammps_data

RHO_NE34 = 2600.0
SECTORS = (360, 180, 90)
N_SEG_FULL = 48          # strips of the full lateral wall (and top wall sectors)


def hole_radius(r_pile):
    """Radius of the top wall's hole for the pile (1.25 R)."""
    return 1.25 * r_pile


def chamber_diameters(N, radius, height, n_target=0.385, shrink=0.75, sector=360, rng=None):
    """NE34 diameters (scaled by N) that fill the sector of the chamber at
    porosity n_target, then multiplied by ``shrink`` (they grow back during
    the radius expansion)."""
    rng = np.random.default_rng(rng)
    d50 = D50_NE34 * N
    volume = (sector / 360.0) * math.pi * radius ** 2 * height
    d = ne34_diameters(int(40 * volume / math.pi / d50 ** 3) + 100, N, rng=rng)
    n = int(np.searchsorted(np.cumsum(np.pi / 6 * d ** 3), (1 - n_target) * volume))
    return d[:n] * shrink


def write_chamber(out, N, radius, height, r_pile, depth, n_target=0.385, shrink=0.75,
                  sector=360, rng=None, fast=None, n_seg_pile=24):
    """Write grains.data and the meshes of a chamber of ``radius`` and ``height``
    with a pile of radius ``r_pile`` pushed to ``depth``, into ``out``.

    Returns a dict: n (grains), tip_z0 (initial cone apex z = height), box,
    R_hole. ``fast`` (default: for more than 20000 grains) uses the vectorised
    :func:`crushpost.packing.rsa_cylinder_fast`.
    """
    if sector not in SECTORS:
        raise ValueError("sector must be one of %s degrees, got %r" % (SECTORS, sector))
    os.makedirs(out, exist_ok=True)
    rng = np.random.default_rng(rng)
    d50 = D50_NE34 * N
    R, H = radius, height
    d = chamber_diameters(N, R, H, n_target, shrink, sector, rng)
    if fast is None:
        fast = d.size > 20000
    if fast:
        pos = rsa_cylinder_fast(d, R, 0.0, H, rng=rng, sector_deg=sector)
    else:
        pos = rsa_cylinder(d, R, 0.0, H, rng=rng, sector_deg=sector)
    tip_z0 = H
    pile = write_pile_stl(out, r_pile, shaft_length=depth + 0.05 * H + 2 * d50, tip_z=tip_z0,
                          n_seg=n_seg_pile)
    L = 1.25 * R
    m = max(1.5 * r_pile, 0.2 * R)         # box margin on the far side of a symmetry plane
    x_lo = -L if sector >= 180 else -m
    y_lo = -L if sector >= 360 else -m
    box = (x_lo, L, y_lo, L, -0.05 * H, pile["z_top"] + 0.02 * H)
    write_lammps_data(os.path.join(out, "grains.data"), pos, d, RHO_NE34, box, ntypes=3)
    r_hole = hole_radius(r_pile)
    if sector >= 360:
        phi0, phi1, n_seg = 0.0, 360.0, N_SEG_FULL
        bottom = plate_triangles(1.15 * R)
    else:
        dphi = 360.0 / N_SEG_FULL          # one strip of margin on each side
        phi0, phi1 = -dphi, sector + dphi
        n_seg = int(round((phi1 - phi0) / dphi))
        bottom = plate_triangles(1.15 * R, lo=(max(x_lo, -1.15 * R) * 0.9, y_lo * 0.9))
    write_stl(os.path.join(out, "side.stl"),
              cylinder_triangles(R, -0.02 * H, 1.1 * H, n_seg, phi0=phi0, phi1=phi1), "side")
    write_stl(os.path.join(out, "bottom.stl"), bottom, "bottom")
    write_stl(os.path.join(out, "top.stl"),
              annulus_triangles(r_hole, 1.15 * R, H, n_seg, phi0=phi0, phi1=phi1), "top")
    write_stl(os.path.join(out, "plug.stl"), plate_triangles(1.4 * r_pile, 1.001 * H), "plug")
    return {"n": int(d.size), "tip_z0": tip_z0, "box": box, "R_hole": r_hole,
            "solid_volume": float(np.sum(np.pi / 6 * d ** 3) / shrink ** 3)}
