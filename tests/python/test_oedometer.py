# SPDX-License-Identifier: GPL-2.0-or-later
"""crushpost.oedometer.crushing_onset on synthetic loading paths."""

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
