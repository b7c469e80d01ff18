# SPDX-License-Identifier: GPL-2.0-or-later
"""Trend fit of tip resistance against depth, ``q_c(h) = a (1 - exp(-b h))`` (docs/model.md §4.5).

``a`` is the steady-state tip resistance (same unit as ``q_c``, e.g. Pa) and
``b`` the inverse of a characteristic depth (1 / unit of ``h``, e.g. 1/m).
"""

from typing import NamedTuple

import numpy as np
from scipy.optimize import curve_fit

__all__ = ["qc_trend", "QcFit", "fit_qc_trend", "virgin_mask", "qc_band_means",
           "mean_of_last_bands"]


def qc_trend(h, a, b):
    """``a (1 - exp(-b h))``: same unit as ``a``; ``h`` in 1/``b`` units."""
    return a * -np.expm1(-b * np.asarray(h, dtype=float))


class QcFit(NamedTuple):
    """Least-squares result: parameters and their one-sigma standard errors."""
    a: float
    b: float
    a_err: float
    b_err: float


def _initial_guess(h, q):
    # a: the plateau, taken as the mean of the deepest 20 % of points.
    order = np.argsort(h)
    tail = q[order][-max(1, len(q) // 5):]
    a0 = float(np.mean(tail))
    if a0 == 0.0:
        a0 = float(np.max(np.abs(q))) or 1.0
    # b: from the depth where the data first reach 63 % of the plateau, 1/b there.
    reached = np.nonzero(q[order] / a0 >= 1.0 - np.exp(-1.0))[0]
    span = float(np.ptp(h)) or 1.0
    h63 = float(h[order][reached[0]]) if reached.size else span
    if h63 <= 0:
        h63 = span / 10.0
    return a0, 1.0 / h63


def fit_qc_trend(h, q_c, p0=None, sigma=None, b_min=None):
    """Fit ``q_c(h) = a (1 - exp(-b h))`` by nonlinear least squares.

    Parameters
    ----------
    h : (n,) penetration depth [m, or any length unit].
    q_c : (n,) tip resistance [Pa, or any stress unit].
    p0 : optional initial guess ``(a, b)``; by default from the plateau and
        the depth where ``q_c`` reaches 63 % of it.
    sigma : optional per-point standard deviations of ``q_c`` (relative
        weights; the errors are scaled by the residual variance).
    b_min : optional lower bound on ``b``. Over a depth range much shorter
        than 1/b the data are nearly linear and the fit runs away to a huge
        ``a`` and ``b -> 0``; a bound such as ``1 / max(h)`` keeps ``a`` finite
        (then ``a`` is a lower estimate of the plateau, not a measured one).

    Returns
    -------
    QcFit(a, b, a_err, b_err); ``a`` in ``q_c`` units, ``b`` in 1/``h`` units.
    """
    h = np.asarray(h, dtype=float).ravel()
    q = np.asarray(q_c, dtype=float).ravel()
    if h.shape != q.shape:
        raise ValueError("h and q_c must have the same length")
    ok = np.isfinite(h) & np.isfinite(q)
    h, q = h[ok], q[ok]
    if sigma is not None:
        sigma = np.asarray(sigma, dtype=float).ravel()[ok]
    if h.size < 3:
        raise ValueError("need at least 3 finite points to fit 2 parameters")
    if p0 is None:
        p0 = _initial_guess(h, q)
    if b_min is None:
        popt, pcov = curve_fit(qc_trend, h, q, p0=p0, sigma=sigma, maxfev=20000)
    else:
        p0 = (p0[0], max(p0[1], 1.01 * b_min))
        popt, pcov = curve_fit(qc_trend, h, q, p0=p0, sigma=sigma, maxfev=20000,
                               bounds=([-np.inf, b_min], [np.inf, np.inf]))
    err = np.sqrt(np.diag(pcov))
    return QcFit(float(popt[0]), float(popt[1]), float(err[0]), float(err[1]))


def virgin_mask(depth, phase=None, atol=None, push_phase=0):
    """Points of virgin penetration: the pile is pushing (``phase ==
    push_phase``, when ``phase`` is given) and the tip is at its deepest so
    far, i.e. ``depth`` is within ``atol`` of its running maximum over all
    earlier points. A re-push after an unload re-enters only once it passes
    the previous deepest point. ``atol`` (depth units) defaults to the
    round-off of the depths, 64 machine epsilons of the largest one.

    Parameters: ``depth`` (n,) in time order; ``phase`` (n,) or None.
    Returns a boolean (n,) array.
    """
    d = np.asarray(depth, dtype=float).ravel()
    if atol is None:
        atol = 64.0 * np.finfo(float).eps * (float(np.max(np.abs(d))) if d.size else 0.0)
    deepest = np.maximum.accumulate(d) if d.size else d
    mask = d >= deepest - atol
    if phase is not None:
        ph = np.asarray(phase).ravel()
        if ph.shape != d.shape:
            raise ValueError("depth and phase must have the same length")
        mask &= ph == push_phase
    return mask


def qc_band_means(h, q_c, width, h_end=None):
    """Mean ``q_c`` over bands of depth ``[k width, (k + 1) width)``, k = 0,
    1, ...: a plateau estimate that, unlike the trend fit, assumes no shape
    (docs/studies/error-vs-runtime.md reads the bands from 75 mm on and the mean of
    the last three). Called by the ``fit-qc`` command and the chamber report
    on the points of virgin penetration.

    Parameters: ``h`` (n,) depth, ``q_c`` (n,) tip resistance, ``width`` the
    band height (``h`` units, > 0), ``h_end`` the depth the bands end at (by
    default the deepest point; its band is the last one, and a point at
    ``h_end`` exactly on a band edge is counted in the shallower band).
    Returns ``(h_bottom, mean, count)``, each (m,): the band's deeper edge
    ``(k + 1) width``, the mean (NaN for an empty band) and the number of
    points. Points with ``h < 0`` or ``h > h_end`` are left out.
    """
    h = np.asarray(h, dtype=float).ravel()
    q = np.asarray(q_c, dtype=float).ravel()
    if h.shape != q.shape:
        raise ValueError("h and q_c must have the same length")
    if not width > 0:
        raise ValueError("band width must be > 0, got %r" % (width,))
    ok = np.isfinite(h) & np.isfinite(q) & (h >= 0)
    if h_end is None:
        h_end = float(h[ok].max()) if ok.any() else 0.0
    ok &= h <= h_end
    # the band holding h_end is the last: h_end = 0.2, width 0.025 gives 8
    # bands, not a 9th holding the deepest point alone
    n_band = max(1, int(np.ceil(h_end / width - 1e-9)))
    k = np.minimum(np.floor(h[ok] / width).astype(np.int64), n_band - 1)
    count = np.bincount(k, minlength=n_band)
    total = np.bincount(k, weights=q[ok], minlength=n_band)
    mean = np.where(count > 0, total / np.maximum(count, 1), np.nan)
    return width * np.arange(1, n_band + 1), mean, count


def mean_of_last_bands(mean, count, n=3):
    """Mean q_c over every point of the last ``n`` bands of
    :func:`qc_band_means` (each band weighted by its count); None with fewer
    than ``n`` bands or no point in them. Called by the ``fit-qc`` command
    and the chamber report."""
    mean, count = np.asarray(mean, dtype=float), np.asarray(count)
    if mean.size < n or count[-n:].sum() == 0:
        return None
    return float(np.nansum(mean[-n:] * count[-n:]) / count[-n:].sum())
