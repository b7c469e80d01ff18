# SPDX-License-Identifier: GPL-2.0-or-later
"""Stress invariants, cylindrical components, particle/sphere stresses, ring averages."""

import numpy as np
import pytest

from crushpost.stress import (invariants, pair_contact_terms, particle_stress,
                              ring_average, ring_averages, sphere_ring_volume,
                              sphere_stress, to_cylindrical)


def rot_y(deg):
    t = np.radians(deg)
    return np.array([[np.cos(t), 0, np.sin(t)], [0, 1, 0], [-np.sin(t), 0, np.cos(t)]])


def test_triaxial_and_hydrostatic():
    s1, s3 = 300e3, 100e3
    tri = np.diag([s3, s3, s1])
    inv = invariants(tri)
    assert inv.q == pytest.approx(s1 - s3, rel=1e-14)  # sqrt(2/3) would give 0.667x
    assert inv.p == pytest.approx((s1 + 2 * s3) / 3, rel=1e-14)
    assert np.allclose(inv.principal, [s1, s3, s3])
    assert inv.theta_major == pytest.approx(0.0, abs=1e-6)
    # Tilt the major axis by 30 degrees in the x-z plane.
    rq = rot_y(30.0)
    inv = invariants(rq @ tri @ rq.T)
    assert inv.q == pytest.approx(s1 - s3, rel=1e-12)
    assert inv.theta_major == pytest.approx(30.0, abs=1e-9)
    # Hydrostatic and a stack of tensors.
    inv = invariants(np.stack([np.eye(3) * 5.0, tri]))
    assert inv.q[0] == pytest.approx(0.0, abs=1e-12) and inv.p[0] == pytest.approx(5.0)
    assert inv.q.shape == (2,) and inv.principal.shape == (2, 3)


def test_q_matches_principal_formula_on_random_tensors():
    rng = np.random.default_rng(3)
    a = rng.normal(size=(50, 3, 3))
    sig = a + np.swapaxes(a, 1, 2)
    inv = invariants(sig)
    ev = np.linalg.eigvalsh(sig)
    q_ref = np.sqrt(0.5 * ((ev[:, 0] - ev[:, 1]) ** 2 + (ev[:, 1] - ev[:, 2]) ** 2
                           + (ev[:, 2] - ev[:, 0]) ** 2))
    assert np.allclose(inv.q, q_ref, rtol=1e-12)
    assert np.all(np.diff(inv.principal, axis=1) <= 0)
    assert np.allclose(inv.principal.sum(1), 3 * inv.p)


def test_to_cylindrical_explicit_positions():
    sig = np.array([[1.0, 0.2, 0.3], [0.2, 2.0, 0.5], [0.3, 0.5, 4.0]])
    # On the +y axis: e_r = y, e_theta = -x.
    sr, st, sz, trz = to_cylindrical(sig, 0.0, 2.0)
    assert (sr, st, sz, trz) == pytest.approx((2.0, 1.0, 4.0, 0.5))
    # On the -x axis: e_r = -x, so tau_rz = -sigma_xz.
    sr, st, sz, trz = to_cylindrical(sig, -3.0, 0.0)
    assert (sr, st, sz, trz) == pytest.approx((1.0, 2.0, 4.0, -0.3))
    # An axisymmetric state written in Cartesian at 45 degrees comes back.
    c = s = np.sqrt(0.5)
    er, et, ez = np.array([c, s, 0]), np.array([-s, c, 0]), np.array([0, 0, 1.0])
    cart = (7 * np.outer(er, er) + 3 * np.outer(et, et) + 9 * np.outer(ez, ez)
            + 1.5 * (np.outer(er, ez) + np.outer(ez, er)))
    out = to_cylindrical(np.stack([cart, cart]), [1.0, 2.0], [1.0, 2.0])
    assert np.allclose(np.array(out), [[7, 7], [3, 3], [9, 9], [1.5, 1.5]])
    # Axis offset: the same point seen from an axis at (1, 1) lies on +x.
    sr, st, _, _ = to_cylindrical(sig, 4.0, 1.0, axis_xy=(1.0, 1.0))
    assert (sr, st) == pytest.approx((1.0, 2.0))


def icosahedron():
    g = (1 + np.sqrt(5)) / 2
    v = []
    for a in (-1, 1):
        for b in (-g, g):
            v += [(0, a, b), (a, b, 0), (b, 0, a)]
    v = np.array(v, dtype=float)
    return v / np.linalg.norm(v, axis=1)[:, None]


def test_particle_stress_isotropic_contacts():
    r, f = 1e-3, 2.0
    vol = 4 / 3 * np.pi * r ** 3
    n = icosahedron()  # sum of n n = 4 I exactly
    sig = particle_stress(np.zeros(12, int), r * n, -f * n, [vol])[0]
    assert np.allclose(sig, np.eye(3) * 12 * r * f / (3 * vol), rtol=1e-12)
    # Many random directions: isotropic to sampling error, compression positive.
    rng = np.random.default_rng(5)
    n = rng.normal(size=(20000, 3))
    n /= np.linalg.norm(n, axis=1)[:, None]
    sig = particle_stress(np.zeros(len(n), int), r * n, -f * n, [vol])[0]
    inv = invariants(sig)
    p_ref = len(n) * r * f / (3 * vol)
    assert inv.p == pytest.approx(p_ref, rel=1e-12)  # trace is exact
    assert inv.q < 0.05 * p_ref
    # Tension-positive option flips the sign.
    sig_t = particle_stress(np.zeros(len(n), int), r * n, -f * n, [vol],
                            compression_positive=False)[0]
    assert np.allclose(sig_t, -sig)


def test_particle_stress_two_particles_and_wall():
    # Particle 0 squeezed along z between particle 1 (above) and a wall (below).
    r, f = 0.5, 3.0
    x = np.array([[0, 0, 0.0], [0, 0, 1.0]])
    idx, s, F = pair_contact_terms([0, 0], [1, -1], x,
                                   [[0, 0, 0.5], [0, 0, -0.5]],
                                   [[0, 0, -f], [0, 0, f]])
    assert list(idx) == [0, 0, 1]
    vol = 4 / 3 * np.pi * r ** 3
    sig = particle_stress(idx, s, F, [vol, vol])
    assert sig[0, 2, 2] == pytest.approx(2 * r * f / vol)
    assert sig[1, 2, 2] == pytest.approx(r * f / vol)
    assert np.count_nonzero(np.abs(sig) > 1e-12) == 2


def test_sphere_stress_cubic_lattice():
    # Simple cubic packing of spacing 2r with normal force f on every bond:
    # sigma_ii = f / (2r)^2 per direction (one bond per direction per cell).
    r, f = 0.5, 1.0
    m = 4
    branches, forces = [], []
    for axis in range(3):
        e = np.eye(3)[axis]
        mag = f * (3.0 if axis == 2 else 1.0)
        for _ in range(m ** 3):  # periodic: one bond per particle per axis
            branches.append(2 * r * e)
            forces.append(-mag * e)  # force on p from q pushes p away
    vol = (2 * r * m) ** 3
    sig = sphere_stress(branches, forces, vol)
    # z bonds carry 3f: anisotropic, compression positive.
    assert np.allclose(np.diag(sig), np.array([1.0, 1.0, 3.0]) * f / (2 * r) ** 2)
    assert np.allclose(sig - np.diag(np.diag(sig)), 0)


def test_sum_of_particle_stresses_equals_love_formula():
    # Sum_p V_p sigma_p over both sides of every contact = V sigma (transposed):
    # s_i (x) f + s_j (x) (-f) = (x_j - x_i) (x) f.
    rng = np.random.default_rng(11)
    x = rng.uniform(0, 1, (30, 3))
    i = rng.integers(0, 30, 80)
    j = (i + rng.integers(1, 30, 80)) % 30
    xc = rng.uniform(0, 1, (80, 3))
    f = rng.normal(size=(80, 3))
    vols = rng.uniform(0.5, 1.5, 30)
    idx, s, F = pair_contact_terms(i, j, x, xc, f)
    total = np.einsum("p,pij->ij", vols, particle_stress(idx, s, F, vols))
    love = sphere_stress(x[j] - x[i], f, 2.5) * 2.5
    assert np.allclose(total, love.T, rtol=1e-12, atol=1e-12)


# ---- sphere / ring intersection volume ---------------------------------------

def vsph(r):
    return 4 / 3 * np.pi * r ** 3


def test_ring_volume_analytic_cases():
    R = 1.0
    c = [[5.0, 0.0, 0.0], [0.0, 5.0, 2.0], [0.0, 0.0, 0.0], [20.0, 0.0, 0.0]]
    v = sphere_ring_volume(c, R, 3.0, 7.0, -1.5, 1.5)
    assert v[0] == pytest.approx(vsph(R), rel=1e-15)       # fully inside
    assert v[1] == pytest.approx(np.pi / 3 * 0.5 ** 2 * (3 * R - 0.5), rel=1e-9)  # cap
    assert v[2] == 0.0 and v[3] == 0.0                       # inside the hole / outside
    # Cut in half by z = const through the centre, off-axis.
    v = sphere_ring_volume([[4.2, -1.1, 0.3]], 0.7, 2.0, 8.0, 0.3, 5.0)
    assert v[0] == pytest.approx(vsph(0.7) / 2, rel=1e-12)
    # Coaxial cylinder of radius c through a sphere: 4pi/3 (R^3 - (R^2 - c^2)^1.5).
    for cr in (0.2, 0.5, 0.9):
        v = sphere_ring_volume([[0, 0, 0]], R, 0.0, cr, -2, 2)
        assert v[0] == pytest.approx(4 * np.pi / 3 * (R ** 3 - (R ** 2 - cr ** 2) ** 1.5),
                                     rel=1e-9)
    # Sphere centred on the ring's inner circle, split by the cylinder r = 3.
    # Not half (curvature), but both sides add up to the sphere.
    a = sphere_ring_volume([[3.0, 0, 0]], R, 3.0, 10.0, -2, 2)[0]
    b = sphere_ring_volume([[3.0, 0, 0]], R, 0.0, 3.0, -2, 2)[0]
    assert a + b == pytest.approx(vsph(R), rel=1e-9) and a > b


def test_ring_volume_against_monte_carlo():
    rng = np.random.default_rng(2024)
    R, c = 1.0, np.array([1.3, 0.4, 0.1])
    n = 2_000_000
    p = rng.uniform(-1, 1, (n, 3))
    p = p[(p ** 2).sum(1) <= 1] * R + c
    rr = np.hypot(p[:, 0], p[:, 1])
    hit = (rr >= 1.0) & (rr <= 2.0) & (p[:, 2] >= -0.3) & (p[:, 2] <= 0.5)
    frac = hit.mean()
    sd = np.sqrt(frac * (1 - frac) / len(p)) * vsph(R)
    v = sphere_ring_volume([c], R, 1.0, 2.0, -0.3, 0.5)[0]
    assert abs(v - frac * vsph(R)) < 4 * sd
    assert 0.2 * vsph(R) < v < 0.8 * vsph(R)


def test_rings_partition_the_sphere():
    rng = np.random.default_rng(8)
    c = rng.uniform(-1.5, 1.5, (40, 3))
    rad = rng.uniform(0.1, 0.6, 40)
    r_edges = np.linspace(0, 3, 7)
    z_edges = np.linspace(-3, 3, 9)
    tot = sum(sphere_ring_volume(c, rad, r_edges[a], r_edges[a + 1],
                                 z_edges[b], z_edges[b + 1])
              for a in range(6) for b in range(8))
    assert np.allclose(tot, vsph(rad), rtol=1e-8)


def test_ring_average_cylindrical_and_cartesian():
    # Eight equal spheres evenly spaced around a ring, all with the same
    # axisymmetric state (sigma_r, sigma_theta, sigma_z, tau_rz) = (5, 2, 9, 1).
    n, rad, rc = 8, 0.2, 2.0
    phi = 2 * np.pi * np.arange(n) / n + 0.1
    x, y = rc * np.cos(phi), rc * np.sin(phi)
    centres = np.stack([x, y, np.zeros(n)], 1)
    sig = []
    for p in phi:
        er, et, ez = np.array([np.cos(p), np.sin(p), 0]), np.array([-np.sin(p), np.cos(p), 0]), np.eye(3)[2]
        sig.append(5 * np.outer(er, er) + 2 * np.outer(et, et) + 9 * np.outer(ez, ez)
                   + np.outer(er, ez) + np.outer(ez, er))
    sig = np.array(sig)
    r_in, r_out, z_lo, z_hi = 1.5, 2.5, -0.5, 0.5
    frac = n * vsph(rad) / (np.pi * (r_out ** 2 - r_in ** 2) * (z_hi - z_lo))
    avg = ring_average(sig, centres, rad, r_in, r_out, z_lo, z_hi)
    assert np.allclose(avg, frac * np.array([[5, 0, 1], [0, 2, 0], [1, 0, 9]]), atol=1e-12)
    # Averaging Cartesian tensors around the ring mixes sigma_r and sigma_theta.
    cart = ring_average(sig, centres, rad, r_in, r_out, z_lo, z_hi, frame="cartesian")
    assert cart[0, 0] == pytest.approx(frac * 3.5) and cart[1, 1] == pytest.approx(frac * 3.5)
    # Cut the ring at z = 0: only the upper half of each sphere counts.
    half = ring_average(sig, centres, rad, r_in, r_out, 0.0, 1.0)
    assert half[2, 2] == pytest.approx(9 * frac / 2, rel=1e-12)
    # Grid version: cells of height 0.5 hold the same solid as the height-1
    # ring above, so twice its average.
    grid = ring_averages(sig, centres, rad, [1.5, 2.5], [-0.5, 0.0, 0.5])
    assert grid.shape == (1, 2, 3, 3)
    assert np.allclose(grid[0, 1], 2 * half, rtol=1e-12)
    assert np.allclose(grid[0, 0] + grid[0, 1], 2 * avg, rtol=1e-12)


def test_ring_average_of_a_sector():
    """A quarter chamber holds the grains of a quarter ring: its average over
    the quarter's volume is that of the full ring with the grains repeated
    in the four quarters."""
    rad, rc = 0.2, 2.0
    phi = np.radians([20.0, 45.0, 70.0])
    quarter = np.stack([rc * np.cos(phi), rc * np.sin(phi), np.zeros(3)], 1)
    full = np.concatenate([quarter @ np.array([[np.cos(t), np.sin(t), 0], [-np.sin(t), np.cos(t), 0],
                                                [0, 0, 1]]) for t in np.radians([0, 90, 180, 270])])
    iso = np.tile(7.0 * np.eye(3), (len(full), 1, 1))
    a = ring_average(iso[:3], quarter, rad, 1.5, 2.5, -0.5, 0.5, sector=90)
    b = ring_average(iso, full, rad, 1.5, 2.5, -0.5, 0.5)
    np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-15)
    g = ring_averages(iso[:3], quarter, rad, [1.5, 2.5], [-0.5, 0.5], sector=90)
    np.testing.assert_allclose(g[0, 0], b, rtol=1e-12, atol=1e-15)
    with pytest.raises(ValueError, match="sector"):
        ring_average(iso, full, rad, 1.5, 2.5, -0.5, 0.5, sector=0)


def test_particle_stress_equals_a_direct_sum():
    """The bincount sums against an unbuffered scatter-add of every term."""
    rng = np.random.default_rng(5)
    idx = rng.integers(0, 50, 400)
    s, f = rng.normal(size=(400, 3)), rng.normal(size=(400, 3))
    vol = rng.uniform(1, 2, 50)
    direct = np.zeros((50, 3, 3))
    np.add.at(direct, idx, s[:, :, None] * f[:, None, :])
    np.testing.assert_allclose(particle_stress(idx, s, f, vol), -direct / vol[:, None, None],
                               rtol=1e-12, atol=1e-12)
