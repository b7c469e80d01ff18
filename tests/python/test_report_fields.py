# SPDX-License-Identifier: GPL-2.0-or-later
"""Known answers for the report's building blocks (issue 10 item 6):
crushpost.rings (sphere-ring volumes, ring averages), crushpost.rotation,
crushpost.fields."""

import math

import numpy as np
import pytest

from crushpost.breakage import breakage, sphere_mass
from crushpost.fields import (binned_mean, cell_breakage, event_density, interp_columns,
                              interp_radius,
                              qc_reference, qc_trend_band, radial_increments, stress_quantities)
from crushpost.materials import D_MAX_BR, D_MIN_BR, RHO_GRAIN
from crushpost.rings import (cylinder_below_volume, ring_fields,
                             ring_volumes, sphere_cell_volumes)
from crushpost.rotation import axis_rotation, major_axis_angle, unwrap_axis
from crushpost.stress import ring_averages, sphere_ring_volume
from crushpost.trend import fit_qc_trend, qc_trend

R_EDGES = np.array([0.0, 0.018, 0.036, 0.054])
Z_EDGES = np.array([0.0, 0.025, 0.05, 0.075])


def _cloud(n, seed, r_max=0.06, z_lo=-0.01, z_hi=0.085, a_lo=0.002, a_hi=0.012):
    rng = np.random.default_rng(seed)
    c = np.column_stack([rng.uniform(-r_max, r_max, n), rng.uniform(-r_max, r_max, n),
                         rng.uniform(z_lo, z_hi, n)])
    return c, rng.uniform(a_lo, a_hi, n)


def _dense(triplets, n, n_cells):
    p, cell, v = triplets
    out = np.zeros((n, n_cells))
    np.add.at(out, (p, cell), v)
    return out


# ---------------------------------------------------------------------------
# sphere-ring volumes
# ---------------------------------------------------------------------------

# spheres cut by each kind of ring boundary: (centre, radius, ring (r_in, r_out, z_lo, z_hi))
MC_CASES = [
    ((0.020, 0.0, 0.030), 0.006, (0.018, 0.036, 0.025, 0.050)),    # inner radius + bottom
    ((0.0, 0.035, 0.049), 0.005, (0.018, 0.036, 0.025, 0.050)),    # outer radius + top
    ((0.002, 0.001, 0.026), 0.007, (0.0, 0.018, 0.025, 0.050)),    # around the axis + bottom
    ((0.012, 0.012, 0.040), 0.012, (0.0, 0.018, 0.025, 0.050)),    # the whole ring's corner
    ((0.027, 0.0, 0.0375), 0.011, (0.018, 0.036, 0.025, 0.050)),   # inner and outer radius
    ((0.018, 0.0, 0.025), 0.008, (0.018, 0.036, 0.025, 0.050)),    # centred on the inner-bottom corner
    ((0.0, 0.027, 0.0375), 0.0135, (0.018, 0.036, 0.025, 0.050)),  # all four boundaries
]


@pytest.mark.parametrize("centre, a, ring", MC_CASES)
def test_partial_volume_matches_monte_carlo(centre, a, ring):
    r_in, r_out, z_lo, z_hi = ring
    re = np.array([r_in, r_out]) if r_in > 0 else np.array([0.0, r_out])
    if r_in > 0:
        re = np.array([0.0, r_in, r_out])
    ze = np.array([z_lo, z_hi])
    p, cell, v = sphere_cell_volumes(np.array([centre]), np.array([a]), re, ze)
    col = re.size - 2                  # the ring (r_in, r_out) is the last column
    got = v[cell == col].sum()
    # independent estimate: uniform points in the sphere's bounding cube
    rng = np.random.default_rng(7)
    n = 400000
    pts = np.asarray(centre) + rng.uniform(-a, a, (n, 3))
    in_sphere = np.sum((pts - centre) ** 2, axis=1) <= a * a
    rho = np.hypot(pts[:, 0], pts[:, 1])
    in_ring = in_sphere & (rho >= r_in) & (rho < r_out) & (pts[:, 2] >= z_lo) & (pts[:, 2] < z_hi)
    frac = in_ring.mean()
    cube = (2 * a) ** 3
    mc, sd = frac * cube, math.sqrt(frac * (1 - frac) / n) * cube
    assert 0.0 < got < 4.0 / 3.0 * math.pi * a ** 3
    assert abs(got - mc) < 4.0 * sd + 1e-15, (got, mc, sd)


def test_partial_volumes_match_the_ring_by_ring_quadrature_and_add_up():
    c, a = _cloud(2000, 1)
    n_cells = (R_EDGES.size - 1) * (Z_EDGES.size - 1)
    M = _dense(sphere_cell_volumes(c, a, R_EDGES, Z_EDGES), len(a), n_cells)
    nz = Z_EDGES.size - 1
    for i in range(R_EDGES.size - 1):
        for k in range(nz):
            ref = sphere_ring_volume(c, a, R_EDGES[i], R_EDGES[i + 1], Z_EDGES[k], Z_EDGES[k + 1])
            assert np.allclose(M[:, i * nz + k], ref, rtol=0, atol=1e-7 * 4 / 3 * np.pi * a ** 3)
    # a sphere wholly inside the grid is shared out in full
    rho = np.hypot(c[:, 0], c[:, 1])
    inside = (rho + a < R_EDGES[-1]) & (c[:, 2] - a > Z_EDGES[0]) & (c[:, 2] + a < Z_EDGES[-1])
    assert inside.sum() > 100
    v = 4.0 / 3.0 * np.pi * a ** 3
    assert np.allclose(M[inside].sum(axis=1), v[inside], rtol=1e-9)


def test_partial_volumes_converge():
    # 16 Gauss points (the default) against 64, for spheres cut every way
    c, a = _cloud(3000, 11)
    n_cells = (R_EDGES.size - 1) * (Z_EDGES.size - 1)
    m16 = _dense(sphere_cell_volumes(c, a, R_EDGES, Z_EDGES), len(a), n_cells)
    m64 = _dense(sphere_cell_volumes(c, a, R_EDGES, Z_EDGES, n_gauss=64), len(a), n_cells)
    v = 4.0 / 3.0 * np.pi * a ** 3
    assert np.max(np.abs(m16 - m64).max(axis=1) / v) < 3e-9


def test_cylinder_volume_closed_forms():
    a = 0.01
    # a cylinder through the centre of a sphere on its axis: a cylinder of
    # radius rho and the two caps, V = 4/3 pi (a^3 - (a^2 - rho^2)^1.5)
    for rho in (0.002, 0.005, 0.0099):
        want = 4.0 / 3.0 * np.pi * (a ** 3 - (a * a - rho * rho) ** 1.5)
        got = cylinder_below_volume(0.0, 0.0, a, rho)
        assert got == pytest.approx(want, rel=1e-10)
        # below the equator: half of it
        assert cylinder_below_volume(0.0, 0.0, a, rho, 0.0) == pytest.approx(want / 2, rel=1e-10)
    # a cylinder that holds the whole sphere, and one that misses it
    assert cylinder_below_volume(0.03, 0.0, a, 0.05) == pytest.approx(4 / 3 * np.pi * a ** 3)
    assert cylinder_below_volume(0.03, 0.0, a, 0.015) == 0.0


# ---------------------------------------------------------------------------
# ring averages
# ---------------------------------------------------------------------------

def test_uniform_stress_averages_back_to_itself_in_every_ring():
    """sigma_ring = sum V_in sigma_p / V_ring: a uniform particle stress s0
    comes back as s0 times the ring's solid fraction, so sigma_ring / (1 - n)
    is s0 in every ring, whatever the cuts; an axisymmetric s0 = diag(a, a, b)
    has the same cylindrical components everywhere."""
    c, a = _cloud(3000, 2)
    s0 = np.diag([80e3, 80e3, 150e3])
    sig = np.broadcast_to(s0, (len(a), 3, 3))
    rf = ring_fields(sig, c, a, R_EDGES, Z_EDGES)
    solid = 1.0 - rf["porosity"]
    assert np.all(solid > 0.05)
    back = rf["sigma"] / solid[..., None, None]
    assert np.allclose(back, s0, rtol=1e-12, atol=1e-6)


def test_ring_fields_agree_with_stress_ring_averages():
    c, a = _cloud(1500, 3)
    rng = np.random.default_rng(4)
    g = rng.normal(size=(len(a), 3, 3)) * 1e5
    sig = g + np.swapaxes(g, 1, 2)
    rf = ring_fields(sig, c, a, R_EDGES, Z_EDGES, sector=180.0)
    ref = ring_averages(sig, c, a, R_EDGES, Z_EDGES, sector=180.0)
    assert np.allclose(rf["sigma"], ref, rtol=1e-7, atol=1e-7 * np.abs(ref).max())
    # the ring volume of a 180 degree sector
    assert rf["V_ring"][0, 0] == pytest.approx(0.5 * np.pi * 0.018 ** 2 * 0.025)
    assert np.allclose(ring_volumes(R_EDGES, Z_EDGES, 360.0), 2 * rf["V_ring"])


def test_grain_counts_are_centre_counts():
    c = np.array([[0.01, 0, 0.01], [0.0, 0.02, 0.01], [0.03, 0.0, 0.06], [0.0, 0.0, 0.2]])
    rf = ring_fields(None, c, np.full(4, 0.001), R_EDGES, Z_EDGES)
    assert rf["n_grains"].sum() == 3
    assert rf["n_grains"][0, 0] == 1 and rf["n_grains"][1, 0] == 1 and rf["n_grains"][1, 2] == 1
    assert rf["n_equiv"].sum() == pytest.approx(3.0)


# ---------------------------------------------------------------------------
# stress quantities, rotation
# ---------------------------------------------------------------------------

def _rz_tensor(s_major, s_minor, s_theta, psi_deg):
    """(r, theta, z) tensor whose (r, z) major axis is psi from the vertical."""
    t = np.radians(psi_deg)
    n = np.array([np.sin(t), np.cos(t)])          # (r, z) major direction
    m = np.array([np.cos(t), -np.sin(t)])
    s2 = s_major * np.outer(n, n) + s_minor * np.outer(m, m)
    out = np.zeros(np.shape(psi_deg) + (3, 3))
    out[..., 0, 0], out[..., 2, 2] = s2[0, 0], s2[1, 1]
    out[..., 0, 2] = out[..., 2, 0] = s2[0, 1]
    out[..., 1, 1] = s_theta
    return out


def test_q_is_sigma1_minus_sigma3_for_a_triaxial_tensor():
    s1, s3 = 400e3, 120e3
    for psi in (0.0, 25.0, 70.0):
        q = stress_quantities(_rz_tensor(s1, s3, s3, psi))
        assert q["q"] == pytest.approx(s1 - s3, rel=1e-12)
        assert q["p"] == pytest.approx((s1 + 2 * s3) / 3, rel=1e-12)
        assert q["sigma_1"] == pytest.approx(s1) and q["sigma_3"] == pytest.approx(s3)
        assert q["psi"] == pytest.approx(psi, abs=1e-9)


def test_rotated_tensor_gives_its_angle_back_past_180_degrees():
    # the axis turns 15 degrees per state, one and a half turns and back
    angles = np.concatenate([np.arange(0.0, 541.0, 15.0), np.arange(525.0, 299.0, -15.0)])
    sig = np.stack([_rz_tensor(300.0, 100.0, 150.0, a) for a in angles])
    psi = stress_quantities(sig)["psi"]
    assert np.all((psi > -90.0) & (psi <= 90.0))
    assert np.allclose(axis_rotation(psi), angles, atol=1e-9)
    # vectorised over points (second axis), and from a non-zero start
    two = np.stack([psi, psi[::-1]], axis=1)
    rot = axis_rotation(two, axis=0)
    assert np.allclose(rot[:, 0], angles, atol=1e-9)
    assert np.allclose(rot[:, 1], angles[::-1] - angles[-1], atol=1e-9)


def test_unwrapping_takes_the_smallest_step_and_skips_nans():
    # a real 100 degree step is read as -80 (aliasing, docs/report.md)
    assert np.allclose(unwrap_axis([0.0, major_axis_angle(*_rz3(100.0))]), [0.0, -80.0])
    psi = np.array([10.0, np.nan, 80.0, -80.0])
    assert np.allclose(unwrap_axis(psi), [10.0, np.nan, 80.0, 100.0], equal_nan=True)


def _rz3(angle):
    t = _rz_tensor(3.0, 1.0, 2.0, angle)
    return t[0, 0], t[2, 2], t[0, 2]


# ---------------------------------------------------------------------------
# displacement increments, profiles, events, Br, q_c
# ---------------------------------------------------------------------------

def test_rigid_motions_give_zero_radial_increment():
    rng = np.random.default_rng(6)
    ids = rng.permutation(1000)[:300] + 1
    x = rng.uniform(-0.05, 0.05, (300, 3))
    # shuffled order, a vertical translation, a rotation about the pile axis
    order = rng.permutation(300)
    t = np.radians(37.0)
    rot = np.array([[np.cos(t), -np.sin(t), 0], [np.sin(t), np.cos(t), 0], [0, 0, 1]])
    x1 = (x @ rot.T + [0.0, 0.0, 0.013])[order]
    inc = radial_increments(ids, x, ids[order], x1)
    assert inc["n_matched"] == 300 and inc["n_only0"] == inc["n_only1"] == 0
    assert np.max(np.abs(inc["dr"])) < 1e-15
    # a radial expansion by 1 % is dr = 0.01 r; a broken grain and its fragments are not matched
    x2 = x * [1.01, 1.01, 1.0]
    ids2 = ids.copy()
    ids2[:3] = [5001, 5002, 5003]
    inc = radial_increments(ids, x, ids2, x2)
    assert inc["n_matched"] == 297 and inc["n_only0"] == 3 and inc["n_only1"] == 3
    r0 = np.hypot(x[inc["rows0"], 0], x[inc["rows0"], 1])
    assert np.allclose(inc["dr"], 0.01 * r0, rtol=1e-12)


def test_interp_columns_is_exact_for_a_linear_field():
    z_mid = np.array([0.01, 0.03, 0.06])
    v = np.array([[1.0 + 2 * z for z in z_mid], [5.0 - z for z in z_mid]])
    out = interp_columns(v, z_mid, [0.02, 0.05, 0.07])
    assert np.allclose(out[:2], [[1.04, 4.98], [1.10, 4.95]])
    assert np.all(np.isnan(out[2]))


def test_interp_radius_is_exact_for_a_linear_field():
    r_mid = np.array([0.5, 1.5, 2.5, 3.5])
    v = np.stack([np.outer(3.0 + 2.0 * r_mid, [1.0, 10.0])] * 2)      # (2, n_r, n_z)
    assert np.allclose(interp_radius(v, r_mid, 3.0, axis=1), [[9.0, 90.0]] * 2)
    assert np.allclose(interp_radius(v, r_mid, 1.5, axis=1), [[6.0, 60.0]] * 2)
    # beyond the last centre: the last column
    assert np.allclose(interp_radius(v, r_mid, 3.9, axis=1), [[10.0, 100.0]] * 2)


def test_event_density_of_uniform_points():
    rng = np.random.default_rng(8)
    n = 1000000
    # uniform in a cylinder of radius 4 and height 6 (R units)
    r = 4.0 * np.sqrt(rng.uniform(0, 1, n))
    h = rng.uniform(-3, 3, n)
    dens, cnt = event_density(h, r, np.arange(-3, 3.01, 1.0), np.arange(0, 4.01, 1.0))
    assert cnt.sum() == n
    assert np.allclose(dens, n / (np.pi * 16 * 6), rtol=0.05)
    # a half chamber holds the same events in half the volume
    d180, _ = event_density(h, r, np.arange(-3, 3.01, 1.0), np.arange(0, 4.01, 1.0), 180.0)
    assert np.allclose(d180, 2 * dens)


def test_binned_mean():
    mean, cnt = binned_mean([0.5, 0.6, 1.5, 9.0], [0.5, 0.5, 0.5, 0.5], [1.0, 3.0, 7.0, 100.0],
                            [0, 1, 2], [0, 1])
    assert cnt.tolist() == [[2], [1]] and mean.tolist() == [[2.0], [7.0]]


def test_cell_breakage_equals_breakage_of_each_cell():
    rng = np.random.default_rng(9)
    N = 39.0
    d_min, d_max = D_MIN_BR * N, D_MAX_BR * N
    d0 = rng.uniform(0.15e-3, 0.26e-3, 900) * N
    cell0 = rng.integers(0, 3, 900)
    # current: some grains broke into the smallest-fragment size, moved cells
    d = d0.copy()
    d[:120] *= 0.3
    cell = cell0.copy()
    cell[50:80] = (cell[50:80] + 1) % 3
    cell[-5:] = -1                                     # left the grid
    ev_cell = rng.integers(0, 3, 40)
    ev_d = rng.uniform(0.15e-3, 0.26e-3, 40) * N
    br, M, M0 = cell_breakage(cell, d, cell0, d0, 3, d_min, d_max, ev_cell, ev_d)
    from crushpost.breakage import break_fines
    for c in range(3):
        sel, sel0, se = cell == c, cell0 == c, ev_cell == c
        ref = breakage(d[sel], sphere_mass(d[sel], RHO_GRAIN), d0[sel0], sphere_mass(d0[sel0], RHO_GRAIN),
                       d_min, d_max, fines=break_fines(ev_d[se], density=RHO_GRAIN))
        assert br[c] == pytest.approx(ref.Br, rel=1e-10, abs=1e-13)
    # the initial state is Br = 0
    br0, _, _ = cell_breakage(cell0, d0, cell0, d0, 3, d_min, d_max)
    assert np.allclose(br0, 0.0)


def test_fit_recovers_a_and_b_from_noisy_data_and_the_band_matches_its_errors():
    a, b = 6e6, 90.0
    hits = 0
    for seed in range(20):
        rng = np.random.default_rng(seed)
        h = np.linspace(0.001, 0.06, 120)
        q = qc_trend(h, a, b) + rng.normal(0.0, 0.2e6, h.size)
        fit = fit_qc_trend(h, q)
        std, cov = qc_trend_band(h, h, q, fit.a, fit.b)
        assert np.sqrt(np.diag(cov)) == pytest.approx([fit.a_err, fit.b_err], rel=1e-4)
        # far below the data, exp(-b h) -> 0 and the band is the error of a
        far, _ = qc_trend_band([0.5], h, q, fit.a, fit.b)
        assert far[0] == pytest.approx(fit.a_err, rel=1e-4)
        assert np.all(std > 0) and std[0] < std[-1] * 5
        assert abs(fit.a - a) < 4 * fit.a_err and abs(fit.b - b) < 4 * fit.b_err
        hits += abs(fit.a - a) < fit.a_err
    assert 8 <= hits <= 19       # one sigma covers ~68 % of 20 noisy samples


def test_qc_reference_is_the_last_push():
    steps = np.array([10, 20, 30, 40, 50, 60])
    qc = np.array([1.0, 2.0, 0.1, 0.0, 3.0, 4.0])
    phase = np.array([0, 0, 1, 2, 0, 0])
    # a push end at 30 (its row shows the unload), a pause end at 50 (its
    # row shows the next push, not loaded yet)
    out = qc_reference([5, 30, 50, 61], steps, qc, phase)
    assert np.isnan(out[0]) and out[1:].tolist() == [2.0, 2.0, 4.0]


