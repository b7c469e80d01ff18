# SPDX-License-Identifier: GPL-2.0-or-later
"""Preparation statistics (crushpost.prep, the ring functions of
crushpost.stress) on synthetic data with known answers: ring edges, ring
averages of a uniform field (mean = solid fraction x stress, sd = 0), the
cylindrical frame, the sector fraction (a quarter or a half with symmetric
copies gives the whole ring's averages), the core volumes and porosities,
and the parsing of the deck's report lines."""

import math

import numpy as np
import pytest

from crushpost.prep import (cap_fraction, coordination, core_area, core_volumes,
                            element_prep_summary, prep_cost,
                            read_prep_report, ring_edges, ring_statistics, sample_porosities)
from crushpost.stress import ring_average, ring_averages, sphere_ring_volume


def test_ring_edges_remainders():
    assert np.allclose(ring_edges(1.0, 3.0), [0, 1, 2, 3])
    # remainder below half a width joins the last ring
    assert np.allclose(ring_edges(1.0, 3.4), [0, 1, 2, 3.4])
    # a wider remainder is a ring of its own
    assert np.allclose(ring_edges(1.0, 3.6), [0, 1, 2, 3, 3.6])
    assert np.allclose(ring_edges(0.025, 0.1, start=0.5), [0.5, 0.525, 0.55, 0.575, 0.6])
    assert np.allclose(ring_edges(1.0, 0.4), [0, 0.4])
    # the paper's chamber: 12 rings of R, 40 layers of 25 mm, no remainder
    assert len(ring_edges(0.018, 0.216)) == 13
    assert len(ring_edges(0.025, 1.0)) == 41


def _spheres_per_ring(r_edges, z_edges, fraction, angle=0.0):
    """8 (a + 1) equal spheres round the middle of ring a, fully inside it,
    together holding ``fraction`` of the ring's volume."""
    c, rad = [], []
    for a in range(len(r_edges) - 1):
        k = 8 * (a + 1)
        rm = 0.5 * (r_edges[a] + r_edges[a + 1])
        for b in range(len(z_edges) - 1):
            v = math.pi * (r_edges[a + 1] ** 2 - r_edges[a] ** 2) * (z_edges[b + 1] - z_edges[b])
            rho = (3 * fraction * v / (4 * math.pi * k)) ** (1 / 3)
            zm = 0.5 * (z_edges[b] + z_edges[b + 1])
            assert rho < 0.5 * min(r_edges[a + 1] - r_edges[a], z_edges[b + 1] - z_edges[b])
            assert 2 * rho < 2 * math.pi * rm / k
            for j in range(k):
                th = math.radians(angle) + 2 * math.pi * j / k
                c.append([rm * math.cos(th), rm * math.sin(th), zm])
                rad.append(rho)
    return np.array(c), np.array(rad)


def test_uniform_field_mean_is_fraction_times_stress_sd_zero():
    """Particle stress diag(a, a, b) everywhere (axisymmetric: sigma_r =
    sigma_theta = a, sigma_z = b in any cylindrical frame); each ring holds
    the same solid fraction f, so every ring average is f (a, a, b): mean
    f a, f b and sd 0."""
    R, H, dz, f = 1.0, 2.0, 0.5, 0.05
    r_e, z_e = ring_edges(R, 4.0), ring_edges(dz, H)
    c, rad = _spheres_per_ring(r_e, z_e, f, angle=37.0)
    sig = np.tile(np.diag([2.0, 2.0, 5.0]), (len(rad), 1, 1))
    st = ring_statistics(sig, c, rad, R, 4.0, H, dz)
    assert st["sigma_r"].shape == (4, 4)
    for name, val in (("sigma_r", 2.0), ("sigma_theta", 2.0), ("sigma_z", 5.0)):
        assert np.allclose(st[name], f * val, rtol=1e-9)
        mean, sd = st["all"][name]
        assert mean == pytest.approx(f * val, rel=1e-9)
        assert sd == pytest.approx(0.0, abs=1e-9)
    assert np.allclose(st["tau_rz"], 0.0)
    # interior rings: neither the outer ring nor the bottom/top layers
    assert st["interior"]["sigma_z"][0] == pytest.approx(f * 5.0)


def test_cylindrical_frame_radial_field():
    """A purely radial stress sigma_r e_r (x) e_r at each particle's azimuth
    averages to (f sigma_r, 0, 0) in the cylindrical frame, although the
    Cartesian tensors differ from particle to particle."""
    r_e, z_e = [1.0, 2.0], [0.0, 1.0]
    c, rad = [], []
    for k in range(8):          # eight equal spheres round the ring
        th = 2 * math.pi * k / 8 + 0.1
        c.append([1.5 * math.cos(th), 1.5 * math.sin(th), 0.5])
        rad.append(0.2)
    c, rad = np.array(c), np.array(rad)
    er = np.column_stack([c[:, 0], c[:, 1], 0 * c[:, 0]]) / 1.5
    sig = 3.0 * er[:, :, None] * er[:, None, :]
    avg = ring_averages(sig, c, rad, r_e, z_e)[0, 0]
    f = 8 * 4 / 3 * math.pi * 0.2 ** 3 / (math.pi * 3.0 * 1.0)
    assert avg[0, 0] == pytest.approx(3.0 * f, rel=1e-9)
    assert avg[1, 1] == pytest.approx(0.0, abs=1e-12)
    assert avg[2, 2] == pytest.approx(0.0, abs=1e-12)


def _rotate(c, sig, deg):
    t = math.radians(deg)
    q = np.array([[math.cos(t), -math.sin(t), 0], [math.sin(t), math.cos(t), 0], [0, 0, 1]])
    return c @ q.T, np.einsum("ik,pkl,jl->pij", q, sig, q)


@pytest.mark.parametrize("sector", [90, 180])
def test_sector_fraction(sector):
    """Random spheres and stresses in a sector (the spheres cut by ring and
    layer boundaries too), and the whole ring made of its rotated copies:
    the sector's ring averages with ``sector`` equal the whole ring's.
    Without the sector fraction they would be sector/360 of them."""
    rng = np.random.default_rng(10007)
    n = 60
    rad = rng.uniform(0.05, 0.15, n)
    rho = rng.uniform(0.2, 2.8, n)
    th = np.radians(rng.uniform(5, sector - 5, n))
    c = np.column_stack([rho * np.cos(th), rho * np.sin(th), rng.uniform(0.2, 1.8, n)])
    a = rng.normal(size=(n, 3, 3))
    sig = a + np.swapaxes(a, 1, 2)
    r_e, z_e = [0.0, 1.0, 2.0, 3.0], [0.0, 1.0, 2.0]
    part = ring_averages(sig, c, rad, r_e, z_e, sector=sector)
    cs, ss = [c], [sig]
    for k in range(1, 360 // sector):
        ck, sk = _rotate(c, sig, k * sector)
        cs.append(ck)
        ss.append(sk)
    whole = ring_averages(np.concatenate(ss), np.concatenate(cs), np.tile(rad, 360 // sector), r_e, z_e)
    assert np.allclose(part, whole, rtol=1e-9, atol=1e-12)
    plain = ring_averages(sig, c, rad, r_e, z_e)
    assert np.allclose(plain, part * sector / 360.0)
    with pytest.raises(ValueError):
        ring_average(sig, c, rad, 0.0, 1.0, 0.0, 1.0, sector=0.0)


def test_ring_volumes_add_up():
    """Volumes of spheres cut by ring boundaries add up to the spheres'
    volumes over a ring grid that covers them (what makes the averages
    volume-consistent)."""
    rng = np.random.default_rng(10009)
    c = np.column_stack([rng.uniform(-2, 2, 40), rng.uniform(-2, 2, 40), rng.uniform(0.5, 2.5, 40)])
    rad = rng.uniform(0.1, 0.4, 40)
    r_e, z_e = ring_edges(0.7, 3.5), ring_edges(0.5, 3.0)
    tot = sum(sphere_ring_volume(c, rad, r_e[a], r_e[a + 1], z_e[b], z_e[b + 1])
              for a in range(len(r_e) - 1) for b in range(len(z_e) - 1))
    assert np.allclose(tot, 4 / 3 * math.pi * rad ** 3, rtol=1e-8)


def test_cap_fraction():
    assert cap_fraction(0.0, 1.0) == pytest.approx(0.5)
    assert cap_fraction(2.0, 1.0) == 1.0 and cap_fraction(-2.0, 1.0) == 0.0
    # a cap of height r/2: pi h^2 (3r - h)/3 over 4/3 pi r^3
    h = 0.5
    assert cap_fraction(-(1 - h), 1.0) == pytest.approx(math.pi * h * h * (3 - h) / 3 / (4 / 3 * math.pi))


@pytest.mark.parametrize("sector", [360, 180, 90])
def test_core_area_against_quadrature(sector):
    R, d = 1.0, 0.15
    a = R - d
    # fine grid count of the points of the core's cross-section
    g = np.linspace(-a, a, 2001)
    x, y = np.meshgrid(g, g)
    ok = x * x + y * y < a * a
    if sector < 360:
        ok &= y > d
    if sector < 180:
        ok &= x > d
    area = ok.sum() * (g[1] - g[0]) ** 2
    assert core_area(R, d, sector) == pytest.approx(area, rel=2e-3)


def test_core_volumes_and_porosities():
    """Spheres well inside the core count whole, one centred on the core's
    top or on its symmetry plane counts half, one outside counts nothing."""
    R, H, d = 1.0, 2.0, 0.2
    c = np.array([[0.0, 0.3, 1.0],          # inside
                  [0.3, 0.4, H - d],        # centred on the core's top
                  [0.3, d, 1.0],            # centred on the plane y = d
                  [0.0, 0.0, 0.05]])        # below the core
    r = np.array([0.05, 0.05, 0.05, 0.04])
    v = 4 / 3 * math.pi * r ** 3
    assert np.allclose(core_volumes(c, r, R, H, d, 360), [v[0], v[1] / 2, v[2], 0.0])
    assert np.allclose(core_volumes(c, r, R, H, d, 180), [v[0], v[1] / 2, v[2] / 2, 0.0])
    por = sample_porosities(c, r, R, H, d, 180)
    assert por["porosity_all"] == pytest.approx(1 - v.sum() / (0.5 * math.pi * R * R * H))
    assert por["porosity_core"] == pytest.approx(
        1 - (v[0] + v[1] / 2 + v[2] / 2) / (core_area(R, d, 180) * (H - 2 * d)))
    with pytest.raises(ValueError):
        core_area(0.3, 0.2)


def test_coordination():
    snap = {"particles": {"id": np.arange(1, 5)},
            "contacts": {"pp": {"id": np.array([[1, 2], [2, 3], [1, 4]])}, "pw": None}}
    assert coordination(snap) == pytest.approx(1.5)


def test_read_prep_report_and_cost(tmp_path):
    log = tmp_path / "log.liggghts"
    log.write_text(
        "Loop time of 1.5 on 2 procs for 2000 steps with 10 atoms\n"
        "EXPANDED porosity_core 0.386 porosity_all 0.44 p 5010.2 coordination 2.7 mu_prep 0.005 cycles 40 ke_rel 1e-05\n"
        "Loop time of 2.5 on 2 procs for 3000 steps with 10 atoms\n"
        "COMPRESSED sv 149900 sr 66000 K0 0.44 porosity_core 0.385 porosity_all 0.44 chunks 3\n"
        "CHAMBER prepared: sv 150010 sr 76002 R 0.04 H 0.0499 porosity_core 0.3851 porosity_all 0.445 "
        "coordination 3.3 ke_rel 5e-06 chunks 3\n"
        "Loop time of 9.0 on 2 procs for 1 steps with 10 atoms\n")
    rep = read_prep_report(str(log))
    assert rep["expanded"]["p"] == pytest.approx(5010.2)
    assert rep["compressed"]["K0"] == pytest.approx(0.44)
    assert rep["prepared"]["sr"] == pytest.approx(76002)
    assert rep["prepared"]["H"] == pytest.approx(0.0499)
    assert prep_cost(str(log)) == (4.0, 5000)
    failed = tmp_path / "failed.log"
    failed.write_text("EXPANDED porosity_core 0.39 p 5000\nPREPARATION FAILED (radial servo, 40 chunks): ...\n")
    assert "prepared" not in read_prep_report(str(failed))


def test_element_prep_summary(tmp_path):
    """The element tests' prep object: the EXPANDED line's numbers, the cost up
    to it (one Loop line of 1.5 s and 2000 steps) and the targets."""
    log = tmp_path / "log.liggghts"
    log.write_text(
        "Loop time of 1.5 on 2 procs for 2000 steps with 10 atoms\n"
        "EXPANDED porosity_core 0.386 porosity_all 0.44 p 5010.2 coordination 2.7 mu_prep 0.005 cycles 40 ke_rel 1e-05\n"
        "Loop time of 2.5 on 2 procs for 3000 steps with 10 atoms\n")
    s = element_prep_summary(str(log), 0.385, 5e3)
    assert s == {"n_target": 0.385, "s_prep": 5e3, "porosity_core": 0.386, "porosity_all": 0.44,
                 "p_static": 5010.2, "coordination": 2.7, "mu_prep_final": 0.005,
                 "liggghts_time_s": 1.5, "steps": 2000}
