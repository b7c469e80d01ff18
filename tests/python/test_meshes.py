# SPDX-License-Identifier: GPL-2.0-or-later
"""Pile meshes (crushpost.meshes): the 60-degree cone tip and the cylindrical
shaft as separate ASCII STL files (docs/model.md §4.5), and the CLI entry
``python3 -m crushpost pile``.

Checked on the files as written (vertices printed with 12 significant digits):
vertex radii and heights, the apex angle, facet normals (right-hand rule,
unit length, pointing out of the pile), a watertight and consistently oriented
cone + shaft surface (open only at the top), lateral areas against the exact
polygon values and against pi R L (cone) and 2 pi R h (shaft) within the
discretisation error, and the enclosed volume.
"""

import json
import math
import os
import subprocess
import sys
from collections import Counter
from pathlib import Path

import numpy as np
import pytest

from crushpost.cli import main
from crushpost.meshes import (cone_height, cone_tip_triangles, default_shaft_rings,
                              plate_triangles, read_stl, shaft_triangles, write_pile_stl)

R = 0.018           # pile radius (m), docs/model.md §4.5
TIP_Z = 0.05
L_SHAFT = 0.2
RTOL_FILE = 1e-10   # 12 significant digits in the STL text


def _pile(tmp_path, n_seg=24, n_rings=None, radius=R, tip_z=TIP_Z, length=L_SHAFT):
    info = write_pile_stl(str(tmp_path), radius, length, tip_z=tip_z, n_seg=n_seg,
                          n_rings=n_rings)
    cone = read_stl(info["cone"])
    shaft = read_stl(info["shaft"])
    return info, cone, shaft


def _area(verts):
    return 0.5 * np.linalg.norm(np.cross(verts[:, 1] - verts[:, 0], verts[:, 2] - verts[:, 0]),
                                axis=1)


def _rh_normals(verts):
    n = np.cross(verts[:, 1] - verts[:, 0], verts[:, 2] - verts[:, 0])
    return n / np.linalg.norm(n, axis=1)[:, None]


def test_cone_height_is_sqrt3_R_for_60_degrees():
    assert cone_height(R) == pytest.approx(math.sqrt(3.0) * R, rel=1e-15)
    assert cone_height(1.0, 90.0) == pytest.approx(1.0, rel=1e-15)


@pytest.mark.parametrize("n_seg", [3, 8, 24, 64])
def test_cone_vertices_and_apex_angle(tmp_path, n_seg):
    info, (normals, verts), _ = _pile(tmp_path, n_seg=n_seg)
    h = math.sqrt(3.0) * R
    assert info["cone_height"] == pytest.approx(h, rel=1e-15)
    assert info["z_base"] == pytest.approx(TIP_Z + h, rel=1e-15)
    assert verts.shape == (n_seg, 3, 3)
    # first vertex of every facet is the apex, pointing down at tip_z
    np.testing.assert_allclose(verts[:, 0], np.tile([0.0, 0.0, TIP_Z], (n_seg, 1)),
                               atol=1e-15)
    base = verts[:, 1:].reshape(-1, 3)
    r = np.hypot(base[:, 0], base[:, 1])
    np.testing.assert_allclose(r, R, rtol=RTOL_FILE)
    np.testing.assert_allclose(base[:, 2], TIP_Z + h, rtol=RTOL_FILE)
    assert np.all(base[:, 2] > TIP_Z)          # apex is the lowest point
    # half angle between every generatrix and the axis is 30 degrees,
    # so the apex angle (between opposite generatrices) is 60 degrees
    half = np.degrees(np.arctan2(r, base[:, 2] - TIP_Z))
    np.testing.assert_allclose(half, 30.0, rtol=1e-9)
    if n_seg % 2 == 0:
        g0 = verts[0, 2] - verts[0, 0]
        g1 = verts[n_seg // 2, 2] - verts[n_seg // 2, 0]   # the opposite base vertex
        cosang = np.dot(g0, g1) / (np.linalg.norm(g0) * np.linalg.norm(g1))
        assert math.degrees(math.acos(cosang)) == pytest.approx(60.0, rel=1e-9)
    # base vertices are the n_seg distinct corners of a regular polygon
    phi = np.sort(np.unique(np.round(np.arctan2(base[:, 1], base[:, 0]), 9)))
    assert len(phi) == n_seg
    np.testing.assert_allclose(np.diff(phi), 2 * np.pi / n_seg, rtol=1e-8)


@pytest.mark.parametrize("n_seg", [3, 8, 24, 64])
def test_cone_normals_point_out_and_down(tmp_path, n_seg):
    _, (normals, verts), _ = _pile(tmp_path, n_seg=n_seg)
    np.testing.assert_allclose(np.linalg.norm(normals, axis=1), 1.0, rtol=1e-8)
    np.testing.assert_allclose(normals, _rh_normals(verts), atol=1e-8)
    centroid = verts.mean(axis=1)
    radial = np.einsum("ij,ij->i", normals[:, :2], centroid[:, :2])
    assert np.all(radial > 0)
    # exact normal of a planar facet through the apex and a chord at distance
    # R cos(pi / n) from the axis: n_z = -R cos / sqrt(R^2 cos^2 + h^2), -> -1/2
    c = R * math.cos(math.pi / n_seg)
    h = math.sqrt(3.0) * R
    np.testing.assert_allclose(normals[:, 2], -c / math.hypot(c, h), rtol=1e-8)


@pytest.mark.parametrize("n_seg", [3, 8, 24, 64, 256])
def test_cone_area_against_pi_R_L(tmp_path, n_seg):
    _, (_, verts), _ = _pile(tmp_path, n_seg=n_seg)
    area = _area(verts).sum()
    h = math.sqrt(3.0) * R
    # exact area of the inscribed pyramid: n triangles of base 2 R sin(pi/n),
    # slant height (apex to chord midpoint) sqrt(h^2 + R^2 cos^2(pi/n))
    c = math.pi / n_seg
    exact_poly = n_seg * R * math.sin(c) * math.hypot(h, R * math.cos(c))
    assert area == pytest.approx(exact_poly, rel=1e-9)
    # smooth cone: pi R L with slant length L = 2 R; the inscribed polygon
    # is smaller, by a relative error below (pi / n)^2 / 2
    smooth = math.pi * R * math.hypot(R, h)
    assert smooth == pytest.approx(2 * math.pi * R ** 2, rel=1e-15)
    err = 1.0 - area / smooth
    assert 0.0 < err < 0.5 * (math.pi / n_seg) ** 2


@pytest.mark.parametrize("n_seg, n_rings", [(3, 1), (24, None), (24, 7), (64, 3)])
def test_shaft_vertices_normals_and_area(tmp_path, n_seg, n_rings):
    info, _, (normals, verts) = _pile(tmp_path, n_seg=n_seg, n_rings=n_rings)
    rings = default_shaft_rings(R, L_SHAFT) if n_rings is None else n_rings
    assert info["n_rings"] == rings
    assert verts.shape == (2 * n_seg * rings, 3, 3)
    z_lo, z_hi = info["z_base"], info["z_base"] + L_SHAFT
    assert info["z_top"] == pytest.approx(z_hi, rel=1e-15)
    pts = verts.reshape(-1, 3)
    np.testing.assert_allclose(np.hypot(pts[:, 0], pts[:, 1]), R, rtol=RTOL_FILE)
    assert pts[:, 2].min() == pytest.approx(z_lo, rel=RTOL_FILE)
    assert pts[:, 2].max() == pytest.approx(z_hi, rel=RTOL_FILE)
    zs = np.unique(np.round(pts[:, 2], 10))
    assert len(zs) == rings + 1
    np.testing.assert_allclose(np.diff(zs), L_SHAFT / rings, rtol=1e-8)
    # normals: unit, right-hand rule, horizontal and outward
    np.testing.assert_allclose(np.linalg.norm(normals, axis=1), 1.0, rtol=1e-8)
    np.testing.assert_allclose(normals, _rh_normals(verts), atol=1e-8)
    assert np.max(np.abs(normals[:, 2])) < 1e-8
    centroid = verts.mean(axis=1)
    cosr = np.einsum("ij,ij->i", normals[:, :2], centroid[:, :2]) / np.hypot(
        centroid[:, 0], centroid[:, 1])
    np.testing.assert_allclose(cosr, 1.0, atol=1e-6 + (math.pi / n_seg) ** 2)
    # area: exact prism n 2 R sin(pi/n) L, smooth 2 pi R L within (pi/n)^2/6
    area = _area(verts).sum()
    assert area == pytest.approx(n_seg * 2 * R * math.sin(math.pi / n_seg) * L_SHAFT, rel=1e-9)
    err = 1.0 - area / (2 * math.pi * R * L_SHAFT)
    assert 0.0 < err < (math.pi / n_seg) ** 2 / 6.0


def _edges(verts, digits=12):
    """Directed edges of all facets, vertices keyed by rounded coordinates."""
    key = lambda p: tuple(np.round(p, digits))  # noqa: E731
    out = []
    for tri in verts:
        k = [key(p) for p in tri]
        out += [(k[0], k[1]), (k[1], k[2]), (k[2], k[0])]
    return out


@pytest.mark.parametrize("n_seg, n_rings", [(3, 1), (12, 4), (24, None)])
def test_cone_and_shaft_form_one_oriented_surface_open_at_the_top(tmp_path, n_seg, n_rings):
    info, (_, cv), (_, sv) = _pile(tmp_path, n_seg=n_seg, n_rings=n_rings)
    both = np.concatenate([cv, sv])
    directed = _edges(both)
    # no directed edge twice (consistent orientation, no duplicate facets)
    assert max(Counter(directed).values()) == 1
    undirected = Counter(frozenset(e) for e in directed)
    assert set(undirected.values()) <= {1, 2}
    boundary = [e for e, c in undirected.items() if c == 1]
    # only the n_seg edges of the top ring are open
    assert len(boundary) == n_seg
    zt = info["z_top"]
    for e in boundary:
        for p in e:
            assert p[2] == pytest.approx(zt, rel=1e-10)
    # every interior edge is traversed once in each direction
    dset = set(directed)
    for a, b in directed:
        if undirected[frozenset((a, b))] == 2:
            assert (b, a) in dset
    # the cone's open base ring is exactly the shaft's bottom ring
    cone_open = [e for e, c in Counter(frozenset(e) for e in _edges(cv)).items() if c == 1]
    shaft_edges = set(frozenset(e) for e in _edges(sv))
    assert len(cone_open) == n_seg and all(e in shaft_edges for e in cone_open)


@pytest.mark.parametrize("n_seg", [6, 24])
def test_enclosed_volume_is_positive_and_exact(tmp_path, n_seg):
    # close the top with a fan to the axis and apply the divergence theorem:
    # outward normals give +V of the polygonal pyramid + prism
    info, (_, cv), (_, sv) = _pile(tmp_path, n_seg=n_seg)
    zt = info["z_top"]
    top = []
    for tri in sv:
        for a, b in ((tri[0], tri[1]), (tri[1], tri[2]), (tri[2], tri[0])):
            if abs(a[2] - zt) < 1e-12 and abs(b[2] - zt) < 1e-12:
                top.append((b, a, np.array([0.0, 0.0, zt])))
    tris = np.concatenate([cv, sv, np.array(top)])
    vol = np.sum(np.einsum("ij,ij->i", tris[:, 0], np.cross(tris[:, 1], tris[:, 2]))) / 6.0
    poly = 0.5 * n_seg * R ** 2 * math.sin(2 * math.pi / n_seg)
    assert vol == pytest.approx(poly * (L_SHAFT + info["cone_height"] / 3.0), rel=1e-9)


def test_bad_arguments():
    with pytest.raises(ValueError, match="n_seg"):
        cone_tip_triangles(R, n_seg=2)
    with pytest.raises(ValueError, match="radius"):
        cone_tip_triangles(0.0)
    with pytest.raises(ValueError, match="length"):
        shaft_triangles(R, -1.0, 0.0)
    with pytest.raises(ValueError, match="n_rings"):
        shaft_triangles(R, 1.0, 0.0, n_rings=0)
    with pytest.raises(ValueError, match="apex angle"):
        cone_height(R, 180.0)


def test_plate_is_unchanged():
    tris = plate_triangles(0.5, z=0.1)
    assert len(tris) == 2
    n = _rh_normals(np.array(tris, dtype=float))
    np.testing.assert_allclose(n, [[0, 0, 1], [0, 0, 1]])


def test_cli_pile(tmp_path, capsys):
    out = tmp_path / "pile"
    assert main(["pile", "--radius", "0.01", "--shaft-length", "0.1", "--tip-z", "0.02",
                 "--segments", "16", "--out", str(out)]) == 0
    info = json.loads(capsys.readouterr().out)
    assert Path(info["cone"]) == out / "cone.stl" and Path(info["shaft"]) == out / "shaft.stl"
    assert info["cone_facets"] == 16 and info["n_seg"] == 16
    assert info["n_rings"] == 5 and info["shaft_facets"] == 2 * 16 * 5
    assert info["z_base"] == pytest.approx(0.02 + math.sqrt(3) * 0.01, rel=1e-15)
    normals, verts = read_stl(out / "cone.stl")
    assert verts[:, 0, 2].min() == pytest.approx(0.02)
    assert main(["pile", "--radius", "0.01", "--shaft-length", "0.1", "--segments", "16",
                 "--shaft-rings", "2", "--out", str(out), "--shaft-name", "s.stl"]) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["shaft_facets"] == 64 and os.path.exists(out / "s.stl")


def test_cli_pile_bad_segments(tmp_path, capsys):
    assert main(["pile", "--radius", "0.01", "--shaft-length", "0.1", "--segments", "2",
                 "--out", str(tmp_path)]) == 1
    assert "n_seg" in capsys.readouterr().err


def test_python_m_crushpost_pile(tmp_path):
    env = dict(os.environ)
    res = subprocess.run([sys.executable, "-m", "crushpost", "pile", "--radius", "0.018",
                          "--shaft-length", "0.3", "--tip-z", "0.0", "--segments", "24",
                          "--out", str(tmp_path)], env=env, stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, universal_newlines=True, timeout=120)
    assert res.returncode == 0, res.stderr
    info = json.loads(res.stdout)
    assert info["cone_facets"] == 24 and (tmp_path / "shaft.stl").is_file()
