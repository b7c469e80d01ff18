"""Breakage index: exact step-grading integral against quadrature and closed forms."""

import numpy as np
import pytest
from scipy.integrate import quad

from crushpost.breakage import (breakage, breakage_index, fractal_grading_integral,
                                fractal_psd, grading_integral, psd_curve, sphere_mass)

D_MIN, D_MAX = 0.01e-3, 0.27e-3


def F_reference(d, dp, mp, mf):
    """Mass fraction finer than d, written out directly."""
    return (mf + mp[dp <= d].sum()) / (mp.sum() + mf)


def test_psd_curve_hand_values():
    d = np.array([3.0, 1.0, 2.0, 2.0])
    m = np.array([4.0, 1.0, 2.0, 1.0])
    F = psd_curve(d, m, 2.0, [0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 9.0])
    # M = 10: fines 2 always finer; d=1 adds 1, d=2 adds 3, d=3 adds 4.
    assert np.allclose(F, [0.2, 0.3, 0.3, 0.6, 0.6, 1.0, 1.0])


def test_unchanged_grading_gives_zero():
    rng = np.random.default_rng(1)
    d = rng.uniform(0.15e-3, 0.27e-3, 500)
    m = sphere_mass(d, 2600.0)
    res = breakage(d, m, d, m, D_MIN, D_MAX)
    assert res.B_t == 0.0 and res.Br == 0.0
    assert res.B_p > 0


def test_exact_integral_matches_quadrature_on_random_psd():
    rng = np.random.default_rng(7)
    # Some sizes outside [d_min, d_max] to exercise the clipping.
    d = np.exp(rng.uniform(np.log(0.004e-3), np.log(0.4e-3), 40))
    m = rng.uniform(0.1, 2.0, 40)
    mf = 3.7
    exact = grading_integral(d, m, mf, D_MIN, D_MAX)
    # Integrate F(e^u) du with the jumps given as break points.
    jumps = np.log(d[(d > D_MIN) & (d < D_MAX)])
    num, _ = quad(lambda u: F_reference(np.exp(u), d, m, mf), np.log(D_MIN),
                  np.log(D_MAX), points=jumps, limit=500, epsabs=1e-12)
    assert exact == pytest.approx(num, rel=1e-9)
    # psd_curve agrees with the direct definition at and between the sizes.
    probe = np.concatenate([d, d * 1.001, d * 0.999])
    assert np.allclose(psd_curve(d, m, mf, probe),
                       [F_reference(s, d, m, mf) for s in probe], rtol=0, atol=1e-15)


@pytest.mark.parametrize("w", [2.6, 2.0, 3.0, 3.4])
def test_fractal_integral_matches_quadrature(w):
    num, _ = quad(lambda u: fractal_psd(np.exp(u), D_MIN, D_MAX, w),
                  np.log(D_MIN), np.log(D_MAX), epsabs=1e-13)
    assert fractal_grading_integral(D_MIN, D_MAX, w) == pytest.approx(num, rel=1e-10)


def test_fractal_psd_formula_and_w3_limit():
    s = np.array([0.02e-3, 0.1e-3, 0.2e-3])
    k = 3.0 - 2.6
    direct = (s ** k - D_MIN ** k) / (D_MAX ** k - D_MIN ** k)
    assert np.allclose(fractal_psd(s, D_MIN, D_MAX, 2.6), direct, rtol=1e-13)
    assert fractal_psd([D_MIN, D_MAX], D_MIN, D_MAX, 2.6) == pytest.approx([0, 1])
    big_l = np.log(D_MAX / D_MIN)
    assert fractal_grading_integral(D_MIN, D_MAX, 3.0) == pytest.approx(big_l / 2, rel=1e-14)
    # Continuous across w = 3 (series branch against closed form).
    for eps in (1e-9, 1e-6, 1e-3):
        lo = fractal_grading_integral(D_MIN, D_MAX, 3.0 - eps)
        hi = fractal_grading_integral(D_MIN, D_MAX, 3.0 + eps)
        # dI_u/dw = L^2/12 at w = 3 (more fines as w grows).
        assert hi - lo == pytest.approx(2 * eps * big_l ** 2 / 12, rel=1e-4)
        assert lo < big_l / 2 < hi


def test_fine_fractal_discretisation_gives_br_one():
    # Initial: uniform sand around d50 = 0.21 mm.
    d0 = np.linspace(0.17e-3, 0.25e-3, 200)
    m0 = np.ones_like(d0)
    # Current: fractal grading binned on a fine log grid, mass per bin at the
    # bin's geometric midpoint (midpoint rule, error ~ 1/n^2).
    edges = np.geomspace(D_MIN, D_MAX, 4001)
    mid = np.sqrt(edges[1:] * edges[:-1])
    mass = np.diff(fractal_psd(edges, D_MIN, D_MAX, 2.6)) * 5.0
    res = breakage(mid, mass, d0, m0, D_MIN, D_MAX, w=2.6)
    assert res.Br == pytest.approx(1.0, abs=1e-5)
    # A coarse version misses by a visible amount: the test can tell.
    edges = np.geomspace(D_MIN, D_MAX, 5)
    coarse = breakage_index(edges[1:], np.diff(fractal_psd(edges, D_MIN, D_MAX)),
                            d0, m0, D_MIN, D_MAX)
    assert abs(coarse - 1.0) > 0.05


def test_fines_count_below_d_min():
    # All mass at d0; a fraction x turns into fines: B_t = x ln(d0/d_min).
    d0, x = 0.21e-3, 0.3
    res = breakage([d0], [1.0 - x], [d0], [1.0], D_MIN, D_MAX, m_fines=x)
    assert res.B_t == pytest.approx(x * np.log(d0 / D_MIN), rel=1e-13)
    # Same as putting that mass in particles at (or below) d_min.
    same = breakage([d0, 0.5 * D_MIN], [1.0 - x, x], [d0], [1.0], D_MIN, D_MAX)
    assert same.B_t == pytest.approx(res.B_t, rel=1e-13)
    # Fines are finer than every size.
    assert psd_curve([d0], [1.0 - x], x, [1e-9])[0] == pytest.approx(x)
    # Initial fines reduce both B_t and B_p consistently.
    r2 = breakage([d0], [0.5], [d0], [0.8], D_MIN, D_MAX, m_fines=0.5, m_fines_initial=0.2)
    lm = np.log(D_MAX / D_MIN)
    i0 = 0.8 * np.log(D_MAX / d0) + 0.2 * lm
    i1 = 0.5 * np.log(D_MAX / d0) + 0.5 * lm
    iu = fractal_grading_integral(D_MIN, D_MAX)
    assert r2.Br == pytest.approx((i1 - i0) / (iu - i0), rel=1e-13)


def test_apollonian_fragments_and_errors():
    # One parent replaced by 6 + 8 fragments: fragment volume 52.39 %.
    r = 0.1e-3
    r1, r2 = r / (1 + np.sqrt(2)), 0.230093 * r
    frag_d = np.array([2 * r1] * 6 + [2 * r2] * 8)
    frag_m = sphere_mass(frag_d, 2600.0)
    parent = sphere_mass(2 * r, 2600.0)
    assert frag_m.sum() / parent == pytest.approx(0.5239, abs=2e-4)
    fines = parent - frag_m.sum()
    res = breakage(frag_d, frag_m, [2 * r], [parent], D_MIN, D_MAX, m_fines=fines)
    expect = (6 * frag_m[0] * np.log(r / r1) + 8 * frag_m[-1] * np.log(r / r2)
              + fines * np.log(2 * r / D_MIN)) / parent
    assert res.B_t == pytest.approx(expect, rel=1e-12)
    with pytest.raises(ValueError):
        breakage([1e-6], [1.0], [1e-6], [1.0], D_MIN, D_MAX)  # B_p <= 0
    with pytest.raises(ValueError):
        grading_integral([1.0, 2.0], [1.0], 0.0, D_MIN, D_MAX)
