# SPDX-License-Identifier: GPL-2.0-or-later
"""examples/cpt_demo/run.py postprocess() on a synthetic run folder: events
placed relative to the real tip (z_ref - depth, z_ref = the sand surface
from jack.txt's header, not the initial apex), the q_c fit on virgin
penetration, and the checks that make the demo exit non-zero (grains
outside the chamber, mass balance above 1e-12, atoms missing against the
breaks, events inside the pile)."""

import argparse
import json
import math

import numpy as np
import pytest

from crushpost.trend import qc_trend

from conftest import write_events_file

R = 0.018
Z_REF = 0.1            # sand surface at the start of jacking
TIP_Z0 = 0.095         # initial apex (the top wall's first height): NOT the depth reference
A, B = 4e6, 80.0


@pytest.fixture(scope="module")
def run(load_script):
    return load_script("examples/cpt_demo/run.py", "cpt_demo_run")


def _args():
    return argparse.Namespace(R_pile=R, mode="cyclic", grains="crushable_ne34", np=2, N=39.0,
                              R_ch=0.05, H_ch=0.07, sector=360, n_target=0.385)


def _write_run(out, M_end_rel=0.0, n_outside=0, events=None, atoms_missing=0):
    """jack.txt (push to 10 mm, unload, re-push to 20 mm), log.liggghts (one
    jacking thermo block, the outside count), breakage_events.txt."""
    area = math.pi * R ** 2
    rows, step = [], 0

    def row(d, q, phase, cycle):
        nonlocal step
        step += 100
        rows.append("%d %.17g %.17g %.17g 0 %.17g %d %d 0" % (step, step * 1e-7, d, q * area,
                                                             q * area, phase, cycle))

    for h in np.linspace(0.0, 0.01, 51)[1:]:
        row(h, qc_trend(h, A, B), 0, 1)
    row(0.009, 0.0, 1, 1)
    row(0.009, 0.0, 2, 1)
    for h in np.linspace(0.009, 0.01, 6)[1:-1]:
        row(h, 0.5 * qc_trend(0.01, A, B), 0, 2)          # re-push: low q_c
    for h in np.linspace(0.01, 0.02, 51)[1:]:
        row(h, qc_trend(h, A, B), 0, 2)
    (out / "jack.txt").write_text(
        "# fix jack/pile jack: mode cyclic\n# forces ...\n"
        "# z_ref %.17g m: depth = z_ref - z of the cone apex; z_ref = keyword surface\n"
        "# step time depth F_cone F_shaft F_head phase cycle v_next\n" % Z_REF
        + "\n".join(rows) + "\n")
    events = events or []
    n_break = len(events)
    M0, fines = 1.0, 0.01 * n_break
    n0 = 1000
    log = ["Step Time Atoms f_jack[2] qc f_jack[4] f_jack[6] sv n_break fines Br M_grains",
           "0 0 %d 0 0 0 0 150000 0 0 0 %.17g" % (n0, M0),
           "%d 1 %d 0.02 %g 0 3 150000 %d %.17g 0.01 %.17g"
           % (step, n0 + 13 * n_break - atoms_missing, A, n_break, fines,
              M0 - fines + M_end_rel * M0),
           "Loop time of 1 on 2 procs for %d steps with %d atoms" % (step, n0),
           "CHAMBER done",
           "CHAMBER outside %d grains: above the top wall %d, below the bottom 0, beyond the "
           "lateral wall 0, across a symmetry plane 0" % (n_outside, n_outside)]
    (out / "log.liggghts").write_text("\n".join(log) + "\n")
    write_events_file(out / "breakage_events.txt", events)
    return n0


def _tip(step):
    # the series' tip at a step of the first push: depth 0.2 mm per 100 steps
    return Z_REF - 0.01 * step / 5000.0


def test_events_are_placed_relative_to_the_real_tip(tmp_path, run):
    # beside the cone face at (h, r) = (R, 0.6 R) (just outside it: the cone's
    # radius there is R tan 30 = 0.577 R), and 0.3 R below the apex; measured
    # from TIP_Z0 - depth the first would lie inside the cone
    events = [(2500, 0.6 * R, 0.0, _tip(2500) + R), (3000, 0.0, -0.1 * R, _tip(3000) - 0.3 * R)]
    n0 = _write_run(tmp_path, events=events)
    s = run.postprocess(_args(), str(tmp_path), 1.0, n0, TIP_Z0)
    m = np.loadtxt(tmp_path / "breakage_map.txt", ndmin=2)
    np.testing.assert_allclose(m[:, 1], [1.0, -0.3], atol=1e-9)      # h / R
    np.testing.assert_allclose(m[:, 2], [0.6, 0.1], atol=1e-9)       # r / R
    np.testing.assert_allclose(m[:, 3], [5.0, 6.0], atol=1e-9)       # tip depth, mm
    assert s["n_events_inside_pile"] == 0 and s["failed_checks"] == []
    assert s["sand_surface_z_m"] == Z_REF
    # the q_c fit takes virgin penetration only: the low re-push is left out
    assert s["qc_steady_MPa"] == pytest.approx(A / 1e6, rel=1e-6)
    assert s["qc_fit_b"] == pytest.approx(B, rel=1e-6)
    assert s["qc_fit_excluded_repush_points"] == 4
    assert s["n_grains_outside"] == 0
    assert json.loads((tmp_path / "summary.json").read_text())["failed_checks"] == []


@pytest.mark.parametrize("case, words", [
    ({"M_end_rel": 2e-12}, "mass_balance_rel_error"),
    ({"n_outside": 1}, "n_grains_outside = 1"),
    ({"atoms_missing": 1}, "n_particles_final"),
    ({"inside": True}, "n_events_inside_pile = 1"),
])
def test_failed_checks(tmp_path, case, words, run):
    events = [(2500, 1.5 * R, 0.0, _tip(2500) + R)]
    if case.pop("inside", False):
        events.append((2500, 0.2 * R, 0.0, _tip(2500) + R))      # on the cone's axis side
    n0 = _write_run(tmp_path, events=events, **case)
    s = run.postprocess(_args(), str(tmp_path), 1.0, n0, TIP_Z0)
    assert len(s["failed_checks"]) == 1 and words in s["failed_checks"][0], s["failed_checks"]


def test_missing_outside_count_fails(tmp_path, run):
    n0 = _write_run(tmp_path)
    log = (tmp_path / "log.liggghts").read_text().replace("CHAMBER outside", "CHAMBER gone")
    (tmp_path / "log.liggghts").write_text(log)
    s = run.postprocess(_args(), str(tmp_path), 1.0, n0, TIP_Z0)
    assert s["n_grains_outside"] is None and "CHAMBER outside" in s["failed_checks"][0]
