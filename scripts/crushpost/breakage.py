"""Einav (2007) relative breakage index from a discrete particle-size distribution.

Grading convention (documented choice, SPEC section 2):

* ``F(d)`` is the cumulative mass fraction finer than ``d``; a particle of
  diameter ``d_p`` counts as finer than every ``d >= d_p`` (a sieve of
  aperture ``d`` passes it), so ``F`` is a right-continuous step function.
* Fines (the 47.61 % of a parent's volume that the 14 Apollonian fragments do
  not fill) have no resolved size: they count as finer than every size, i.e.
  they sit below ``d_min``. They enter both the numerator of ``F`` and the
  total mass ``M = sum m_p + m_fines``.
* ``B_t`` and ``B_p`` integrate over ``ln d`` on ``[d_min, d_max]``; sizes
  outside are clipped to that range (a particle coarser than ``d_max`` adds
  nothing, one finer than ``d_min`` counts like fines).

With these rules the integral of a step grading is exact:
``I = (1/M) [ sum_p m_p ln(d_max / clip(d_p)) + m_fines ln(d_max / d_min) ]``
and ``Br = (I - I_0) / (I_u - I_0)``.

Units: diameters in any one length unit (the ratios matter only); masses in
any one mass unit. All integrals are dimensionless.
"""

from typing import NamedTuple

import numpy as np

__all__ = [
    "W_FRACTAL", "sphere_mass", "psd_curve", "fractal_psd",
    "grading_integral", "fractal_grading_integral", "Breakage", "breakage",
    "breakage_index",
]

#: Fractal dimension of the limit grading used in the calibration (SPEC 2).
W_FRACTAL = 2.6


def sphere_mass(d, density):
    """Mass [kg] of spheres of diameter ``d`` [m] and ``density`` [kg/m^3]."""
    d = np.asarray(d, dtype=float)
    return density * np.pi / 6.0 * d ** 3


def _as_grading(d, m, m_fines):
    d = np.asarray(d, dtype=float).ravel()
    m = np.asarray(m, dtype=float).ravel()
    if d.shape != m.shape:
        raise ValueError("d and m must have the same length (%d != %d)" % (d.size, m.size))
    if np.any(d <= 0) or np.any(m < 0) or m_fines < 0:
        raise ValueError("diameters must be > 0 and masses >= 0")
    total = m.sum() + float(m_fines)
    if total <= 0:
        raise ValueError("total mass must be positive")
    return d, m, float(m_fines), total


def psd_curve(d, m, m_fines, sizes):
    """Cumulative mass fraction finer than each of ``sizes``.

    Parameters
    ----------
    d : (n,) particle diameters [length].
    m : (n,) particle masses [mass].
    m_fines : mass of unresolved fines [mass]; finer than every size.
    sizes : sieve sizes [length], any shape.

    Returns
    -------
    F : array shaped like ``sizes``, in [0, 1]:
        ``(m_fines + sum of m_p with d_p <= size) / (sum m_p + m_fines)``.
    """
    d, m, m_fines, total = _as_grading(d, m, m_fines)
    sizes = np.asarray(sizes, dtype=float)
    order = np.argsort(d, kind="stable")
    cum = np.concatenate([[0.0], np.cumsum(m[order])])
    # side='right' puts d_p == size on the finer side (right-continuous F).
    k = np.searchsorted(d[order], sizes, side="right")
    return (m_fines + cum[k]) / total


def fractal_psd(sizes, d_min, d_max, w=W_FRACTAL):
    """Limit (fractal) grading ``F_u(d) = (d^(3-w) - d_min^(3-w)) / (d_max^(3-w) - d_min^(3-w))``.

    Clipped to 0 below ``d_min`` and 1 above ``d_max``; ``w = 3`` gives the
    limit ``ln(d/d_min) / ln(d_max/d_min)``. Sizes in one length unit.
    """
    sizes = np.clip(np.asarray(sizes, dtype=float), d_min, d_max)
    k = 3.0 - w
    big_l = np.log(d_max / d_min)
    x = np.log(sizes / d_min)
    if abs(k * big_l) < 1e-12:
        return x / big_l
    # expm1 keeps accuracy when k is small but not zero.
    return np.expm1(k * x) / np.expm1(k * big_l)


def grading_integral(d, m, m_fines, d_min, d_max):
    """Exact ``I = integral of F(d) d(ln d)`` over ``[d_min, d_max]`` for a step grading.

    Parameters as in :func:`psd_curve`; ``d_min < d_max`` in the same length
    unit as ``d``. Returns a dimensionless float in ``[0, ln(d_max/d_min)]``.
    """
    if not 0 < d_min < d_max:
        raise ValueError("need 0 < d_min < d_max")
    d, m, m_fines, total = _as_grading(d, m, m_fines)
    # Each particle raises F by m_p/M from clip(d_p) up to d_max.
    s = np.dot(m, np.log(d_max / np.clip(d, d_min, d_max)))
    return (s + m_fines * np.log(d_max / d_min)) / total


def fractal_grading_integral(d_min, d_max, w=W_FRACTAL):
    """Analytic ``I_u = integral of F_u(d) d(ln d)`` over ``[d_min, d_max]``.

    With ``k = 3 - w``, ``L = ln(d_max/d_min)`` and ``x = k L``:
    ``I_u = L (1/x - 1/(e^x - 1))``, which tends to ``L/2`` as ``w -> 3``.
    Dimensionless.
    """
    if not 0 < d_min < d_max:
        raise ValueError("need 0 < d_min < d_max")
    big_l = np.log(d_max / d_min)
    x = (3.0 - w) * big_l
    if abs(x) < 1e-4:
        # Series of 1/x - 1/(e^x - 1); the closed form cancels badly here.
        return big_l * (0.5 - x / 12.0 + x ** 3 / 720.0)
    return big_l * (1.0 / x - 1.0 / np.expm1(x))


class Breakage(NamedTuple):
    """Relative breakage ``Br = B_t / B_p`` with its two parts (dimensionless)."""
    Br: float
    B_t: float
    B_p: float


def breakage(d, m, d_initial, m_initial, d_min, d_max, m_fines=0.0,
             m_fines_initial=0.0, w=W_FRACTAL):
    """Einav breakage of the current grading relative to the initial one.

    Parameters
    ----------
    d, m : current particle diameters [length] and masses [mass].
    d_initial, m_initial : initial diameters and masses.
    d_min, d_max : integration range [length] (they scale with the
        up-scaling factor N of the scene).
    m_fines, m_fines_initial : unresolved fines mass now and initially [mass].
    w : fractal dimension of the limit grading (2.6 in the calibration).

    Returns
    -------
    Breakage(Br, B_t, B_p) where ``B_t = I - I_0`` and ``B_p = I_u - I_0``.
    """
    i0 = grading_integral(d_initial, m_initial, m_fines_initial, d_min, d_max)
    i_now = grading_integral(d, m, m_fines, d_min, d_max)
    i_u = fractal_grading_integral(d_min, d_max, w)
    b_t = i_now - i0
    b_p = i_u - i0
    if b_p <= 0:
        raise ValueError("initial grading is already at or beyond the limit grading (B_p <= 0)")
    return Breakage(b_t / b_p, b_t, b_p)


def breakage_index(d, m, d_initial, m_initial, d_min, d_max, m_fines=0.0,
                   m_fines_initial=0.0, w=W_FRACTAL):
    """``Br`` only; see :func:`breakage` for the parameters."""
    return breakage(d, m, d_initial, m_initial, d_min, d_max, m_fines,
                    m_fines_initial, w).Br
