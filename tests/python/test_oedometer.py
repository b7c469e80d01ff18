# SPDX-License-Identifier: GPL-2.0-or-later
"""crushpost.oedometer: crushing_onset, loading_state_at and loading_curve on synthetic loading paths."""

import json
import math

import numpy as np
import pytest

from crushpost import oedometer


def _path(sv, nb, phase=None):
    sv = np.asarray(sv, float)
    return {"sv": sv, "n_break": np.asarray(nb, float),
            "phase": np.zeros(sv.size, int) if phase is None else np.asarray(phase)}


def test_onset_is_where_one_percent_of_the_grains_have_broken():
    # 500 grains: 1 % = 5 events; the count passes 5 at sv = 3 MPa
    sv = [0.1e6, 0.5e6, 1e6, 2e6, 3e6, 4e6]
    nb = [0, 1, 2, 4, 5, 9]
    onset, first = oedometer.crushing_onset(_path(sv, nb), 500)
    assert onset == 3e6
    assert first == 0.5e6


def test_onset_uses_the_loading_branch_only_and_nan_when_not_reached():
    sv = [1e6, 2e6, 3e6, 2e6, 1e6]
    nb = [0, 0, 1, 9, 9]            # counts reached on unloading do not count
    onset, first = oedometer.crushing_onset(_path(sv, nb, [0, 0, 0, 1, 1]), 500)
    assert math.isnan(onset)
    assert first == 3e6
    onset, first = oedometer.crushing_onset(_path(sv, [0] * 5, [0, 0, 0, 1, 1]), 500)
    assert math.isnan(onset) and math.isnan(first)


def test_onset_needs_at_least_one_event():
    # 50 grains: 1 % is half an event; one event is the least that counts
    onset, _ = oedometer.crushing_onset(_path([1e6, 2e6], [0, 1]), 50)
    assert onset == 2e6
    with pytest.raises(KeyError):
        oedometer.crushing_onset({"sv": [1.0]}, 10)


def test_onset_is_the_largest_stress_carried_so_far():
    # the stress dips when grains break: the onset is the largest sigma_v
    # carried up to the event that completes 1 %, never below the first break's
    sv = [0.5e6, 0.3e6, 0.8e6, 0.6e6, 1.5e6]
    nb = [1, 2, 3, 5, 6]
    onset, first = oedometer.crushing_onset(_path(sv, nb), 500)
    assert first == 0.5e6
    assert onset == 0.8e6


def test_loading_state_at_interpolates_in_stress_on_the_first_crossing():
    # e falls linearly in sv from 0.6 at 5 MPa to 0.4 at 15 MPa; a break
    # relaxes sv to 9 MPa after 12 MPa (running maximum: no second crossing
    # of 10 MPa); unloading (phase 1) never counts
    sv = [5e6, 12e6, 9e6, 15e6, 35e6, 20e6]
    e = [0.6, 0.46, 0.45, 0.4, 0.3, 0.31]
    path = {"sv": np.array(sv), "e_void": np.array(e), "phase": np.array([0, 0, 0, 0, 0, 1])}
    got = oedometer.loading_state_at(path, [10e6, 30e6, 40e6, 1e6])
    # 10 MPa: between 5 (0.6) and 12 MPa (0.46): 0.6 - 0.14 * 5/7
    assert got[0] == pytest.approx(0.6 - 0.14 * 5.0 / 7.0, rel=1e-12)
    # 30 MPa: between 15 (0.4) and 35 MPa (0.3)
    assert got[1] == pytest.approx(0.4 - 0.1 * 15.0 / 20.0, rel=1e-12)
    assert math.isnan(got[2])        # never reached on loading
    assert math.isnan(got[3])        # below the first line


def test_loading_curve_samples_the_loading_branch_on_a_log_grid():
    # e_core falls linearly in log10(sv) from 0.7 at 0.1 MPa to 0.4 at 100 MPa
    # (dense thermo lines, so linear interpolation in sv is exact only at the
    # lines: compare at 1e-3); Br rises in sv; unloading lines never count;
    # a column the log lacks gives None throughout
    sv = np.geomspace(0.1e6, 100e6, 3001)
    e = 0.7 - 0.1 * np.log10(sv / 0.1e6)
    path = {"sv": np.r_[sv, 50e6], "e_core": np.r_[e, 0.9], "Br": np.r_[sv / 100e6, 0.0],
            "phase": np.r_[np.zeros(sv.size, int), 1]}
    c = oedometer.loading_curve(path, keys=("e_core", "Br", "e_void"))
    s = np.array(c["sigma_v_MPa"])
    # three decades at CURVE_POINTS_PER_DECADE points, both ends included
    assert s.size == 3 * oedometer.CURVE_POINTS_PER_DECADE + 1
    assert s[0] == pytest.approx(0.1) and s[-1] == pytest.approx(100.0)
    assert np.allclose(np.diff(np.log10(s)), 1.0 / oedometer.CURVE_POINTS_PER_DECADE)
    want = 0.7 - 0.1 * np.log10(s / 0.1)
    got = np.array(c["e_core"][1:], float)   # the first point is the first line: NaN by design
    assert c["e_core"][0] is None
    assert np.allclose(got, want[1:], atol=1e-3)
    assert np.allclose(np.array(c["Br"][1:], float), s[1:] / 100.0, rtol=1e-9)
    assert c["e_void"] == [None] * s.size
    json.dumps(c)                             # a summary's field: plain JSON


def test_hdf5_keeps_a_null_attribute_as_json(tmp_path):
    # summary.json's crush_reading is null for unbreakable grains, and a
    # nested value (loading_curve) is a JSON string
    h5py = pytest.importorskip("h5py")
    path = {"sv": np.array([1e6, 2e6]), "phase": np.array([0, 0])}
    f = tmp_path / "o.h5"
    oedometer.write_hdf5(str(f), path, attrs={"crush_reading": None, "N": 39.0,
                                              "loading_curve": {"sigma_v_MPa": [1.0]}})
    with h5py.File(str(f), "r") as h:
        assert json.loads(h.attrs["crush_reading"]) is None
        assert json.loads(h.attrs["loading_curve"]) == {"sigma_v_MPa": [1.0]}
        assert h.attrs["N"] == 39.0
        np.testing.assert_array_equal(h["path/sv"][()], path["sv"])
