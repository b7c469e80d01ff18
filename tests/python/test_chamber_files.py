# SPDX-License-Identifier: GPL-2.0-or-later
"""Input files of the chamber decks: sector meshes, sector packings and the
vectorised random sequential addition (crushpost.chamber, crushpost.packing,
crushpost.meshes). Checked against brute-force geometry."""

import math

import numpy as np
import pytest
from scipy.spatial import cKDTree

from crushpost.chamber import N_ATOM_TYPES, symmetry_planes, write_chamber
from crushpost.meshes import annulus_triangles, cylinder_triangles, read_stl
from crushpost.packing import ne34_diameters, rsa_cylinder, rsa_cylinder_fast


def overlaps(pos, d):
    """Number of overlapping pairs, brute force over k-d tree candidates."""
    pairs = cKDTree(pos).query_pairs(d.max(), output_type="ndarray")
    if pairs.size == 0:
        return 0
    gap = np.linalg.norm(pos[pairs[:, 0]] - pos[pairs[:, 1]], axis=1) - 0.5 * (d[pairs[:, 0]] + d[pairs[:, 1]])
    return int(np.sum(gap < 0.0))


def loose_diameters(n_target_solid, R, H, sector, seed):
    rng = np.random.default_rng(seed)
    d = ne34_diameters(20000, 39, rng=rng)
    vol = sector / 360.0 * math.pi * R * R * H
    n = int(np.searchsorted(np.cumsum(np.pi / 6 * d ** 3), n_target_solid * vol))
    return d[:n]


@pytest.mark.parametrize("sector", [360.0, 180.0, 90.0])
def test_fast_rsa_places_every_sphere_without_overlap_inside(sector):
    R, H = 0.06, 0.08
    d = loose_diameters(0.26, R, H, sector, 10007)      # the decks' initial solid fraction
    pos = rsa_cylinder_fast(d, R, 0.0, H, rng=10009, sector_deg=sector)
    r = 0.5 * d
    assert not np.isnan(pos).any()
    assert overlaps(pos, d) == 0
    assert np.all(np.hypot(pos[:, 0], pos[:, 1]) + r <= R * (1 + 1e-12))
    assert np.all(pos[:, 2] - r >= -1e-15) and np.all(pos[:, 2] + r <= H * (1 + 1e-12))
    if sector < 360:
        assert np.all(pos[:, 1] >= r)                    # plane y = 0
    if sector == 90:
        assert np.all(pos[:, 0] >= r)                    # plane x = 0
    # the grains fill the sector: azimuths cover it (no empty half)
    phi = np.degrees(np.arctan2(pos[:, 1], pos[:, 0])) % 360.0
    hist = np.histogram(phi, bins=4, range=(0, sector))[0]
    assert hist.min() > 0.15 * d.size


def test_fast_rsa_is_reproducible():
    d = loose_diameters(0.2, 0.05, 0.05, 360.0, 10037)
    a = rsa_cylinder_fast(d, 0.05, 0.0, 0.05, rng=10039)
    b = rsa_cylinder_fast(d, 0.05, 0.0, 0.05, rng=10039)
    np.testing.assert_array_equal(a, b)


def test_sequential_rsa_in_a_quarter():
    d = loose_diameters(0.2, 0.05, 0.04, 90.0, 10061)
    pos = rsa_cylinder(d, 0.05, 0.0, 0.04, rng=10067, sector_deg=90.0)
    assert overlaps(pos, d) == 0
    assert np.all(pos[:, 0] >= 0.5 * d) and np.all(pos[:, 1] >= 0.5 * d)


def test_arc_meshes_span_the_requested_azimuths():
    tris = np.array(cylinder_triangles(0.1, 0.0, 0.2, 14, phi0=-7.5, phi1=97.5))
    pts = tris.reshape(-1, 3)
    phi = np.degrees(np.arctan2(pts[:, 1], pts[:, 0]))
    assert phi.min() == pytest.approx(-7.5, abs=1e-9) and phi.max() == pytest.approx(97.5, abs=1e-9)
    np.testing.assert_allclose(np.hypot(pts[:, 0], pts[:, 1]), 0.1, rtol=1e-12)
    # the full default is unchanged: nodes at 2 pi k / n
    full = np.array(cylinder_triangles(0.1, 0.0, 0.2, 48)).reshape(-1, 3)
    ang = np.sort(np.unique(np.round(np.degrees(np.arctan2(full[:, 1], full[:, 0])), 6) % 360.0))
    np.testing.assert_allclose(ang, 7.5 * np.arange(48), atol=1e-9)
    ring = np.array(annulus_triangles(0.02, 0.1, 0.3, 14, phi0=-7.5, phi1=97.5)).reshape(-1, 3)
    assert np.all(ring[:, 2] == 0.3)
    area = sum(0.5 * np.linalg.norm(np.cross(t[1] - t[0], t[2] - t[0]))
               for t in np.array(annulus_triangles(0.02, 0.1, 0.3, 14, phi0=-7.5, phi1=97.5)))
    # polygonal annulus sector: 14 trapezoids of half-angle 3.75 degrees
    h = math.radians(3.75)
    assert area == pytest.approx(14 * math.sin(2 * h) * (0.1 ** 2 - 0.02 ** 2) / 2, rel=1e-12)


@pytest.mark.parametrize("sector", [360, 180, 90])
def test_chamber_files_fit_in_the_box(tmp_path, sector):
    c = write_chamber(str(tmp_path), 39, 0.05, 0.05, 0.018, 0.01, sector=sector, rng=10069)
    xlo, xhi, ylo, yhi, zlo, zhi = c["box"]
    data = np.loadtxt(tmp_path / "grains.data", skiprows=11)
    assert data.shape[0] == c["n"]
    # materials_ne34.in has 4 types (grain, steel, chamber wall, symmetry plane)
    assert "\n%d atom types\n" % N_ATOM_TYPES in (tmp_path / "grains.data").read_text()
    assert N_ATOM_TYPES == 4 and np.all(data[:, 1] == 1)
    planes = {360: [], 180: ["sym_y"], 90: ["sym_x", "sym_y"]}[sector]
    assert c["symmetry_planes"] == planes
    assert sorted(p.stem for p in tmp_path.glob("sym_*.stl")) == planes
    for name in ["side", "top", "plug", "bottom", "cone", "shaft"] + planes:
        _, v = read_stl(str(tmp_path / (name + ".stl")))
        v = v.reshape(-1, 3)
        assert v[:, 0].min() >= xlo and v[:, 0].max() <= xhi, name
        assert v[:, 1].min() >= ylo and v[:, 1].max() <= yhi, name
        assert v[:, 2].min() >= zlo and v[:, 2].max() <= zhi, name
    if sector == 90:
        r = 0.5 * data[:, 2]
        assert np.all(data[:, 4] >= r) and np.all(data[:, 5] >= r)
        # the sector's solid volume is a quarter of the full chamber's
        full = write_chamber(str(tmp_path / "full"), 39, 0.05, 0.05, 0.018, 0.01, sector=360, rng=10069)
        assert c["solid_volume"] == pytest.approx(0.25 * full["solid_volume"], rel=0.03)


@pytest.mark.parametrize("sector", [180, 90])
def test_symmetry_planes_cover_the_sector(tmp_path, sector):
    """Each plane lies in its plane through the axis, covers the sector's
    grains from below the bottom to above the top and out past the lateral
    wall, and reaches past the axis (where the two planes of a quarter meet)."""
    R, H = 0.05, 0.05
    c = write_chamber(str(tmp_path), 39, R, H, 0.018, 0.01, sector=sector, rng=10069)
    data = np.loadtxt(tmp_path / "grains.data", skiprows=11)
    for name, axis in (("sym_y", 1), ("sym_x", 0)):
        if name not in c["symmetry_planes"]:
            continue
        n, v = read_stl(str(tmp_path / (name + ".stl")))
        pts = v.reshape(-1, 3)
        assert np.all(pts[:, axis] == 0.0)
        # normals into the sector (+y for y = 0, +x for x = 0)
        np.testing.assert_allclose(n, np.tile(np.eye(3)[axis], (len(n), 1)), atol=1e-12)
        other = 1 - axis
        span = (pts[:, other].min(), pts[:, other].max())
        assert span[0] < 0.0 and span[1] > R * 1.1
        if sector == 180:
            assert span[0] < -R * 1.1                  # the whole diameter
        assert pts[:, 2].min() < 0.0 and pts[:, 2].max() > H
        assert data[:, 4 + other].max() < span[1] and data[:, 6].max() < pts[:, 2].max()
        # two facets covering the rectangle
        area = sum(0.5 * np.linalg.norm(np.cross(t[1] - t[0], t[2] - t[0])) for t in v)
        assert area == pytest.approx((span[1] - span[0]) * np.ptp(pts[:, 2]), rel=1e-12)
    assert symmetry_planes(360, R, 0.0, H, 0.01) == {}
    with pytest.raises(ValueError, match="sector"):
        symmetry_planes(45, R, 0.0, H, 0.01)
