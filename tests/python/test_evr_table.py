# SPDX-License-Identifier: GPL-2.0-or-later
"""bench/error_vs_runtime/run.py: its tables (a chamber run whose q_c fit
did not level off is flagged and kept off the Pareto front, issue 11) and
its claims on pieces."""


import numpy as np
import pytest


@pytest.fixture(scope="module")
def evr(load_script):
    return load_script("bench/error_vs_runtime/run.py", "evr_run_table")


def chamber_run(name, grains, role, seed, qc, p_steps, levelled=True):
    return {"name": name, "scene": "chamber", "grains": grains, "role": role,
            "setting": {"packing_seed": seed}, "core_s": 3600.0, "particle_steps": p_steps,
            "metrics": {"qc_steady_MPa": qc, "Br_band_1_2": 0.03, "sigma_r_2R_kPa": 1600.0,
                        "qc_levelled_off": levelled}}


def study_data(cheap_levelled):
    """References of both models and seeds, one expensive variant 10 % off,
    and one cheap variant 1 % off whose push may not have levelled off: with
    it levelled, nothing beats the cheap one."""
    runs = {}
    for g, tag, qc in (("crushable_ne34", "crush", 15.0), ("unbreakable", "rigid", 16.5)):
        for name, role, seed, q, ps, lev in (
                ("ref", "reference", 2024, qc, 2e10, True),
                ("ref_seed2025", "reference_seed", 2025, 1.02 * qc, 2e10, True),
                ("X=big", "variant", 2024, 1.10 * qc, 5e10, True),
                ("X=cheap", "variant", 2024, 1.01 * qc, 1e10, cheap_levelled)):
            key = "chamber_%s_%s" % (tag, name)
            runs[key] = chamber_run(key, g, role, seed, q, ps, lev)
    return {"runs": runs}


def test_a_push_that_did_not_level_off_is_flagged_and_off_the_front(evr, tmp_path):
    for levelled in (True, False):
        data = study_data(levelled)
        rows = {r["name"]: r for r in evr.table(data)}
        cheap = rows["chamber_crush_X=cheap"]
        assert cheap["error"]["qc_steady_MPa"] == pytest.approx(0.01)
        assert cheap["qc_levelled_off"] is levelled
        assert cheap["pareto"] is levelled
        # the expensive variant is dominated by the reference (cheaper, closer)
        assert not rows["chamber_crush_X=big"]["pareto"]

        ratio = {r["setting"]: r for r in evr.qc_ratio(data)}
        assert ratio["X=cheap"]["ratio"] == pytest.approx(1.1)
        assert ratio["X=cheap"]["qc_levelled_off"] is levelled
        assert ratio["X=big"]["qc_levelled_off"]

        sp = evr.spread(data, settings=("ref", "ref_seed2025"))
        pooled = {r["name"]: r for r in sp["runs"]}
        assert pooled["chamber_rigid_X=cheap"]["pareto"] is levelled
        assert pooled["chamber_rigid_X=cheap"]["qc_levelled_off"] is levelled

        md = tmp_path / ("table_%s.md" % levelled)
        evr.write_table(list(rows.values()), str(md), str(tmp_path / "t.png"),
                        ratio_rows=list(ratio.values()), spread_rows=sp)
        lines = md.read_text().splitlines()
        flagged = [ln for ln in lines if "not levelled off" in ln]
        if levelled:
            assert flagged == []
        else:
            # both models' rows in the main table and in the pooled table, and the ratio
            assert len(flagged) == 5
            assert all("X=cheap" in ln for ln in flagged)
            assert any(ln.startswith("| chamber_crush_X=cheap |") and "| 15.15 (+1.0, not levelled off) |" in ln
                       for ln in lines)
            assert np.isfinite(cheap["core_h"])


def test_a_piece_is_claimed_by_one_live_call(evr, tmp_path, dead_pid):
    """Two calls side by side take different pieces; a killed call's claim
    (running.pid of a process that is gone) is taken over."""
    import os

    out = str(tmp_path / "piece")
    assert evr.claim(out)                        # no claim yet
    assert evr.claim(out)                        # this process's own
    with open(os.path.join(out, evr.CLAIM), "w") as f:
        f.write("%d\n" % os.getppid())           # another live call's
    assert not evr.claim(out)
    with open(os.path.join(out, evr.CLAIM), "w") as f:
        f.write("%d\n" % dead_pid)               # a killed call's
    assert evr.claim(out)
    with open(os.path.join(out, evr.CLAIM)) as f:
        assert int(f.read()) == os.getpid()
