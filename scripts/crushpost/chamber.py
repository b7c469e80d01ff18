"""Input files of the calibration chamber decks (examples/cpt_demo,
examples/cpt_paper): the loose packing and the meshes read by
inputs/chamber_walls.in, for the full chamber or a sector of it.

A sector of ``sector`` degrees (180: y >= 0, 90: x >= 0 and y >= 0) is bounded
by rigid frictionless symmetry planes through the pile axis: planar meshes
sym_y.stl (the plane y = 0) and, for 90 degrees, sym_x.stl (x = 0), material
type 4 in inputs/chamber_sym_<sector>.in, part of the chamber's one mesh wall
fix. Its chamber meshes (lateral wall, top wall, bottom) cover the sector plus
one strip of margin on each side, the pile meshes are whole, and the
simulation box holds the sector and the pile.

The data file declares 4 atom types (inputs/materials_ne34.in has one entry
per type: grain, steel, chamber wall, symmetry plane); the grains are type 1.
"""

import math
import os

import numpy as np

from .meshes import (annulus_triangles, cylinder_triangles, plate_triangles, rectangle_triangles,
                     write_pile_stl, write_stl)
from .packing import D50_NE34, ne34_diameters, rsa_cylinder, rsa_cylinder_fast, write_lammps_data

RHO_NE34 = 2600.0
SECTORS = (360, 180, 90)
N_SEG_FULL = 48          # strips of the full lateral wall (and top wall sectors)
N_ATOM_TYPES = 4         # material types of inputs/materials_ne34.in


def hole_radius(r_pile):
    """Radius of the top wall's hole for the pile (1.25 R)."""
    return 1.25 * r_pile


def symmetry_planes(sector, radius, z_lo, z_hi, far_side):
    """Triangles of the symmetry planes of a chamber sector, as a dict
    ``{name: triangles}``: ``sym_y`` (the plane y = 0, normal +y) for sector
    180 and 90, ``sym_x`` (x = 0, normal +x) for 90; none for 360.

    Each plane is a rectangle (two facets) through the pile axis, from
    ``z_lo`` to ``z_hi`` and from ``-far_side`` (a strip beyond the axis, on
    the side of the plane outside the sector) to 1.15 ``radius`` (beyond the
    lateral wall) along the plane, so it covers every place a grain of the
    sector can reach. LIGGGHTS stops a run when a mesh leaves the box: the
    caller keeps these bounds inside it.
    """
    if sector not in SECTORS:
        raise ValueError("sector must be one of %s degrees, got %r" % (SECTORS, sector))
    if sector == 360:
        return {}
    lo = -1.15 * radius if sector == 180 else -far_side
    hi = 1.15 * radius
    half_z, half_s = 0.5 * (z_hi - z_lo), 0.5 * (hi - lo)
    cz, cs = 0.5 * (z_hi + z_lo), 0.5 * (hi + lo)
    # rectangle_triangles: axis 1 (y = 0) spans u = z, v = x; axis 0 (x = 0) spans u = y, v = z
    planes = {"sym_y": rectangle_triangles(1, 0.0, (cs, 0.0, cz), half_z, half_s)}
    if sector == 90:
        planes["sym_x"] = rectangle_triangles(0, 0.0, (0.0, cs, cz), half_s, half_z)
    return planes


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
    R_hole, symmetry_planes (names of the plane meshes written, sym_<axis>.stl). ``fast`` (default: for more than 20000 grains) uses the vectorised
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
    write_lammps_data(os.path.join(out, "grains.data"), pos, d, RHO_NE34, box, ntypes=N_ATOM_TYPES)
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
    # symmetry planes: the side wall's height, on the far side of the axis as
    # far as the bottom plate reaches (both inside the box)
    planes = symmetry_planes(sector, R, -0.02 * H, 1.1 * H, 0.9 * m)
    for name, tris in planes.items():
        write_stl(os.path.join(out, name + ".stl"), tris, name)
    return {"n": int(d.size), "tip_z0": tip_z0, "box": box, "R_hole": r_hole,
            "symmetry_planes": sorted(planes),
            "solid_volume": float(np.sum(np.pi / 6 * d ** 3) / shrink ** 3)}
