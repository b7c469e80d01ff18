"""q_c(h) = a (1 - exp(-b h)) fit on synthetic data with known parameters."""

import numpy as np
import pytest

from crushpost.trend import fit_qc_trend, qc_trend


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
