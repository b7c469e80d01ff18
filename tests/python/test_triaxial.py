# SPDX-License-Identifier: GPL-2.0-or-later
"""crushpost.triaxial on synthetic triaxial paths with known answers."""

import json
import math

import numpy as np
import pytest

from crushpost import triaxial as tx

SIGMA3 = 100e3


def synthetic_path(n=501, eps_max=0.25, noise=0.0, s3_wobble=0.0, seed=1):
    """Drained path at constant sigma_3 with a known peak, critical state and
    dilatancy:
      eta: linear to 1.5 at eps_a = 0.05, linear down to 1.2 at 0.15, then 1.2;
      eps_v: slope +0.2 up to 0.02 (contraction), slope -0.6 up to 0.12
      (dilation, D = 0.6), then constant.
    """
    rng = np.random.default_rng(seed)
    ea = np.linspace(0.0, eps_max, n)
    eta = np.interp(ea, [0.0, 0.05, 0.15, 1.0], [0.0, 1.5, 1.2, 1.2])
    ev = np.interp(ea, [0.0, 0.02, 0.12, 1.0], [0.0, 0.004, 0.004 - 0.06, 0.004 - 0.06])
    ev = ev + noise * rng.standard_normal(n)
    s3 = SIGMA3 * (1.0 + s3_wobble * np.sin(40 * ea))
    q = eta * s3 / (1.0 - eta / 3.0)          # q = eta p', p' = s3 + q / 3
    s1 = s3 + q
    path = {"eps_a": ea, "eps_v": ev, "sigma_x": s3, "sigma_y": s3,
            "sxm": s3, "sxp": s3, "sym": s3, "syp": s3}
    path.update(tx.triaxial_invariants(s1, s3, s3))
    return path


def test_friction_angle_known_values():
    # eta = 1.2 <=> sin(phi) = 3.6 / 7.2 = 0.5 <=> phi = 30 deg
    assert tx.friction_angle(1.2) == pytest.approx(30.0, abs=1e-12)
    assert tx.friction_angle(0.0) == pytest.approx(0.0, abs=1e-12)
    phi = np.array([20.0, 33.0, 41.5])
    np.testing.assert_allclose(tx.friction_angle(tx.stress_ratio(phi)), phi, rtol=1e-12)
    # M = 6 sin(phi) / (3 - sin(phi)), the classical critical-state relation
    s = math.sin(math.radians(33.0))
    assert tx.stress_ratio(33.0) == pytest.approx(6 * s / (3 - s), rel=1e-14)


def test_dilatancy_angle_known_values():
    assert tx.dilatancy_angle(0.0) == pytest.approx(0.0, abs=1e-12)
    assert tx.dilatancy_angle(2.0) == pytest.approx(30.0, abs=1e-12)   # sin psi = 1/2
    # contraction gives a negative angle
    assert tx.dilatancy_angle(-0.5) < 0


def test_invariants_conventional_triaxial():
    inv = tx.triaxial_invariants([300e3, 100e3], [100e3, 100e3], [100e3, 100e3])
    np.testing.assert_allclose(inv["q"], [200e3, 0.0])
    np.testing.assert_allclose(inv["p"], [500e3 / 3, 100e3])
    np.testing.assert_allclose(inv["eta"], [1.2, 0.0])
    # unequal lateral stresses: sigma_3 is their mean, p' the mean normal stress
    inv = tx.triaxial_invariants(250e3, 90e3, 110e3)
    assert inv["sigma_3"] == pytest.approx(100e3)
    assert inv["p"] == pytest.approx((250e3 + 90e3 + 110e3) / 3)


def test_strains_from_positions():
    # 10 x 10 x 20 box; then 11 x 10.5 x 16: eps_a = 0.2, eps_v = 1 - 1848/2000
    st = tx.strains_from_positions(xm=[-5, -5.5], xp=[5, 5.5], ym=[-5, -5.0], yp=[5, 5.5],
                                   zb=[0, 1.0], zt=[20, 17.0])
    np.testing.assert_allclose(st["eps_a"], [0.0, 0.2])
    np.testing.assert_allclose(st["eps_x"], [0.0, -0.1])
    np.testing.assert_allclose(st["eps_y"], [0.0, -0.05])
    np.testing.assert_allclose(st["eps_v"], [0.0, 1 - 11 * 10.5 * 16 / 2000.0])
    # small strains: eps_v ~ eps_a + eps_x + eps_y
    st = tx.strains_from_positions([-1, -1.0001], [1, 1.0001], [-1, -1.0002], [1, 1.0],
                                   [0, 0.0003], [2, 2.0])
    lin = st["eps_a"][1] + st["eps_x"][1] + st["eps_y"][1]
    assert st["eps_v"][1] == pytest.approx(lin, rel=1e-3)


def test_local_slope_exact_on_quadratic():
    # a least-squares line on a symmetric window of a parabola has the exact
    # derivative at the window centre
    x = np.linspace(0.0, 1.0, 201)
    y = 3.0 * x ** 2 - x
    s, full = tx.local_slope(x, y, 0.1)
    np.testing.assert_allclose(s[full], (6.0 * x - 1.0)[full], rtol=1e-9, atol=1e-9)
    assert not full[0] and not full[-1] and full[100]


def test_analyse_recovers_known_measures():
    path = synthetic_path()
    r = tx.analyse(path, SIGMA3, cs_window=0.05, dil_window=0.02, settle=0.01)
    assert r["eta_peak"] == pytest.approx(1.5, rel=1e-12)
    assert r["eps_a_peak"] == pytest.approx(0.05, abs=1e-12)
    assert r["phi_peak_deg"] == pytest.approx(math.degrees(math.asin(4.5 / 7.5)), rel=1e-12)
    assert r["eta_cs"] == pytest.approx(1.2, rel=1e-12)
    assert r["phi_cs_deg"] == pytest.approx(30.0, rel=1e-12)
    assert r["dilatancy_max"] == pytest.approx(0.6, rel=1e-9)
    assert 0.03 <= r["eps_a_dilatancy_max"] <= 0.11
    assert r["psi_max_deg"] == pytest.approx(math.degrees(math.asin(0.6 / 2.6)), rel=1e-9)
    assert r["eps_v_cs"] == pytest.approx(-0.056, rel=1e-12)
    assert r["dilatancy_cs"] == pytest.approx(0.0, abs=1e-12)   # volume settled
    # constant sigma_3: q = 3 (p' - sigma_3) exactly
    assert r["stress_path_slope"] == pytest.approx(3.0, rel=1e-12)
    assert r["stress_path_intercept"] == pytest.approx(-3 * SIGMA3, rel=1e-9)
    for e in r["servo_pairs"].values():
        assert abs(e["mean"]) < 1e-15 and e["max_abs"] < 1e-15
    assert r["q_start"] == pytest.approx(0.0, abs=1e-9)
    json.dumps(r)   # JSON-able


def test_analyse_with_noise():
    path = synthetic_path(noise=2e-5)
    r = tx.analyse(path, SIGMA3, dil_window=0.02)
    assert r["dilatancy_max"] == pytest.approx(0.6, rel=0.1)


def test_slope_and_servo_errors_detect_a_varying_cell_pressure():
    # sigma_3 off by a few per cent: the path slope leaves 3, the servo error shows it
    path = synthetic_path(s3_wobble=0.05)
    r = tx.analyse(path, SIGMA3)
    assert abs(r["stress_path_slope"] - 3.0) > 0.02
    assert r["servo_pairs"]["x"]["max_abs"] == pytest.approx(0.05, rel=1e-3)
    # a constant offset of the cell pressure shifts the line but keeps slope 3
    path = synthetic_path()
    for k in ("sigma_x", "sigma_y", "sxm", "sxp", "sym", "syp"):
        path[k] = path[k] * 1.04
    s1 = path["sigma_1"] * 0 + path["sigma_3"] * 1.04 + path["q"]
    path.update(tx.triaxial_invariants(s1, path["sigma_x"], path["sigma_y"]))
    r = tx.analyse(path, SIGMA3)
    assert r["stress_path_slope"] == pytest.approx(3.0, rel=1e-12)
    assert r["servo_pairs"]["y"]["mean"] == pytest.approx(0.04, rel=1e-9)


def test_servo_errors():
    e = tx.servo_errors({"a": [90.0, 110.0, 100.0, 104.0]}, 100.0)["a"]
    assert e["mean"] == pytest.approx(0.01)
    assert e["rms"] == pytest.approx(math.sqrt((0.01 + 0.01 + 0 + 0.0016) / 4))
    assert e["max_abs"] == pytest.approx(0.1)


LOG = """\
LIGGGHTS (Version LIGGGHTS-PUBLIC 3.8.0)
Step Atoms porosity p_mean KinEng
0 10 0.5 0 0
Loop time of 0.1 on 1 procs for 0 steps with 10 atoms
Step Time Atoms phase xm xp ym yp zb zt sxm sxp sym syp szb szt
{cons}
Loop time of 0.1 on 1 procs for 0 steps with 10 atoms
Step Time Atoms phase xm xp ym yp zb zt sxm sxp sym syp szb szt eps_a eps_v
{rows1}
Loop time of 0.1 on 1 procs for 10 steps with 10 atoms
Step Time Atoms phase xm xp ym yp zb zt sxm sxp sym syp szb szt eps_a eps_v
{rows2}
Loop time of 0.1 on 1 procs for 10 steps with 10 atoms
"""


def _row(step, xm, xp, ym, yp, zb, zt, s_lat, s_ax, H0, V0):
    Lx, Ly, Lz = xp - xm, yp - ym, zt - zb
    vals = [step, step * 1e-6, 10, 2, xm, xp, ym, yp, zb, zt, s_lat, s_lat, s_lat, s_lat,
            s_ax, s_ax, 1 - Lz / H0, 1 - Lx * Ly * Lz / V0]
    return " ".join("%.12g" % v for v in vals)


def test_shear_path_from_log(tmp_path):
    H0, V0 = 2.0, 2.0 * 1.0 * 1.0
    rows = []
    for k in range(21):
        e = 0.01 * k
        a = 0.5 * (1 + 0.004 * k)
        rows.append(_row(10 * k, -a, a, -a, a, 0.5 * e * H0, H0 - 0.5 * e * H0,
                         1e5, 1e5 + 3e4 * k, H0, V0))
    # consolidation ends at step 0 with the right stresses; the set-up row of
    # the first shearing run shows them doubled (LIGGGHTS quirk) and is mended
    cons = rows[0].split()[:16]
    setup = rows[0].split()
    setup[10:16] = ["%.12g" % (2 * float(v)) for v in setup[10:16]]
    rows1 = [" ".join(setup)] + rows[1:11]
    # the second run repeats the last row of the first (dropped on reading)
    text = LOG.format(cons=" ".join(cons), rows1="\n".join(rows1), rows2="\n".join(rows[10:]))
    log = tmp_path / "log.liggghts"
    log.write_text(text)
    p = tx.shear_path(str(log))
    assert p["Step"].tolist() == [10 * k for k in range(21)]
    assert p["sxm"][0] == pytest.approx(1e5) and p["szt"][0] == pytest.approx(1e5)
    np.testing.assert_allclose(p["eps_a_pos"], p["eps_a"], rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(p["eps_v_pos"], p["eps_v"], rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(p["q"], 3e4 * np.arange(21))
    np.testing.assert_allclose(p["p"], 1e5 + 1e4 * np.arange(21))
    r = tx.analyse(p, 1e5, settle=0.0)
    assert r["stress_path_slope"] == pytest.approx(3.0, rel=1e-9)


def test_hdf5_and_plots(tmp_path):
    h5py = pytest.importorskip("h5py")
    path = synthetic_path()
    r = tx.analyse(path, SIGMA3)
    f = tmp_path / "t.h5"
    # crush_reading is None for unbreakable grains: HDF5 has no null attribute
    tx.write_hdf5(str(f), path, {"N": 39.0, "res": r, "crush_reading": None})
    with h5py.File(str(f), "r") as h:
        np.testing.assert_array_equal(h["shear/eps_a"][()], path["eps_a"])
        assert json.loads(h.attrs["res"])["eta_cs"] == pytest.approx(1.2)
        assert h.attrs["N"] == 39.0
        assert json.loads(h.attrs["crush_reading"]) is None
    files = tx.plot_all(str(tmp_path), path, r, "synthetic")
    assert [f.rsplit("/", 1)[-1] for f in files] == ["q_p_eps_a.png", "stress_path.png"]
    for name in files:
        with open(name, "rb") as fh:
            assert fh.read(8) == b"\x89PNG\r\n\x1a\n"


def test_path_slope_unbiased_by_cell_pressure_noise():
    # p' = sigma_3 + q / 3 with sigma_3 fluctuating at random around its target:
    # fitting p' on q recovers 3, a plain fit of q on p' is attenuated
    rng = np.random.default_rng(7)
    q = np.linspace(0.0, 250e3, 400)
    s3 = SIGMA3 * (1.0 + 0.05 * rng.standard_normal(q.size))
    p = s3 + q / 3.0
    slope, intercept = tx.path_slope(p, q)
    assert slope == pytest.approx(3.0, rel=0.02)
    assert -intercept / slope == pytest.approx(SIGMA3, rel=0.02)
    naive = np.polyfit(p, q, 1)[0]
    assert naive < 2.95   # attenuated by var(q)/9 / (var(q)/9 + var(sigma_3)) ~ 0.96


def test_smoothed_peak_ignores_a_spike():
    # smooth bump to 1.5 at 3 % on a plateau of 1.3, and one spike of 5 later
    ea = np.linspace(0.0, 0.2, 2001)
    eta = 1.3 + 0.2 * np.exp(-((ea - 0.03) / 0.02) ** 2)
    eta[1500] = 5.0
    pk, at = tx.smoothed_peak(ea, eta, window=0.01)
    # the running mean of a Gaussian bump of width 0.02 over +-0.005:
    # peak 1.3 + 0.2 * mean of exp(-u^2) over |u| <= 0.25
    u = np.linspace(-0.25, 0.25, 101)
    assert pk == pytest.approx(1.3 + 0.2 * np.exp(-u ** 2).mean(), abs=2e-4)
    assert at == pytest.approx(0.03, abs=5e-4)
    assert tx.peak_state(ea, eta)[2] == 5.0          # the raw peak is the spike
    with pytest.raises(ValueError):
        tx.smoothed_peak(ea[:5], eta[:5], window=0.01)


def test_analyse_reports_the_smoothed_peak():
    r = tx.analyse(synthetic_path(), SIGMA3)
    # tent peak 1.5 at 5 %, slopes +30 and -3 per unit strain: the best window
    # of width w has equal values at its ends, i.e. starts x = w/11 before
    # the apex; its mean is 1.5 - (30 x^2 + 3 (w - x)^2) / (2 w)
    w = 0.01
    x = w / 11
    assert r["eta_peak_smooth"] == pytest.approx(1.5 - (30 * x ** 2 + 3 * (w - x) ** 2) / (2 * w),
                                                 abs=2e-3)
    assert r["eps_a_peak_smooth"] == pytest.approx(0.05 - x + w / 2, abs=1e-3)
    assert r["phi_peak_smooth_deg"] == pytest.approx(tx.friction_angle(r["eta_peak_smooth"]))


def _cubic_lattice(n, a, f):
    """Simple cubic lattice of n^3 grains at spacing a in a periodic cell of
    side n a, every grain pushed by its six neighbours with force f: the
    contacts (each once: towards +x, +y, +z) with positions wrapped."""
    idx = np.array(np.meshgrid(*[np.arange(n)] * 3, indexing="ij")).reshape(3, -1).T
    xi, xj, F = [], [], []
    for axis in range(3):
        e = np.zeros(3)
        e[axis] = 1.0
        nb = (idx + e.astype(int)) % n
        xi.append(a * idx + 0.5 * a)
        xj.append(a * nb + 0.5 * a)
        F.append(np.tile(-f[axis] * e, (len(idx), 1)))     # j pushes i away (towards -e)
    return np.vstack(xi), np.vstack(xj), np.vstack(F)


def test_cell_stress_of_a_compressed_cubic_lattice():
    # sigma_kk = f_k / a^2 (one contact per grain and direction, branch a),
    # no shear; contacts across the cell's faces need the nearest image
    n, a = 4, 2e-3
    f = np.array([3.0, 5.0, 7.0])
    xi, xj, F = _cubic_lattice(n, a, f)
    s = tx.cell_stress_from_contacts(xi, xj, F, [n * a] * 3)
    np.testing.assert_allclose(np.diag(s), f / a ** 2, rtol=1e-12)
    np.testing.assert_allclose(s - np.diag(np.diag(s)), 0.0, atol=1e-9 * f.max() / a ** 2)
    # a shear force on the x contacts (along y) gives sigma_yx only
    F2 = F.copy()
    nx = n ** 3
    F2[:nx, 1] = -2.0
    s2 = tx.cell_stress_from_contacts(xi, xj, F2, [n * a] * 3)
    assert s2[1, 0] == pytest.approx(2.0 / a ** 2, rel=1e-12)
    assert s2[0, 1] == pytest.approx(0.0, abs=1e-9)


def test_read_local_dump(tmp_path):
    text = ("ITEM: TIMESTEP\n120\nITEM: NUMBER OF ENTRIES\n2\n"
            "ITEM: BOX BOUNDS pp pp pp\n-1 1\n-2 2\n0 3\n"
            "ITEM: ENTRIES c_a[1] c_a[2]\n1 2\n3 4.5\n")
    (tmp_path / "c.txt").write_text(text)
    d = tx.read_local_dump(str(tmp_path / "c.txt"))
    assert d["timestep"] == 120
    np.testing.assert_array_equal(d["box"], [[-1, 1], [-2, 2], [0, 3]])
    np.testing.assert_array_equal(d["entries"]["c_a[2]"], [2.0, 4.5])
    (tmp_path / "bad.txt").write_text("hello\n")
    with pytest.raises(ValueError):
        tx.read_local_dump(str(tmp_path / "bad.txt"))


def test_shear_curve_samples_every_half_percent_of_axial_strain():
    # eta = 1.2 eps_a / (0.01 + eps_a) and eps_v = 0.5 eps_a - 10 eps_a^2 on a
    # fine, uneven eps_a grid to 0.123, with a repeated point (a pause of the
    # servo) and a small strain reversal that the running maximum removes
    ea = np.sort(np.r_[np.linspace(0.0, 0.123, 4001), 0.05])
    ea[2000] -= 1e-7
    path = {"eps_a": ea, "eta": 1.2 * ea / (0.01 + ea), "eps_v": 0.5 * ea - 10 * ea ** 2}
    c = tx.shear_curve(path, keys=("eta", "eps_v", "Br"))
    g = np.array(c["eps_a"])
    assert g.size == 25 and g[0] == 0.0 and g[-1] == pytest.approx(0.12)
    assert np.allclose(np.diff(g), tx.CURVE_EPS_STEP)
    assert np.allclose(c["eta"], 1.2 * g / (0.01 + g), atol=1e-4)
    assert np.allclose(c["eps_v"], 0.5 * g - 10 * g ** 2, atol=1e-6)
    assert c["Br"] == [None] * g.size
    json.dumps(c)
