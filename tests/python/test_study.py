# SPDX-License-Identifier: GPL-2.0-or-later
"""crushpost.study (bench/error_vs_runtime) on synthetic numbers with known answers."""

import math

import numpy as np
import pytest

from crushpost import study


def test_particle_steps_follow_a_growing_count():
    # 1000 grains for 100 steps, then growing linearly to 1200 over 100 steps
    step = [0, 100, 200]
    atoms = [1000, 1000, 1200]
    assert study.particle_steps(step, atoms) == pytest.approx(1000 * 100 + 1100 * 100)
    assert study.particle_steps([5], [10]) == 0.0


def test_relative_error_and_seed_scatter():
    err = study.relative_error([11.0, 9.0, 1.0], [10.0, 10.0, 0.0])
    assert err[0] == pytest.approx(0.1) and err[1] == pytest.approx(-0.1)
    assert math.isnan(err[2])
    # two seeds 9 and 11: half range 1 over mean 10
    sc = study.seed_scatter(np.array([[9.0, 0.2], [11.0, 0.3]]))
    assert sc[0] == pytest.approx(0.1) and sc[1] == pytest.approx(0.05 / 0.25)
    assert list(study.is_noise([0.05, -0.05, 0.2, np.nan], [0.1, 0.01, 0.1, 0.1])) == \
        [True, False, False, False]


def test_replicate_spread_is_the_sample_std_over_the_mean():
    # runs 9, 10, 11 and 14: mean 11, sample variance (4 + 1 + 0 + 9) / 3
    mean, rel = study.replicate_spread(np.array([[9.0, 1.0], [10.0, np.nan], [11.0, np.nan],
                                                 [14.0, np.nan]]))
    assert mean[0] == pytest.approx(11.0)
    assert rel[0] == pytest.approx(math.sqrt(14.0 / 3.0) / 11.0)
    assert mean[1] == pytest.approx(1.0) and math.isnan(rel[1])   # one run: no spread
    m, r = study.replicate_spread([-2.0, -4.0])
    assert m == pytest.approx(-3.0) and r == pytest.approx(math.sqrt(2.0) / 3.0)


def test_pareto_front_marks_the_runs_nothing_beats():
    cost = np.array([1.0, 2.0, 3.0, 2.0, 4.0, 1.0])
    err = np.array([0.5, 0.2, 0.1, 0.3, 0.1, np.nan])
    front = study.pareto_front(cost, err)
    # run 3 is beaten by run 1 (same cost, smaller error); run 4 by run 2
    # (cheaper, same error); run 5 has no error
    assert list(front) == [True, True, True, False, False, False]
    # the sign of an error does not matter
    assert list(study.pareto_front([1.0, 2.0], [-0.5, 0.1])) == [True, True]


def test_bilinear_reproduces_a_plane_and_is_nan_outside():
    x = np.array([0.5, 1.5, 2.5])
    y = np.array([0.0, 1.0, 3.0])
    v = 2.0 * x[:, None] - 3.0 * y[None, :] + 1.0
    assert study.bilinear(v, x, y, 2.0, 0.5) == pytest.approx(2 * 2.0 - 3 * 0.5 + 1)
    assert study.bilinear(v, x, y, 1.0, 2.0) == pytest.approx(2 * 1.0 - 3 * 2.0 + 1)
    assert math.isnan(study.bilinear(v, x, y, 3.0, 0.5))


def test_band_value_picks_the_band_by_its_edges():
    edges = [0.0, 1.0, 2.0, 3.0]
    assert study.band_value(edges, [0.3, 0.2, 0.1], 1.0, 2.0) == 0.2
    assert math.isnan(study.band_value(edges, [0.3, 0.2, 0.1], 1.0, 2.5))


def test_chamber_metrics_read_back_from_a_fields_file(tmp_path):
    h5py = pytest.importorskip("h5py")
    p = tmp_path / "fields.h5"
    r_over_R = np.array([1.5, 2.5, 3.5])
    with h5py.File(p, "w") as f:
        f["states/kind"] = np.array([b"initial", b"push_end", b"pause_end"])
        f["states/qc_norm"] = np.array([np.nan, 10e6, 9e6])
        f["rings/r_over_R"] = r_over_R
        h = np.array([[-1.0, 0.0, 1.0]] * 3)            # h/R of the layers, per state
        f["rings/h_over_R"] = h
        # sigma_r = 100 kPa * r/R + 10 kPa * h/R in the push state
        sr = np.zeros((3, 3, 3))
        sr[1] = 1e5 * r_over_R[:, None] + 1e4 * h[1][None, :]
        f["rings/sigma_r"] = sr
        f["breakage/bands/band_edges_over_R"] = np.array([0.0, 1.0, 2.0, 3.0])
        f["breakage/bands/Br_band"] = np.array([[0, 0, 0], [0.3, 0.2, 0.1], [0.31, 0.21, 0.11]])
        f["qc/band_mean"] = np.array([1e6, np.nan, 14e6])
        f["qc"].attrs["band_height"] = 0.025
        f.require_group("headline").attrs["qc_last3_bands_MPa"] = 13.5
        f["headline"].attrs["n_break_events_first_step"] = 3
        # no break during penetration: counts 0, the fraction undefined
        f["headline"].attrs["events_in_zone"] = 0
        f["headline"].attrs["fraction_in_zone"] = np.nan
        f["headline"].attrs["Br_penetrated_1_2R"] = 0.0077
    summ = {"qc_steady_MPa": 12.0, "qc_fit_b": 40.0, "final_depth_m": 0.1,
            "qc_levelled_off": True, "n_break_events": 7}
    m = study.chamber_metrics(summ, str(p))
    assert m["events_in_zone"] == 0 and m["fraction_in_zone"] is None
    assert m["Br_penetrated_1_2R"] == pytest.approx(0.0077)
    assert m["sigma_r_2R_kPa"] == pytest.approx(100 * 2.0 + 10 * 0.5)
    assert m["sigma_r_2R_over_qc"] == pytest.approx(205e3 / 10e6)
    assert m["Br_band_1_2"] == pytest.approx(0.21)      # last state
    assert m["b_h"] == pytest.approx(4.0)
    assert m["qc_band_means_MPa"] == [1.0, None, 14.0] and m["qc_band_height_m"] == 0.025
    assert m["qc_last3_bands_MPa"] == 13.5 and m["n_break_events_first_step"] == 3


def test_paired_ratio_pairs_settings_run_with_both_models():
    # unbreakable runs of three settings, crushable runs of three (two shared)
    keys, ratio = study.paired_ratio(["ref", "dt_frac=0.2", "N=50"], [30.0, 33.0, 40.0],
                                     ["N=30", "ref", "dt_frac=0.2"], [10.0, 15.0, 0.0])
    assert keys == ["ref", "dt_frac=0.2"]
    assert ratio[0] == pytest.approx(2.0)
    assert math.isnan(ratio[1])          # crushable value 0: no ratio
    keys, ratio = study.paired_ratio(["a"], [1.0], ["b"], [1.0])
    assert keys == [] and ratio.size == 0


# ---------------------------------------------------------------------------
# the run-to-run scatter a single run's report quotes


def _spread_table(path, runs_crush, runs_rigid):
    """A results_table.json with the layout run.py --table writes: its
    chamber_spread from replicate_spread over the given steady q_c values."""
    import json
    models = {}
    for name, q in (("crushable_ne34", runs_crush), ("unbreakable", runs_rigid)):
        mean, rel = study.replicate_spread(np.asarray(q, float))
        models[name] = {"runs": ["r%d" % k for k in range(len(q))],
                        "mean": {"qc_steady_MPa": float(mean)},
                        "rel_std": {"qc_steady_MPa": float(rel)}}
    path.write_text(json.dumps({"chamber_spread": {"settings": [], "models": models}}))
    return path


def test_qc_run_scatter_reads_the_pooled_spread_of_the_grain_model(tmp_path):
    # crushable runs 9, 10, 11, 10: mean 10, sample sd sqrt(2/3); unbreakable 18, 22
    p = _spread_table(tmp_path / "t.json", [9.0, 10.0, 11.0, 10.0], [18.0, 22.0])
    c = study.qc_run_scatter("crushable_ne34", p)
    assert c["rel_sd"] == pytest.approx(math.sqrt(2.0 / 3.0) / 10.0, rel=1e-12)
    assert c["mean_MPa"] == pytest.approx(10.0) and len(c["runs"]) == 4
    u = study.qc_run_scatter("unbreakable", p)
    assert u["rel_sd"] == pytest.approx(math.sqrt(8.0) / 20.0, rel=1e-12)
    assert study.qc_run_scatter("glass_beads", p) is None
    assert study.qc_run_scatter("crushable_ne34", tmp_path / "absent.json") is None


def test_committed_study_table_gives_the_documented_spread():
    # docs/studies/error-vs-runtime.md "Run-to-run spread, pooled": sd 3.6 % (crushable)
    # and 4.2 % (unbreakable) in steady q_c; recomputed here from the
    # pooled runs' own records in results.json, not read back from the table
    import json
    with open(study.STUDY_TABLE) as f:
        table = json.load(f)["chamber_spread"]
    with open(study.STUDY_TABLE.replace("results_table.json", "results.json")) as f:
        runs = json.load(f)["runs"]
    for grains, doc in (("crushable_ne34", 0.036), ("unbreakable", 0.042)):
        sc = study.qc_run_scatter(grains)
        assert sc is not None and round(sc["rel_sd"], 3) == doc
        names = table["models"][grains]["runs"]
        assert len(names) == 4
        q = [runs[n]["metrics"]["qc_steady_MPa"] for n in names]
        _, rel = study.replicate_spread(np.asarray(q))
        assert sc["rel_sd"] == pytest.approx(float(rel), rel=1e-12)


def test_qc_uncertainty_says_which_dominates():
    # q_c 15 MPa with 3.6 % scatter: 0.54 MPa; against a fit s.e. of 0.2 and 0.9 MPa
    scatter, dom = study.qc_uncertainty([15.0, -15.0, 15.0, 15.0], [0.2, 0.2, 0.9, np.nan], 0.036)
    np.testing.assert_allclose(scatter, 0.54, rtol=1e-12)
    assert dom.tolist() == [True, True, False, False]
    s, d = study.qc_uncertainty(15.0, 0.54, 0.036)     # equal: the scatter does not exceed it
    assert float(s) == pytest.approx(0.54) and not bool(d)
