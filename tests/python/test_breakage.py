# SPDX-License-Identifier: GPL-2.0-or-later
"""Breakage index: exact step-grading integral against quadrature and closed forms."""

import numpy as np
import pytest
from scipy.integrate import quad

from crushpost.breakage import (breakage, breakage_index, fractal_grading_integral,
                                fractal_psd, grading_integral, psd_curve, sphere_mass)
from crushpost.materials import D50, D_COMM_RATIO, D_MAX_BR, D_MIN_BR, RHO_GRAIN

D_MIN, D_MAX = D_MIN_BR, D_MAX_BR


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
    m = sphere_mass(d, RHO_GRAIN)
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
    d0, x = D50, 0.3
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
    # Einav's unclipped ratio is 2.1 here (all fines at d_min overshoot the
    # limit grading below d50); the bounded Br stays within [0, 1].
    assert r2.Br_einav == pytest.approx((i1 - i0) / (iu - i0), rel=1e-13)
    assert r2.Br_einav > 1 and 0 < r2.Br < 1


def test_apollonian_fragments_and_errors():
    # One parent replaced by 6 + 8 fragments: fragment volume 52.39 %.
    r = 0.1e-3
    r1, r2 = r / (1 + np.sqrt(2)), 0.230093 * r
    frag_d = np.array([2 * r1] * 6 + [2 * r2] * 8)
    frag_m = sphere_mass(frag_d, RHO_GRAIN)
    parent = sphere_mass(2 * r, RHO_GRAIN)
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


# ---------------------------------------------------------------------------
# binned integrals, fines conventions and the bound
# ---------------------------------------------------------------------------

from crushpost.breakage import (N_BINS, R1_RATIO, R2_RATIO, BreakFines,  # noqa: E402
                                bin_integrals, bounded_breakage_index, break_fines,
                                limit_bin_integrals)

RHO = RHO_GRAIN


def F_direct(x, d, m, lost, d_top, dropped_d, dropped_m, w, fractal=True):
    """Mass fraction finer than x written out from the formula of docs/model.md §2.8: particles
    and dropped fragments at their size, each break's unfilled volume spread as
    (x^k - d_min^k) / (d_top^k - d_min^k) over [d_min, d_top] (fractal) or
    finer than d_min."""
    k = 3.0 - w
    M = m.sum() + lost.sum() + dropped_m.sum()
    s = m[d <= x].sum()
    if not fractal:
        return (s + lost.sum() + dropped_m.sum()) / M
    s += dropped_m[dropped_d <= x].sum()
    xc = min(max(x, D_MIN), 1.0)
    for mf, top in zip(lost, d_top):
        if xc >= top:
            s += mf
        elif k == 0:
            s += mf * np.log(xc / D_MIN) / np.log(top / D_MIN)
        else:
            s += mf * (xc ** k - D_MIN ** k) / (top ** k - D_MIN ** k)
    return s / M


def _history(seed, fractal, d_comm, d_frag_min, nbreaks, n0=60, w=2.6):
    """Random breakage history of a uniform sand (0.15-0.27 mm): a random
    breakable grain at a time becomes its kept Apollonian fragments. Yields
    (d, m, BreakFines of all breaks so far) after every break."""
    rng = np.random.default_rng(seed)
    d = np.exp(rng.uniform(np.log(0.15e-3), np.log(0.27e-3), n0))
    parents = []
    for _ in range(nbreaks):
        can = np.flatnonzero(d >= d_comm)
        if can.size == 0:
            return
        p = rng.choice(can)
        dp = d[p]
        parents.append(dp)
        kids = [np.full(6, R1_RATIO * dp)] if R1_RATIO * dp >= d_frag_min else []
        kids += [np.full(8, R2_RATIO * dp)] if R2_RATIO * dp >= d_frag_min else []
        d = np.concatenate([np.delete(d, p)] + kids)
        yield d, sphere_mass(d, RHO), break_fines(parents, density=RHO, d_frag_min=d_frag_min)


def test_break_fines_mass_accounting():
    dp = np.array([0.2e-3, 0.05e-3, 0.02e-3])
    fines = break_fines(dp, density=RHO, d_frag_min=0.015e-3)
    mp = sphere_mass(dp, RHO)
    kept_vol = 6 * R1_RATIO ** 3 + 8 * R2_RATIO ** 3
    assert kept_vol == pytest.approx(0.5239, abs=1e-4)
    np.testing.assert_allclose(fines.lost, mp * (1 - kept_vol), rtol=1e-13)
    np.testing.assert_allclose(fines.d_small, R2_RATIO * dp, rtol=1e-15)
    # 0.02 mm parent: small fragments (0.0046 mm) dropped, large (0.0083 mm) dropped too
    # 0.05 mm parent: small (0.0115 mm) dropped, large (0.0207 mm) kept
    np.testing.assert_allclose(np.sort(fines.dropped_d),
                               np.sort([2 * R1_RATIO * 0.01e-3, 2 * R2_RATIO * 0.01e-3,
                                        2 * R2_RATIO * 0.025e-3]), rtol=1e-13)
    kept = (sphere_mass(2 * R1_RATIO * 0.1e-3, RHO) * 6 + sphere_mass(2 * R2_RATIO * 0.1e-3, RHO) * 8
            + sphere_mass(2 * R1_RATIO * 0.025e-3, RHO) * 6)
    assert fines.total == pytest.approx(mp.sum() - kept, rel=1e-13)
    # masses may be given instead of the density
    same = break_fines(dp, parent_m=mp, d_frag_min=0.015e-3)
    assert same.total == pytest.approx(fines.total, rel=1e-15)
    with pytest.raises(ValueError):
        break_fines(dp)


@pytest.mark.parametrize("w", [2.6, 3.0, 2.0])
@pytest.mark.parametrize("fractal", [True, False])
def test_bin_integrals_match_quadrature(w, fractal):
    rng = np.random.default_rng(3)
    d = np.exp(rng.uniform(np.log(D_MIN / 3), np.log(3 * D_MAX), 60))
    m = rng.uniform(0.2, 1.0, 60) * 1e-9
    fines = break_fines([D50, 0.1e-3, 0.03e-3, 0.02e-3], density=RHO, d_frag_min=0.012e-3)
    J, M = bin_integrals(d, m, D_MIN, D_MAX, fines, "fractal" if fractal else "d_min", w)
    assert M == pytest.approx(m.sum() + fines.total, rel=1e-15)
    edges = np.log(D_MIN) + np.arange(N_BINS + 1) * np.log(D_MAX / D_MIN) / N_BINS
    kinks = np.log(np.concatenate([d, fines.dropped_d, fines.d_small]))
    for b in list(range(0, N_BINS, 7)) + [N_BINS - 1]:
        lo, hi = edges[b], edges[b + 1]
        pts = kinks[(kinks > lo) & (kinks < hi)]
        num, _ = quad(lambda u: F_direct(np.exp(u), d, m, fines.lost, fines.d_small,
                                         fines.dropped_d, fines.dropped_m, w, fractal),
                      lo, hi, points=pts if pts.size else None, limit=200, epsabs=1e-15)
        assert J[b] == pytest.approx(num, abs=1e-13), b


def test_psd_curve_with_fractal_fines_is_the_integrated_grading():
    d = np.array([0.2e-3, 0.083e-3, 0.046e-3])
    m = sphere_mass(d, RHO)
    fines = break_fines([0.2e-3, 0.05e-3], density=RHO, d_frag_min=0.02e-3)
    sizes = np.geomspace(0.5 * D_MIN, 2 * D_MAX, 57)
    F = psd_curve(d, m, 0.0, sizes, fines=fines, d_min=D_MIN)
    ref = [F_direct(x, d, m, fines.lost, fines.d_small, fines.dropped_d, fines.dropped_m, 2.6)
           for x in sizes]
    np.testing.assert_allclose(F, ref, rtol=1e-12, atol=1e-15)
    assert F[-1] == pytest.approx(1.0, rel=1e-14)
    # the fines are not all finer than d_min any more, unlike with 'd_min'
    F_dmin = psd_curve(d, m, 0.0, sizes, fines=fines, fines_grading="d_min")
    assert F[0] == 0.0 and F_dmin[0] == pytest.approx(fines.total / (m.sum() + fines.total))
    # the bins integrate this curve
    J, _ = bin_integrals(d, m, D_MIN, D_MAX, fines)
    num, _ = quad(lambda u: psd_curve(d, m, 0.0, np.exp(u), fines=fines, d_min=D_MIN),
                  np.log(D_MIN), np.log(D_MAX), limit=400,
                  points=np.log(np.concatenate([d, fines.dropped_d, fines.d_small])))
    assert J.sum() == pytest.approx(num, rel=1e-9)


def test_d_min_convention_sums_to_the_former_formula():
    for d, m, fines in _history(5, False, 0.0, 0.02e-3, 150):
        J, _ = bin_integrals(d, m, D_MIN, D_MAX, fines, "d_min")
        assert J.sum() == pytest.approx(grading_integral(d, m, fines.total, D_MIN, D_MAX),
                                        rel=1e-13)


def test_limit_bins_and_br_endpoints():
    U = limit_bin_integrals(D_MIN, D_MAX)
    assert U.sum() == pytest.approx(fractal_grading_integral(D_MIN, D_MAX), rel=1e-14)
    # omega = 3: int over bin b of u/L du = h^2 (b + 1/2) / L
    h = np.log(D_MAX / D_MIN) / N_BINS
    np.testing.assert_allclose(limit_bin_integrals(D_MIN, D_MAX, 3.0),
                               h * h * (np.arange(N_BINS) + 0.5) / (N_BINS * h), rtol=1e-13)
    np.testing.assert_allclose(limit_bin_integrals(D_MIN, D_MAX, 3.0 - 1e-12),
                               limit_bin_integrals(D_MIN, D_MAX, 3.0), rtol=0, atol=1e-13)
    rng = np.random.default_rng(2)
    d0 = rng.uniform(0.15e-3, 0.27e-3, 300)
    m0 = sphere_mass(d0, RHO)
    J0, _ = bin_integrals(d0, m0, D_MIN, D_MAX)
    assert bounded_breakage_index(J0, J0, U) == 0.0
    assert bounded_breakage_index(U, J0, U) == 1.0
    res = breakage(d0, m0, d0, m0, D_MIN, D_MAX)
    assert res.Br == 0.0 and res.Br_einav == 0.0


@pytest.mark.parametrize("fractal", [True, False])
@pytest.mark.parametrize("d_comm,d_frag_min", [(D_COMM_RATIO * D50, 0.0), (0.0, 0.03e-3),
                                               (D_COMM_RATIO * D50, 0.03e-3)])
def test_br_bounded_for_random_histories(fractal, d_comm, d_frag_min):
    grading = "fractal" if fractal else "d_min"
    U = limit_bin_integrals(D_MIN, D_MAX)
    clipped = False
    for seed in range(3):
        prev, n = 0.0, 0
        d0, m0 = _initial(100 + seed)
        J0, _ = bin_integrals(d0, m0, D_MIN, D_MAX)
        for d, m, fines in _history(100 + seed, fractal, d_comm, d_frag_min, 150):
            n += 1
            res = breakage(d, m, d0, m0, D_MIN, D_MAX, fines=fines, fines_grading=grading)
            assert 0.0 <= res.Br <= 1.0
            assert res.Br >= prev - 1e-14      # breakage only moves mass finer
            prev = res.Br
            # equal to Einav's ratio while no bin is clipped
            J, _ = bin_integrals(d, m, D_MIN, D_MAX, fines, grading)
            if np.all((J0 <= J) & (J <= U) & (J0 <= U)):
                assert res.Br == pytest.approx(res.Br_einav, rel=1e-12)
            else:
                clipped = True
        assert n >= 60
    assert clipped      # the histories go far enough for the bound to act


def _initial(seed, n0=60):
    d = np.exp(np.random.default_rng(seed).uniform(np.log(0.15e-3), np.log(0.27e-3), n0))
    return d, sphere_mass(d, RHO)


def test_bound_when_every_grain_broke_once():
    # Every grain of a uniform sand (0.15-0.27 mm) broken once: all mass is now
    # below 0.414 x 0.27 = 0.11 mm, where the limit grading still has 41 % of
    # its mass above. Finer than the limit grading at every size, whatever the
    # fines convention: Einav's unclipped ratio passes 1 (1.84 with the fines
    # at d_min, 1.45 fractal), the bounded Br is exactly 1.
    d0, m0 = _initial(9)
    d = np.concatenate([np.repeat(R1_RATIO * d0, 6), np.repeat(R2_RATIO * d0, 8)])
    m = sphere_mass(d, RHO)
    fines = m0.sum() - m.sum()
    old = breakage(d, m, d0, m0, D_MIN, D_MAX, m_fines=fines)   # scalar fines: below d_min
    fr = breakage(d, m, d0, m0, D_MIN, D_MAX, fines=break_fines(d0, density=RHO))
    assert old.Br_einav > 1.7 and fr.Br_einav > 1.3
    assert old.Br == 1.0 and fr.Br == 1.0
    # half of them broken: below 1, the fractal fines count less than fines at d_min
    half = np.arange(d0.size) % 2 == 0
    d = np.concatenate([d0[~half], np.repeat(R1_RATIO * d0[half], 6),
                        np.repeat(R2_RATIO * d0[half], 8)])
    m = sphere_mass(d, RHO)
    fines = break_fines(d0[half], density=RHO)
    a = breakage(d, m, d0, m0, D_MIN, D_MAX, fines=fines)
    b = breakage(d, m, d0, m0, D_MIN, D_MAX, fines=fines, fines_grading="d_min")
    assert 0.0 < a.Br < b.Br < 1.0


def test_fractal_fines_give_smaller_br_than_fines_at_d_min():
    for d, m, fines in _history(8, True, D_COMM_RATIO * D50, 0.0, 40):
        d0, m0 = _initial(8)
        a = breakage(d, m, d0, m0, D_MIN, D_MAX, fines=fines)
        b = breakage(d, m, d0, m0, D_MIN, D_MAX, fines=fines, fines_grading="d_min")
        assert a.B_t < b.B_t


def test_bad_fines_grading():
    with pytest.raises(ValueError, match="fines_grading"):
        breakage([1e-4], [1.0], [2e-4], [1.0], D_MIN, D_MAX, fines_grading="sieve")
    with pytest.raises(ValueError, match="d_min"):
        psd_curve([1e-4], [1.0], 0.0, [1e-4], fines=break_fines([2e-4], density=RHO))
    assert isinstance(break_fines([2e-4], density=RHO), BreakFines)


def test_oedometer_psd_snapshots_with_event_log(tmp_path):
    from crushpost.dump import read_crush_log
    from crushpost.oedometer import psd_snapshots
    r = 0.1e-3
    frag = [r] * 3 + [R1_RATIO * r] * 6 + [R2_RATIO * r] * 8
    with open(tmp_path / "dump.0.txt", "w") as fh:
        for step, radii in ((0, [r] * 4), (500, frag)):
            fh.write("ITEM: TIMESTEP\n%d\nITEM: NUMBER OF ATOMS\n%d\n" % (step, len(radii)))
            fh.write("ITEM: BOX BOUNDS ff ff ff\n0 1\n0 1\n0 1\nITEM: ATOMS id radius\n")
            for k, x in enumerate(radii):
                fh.write("%d %.17g\n" % (k + 1, x))
    (tmp_path / "events.txt").write_text("500 1e-4 4 %.17g 0 0 0 1 1 wall 0\n" % (2 * r))
    ev = read_crush_log(tmp_path / "events.txt")
    sizes = np.geomspace(D_MIN, D_MAX, 9)
    steps, F = psd_snapshots(str(tmp_path / "dump.*.txt"), RHO, sizes, events=ev, d_min=D_MIN)
    assert list(steps) == [0, 500]
    d = 2 * np.array(frag)
    expect = psd_curve(d, sphere_mass(d, RHO), 0.0, sizes, fines=break_fines([2 * r], density=RHO),
                       d_min=D_MIN)
    np.testing.assert_allclose(F[1], expect, rtol=1e-14)
    np.testing.assert_array_equal(F[0], (sizes >= 2 * r).astype(float))
