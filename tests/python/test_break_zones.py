# SPDX-License-Identifier: GPL-2.0-or-later
"""crushpost.pile.break_zones on a synthetic event set with a known answer."""

import math

import numpy as np
import pytest

from crushpost.pile import break_zones

SHOULDER = 1.0 / math.tan(math.radians(30.0))


def test_each_event_lands_in_its_zone():
    # (h/R, r/R, tip depth/R, switch_on) -> zone
    events = [
        (0.5, 1.2, 6.0, False, "in_zone"),          # beside the cone
        (-4.9, 0.2, 6.0, False, "in_zone"),         # deep below the tip, inside the zone
        (SHOULDER - 1e-9, 2.99, 6.0, False, "in_zone"),
        (SHOULDER, 1.1, 6.0, False, "along_shaft"),  # at the shoulder: shaft
        (4.0, 2.5, 6.0, False, "along_shaft"),
        (-5.0, 0.5, 6.0, False, "beyond_5R_below"),  # on the limit: beyond
        (-9.0, 4.0, 6.0, False, "beyond_5R_below"),
        (0.0, 3.0, 6.0, False, "elsewhere"),         # r = 3R: outside
        (5.0, 6.0, 6.0, False, "elsewhere"),
        (0.5, 1.2, 2.0, False, "entry"),             # tip at 2R: not yet penetrating
        (-8.0, 5.0, 0.0, True, "switch_on"),         # first step, anywhere
        (0.5, 1.2, 6.0, True, "switch_on"),
    ]
    h, r, d, first, zone = map(list, zip(*events))
    out = break_zones(h, r, d, first)
    expect = {z: zone.count(z) for z in ("in_zone", "along_shaft", "beyond_5R_below", "elsewhere",
                                         "entry", "switch_on")}
    for k, n in expect.items():
        assert out[k] == n, (k, out)
    assert out["n_events"] == 12
    assert out["penetration"] == 9
    assert out["fraction_in_zone"] == pytest.approx(3 / 9)
    # the zones partition the events
    assert sum(out[k] for k in expect) == out["n_events"]


def test_no_penetration_gives_nan_fraction_and_bad_shapes_are_refused():
    out = break_zones([0.0], [1.0], [1.0], [False])
    assert out["entry"] == 1 and math.isnan(out["fraction_in_zone"])
    out = break_zones(np.array([]), np.array([]), np.array([]), np.array([], dtype=bool))
    assert out["n_events"] == 0
    with pytest.raises(ValueError, match="one value per event"):
        break_zones([0.0, 1.0], [1.0], [1.0], [False])


def test_utilisation_by_zone_known_answer():
    from crushpost.pile import utilisation_by_zone
    # one grain per zone, two in the far field, one outside every zone
    h = [-1.0, 0.5, 1.0, 0.0, 3.0, 10.0]
    r = [0.5, 1.5, 2.5, 5.0, 9.0, 3.5]
    u = [0.04, 0.02, 0.01, 0.001, 0.003, 0.5]
    out = utilisation_by_zone(h, r, u)
    assert out["below_tip"]["n"] == 1 and out["below_tip"]["max"] == 0.04
    assert out["beside_cone"]["median"] == 0.02
    assert out["band_2_3R"]["n"] == 1
    assert out["far_field"]["n"] == 2 and out["far_field"]["median"] == pytest.approx(0.002)
    assert out["far_field"]["max"] == 0.003
    assert sum(out[z]["n"] for z in ("below_tip", "beside_cone", "band_2_3R", "far_field")) == 5
    empty = utilisation_by_zone([], [], [])
    assert empty["below_tip"]["n"] == 0 and math.isnan(empty["below_tip"]["median"])


def test_event_phases_split_preparation_and_switch_on():
    from crushpost.pile import event_phases
    steps = [5, 9, 10, 10, 11, 30]
    prep, on = event_phases(steps, 10, crushing_before=False)
    assert prep.tolist() == [True, True, False, False, False, False]
    assert on.tolist() == [False, False, True, True, False, False]
    prep, on = event_phases(steps, 10, crushing_before=True)
    assert not on.any() and prep.sum() == 2
    prep, on = event_phases(steps, None, crushing_before=False)
    assert not prep.any() and not on.any()


def test_events_by_zone_from_log_and_jack_series():
    """The shared path of the report and cpt_demo: tip from the jack series
    (linear between rows), place relative to the apex, phases, zones."""
    from crushpost.pile import events_by_zone
    R, z_ref = 0.01, 0.5
    # the apex goes down 1 mm per 100 steps from the surface at step 100
    jack_step = np.array([100, 200, 1100])
    jack_depth = np.array([0.0, 0.001, 0.010])
    # apex z at step s (>= 100): z_ref - (s - 100) * 1e-5
    ev = {"step": np.array([100, 150, 900, 900, 900]),
          "x": np.array([0.0, 0.012, 0.015, 0.0, 0.04]),
          "y": np.array([0.0, 0.0, 0.0, 0.003, 0.0]),
          # at step 900 the apex is 0.001 + 700/900 * 0.009 = 0.008 m deep
          # (0.8 R: entry), at z = 0.492
          "z": np.array([0.45, 0.5, 0.497, 0.46, 0.49])}
    zones, hh, rr, z_tip = events_by_zone(ev, jack_step, jack_depth, z_ref, R, first_step=100)
    assert z_tip == pytest.approx([0.5, 0.4995, 0.492, 0.492, 0.492])
    assert hh == pytest.approx([-5.0, 0.05, 0.5, -3.2, -0.2])
    assert rr == pytest.approx([0.0, 1.2, 1.5, 0.3, 4.0])
    # step 100 is the first step: switch-on; the rest with the tip under 2R: entry
    assert zones["switch_on"] == 1 and zones["entry"] == 4 and zones["penetration"] == 0
    # a deeper series: the step-900 events are now during penetration
    deep = jack_depth * 4.0                      # apex 32 mm = 3.2 R deep at step 900
    zones, hh, rr, _ = events_by_zone(ev, jack_step, deep, z_ref, R, first_step=100)
    assert hh[2:] == pytest.approx([2.9, -0.8, 2.2])     # apex at 0.468 m
    assert (zones["in_zone"], zones["along_shaft"], zones["elsewhere"]) == (1, 1, 1)
    # crushing on before jacking: no switch-on, and events before the first
    # step say so by themselves
    zones, *_ = events_by_zone(ev, jack_step, deep, z_ref, R, first_step=100,
                               crushing_before=True)
    assert zones["switch_on"] == 0
    zones, *_ = events_by_zone(ev, jack_step, deep, z_ref, R, first_step=150)
    assert zones["prep"] == 1 and zones["switch_on"] == 0
