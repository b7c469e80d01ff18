# SPDX-License-Identifier: GPL-2.0-or-later
"""Einav (2007) relative breakage index Br from a discrete particle-size
distribution plus the fines of the breaks; the same definition as
``fix crush/particle`` (docs/fix_crush_particle.md, "Breakage index").

Grading convention (docs/model.md §2.8):

* ``F(d)`` is the cumulative mass fraction finer than ``d``; a particle of
  diameter ``d_p`` counts as finer than every ``d >= d_p`` (a sieve of
  aperture ``d`` passes it). The total mass ``M`` includes the fines.
* Fines are the mass a break does not keep in particles: the 47.61 % of the
  parent's volume that the 14 Apollonian fragments do not fill, plus any
  fragment finer than ``d_frag_min`` that was not created. How they enter
  ``F`` is ``fines_grading``:

  - ``'fractal'`` (default, as the fix): the unfilled volume of a break of a
    parent of diameter ``d`` spreads over ``[d_min, R2_RATIO d]`` (up to the
    smallest Apollonian fragment) with the shape of the limit grading,
    ``G(x) = (x^(3-w) - d_min^(3-w)) / ((R2_RATIO d)^(3-w) - d_min^(3-w))``:
    the Apollonian packing continued below its smallest resolved sphere is
    self-similar, so its sizes follow a power law, and the limit grading's own
    exponent is the natural one. Fragments not created count at their own
    diameter.
  - ``'d_min'`` (the former convention): all fines are finer than ``d_min``.

* ``B_t`` and ``B_p`` integrate over ``ln d`` on ``[d_min, d_max]``; a
  particle coarser than ``d_max`` adds nothing, one finer than ``d_min``
  counts as at ``d_min``.
* Bound: the range is cut into ``N_BINS`` log-uniform bins; in each bin the
  integral ``J_b`` of ``F`` is clipped to ``[J0_b, max(U_b, J0_b)]`` (initial
  and limit gradings) and
  ``Br = sum(clipped_b - J0_b) / sum(max(U_b, J0_b) - J0_b)``:
  0 for the initial grading, 1 for the limit grading, in [0, 1] always, and
  the unclipped Einav ratio ``(I - I0) / (I_u - I0)`` (``Br_einav``)
  whenever ``J0_b <= J_b <= U_b`` in every bin.

Units: diameters in any one length unit (the ratios matter only); masses in
any one mass unit. All integrals are dimensionless.
"""

import math
from typing import NamedTuple

import numpy as np

from .materials import OMEGA

__all__ = [
    "W_FRACTAL", "N_BINS", "R1_RATIO", "R2_RATIO", "FINES_GRADINGS", "sphere_mass",
    "psd_curve", "fractal_psd", "grading_integral", "fractal_grading_integral",
    "BreakFines", "break_fines", "bin_integrals", "limit_bin_integrals",
    "bounded_breakage_index", "Breakage", "breakage", "breakage_index",
    "CRUSH_READING_PRINTED", "GRAIN_MODELS", "grain_model_reading", "effective_reading",
]

#: Fractal dimension of the limit grading used in the calibration (docs/model.md §2.8).
W_FRACTAL = OMEGA          # crushpost.materials

#: The printed criterion reading of fix crush/particle (docs/fix_crush_particle.md
#: "Criterion readings"): the default of inputs/crushable_ne34.in's crush_reading
#: (tests/python/test_true_mass.py checks the two agree).
CRUSH_READING_PRINTED = "pressure mean force normal size_law printed scatter normal"

#: The grain models of the decks (inputs/<name>.in; the drivers' --grains
#: choices, docs/grain_models.md) -> the criterion reading the block gives fix
#: crush/particle, or None for grains that do not break. A named model sets its
#: reading itself: a driver must not pass crush_reading with it
#: (tests/python/test_true_mass.py checks the blocks say the same).
GRAIN_MODELS = {
    "crushable_ne34": CRUSH_READING_PRINTED,
    "crushable_ne34_peak": "pressure peak force normal size_law printed scatter normal",
    "crushable_ne34_peak_weibull": "pressure peak force normal size_law printed scatter weibull",
    "unbreakable": None,
}


def grain_model_reading(grains, crush_reading=CRUSH_READING_PRINTED):
    """Check a driver's --grains and --crush-reading together. Returns the
    crush_reading a deck must be given (None: leave the block's own). Raises
    ValueError naming the option when the grain model is unknown, when
    unbreakable grains are given a reading, or when a named model (one that
    sets its own reading) is given another."""
    if grains not in GRAIN_MODELS:
        raise ValueError("--grains %s: not a grain model of the decks (%s)"
                         % (grains, ", ".join(GRAIN_MODELS)))
    given = crush_reading not in (None, "", CRUSH_READING_PRINTED)
    if not given:
        return None
    if GRAIN_MODELS[grains] is None:
        raise ValueError("--crush-reading '%s' with --grains %s: unbreakable grains have no "
                         "criterion" % (crush_reading, grains))
    if GRAIN_MODELS[grains] != CRUSH_READING_PRINTED:
        raise ValueError("--crush-reading '%s' with --grains %s: this grain model sets its own "
                         "reading (%s); use --grains crushable_ne34 with --crush-reading"
                         % (crush_reading, grains, GRAIN_MODELS[grains]))
    return crush_reading


def effective_reading(grains, crush_reading=CRUSH_READING_PRINTED):
    """The criterion reading a run with --grains `grains` and --crush-reading
    `crush_reading` gives fix crush/particle (what its summary.json records):
    the reading given, else the grain model's own; None for unbreakable grains.
    Raises as grain_model_reading does."""
    return grain_model_reading(grains, crush_reading) or GRAIN_MODELS[grains]


#: Log-uniform bins of [d_min, d_max] for the bound (as the fix's kBrBins).
N_BINS = 128
#: Apollonian fragment radii over the parent radius (docs/model.md §2.6): 6 large, 8 small.
R1_RATIO = 1.0 / (1.0 + math.sqrt(2.0))
# small fragment: centre at u = r - r2 on a cube diagonal, tangent to the three
# large ones at a = r - r1 on the axes: u^2 - 2 a u / sqrt3 + a^2 = (r1 + r2)^2
# with r2 = r - u is linear in u (r = 1)
R2_RATIO = 1.0 - ((1.0 + R1_RATIO) ** 2 - (1.0 - R1_RATIO) ** 2) / (
    2.0 * (1.0 + R1_RATIO) - 2.0 * (1.0 - R1_RATIO) / math.sqrt(3.0))
FINES_GRADINGS = ("fractal", "d_min")


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


def _check_range(d_min, d_max):
    if not 0 < d_min < d_max:
        raise ValueError("need 0 < d_min < d_max")


def _check_grading(fines_grading):
    if fines_grading not in FINES_GRADINGS:
        raise ValueError("fines_grading must be 'fractal' or 'd_min', got %r" % (fines_grading,))


# --------------------------------------------------------------------------
# fines of the breaks
# --------------------------------------------------------------------------

class BreakFines(NamedTuple):
    """Fines of a list of breaks (arrays over the events, masses [mass]).

    ``lost``: volume the 14 fragments do not fill (fractal below ``d_small``);
    ``d_small``: diameter of the small fragments ``R2_RATIO d``;
    ``dropped_d``, ``dropped_m``: fragments not created (finer than
    ``d_frag_min``), one entry per fragment group (6 large or 8 small).
    """
    lost: np.ndarray
    d_small: np.ndarray
    dropped_d: np.ndarray
    dropped_m: np.ndarray

    @property
    def total(self):
        """All fines mass (what the fix counts in f_ID[3])."""
        return float(self.lost.sum() + self.dropped_m.sum())


def break_fines(parent_d, parent_m=None, density=None, d_frag_min=0.0):
    """Fines of breaks of parents of diameters ``parent_d`` (the event log's
    ``parent_diameter``) and masses ``parent_m`` (default: spheres of
    ``density``). A fragment exists when its diameter is at least
    ``d_frag_min`` (as in the fix); fines mass per event = parent mass - mass
    of the kept fragments. Returns :class:`BreakFines`.
    """
    d = np.asarray(parent_d, dtype=float).ravel()
    if parent_m is None:
        if density is None:
            raise ValueError("give the parents' masses (parent_m) or the density")
        m = sphere_mass(d, density)
    else:
        m = np.asarray(parent_m, dtype=float).ravel()
        if m.shape != d.shape:
            raise ValueError("parent_d and parent_m must have the same length")
    if np.any(d <= 0) or np.any(m < 0):
        raise ValueError("parent diameters must be > 0 and masses >= 0")
    # fragment masses from the parent's density, like the fix: m_f = rho 4/3 pi r_f^3
    rho = m / (np.pi / 6.0 * d ** 3)
    r = 0.5 * d
    m1 = 4.0 * np.pi / 3.0 * (R1_RATIO * r) ** 3 * rho
    m2 = 4.0 * np.pi / 3.0 * (R2_RATIO * r) ** 3 * rho
    lost = m - 6.0 * m1 - 8.0 * m2
    drop1 = 2.0 * (R1_RATIO * r) < d_frag_min
    drop2 = 2.0 * (R2_RATIO * r) < d_frag_min
    dropped_d = np.concatenate([2.0 * R1_RATIO * r[drop1], 2.0 * R2_RATIO * r[drop2]])
    dropped_m = np.concatenate([6.0 * m1[drop1], 8.0 * m2[drop2]])
    return BreakFines(lost, 2.0 * R2_RATIO * r, dropped_d, dropped_m)


# --------------------------------------------------------------------------
# bin integrals
# --------------------------------------------------------------------------

def _psi(z):
    """(e^z - 1 - z) / z^2, 1/2 at 0 (series where the closed form cancels)."""
    z = np.asarray(z, dtype=float)
    out = np.empty_like(z)
    small = np.abs(z) < 0.5
    zs = z[small]
    term = np.full_like(zs, 0.5)
    acc = term.copy()
    for n in range(1, 24):
        term = term * zs / (n + 2)
        acc = acc + term
    out[small] = acc
    zl = z[~small]
    out[~small] = (np.expm1(zl) - zl) / (zl * zl)
    return out


def _expm1_ratio(z):
    z = np.asarray(z, dtype=float)
    safe = np.where(z == 0.0, 1.0, z)
    return np.where(z == 0.0, 1.0, np.expm1(safe) / safe)


def _fractal_P(u, U, k):
    """int_0^u G ds of the fractal distribution on [0, U] (G = 1 beyond U);
    u (..., nb), U (..., 1)."""
    inside = u * u * _psi(k * u) / (U * _expm1_ratio(k * U))
    full = U * _psi(k * U) / _expm1_ratio(k * U) + (u - U)
    return np.where(u <= 0.0, 0.0, np.where(u >= U, full, inside))


def cell_particle_bins(cell, d, m, d_min, d_max, n_cells, n):
    """(n_cells, n) unnormalised bin integrals of point masses m at diameters
    d, summed per cell (``cell``: each particle's cell index), and the
    particle mass of each cell: J_b = (mass finer than the bin's lower edge) h
    + sum over the bin of m (u_hi - u_p), with np.bincount sums keyed by
    (cell, bin)."""
    h = math.log(d_max / d_min) / n
    below = d <= d_min
    inside = (~below) & (d < d_max)
    u = np.log(d[inside] / d_min)
    b = np.minimum((u / h).astype(np.int64), n - 1)
    t = np.clip((b + 1) * h - u, 0.0, h)
    key = cell[inside] * n + b
    mass = np.bincount(key, weights=m[inside], minlength=n_cells * n).reshape(n_cells, n)
    term = np.bincount(key, weights=m[inside] * t, minlength=n_cells * n).reshape(n_cells, n)
    finer = np.bincount(cell[below], weights=m[below], minlength=n_cells)[:, None] + \
        np.cumsum(mass, axis=1) - mass
    total = np.bincount(cell, weights=m, minlength=n_cells)
    return finer * h + term, total


def _particle_bins(d, m, d_min, d_max, n):
    """Unnormalised bin integrals of point masses m at diameters d (one cell)."""
    d, m = np.asarray(d, dtype=float), np.asarray(m, dtype=float)
    return cell_particle_bins(np.zeros(d.size, dtype=np.int64), d, m, d_min, d_max, 1, n)[0][0]


def _fractal_bins(m, d_f, d_min, d_max, w, n, chunk=4096):
    """Unnormalised bin integrals of masses m spread like the limit grading
    over [d_min, d_f] (one entry per break); d_f <= d_min: below d_min."""
    m = np.asarray(m, dtype=float).ravel()
    d_f = np.asarray(d_f, dtype=float).ravel()
    L = math.log(d_max / d_min)
    h = L / n
    out = np.zeros(n)
    k = 3.0 - w
    low = d_f <= d_min
    out += m[low].sum() * h
    m, U = m[~low], np.log(d_f[~low] / d_min)
    edges = np.arange(n + 1) * h
    for s in range(0, m.size, chunk):
        P = _fractal_P(edges[None, :], U[s:s + chunk, None], k)
        out += m[s:s + chunk] @ np.diff(P, axis=1)
    return out


def bin_integrals(d, m, d_min, d_max, fines=None, fines_grading="fractal", w=W_FRACTAL,
                  n=N_BINS, m_fines_below=0.0):
    """Normalised bin integrals ``J_b = int_bin F d(ln d)`` (n bins) of a grading.

    d, m: particle diameters and masses; fines: :class:`BreakFines` or None;
    m_fines_below: extra fines mass finer than d_min. Returns (J, M) with M
    the total mass (particles + fines). ``J.sum()`` equals the exact
    integral of F over [d_min, d_max].
    """
    _check_range(d_min, d_max)
    _check_grading(fines_grading)
    d, m, m_fines_below, _ = _as_grading(d, m, m_fines_below)
    h = math.log(d_max / d_min) / n
    J = _particle_bins(d, m, d_min, d_max, n) + m_fines_below * h
    M = m.sum() + m_fines_below
    if fines is not None:
        M += fines.total
        if fines_grading == "d_min":
            J = J + fines.total * h
        else:
            J = J + _fractal_bins(fines.lost, fines.d_small, d_min, d_max, w, n)
            J = J + _particle_bins(fines.dropped_d, fines.dropped_m, d_min, d_max, n)
    if M <= 0:
        raise ValueError("total mass must be positive")
    return J / M, M


def limit_bin_integrals(d_min, d_max, w=W_FRACTAL, n=N_BINS):
    """Analytic bin integrals ``U_b`` of the limit grading F_u."""
    _check_range(d_min, d_max)
    return _fractal_bins([1.0], [d_max], d_min, d_max, w, n)


def bounded_breakage_index(J, J0, U):
    """Br from the bin integrals of the current (J), initial (J0) and limit
    (U) gradings: each J_b clipped to [J0_b, max(U_b, J0_b)]. 0 when the
    initial grading is at or above the limit one in every bin."""
    J, J0, U = (np.asarray(a, dtype=float) for a in (J, J0, U))
    top = np.maximum(U, J0)
    num = (np.minimum(np.maximum(J, J0), top) - J0).sum()
    den = (top - J0).sum()
    return float(num / den) if den > 0 else 0.0


# --------------------------------------------------------------------------
# grading curves and unbinned integrals
# --------------------------------------------------------------------------

def psd_curve(d, m, m_fines, sizes, fines=None, fines_grading="fractal", d_min=None,
              w=W_FRACTAL):
    """Cumulative mass fraction finer than each of ``sizes``.

    Parameters
    ----------
    d : (n,) particle diameters [length].
    m : (n,) particle masses [mass].
    m_fines : mass of fines without a size [mass]; finer than every size.
    sizes : sieve sizes [length], any shape.
    fines : :class:`BreakFines` of the breaks (optional). With
        ``fines_grading='fractal'`` their unfilled volume is spread like the
        limit grading over ``[d_min, d_small]`` (needs ``d_min``) and the
        fragments not created count at their size; with ``'d_min'`` they are
        finer than every size.

    Returns
    -------
    F : array shaped like ``sizes``, in [0, 1]: mass finer than the size over
        the total mass (particles + all fines).
    """
    d, m, m_fines, total = _as_grading(d, m, m_fines)
    _check_grading(fines_grading)
    sizes = np.asarray(sizes, dtype=float)
    if fines is not None and fines_grading == "fractal":
        d = np.concatenate([d, fines.dropped_d])
        m = np.concatenate([m, fines.dropped_m])
    order = np.argsort(d, kind="stable")
    cum = np.concatenate([[0.0], np.cumsum(m[order])])
    # side='right' puts d_p == size on the finer side (right-continuous F).
    finer = m_fines + cum[np.searchsorted(d[order], sizes, side="right")]
    if fines is not None:
        total += fines.total
        if fines_grading == "d_min":
            finer = finer + fines.total
        else:
            if d_min is None:
                raise ValueError("fractal fines need d_min")
            finer = finer + _fractal_finer(fines.lost, fines.d_small, d_min, sizes, w)
    return finer / total


def _fractal_finer(m, d_f, d_min, sizes, w, chunk=4096):
    """Mass of the fractal fines finer than each size (sizes any shape)."""
    flat = np.asarray(sizes, dtype=float).ravel()
    out = np.zeros(flat.size)
    k = 3.0 - w
    u = np.log(np.maximum(flat, d_min) / d_min)
    low = d_f <= d_min
    out += m[low].sum()
    m, U = m[~low], np.log(d_f[~low] / d_min)
    for s in range(0, m.size, chunk):
        Uc = U[s:s + chunk, None]
        uc = np.minimum(u[None, :], Uc)
        G = uc * _expm1_ratio(k * uc) / (Uc * _expm1_ratio(k * Uc))
        out += m[s:s + chunk] @ G
    return out.reshape(np.shape(sizes))


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
    """Exact ``I = integral of F(d) d(ln d)`` over ``[d_min, d_max]`` for a step
    grading whose fines ``m_fines`` are all finer than ``d_min``.

    Parameters as in :func:`psd_curve`; ``d_min < d_max`` in the same length
    unit as ``d``. Returns a dimensionless float in ``[0, ln(d_max/d_min)]``.
    """
    _check_range(d_min, d_max)
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
    _check_range(d_min, d_max)
    big_l = math.log(d_max / d_min)
    x = (3.0 - w) * big_l
    return float(big_l * _psi(np.array([x]))[0] / _expm1_ratio(np.array([x]))[0])


# --------------------------------------------------------------------------
# breakage index
# --------------------------------------------------------------------------

class Breakage(NamedTuple):
    """Relative breakage (dimensionless).

    ``Br``: bounded to [0, 1] (the fix's f_ID[5]); ``B_t = I - I_0`` and
    ``B_p = I_u - I_0``: Einav's unclipped parts; ``Br_einav = B_t / B_p``
    (the fix's f_ID[8], can leave [0, 1]).
    """
    Br: float
    B_t: float
    B_p: float
    Br_einav: float


def breakage(d, m, d_initial, m_initial, d_min, d_max, m_fines=0.0,
             m_fines_initial=0.0, w=W_FRACTAL, fines=None, fines_grading="fractal",
             n=N_BINS):
    """Einav breakage of the current grading relative to the initial one.

    Parameters
    ----------
    d, m : current particle diameters [length] and masses [mass].
    d_initial, m_initial : initial diameters and masses.
    d_min, d_max : integration range [length] (they scale with the
        up-scaling factor N of the scene).
    m_fines : fines mass without a size (finer than d_min) [mass]; for fines
        from breaks give ``fines`` instead, so their sizes are known.
    m_fines_initial : initial fines mass (finer than d_min) [mass].
    w : fractal dimension of the limit grading (2.6 in the calibration).
    fines : :class:`BreakFines` of all breaks so far (see :func:`break_fines`).
    fines_grading : 'fractal' (default, as the fix) or 'd_min'; how
        ``fines`` enter F (module doc).
    n : number of bins of the bound (N_BINS as in the fix).

    Returns
    -------
    Breakage(Br, B_t, B_p, Br_einav).
    """
    J, _ = bin_integrals(d, m, d_min, d_max, fines, fines_grading, w, n, m_fines)
    J0, _ = bin_integrals(d_initial, m_initial, d_min, d_max, None, fines_grading, w, n,
                          m_fines_initial)
    U = limit_bin_integrals(d_min, d_max, w, n)
    i0 = J0.sum()
    b_t = J.sum() - i0
    b_p = fractal_grading_integral(d_min, d_max, w) - i0
    if b_p <= 0:
        raise ValueError("initial grading is already at or beyond the limit grading (B_p <= 0)")
    return Breakage(bounded_breakage_index(J, J0, U), b_t, b_p, b_t / b_p)


def breakage_index(d, m, d_initial, m_initial, d_min, d_max, m_fines=0.0,
                   m_fines_initial=0.0, w=W_FRACTAL, fines=None, fines_grading="fractal",
                   n=N_BINS):
    """``Br`` (bounded) only; see :func:`breakage` for the parameters."""
    return breakage(d, m, d_initial, m_initial, d_min, d_max, m_fines, m_fines_initial, w,
                    fines, fines_grading, n).Br
