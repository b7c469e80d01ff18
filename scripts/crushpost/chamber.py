# SPDX-License-Identifier: GPL-2.0-or-later
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
from .materials import D_COMM_RATIO, RHO_GRAIN
from .packing import D50_NE34, ne34_diameters, rsa_cylinder, rsa_cylinder_fast, write_lammps_data

RHO_NE34 = RHO_GRAIN      # crushpost.materials
SECTORS = (360, 180, 90)
N_SEG_FULL = 48          # strips of the full lateral wall (and top wall sectors)
N_ATOM_TYPES = 4         # material types of inputs/materials_ne34.in


def hole_radius(r_pile):
    """Radius of the top wall's hole for the pile: R, the circle through the
    shaft's vertices.

    Grains escaped through a wider hole: 1.25 R left a ring 4.5 mm wide
    around the shaft (R = 18 mm), which fragments (1.0-3.4 mm at N = 39) and
    the smallest unbroken grains passed. The hole polygon (the annulus' inner
    ring, 7.5 degree segments whose vertices include every vertex of the
    24-segment shaft) now holds the shaft polygon and touches it at the
    shaft's vertices; the widest gap, in the middle of a shaft facet, is
    R (1 - cos(pi / 24)) = 0.0086 R (0.15 mm for R = 18 mm), under the
    smallest fragment for N >= 6 (:func:`hole_gap`,
    :func:`smallest_fragment_diameter`). Rigid meshes do not collide, so the
    pile still moves freely through it.
    """
    return float(r_pile)


def _small_fragment_ratio():
    # the small sphere of the 14-sphere Apollonian fragmentation (docs/model.md
    # §2.6), at distance u = r - r2 along a cube diagonal, touches three
    # large ones (r1 = r / (1 + sqrt 2), at a = r - r1 on the axes):
    # u^2 - 2 a u / sqrt 3 + a^2 = (r + r1 - u)^2, linear in u (r = 1)
    r1 = 1.0 / (1.0 + math.sqrt(2.0))
    a, b = 1.0 - r1, 1.0 + r1
    return 1.0 - (b * b - a * a) / (2.0 * b - 2.0 * a / math.sqrt(3.0))


#: Small-fragment radius over parent radius, 0.230093...
SMALL_FRAGMENT_RATIO = _small_fragment_ratio()


def smallest_fragment_diameter(N, d_comm_over_d50=D_COMM_RATIO):
    """Diameter [m] of the smallest fragment that can exist at up-scaling N:
    the small fragment of the smallest breakable grain (d = d_comm =
    0.55 d50, d50 = 0.21 mm N): 0.230093 d_comm, 1.04 mm at N = 39."""
    return SMALL_FRAGMENT_RATIO * d_comm_over_d50 * D50_NE34 * N


def _polygon_radius(theta, r_vertex, phi0, dphi):
    # distance from the axis to a regular polygon's edge (vertices at radius
    # r_vertex, azimuths phi0 + k dphi) along the ray at azimuth theta
    t = np.mod(theta - phi0, dphi) - 0.5 * dphi
    return r_vertex * math.cos(0.5 * dphi) / np.cos(t)


def hole_gap(r_pile, r_hole, n_seg_pile=24, n_seg_hole=N_SEG_FULL, phi0_hole=0.0,
             phi1_hole=360.0, n_theta=20000):
    """Radial gap [m] between the shaft polygon (``n_seg_pile`` vertices at
    radius ``r_pile``, azimuths 360 k / n_seg_pile, crushpost.meshes) and the
    hole polygon of the top wall (``n_seg_hole`` segments from azimuth
    ``phi0_hole`` to ``phi1_hole``, vertices at ``r_hole``), over the hole's
    arc: returns (smallest, largest). A sphere whose diameter exceeds the
    largest radial gap cannot pass (its equator, in the wall's plane, would
    have to fit between the polygons along the radius through its centre);
    a negative smallest gap means the wall cuts into the shaft.
    """
    dphi_h = math.radians(phi1_hole - phi0_hole) / n_seg_hole
    dphi_p = 2.0 * math.pi / n_seg_pile
    a0, a1 = math.radians(phi0_hole), math.radians(phi1_hole)
    # a fine sweep plus the extremes' candidates: both polygons' vertices and
    # facet middles
    theta = np.concatenate([
        np.linspace(a0, a1, n_theta),
        a0 + dphi_h * np.arange(n_seg_hole + 1), a0 + dphi_h * (np.arange(n_seg_hole) + 0.5),
        dphi_p * np.arange(-n_seg_pile, 2 * n_seg_pile) / 2.0])
    theta = theta[(theta >= a0) & (theta <= a1)]
    gap = (_polygon_radius(theta, r_hole, a0, dphi_h)
           - _polygon_radius(theta, r_pile, 0.0, dphi_p))
    return float(gap.min()), float(gap.max())


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
