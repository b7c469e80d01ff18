# SPDX-License-Identifier: GPL-2.0-or-later
"""Crushing during the preparation (examples/cpt_demo --crush-in-prep, deck
variable crush_in_prep; docs/cpt.md "Crushing during preparation") on
synthetic data with a known answer:

1. crushpost.pile.break_zones counts the events of the preparation in their
   own zone `prep`, never as switch-on, entry or penetration events, and the
   zones still partition the events;
2. run.py's postprocess on a synthetic run folder whose fix crush/particle
   was defined before jacking: its counters (events, fines) start the
   jacking above 0, so the preparation's breaks are counted apart
   (n_break_events_prep, break_zones "prep"), the atom count is checked
   against the breaks while jacking only, the mass balance and the fines
   fraction refer to the whole sample (grains + fines at the start of
   jacking), and an event at the jacking's first step is not a switch-on
   event (crushing was on already)."""

import argparse
import json
import math

import numpy as np
import pytest

from crushpost.pile import break_zones
from crushpost.trend import qc_trend

from conftest import write_events_file

SHOULDER = 1.0 / math.tan(math.radians(30.0))


def test_prep_events_have_their_own_zone():
    # (h/R, r/R, tip depth/R, switch_on, prep) -> zone
    events = [
        (0.5, 1.2, 6.0, False, False, "in_zone"),
        (SHOULDER, 1.1, 6.0, False, False, "along_shaft"),
        (-5.0, 0.5, 6.0, False, False, "beyond_5R_below"),
        (5.0, 6.0, 6.0, False, False, "elsewhere"),
        (0.5, 1.2, 2.0, False, False, "entry"),
        (-8.0, 5.0, 0.0, True, False, "switch_on"),
        # before jacking: prep wherever they lie and whatever switch_on says
        (-8.0, 5.0, 0.0, False, True, "prep"),          # would be entry
        (0.5, 1.2, 6.0, False, True, "prep"),           # would be in_zone
        (-3.0, 0.2, 0.0, True, True, "prep"),           # would be switch_on
    ]
    h, r, d, first, prep, zone = map(list, zip(*events))
    out = break_zones(h, r, d, first, prep=prep)
    names = ("prep", "switch_on", "entry", "in_zone", "along_shaft", "beyond_5R_below",
             "elsewhere")
    for k in names:
        assert out[k] == zone.count(k), (k, out)
    assert out["prep"] == 3 and out["switch_on"] == 1 and out["entry"] == 1
    assert out["n_events"] == 9 and out["penetration"] == 4
    assert out["fraction_in_zone"] == pytest.approx(1 / 4)
    assert sum(out[k] for k in names) == out["n_events"]
    # without prep (the default) nothing is in it, the rest as before
    out = break_zones(h[:6], r[:6], d[:6], first[:6])
    assert out["prep"] == 0 and out["switch_on"] == 1 and out["penetration"] == 4
    with pytest.raises(ValueError, match="one value per event"):
        break_zones([0.0], [1.0], [1.0], [False], prep=[True, False])


# ---------------------------------------------------------------------------
# run.py postprocess on a synthetic run folder
# ---------------------------------------------------------------------------

R = 0.018
Z_REF = 0.1
TIP_Z0 = 0.095
A, B = 4e6, 80.0
S0 = 200000            # the step jacking starts at (the first jacking thermo row)
N_PREP = 3             # breaks during the preparation
FINES_EVENT = 0.01     # fines of one break (kg)
M_SAMPLE = 1.0         # grains + fines: the packing's mass (kg)
N0 = 1000              # grains of the packing


@pytest.fixture(scope="module")
def run(load_script):
    return load_script("examples/cpt_demo/run.py", "cpt_demo_run_prep")


def _args(crush_in_prep=True):
    return argparse.Namespace(R_pile=R, mode="monotonic", grains="crushable_ne34", np=1, N=39.0,
                              R_ch=0.05, H_ch=0.07, sector=360, n_target=0.385,
                              crush_in_prep=crush_in_prep)


def _tip(step):
    return Z_REF - 0.06 * (step - S0) / 10000.0      # 0.6 mm per 100 steps


def _write_run(out, n_jack_events, atoms_missing=0, counters_from_zero=False):
    """A monotonic push to 60 mm (3.3 R) from step S0 on; N_PREP events before S0,
    one at the jacking's first step, n_jack_events - 1 later beside the cone;
    the fix's counters in the log include the preparation's breaks unless
    counters_from_zero (a fix defined at the start of jacking)."""
    area = math.pi * R ** 2
    rows = []
    for k, h in enumerate(np.linspace(0.0, 0.06, 101)[1:], 1):
        step = S0 + 100 * k
        q = qc_trend(h, A, B)
        rows.append("%d %.17g %.17g %.17g 0 %.17g 0 1 0" % (step, step * 1e-7, h, q * area,
                                                          q * area))
    step_end = S0 + 100 * 100
    (out / "jack.txt").write_text(
        "# fix jack/pile jack: mode monotonic\n# forces ...\n"
        "# z_ref %.17g m: depth = z_ref - z of the cone apex; z_ref = keyword surface\n"
        "# step time depth F_cone F_shaft F_head phase cycle v_next\n" % Z_REF
        + "\n".join(rows) + "\n")
    prep = 0 if counters_from_zero else N_PREP
    n_start = N0 + 13 * N_PREP                        # the preparation's fragments are there
    fines0 = FINES_EVENT * prep
    M_grains0 = M_SAMPLE - FINES_EVENT * N_PREP       # the grains' mass at the start of jacking
    n_total = prep + n_jack_events
    fines_end = fines0 + FINES_EVENT * n_jack_events
    log = ["Step Time Atoms f_jack[2] qc f_jack[4] f_jack[6] sv n_break fines Br M_grains",
           "%d 0 %d 0 0 0 0 150000 %d %.17g 0.001 %.17g" % (S0, n_start, prep, fines0, M_grains0),
           "%d 1 %d 0.06 %g 0 3 150000 %d %.17g 0.01 %.17g"
           % (step_end, n_start + 13 * n_jack_events - atoms_missing, A, n_total, fines_end,
              M_grains0 - FINES_EVENT * n_jack_events),
           "Loop time of 1 on 1 procs for %d steps with %d atoms" % (step_end - S0, n_start),
           "CHAMBER done",
           "CHAMBER outside 0 grains: above the top wall 0, below the bottom 0, beyond the "
           "lateral wall 0, across a symmetry plane 0"]
    (out / "log.liggghts").write_text("\n".join(log) + "\n")
    events = [(S0 - 50000 + 1000 * k, 2.5 * R, 0.0, 0.03) for k in range(N_PREP)]
    events.append((S0 + 1, 3.0 * R, 0.0, 0.02))       # the jacking's first step
    for k in range(1, n_jack_events):
        st = S0 + 8000 + 100 * k                       # tip 2.7 R deep: penetration
        events.append((st, 0.6 * R, 0.0, _tip(st) + R))
    write_events_file(out / "breakage_events.txt", events)
    return fines_end


def test_prep_breaks_are_counted_apart(tmp_path, run):
    fines_end = _write_run(tmp_path, n_jack_events=4)
    s = run.postprocess(_args(), str(tmp_path), 1.0, N0, TIP_Z0)
    assert s["failed_checks"] == [], s["failed_checks"]
    assert s["crush_in_prep"] is True
    assert s["n_break_events"] == N_PREP + 4            # the fix's count: every event
    assert s["n_break_events_prep"] == N_PREP
    assert s["n_particles_jacking_start"] == N0 + 13 * N_PREP
    assert s["n_particles_expected"] == N0 + 13 * N_PREP + 13 * 4
    assert s["n_particles_final"] == s["n_particles_expected"]
    assert s["mass_balance_rel_error"] < 1e-15
    # fines over the sample's mass (grains + fines), the preparation's included
    assert s["fines_mass_fraction"] == pytest.approx(fines_end / M_SAMPLE, rel=1e-14)
    z = s["break_zones"]
    assert z["prep"] == N_PREP and z["switch_on"] == 0     # crushing was on before
    assert z["entry"] == 1 and z["in_zone"] == 3 and z["n_events"] == N_PREP + 4
    m = np.loadtxt(tmp_path / "breakage_map.txt", ndmin=2)
    assert len(m) == s["n_break_events"]


def test_atoms_are_checked_against_the_breaks_while_jacking(tmp_path, run):
    """One atom missing is still found with the preparation's breaks in the
    counters; counting them as jacking breaks would expect 13 * N_PREP more."""
    _write_run(tmp_path, n_jack_events=4, atoms_missing=1)
    s = run.postprocess(_args(), str(tmp_path), 1.0, N0, TIP_Z0)
    assert len(s["failed_checks"]) == 1 and "n_particles_final" in s["failed_checks"][0]
    assert "while jacking (4)" in s["failed_checks"][0], s["failed_checks"]


def test_option_off_keeps_the_switch_on_zone(tmp_path, run):
    """Without the option (fix defined at the start of jacking, counters from
    0) nothing is prep, and the first step's event is a switch-on event."""
    _write_run(tmp_path, n_jack_events=4, counters_from_zero=True)
    # the fix would have written no preparation events: drop them
    ev = tmp_path / "breakage_events.txt"
    lines = ev.read_text().splitlines()
    ev.write_text("\n".join([lines[0]] + lines[1 + N_PREP:]) + "\n")
    log = tmp_path / "log.liggghts"
    text = log.read_text().replace("%d 0 %d " % (S0, N0 + 13 * N_PREP), "%d 0 %d " % (S0, N0))
    text = text.replace("%d 1 %d " % (S0 + 10000, N0 + 13 * N_PREP + 52),
                        "%d 1 %d " % (S0 + 10000, N0 + 52))
    log.write_text(text)
    s = run.postprocess(_args(crush_in_prep=False), str(tmp_path), 1.0, N0, TIP_Z0)
    assert s["n_break_events_prep"] == 0 and s["crush_in_prep"] is False
    assert s["break_zones"]["prep"] == 0 and s["break_zones"]["switch_on"] == 1
    assert s["n_particles_expected"] == N0 + 13 * 4
    assert s["failed_checks"] == [], s["failed_checks"]


def test_a_run_without_a_break_counts_zero_in_every_zone(tmp_path, run):
    """Crushable grains that never broke (an empty event log): summary.json's
    zones are measured as 0, not left out, and the in-zone fraction is null
    (undefined), so that the file stays strict JSON."""
    _write_run(tmp_path, n_jack_events=0, counters_from_zero=True)
    write_events_file(tmp_path / "breakage_events.txt", [])
    log = tmp_path / "log.liggghts"
    log.write_text(log.read_text().replace(" %d " % (N0 + 13 * N_PREP), " %d " % N0))
    s = run.postprocess(_args(crush_in_prep=False), str(tmp_path), 1.0, N0, TIP_Z0)
    assert s["failed_checks"] == [], s["failed_checks"]
    z = s["break_zones"]
    assert z["fraction_in_zone"] is None
    assert all(v == 0 for k, v in z.items() if k != "fraction_in_zone"), z
    json.loads(json.dumps(s), parse_constant=lambda c: pytest.fail("not strict JSON: " + c))
    assert "breakage_map.png" not in s["plots"]
