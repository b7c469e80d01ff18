"""The jacked pile: the time series of ``fix jack/pile`` (``file`` keyword),
the tip's position, and points (breakage events) located relative to the tip.

Geometry (SPEC section 4 item 5, ``crushpost.meshes``): the pile axis is the
z axis (x = y = 0, in every chamber sector), the cone's apex points down and
has a full apex angle of 60 degrees, base radius R; the shaft (radius R)
continues above the cone's base. ``h`` is the height above the apex, ``r``
the distance from the pile axis.

The depth in the series is measured from the fix's depth reference ``z_ref``
(the ``surface`` keyword, or the apex's z at the first run): the apex is at
``z = z_ref - depth``. The fix writes ``z_ref`` into the file's header
(``# z_ref <value> m ...``); :func:`read_jack` returns it.
"""

import math
import re

import numpy as np

from .meshes import PILE_APEX_ANGLE_DEG

__all__ = ["JACK_COLUMNS", "PHASE_PUSH", "PHASE_UNLOAD", "PHASE_PAUSE", "PHASE_DONE",
           "read_jack", "tip_z", "tip_z_at", "relative_to_tip", "pile_penetration",
           "inside_pile"]

#: Columns of the fix jack/pile time series, in file order.
JACK_COLUMNS = ("step", "time", "depth", "F_cone", "F_shaft", "F_head", "phase", "cycle",
                "v_next")
PHASE_PUSH, PHASE_UNLOAD, PHASE_PAUSE, PHASE_DONE = 0, 1, 2, 3

_Z_REF = re.compile(r"^#\s*z_ref\s+(\S+)\s+m\b")


def read_jack(path):
    """Read a ``fix jack/pile`` time series.

    Returns a dict of (n,) float arrays keyed by :data:`JACK_COLUMNS` (as many
    as the file has; ``step``, ``phase`` and ``cycle`` as int64), plus
    ``z_ref``: the depth reference [m] from the header, or None when the file
    has none (written before the fix wrote it; then the tip's position is not
    known from the file alone).
    """
    z_ref = None
    with open(path) as fh:
        for line in fh:
            if not line.startswith("#"):
                if line.strip():
                    break
                continue
            m = _Z_REF.match(line)
            if m:
                z_ref = float(m.group(1))
    data = np.loadtxt(path, comments="#", ndmin=2)
    if data.shape[1] < 3:
        raise ValueError("%s: a fix jack/pile series has at least step, time and depth "
                         "columns, got %d" % (path, data.shape[1]))
    out = {}
    for k, name in enumerate(JACK_COLUMNS[:data.shape[1]]):
        col = data[:, k]
        out[name] = col.astype(np.int64) if name in ("step", "phase", "cycle") else col
    out["z_ref"] = z_ref
    return out


def tip_z(depth, z_ref):
    """z of the cone apex [m] for tip depths ``depth`` [m] below ``z_ref``."""
    return z_ref - np.asarray(depth, dtype=float)


def tip_z_at(step, jack_step, jack_depth, z_ref):
    """z of the apex at the (integer) steps ``step``, linear between the rows
    of the series (``jack_step`` increasing): exact while the pile moves at a
    constant velocity between two rows. Steps outside the series take the
    nearest row's value."""
    js = np.asarray(jack_step, dtype=float)
    if js.ndim != 1 or js.size == 0 or np.any(np.diff(js) < 0):
        raise ValueError("jack_step must be a non-empty increasing 1-D array")
    return tip_z(np.interp(np.asarray(step, dtype=float), js,
                           np.asarray(jack_depth, dtype=float)), z_ref)


def relative_to_tip(x, y, z, z_tip, R):
    """Positions (x, y, z) [m] relative to the apex at ``z_tip`` [m] (one per
    point, or one for all): returns ``(h / R, r / R)`` with ``h = z - z_tip``
    the height above the apex and ``r`` the distance from the pile axis
    (x = y = 0)."""
    h = (np.asarray(z, dtype=float) - z_tip) / R
    r = np.hypot(np.asarray(x, dtype=float), np.asarray(y, dtype=float)) / R
    return h, r


def pile_penetration(h_over_R, r_over_R, apex_angle_deg=PILE_APEX_ANGLE_DEG):
    """How far inside the (circular) pile each point lies, in units of R:
    the distance to the nearest of the cone's and the shaft's surfaces for a
    point inside (> 0), a negative number for a point outside (not a
    distance; only its sign matters). The pile is the convex solid
    ``r <= R`` and ``r <= h tan(apex / 2)``; the shaft is unbounded above."""
    h = np.asarray(h_over_R, dtype=float)
    r = np.asarray(r_over_R, dtype=float)
    half = math.radians(0.5 * apex_angle_deg)
    to_cone = h * math.sin(half) - r * math.cos(half)
    to_shaft = 1.0 - r
    return np.minimum(to_cone, to_shaft)


def inside_pile(h_over_R, r_over_R, tol=0.0, apex_angle_deg=PILE_APEX_ANGLE_DEG):
    """True where a point lies inside the pile by more than ``tol`` (in R)."""
    return pile_penetration(h_over_R, r_over_R, apex_angle_deg) > tol
