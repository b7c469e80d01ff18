# SPDX-License-Identifier: GPL-2.0-or-later
"""q_c(h) = a (1 - exp(-b h)) fit on synthetic data with known parameters."""

import numpy as np
import pytest

from crushpost.trend import (fit_qc_trend, mean_of_last_bands, qc_band_means, qc_trend,
                             virgin_mask)


def test_model_values():
    assert qc_trend(0.0, 5.0, 2.0) == 0.0
    assert qc_trend(0.5, 5.0, 2.0) == pytest.approx(5.0 * (1 - np.exp(-1.0)), rel=1e-15)


@pytest.mark.parametrize("a,b", [(12e6, 3.5), (4e6, 20.0), (30e6, 1.2)])
def test_recovers_known_parameters(a, b):
    rng = np.random.default_rng(42)
    h = np.linspace(0.0, 1.0, 400)
    q = qc_trend(h, a, b) + rng.normal(0.0, 0.03 * a, h.size)
    fit = fit_qc_trend(h, q)
    assert fit.a == pytest.approx(a, rel=0.03)
    assert fit.b == pytest.approx(b, rel=0.05)
    # Standard errors are plausible: positive and the truth lies within 4 of them.
    assert 0 < fit.a_err < 0.05 * a and 0 < fit.b_err < 0.1 * b
    assert abs(fit.a - a) < 4 * fit.a_err and abs(fit.b - b) < 4 * fit.b_err


def test_noise_free_is_exact_and_nan_ignored():
    h = np.linspace(0.01, 1.0, 50)
    q = qc_trend(h, 7.0, 4.0)
    q[10] = np.nan
    fit = fit_qc_trend(h, q)
    assert fit.a == pytest.approx(7.0, rel=1e-8)
    assert fit.b == pytest.approx(4.0, rel=1e-8)
    with pytest.raises(ValueError):
        fit_qc_trend([0.1, 0.2], [1.0, 2.0])


def test_virgin_penetration_excludes_every_repush_until_it_passes_the_deepest_point():
    # push to 3, unload to 2.4, pause, re-push through 3 to 5, unload, re-push
    depth = np.array([0, 1, 2, 3, 2.8, 2.4, 2.4, 2.5, 2.9, 3.0, 3.2, 4, 5, 4.5, 4.6, 5.2])
    phase = np.array([0, 0, 0, 0, 1, 1, 2, 0, 0, 0, 0, 0, 0, 1, 0, 0])
    m = virgin_mask(depth, phase)
    expect = [1, 1, 1, 1, 0, 0, 0, 0, 0, 1, 1, 1, 1, 0, 0, 1]
    assert list(m.astype(int)) == expect
    # without phases: the running maximum alone (the pause at the deepest
    # point would count)
    assert list(virgin_mask([0, 1, 1, 0.5, 2]).astype(int)) == [1, 1, 1, 0, 1]
    # round-off of the depth: a re-push that arrives 1e-16 m short of the old
    # deepest point counts as reaching it
    assert virgin_mask([0.0, 0.03, 0.02, 0.03 - 1e-16], [0, 0, 0, 0]).tolist() == \
        [True, True, False, True]
    with pytest.raises(ValueError):
        virgin_mask([0, 1], [0])


def test_fit_on_virgin_points_is_unbiased_by_repushes():
    """A cyclic record: q_c follows a (1 - exp(-b h)) on virgin penetration;
    each re-push after an unload reloads from zero and meets the curve only
    at the previous deepest point. Fitting every push point biases a low;
    the virgin points give a and b back exactly."""
    a, b = 6e6, 40.0
    depth, qc, phase = [], [], []
    deepest = 0.0
    for end in (0.02, 0.04, 0.06, 0.08):
        if deepest > 0:                       # unload by 2 mm, then re-push
            d_un = deepest - 0.002
            depth += [deepest - 0.001, d_un]
            qc += [0.3 * qc_trend(deepest, a, b), 0.0]
            phase += [1, 1]
            h = np.linspace(d_un, deepest, 20, endpoint=False)[1:]
            depth += list(h)
            qc += list(qc_trend(deepest, a, b) * (h - d_un) / (deepest - d_un))
            phase += [0] * len(h)
        h = np.linspace(deepest, end, 60)
        depth += list(h)
        qc += list(qc_trend(h, a, b))
        phase += [0] * len(h)
        deepest = end
    depth, qc, phase = map(np.asarray, (depth, qc, phase))
    push = phase == 0
    v = virgin_mask(depth, phase)
    assert v.sum() < push.sum()
    fit = fit_qc_trend(depth[v], qc[v])
    assert fit.a == pytest.approx(a, rel=1e-8) and fit.b == pytest.approx(b, rel=1e-8)
    biased = fit_qc_trend(depth[push], qc[push])
    assert biased.a < 0.98 * a        # 3.3 % low here


def test_band_means_of_a_linear_q_c_are_the_band_centres():
    # q_c = h on a uniform grid with no point on a band's edge: each band's
    # mean is its centre depth
    h = (np.arange(8000) + 0.5) * 2.5e-5
    bottom, mean, count = qc_band_means(h, h, 0.025, h_end=0.2)
    assert np.allclose(bottom, 0.025 * np.arange(1, 9), rtol=0, atol=1e-15)
    assert np.allclose(mean, bottom - 0.0125, rtol=0, atol=1e-12)
    assert count.tolist() == [1000] * 8
    # the deepest point on a band's edge ends the last band, not a band of
    # its own
    bottom, mean, count = qc_band_means([0.01, 0.05], [1.0, 2.0], 0.025)
    assert bottom.size == 2 and count.tolist() == [1, 1]


def test_band_means_exact_on_known_points():
    h = [0.01, 0.02, 0.03, 0.06, 0.07, -0.01, np.nan]
    q = [1.0, 3.0, 10.0, 5.0, 7.0, 100.0, 100.0]
    bottom, mean, count = qc_band_means(h, q, 0.025)
    assert bottom.tolist() == pytest.approx([0.025, 0.05, 0.075])
    assert mean[0] == 2.0 and mean[1] == 10.0 and mean[2] == 6.0
    assert count.tolist() == [2, 1, 2]          # h < 0 and NaN left out
    # an empty band is NaN with count 0; h_end cuts the deeper points off
    bottom, mean, count = qc_band_means([0.01, 0.06], [1.0, 2.0], 0.025)
    assert np.isnan(mean[1]) and count.tolist() == [1, 0, 1]
    bottom, mean, count = qc_band_means(h, q, 0.025, h_end=0.05)
    assert count.tolist() == [2, 1] and mean.tolist() == [2.0, 10.0]
    with pytest.raises(ValueError):
        qc_band_means([0.1], [1.0], 0.0)
    with pytest.raises(ValueError):
        qc_band_means([0.1, 0.2], [1.0], 0.025)


def test_mean_of_last_bands_weights_each_band_by_its_points():
    # bands of 1 (x1), 2 (x3), NaN (empty), 5 (x1): the last three hold
    # points 2, 2, 2, 5 -> 11 / 4
    assert mean_of_last_bands([1.0, 2.0, np.nan, 5.0], [1, 3, 0, 1]) == 2.75
    assert mean_of_last_bands([2.0, 5.0], [1, 1]) is None          # two bands only
    assert mean_of_last_bands([1.0, np.nan, np.nan, np.nan], [1, 0, 0, 0]) is None
    assert mean_of_last_bands([1.0, 3.0], [1, 1], n=1) == 3.0
