# SPDX-License-Identifier: GPL-2.0-or-later
"""No grain can leave the chamber through the top wall's hole for the pile
(issue 5 item 6): measured on the mesh files write_chamber writes, the gap
between the shaft and the hole is narrower than the smallest fragment that
can exist, everywhere around the axis, and the hole never cuts into the
shaft. Independent of crushpost.chamber.hole_gap: rays from the axis are
intersected with the polygon edges read from the STL files."""

import math

import numpy as np
import pytest

from crushpost.chamber import (SMALL_FRAGMENT_RATIO, hole_gap, hole_radius,
                               smallest_fragment_diameter, write_chamber)
from crushpost.materials import D50, D_COMM_RATIO
from crushpost.meshes import read_stl

N = 39
R_PILE = 0.018


def _hole_edges(top):
    """Edges of the top wall's inner ring (both ends at the smallest radius)."""
    _, tri = read_stl(top)
    r = np.hypot(tri[..., 0], tri[..., 1])
    r_in = r.min()
    edges = []
    for t, rt in zip(tri, r):
        on = np.flatnonzero(np.abs(rt - r_in) < 1e-9 * r_in)
        if len(on) == 2:
            edges.append((t[on[0], :2], t[on[1], :2]))
    return edges


def _shaft_edges(shaft):
    """Edges of the shaft's cross-section: its bottom ring's polygon."""
    _, tri = read_stl(shaft)
    z0 = tri[..., 2].min()
    pts = np.unique(np.round(tri.reshape(-1, 3)[tri.reshape(-1, 3)[:, 2] < z0 + 1e-12][:, :2],
                             15), axis=0)
    phi = np.arctan2(pts[:, 1], pts[:, 0])
    pts = pts[np.argsort(phi)]
    return [(pts[k], pts[(k + 1) % len(pts)]) for k in range(len(pts))]


def _ray_distance(theta, edges):
    """Distance from the axis to the first of ``edges`` along each ray."""
    d = np.full(theta.shape, np.inf)
    u = np.column_stack([np.cos(theta), np.sin(theta)])
    for a, b in edges:
        e = b - a
        den = u[:, 0] * (-e[1]) - u[:, 1] * (-e[0])
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (a[0] * (-e[1]) - a[1] * (-e[0])) / den          # along the ray
            s = (u[:, 0] * a[1] - u[:, 1] * a[0]) / den          # along the edge
        hit = (np.abs(den) > 1e-300) & (t > 0) & (s >= -1e-12) & (s <= 1 + 1e-12)
        d = np.where(hit & (t < d), t, d)
    return d


@pytest.mark.parametrize("sector", [360, 180, 90])
def test_hole_gap_is_smaller_than_the_smallest_fragment(tmp_path, sector):
    write_chamber(str(tmp_path), N, 0.05, 0.05, R_PILE, 0.01, sector=sector, rng=10069)
    hole = _hole_edges(tmp_path / "top.stl")
    shaft = _shaft_edges(tmp_path / "shaft.stl")
    span = math.radians(sector)
    theta = np.concatenate([np.linspace(0.0, span, 40001),
                            np.radians(np.arange(0.0, sector + 1e-9, 3.75))])
    gap = _ray_distance(theta, hole) - _ray_distance(theta, shaft)
    assert np.all(np.isfinite(gap))
    d_frag = SMALL_FRAGMENT_RATIO * D_COMM_RATIO * D50 * N        # 1.036 mm
    assert d_frag == pytest.approx(1.0365e-3, rel=1e-4)
    # narrower than the smallest fragment with a wide margin (grains overlap
    # walls by far less than half their size)
    assert gap.max() < 0.5 * d_frag, gap.max()
    # and the hole never cuts into the shaft
    assert gap.min() > -1e-12 * R_PILE, gap.min()
    # the closed form agrees with the meshes
    lo, hi = hole_gap(R_PILE, hole_radius(R_PILE))
    assert hi == pytest.approx(gap.max(), rel=1e-6)
    assert hi < smallest_fragment_diameter(N)


def test_hole_gap_closed_form():
    # a hole of 1.25 R (the former one) around a 24-gon: the widest gap is
    # 1.25 R - R cos(7.5 deg), in the middle of a shaft facet
    lo, hi = hole_gap(R_PILE, 1.25 * R_PILE)
    assert hi == pytest.approx(1.25 * R_PILE - R_PILE * math.cos(math.pi / 24), rel=1e-9)
    assert lo == pytest.approx(0.25 * R_PILE, rel=1e-9)
    assert hi > smallest_fragment_diameter(N)
    # hole on the shaft's vertex circle: touching at the vertices
    lo, hi = hole_gap(R_PILE, R_PILE)
    assert lo == pytest.approx(0.0, abs=1e-15)
    assert hi == pytest.approx(R_PILE * (1 - math.cos(math.pi / 24)), rel=1e-9)
