# SPDX-License-Identifier: GPL-2.0-or-later
"""The jacked pile: the time series of ``fix jack/pile`` (``file`` keyword),
the tip's position, and points (breakage events) located relative to the tip.

Geometry (docs/model.md §4.5, ``crushpost.meshes``): the pile axis is the
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
           "inside_pile", "event_phases", "break_zones", "events_by_zone",
           "ZONE_R_MAX", "ZONE_H_BELOW", "ZONE_DEPTH_MIN",
           "UTILISATION_ZONES", "utilisation_by_zone"]

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


#: The crushing zone of the paper's chamber (issue "Crushing where the paper
#: found it"): within ZONE_R_MAX pile radii of the axis, from ZONE_H_BELOW
#: radii below the apex up to the cone's shoulder (h = R / tan(30 deg) =
#: 1.73 R), counted once the tip is deeper than ZONE_DEPTH_MIN radii.
ZONE_R_MAX = 3.0
ZONE_H_BELOW = 5.0
ZONE_DEPTH_MIN = 2.0


def event_phases(steps, first_step, crushing_before):
    """Masks (prep, switch_on) of break events by the jacking's first step
    ``first_step`` (None: no jacking, both all False): ``prep`` the events
    before it (crushing on in the preparation, cpt_demo --crush-in-prep),
    ``switch_on`` those at it when crushing was switched on there, i.e. not
    on before (``crushing_before`` False). The inputs of :func:`break_zones`."""
    steps = np.asarray(steps)
    if first_step is None:
        none = np.zeros(steps.shape, dtype=bool)
        return none, none.copy()
    return steps < first_step, (steps == first_step) & (not crushing_before)


def break_zones(h_over_R, r_over_R, tip_depth_over_R, switch_on,
                apex_angle_deg=PILE_APEX_ANGLE_DEG, prep=None):
    """Breakage events counted by where they happen relative to the tip.

    Inputs, one per event: ``h_over_R``, ``r_over_R`` (the parent's centre
    relative to the apex at the event, :func:`relative_to_tip`),
    ``tip_depth_over_R`` (the apex's depth below the sand surface at the event,
    in R), ``switch_on`` (bool: the event is at the first step of jacking,
    when crushing is switched on: the prepared state broke the grain, not the
    pile) and, optional, ``prep`` (bool: the event happened during the
    preparation, before jacking started: crushing on in the preparation,
    examples/cpt_demo --crush-in-prep; default none). Zones, in R (shoulder =
    1 / tan(apex / 2), 1.73 for 60 degrees):

    - ``prep``: during the preparation (whatever ``switch_on`` says);
    - ``switch_on``: at the first step;
    - ``entry``: later, with the tip at most ZONE_DEPTH_MIN deep;
    - penetration (the rest), split into
      ``in_zone`` (r < ZONE_R_MAX and -ZONE_H_BELOW < h < shoulder),
      ``along_shaft`` (h >= shoulder and r < ZONE_R_MAX),
      ``beyond_5R_below`` (h <= -ZONE_H_BELOW) and
      ``elsewhere`` (r >= ZONE_R_MAX above that).

    Returns a dict of counts (int) with these keys plus ``n_events`` and
    ``penetration``, and ``fraction_in_zone`` (in_zone / penetration, NaN
    without penetration events)."""
    h = np.asarray(h_over_R, dtype=float)
    r = np.asarray(r_over_R, dtype=float)
    depth = np.asarray(tip_depth_over_R, dtype=float)
    in_prep = (np.zeros(h.shape, dtype=bool) if prep is None
               else np.asarray(prep, dtype=bool))
    if not (h.shape == r.shape == depth.shape == np.shape(switch_on) == in_prep.shape):
        raise ValueError("break_zones: h, r, tip depth, switch_on and prep need one value per "
                         "event, got shapes %s %s %s %s %s"
                         % (h.shape, r.shape, depth.shape, np.shape(switch_on), in_prep.shape))
    first = np.asarray(switch_on, dtype=bool) & ~in_prep
    shoulder = 1.0 / math.tan(math.radians(0.5 * apex_angle_deg))
    entry = ~in_prep & ~first & (depth <= ZONE_DEPTH_MIN)
    pen = ~in_prep & ~first & ~entry
    below = pen & (h <= -ZONE_H_BELOW)
    near = r < ZONE_R_MAX
    in_zone = pen & near & (h > -ZONE_H_BELOW) & (h < shoulder)
    shaft = pen & near & (h >= shoulder)
    elsewhere = pen & ~below & ~in_zone & ~shaft
    n_pen = int(pen.sum())
    return {"n_events": int(h.size), "prep": int(in_prep.sum()), "switch_on": int(first.sum()),
            "entry": int(entry.sum()),
            "penetration": n_pen, "in_zone": int(in_zone.sum()), "along_shaft": int(shaft.sum()),
            "beyond_5R_below": int(below.sum()), "elsewhere": int(elsewhere.sum()),
            "fraction_in_zone": float(in_zone.sum()) / n_pen if n_pen else float("nan")}


def events_by_zone(events, jack_step, jack_depth, z_ref, R, first_step, crushing_before=False):
    """Break events of a jacked run counted by zone (:func:`break_zones`),
    from the event log and the jack series: the one path the report and
    examples/cpt_demo share.

    ``events``: the crush log (``step``, ``x``, ``y``, ``z`` arrays,
    crushpost.dump.read_crush_log); ``jack_step``, ``jack_depth``: the
    fix jack/pile series (depth below ``z_ref`` [m]); ``R`` the pile radius
    [m]; ``first_step`` the jacking's first step (None: no jacking);
    ``crushing_before``: crushing was on before jacking (cpt_demo
    --crush-in-prep). Events before ``first_step`` also mean crushing was on
    before it, so none is then read as switch-on.

    Returns ``(zones, h_over_R, r_over_R, z_tip)``: the counts of
    :func:`break_zones` and, per event, the parent's place relative to the
    apex and the apex's z [m] at the event."""
    steps = np.asarray(events["step"])
    z_tip = tip_z_at(steps, jack_step, jack_depth, z_ref)
    hh, rr = relative_to_tip(events["x"], events["y"], events["z"], z_tip, R)
    on_before = bool(crushing_before) or (
        first_step is not None and bool(np.any(steps < first_step)))
    prep, switch_on = event_phases(steps, first_step, on_before)
    zones = break_zones(hh, rr, (z_ref - z_tip) / R, switch_on, prep=prep)
    return zones, hh, rr, z_tip


#: Zones of the utilisation census (issue "Crushing where the paper found
#: it", item 1), in R relative to the apex: (name, r_lo, r_hi, h_lo, h_hi).
UTILISATION_ZONES = (
    ("below_tip", 0.0, 1.5, -2.0, 0.0),       # under the cone's apex
    ("beside_cone", 1.0, 2.0, 0.0, 1.0 / math.tan(math.radians(30.0))),
    ("band_2_3R", 2.0, 3.0, -2.0, 1.0 / math.tan(math.radians(30.0))),
    ("far_field", 4.0, math.inf, -math.inf, math.inf),
)


def utilisation_by_zone(h_over_R, r_over_R, utilisation, zones=UTILISATION_ZONES):
    """Per zone (UTILISATION_ZONES: half-open r and h ranges, lower edge
    included) the grains' utilisation (largest F_n / F_lim over their
    contacts, compute crush/atom column 4) and its statistics.

    Returns {zone: {"n", "median", "p90", "max"}} (NaN statistics for an
    empty zone) and, under the key "values", {zone: array} of the values."""
    h = np.asarray(h_over_R, dtype=float)
    r = np.asarray(r_over_R, dtype=float)
    u = np.asarray(utilisation, dtype=float)
    if not (h.shape == r.shape == u.shape):
        raise ValueError("utilisation_by_zone: h, r and utilisation need one value per grain, "
                         "got shapes %s %s %s" % (h.shape, r.shape, u.shape))
    out, values = {}, {}
    for name, r_lo, r_hi, h_lo, h_hi in zones:
        sel = (r >= r_lo) & (r < r_hi) & (h >= h_lo) & (h < h_hi)
        v = u[sel]
        values[name] = v
        out[name] = {"n": int(v.size),
                     "median": float(np.median(v)) if v.size else float("nan"),
                     "p90": float(np.percentile(v, 90)) if v.size else float("nan"),
                     "max": float(v.max()) if v.size else float("nan")}
    out["values"] = values
    return out
