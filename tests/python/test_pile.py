# SPDX-License-Identifier: GPL-2.0-or-later
"""crushpost.pile: the jack/pile series with its depth reference, the tip
position, and points placed relative to the tip, on synthetic data with
known answers."""

import math

import numpy as np
import pytest

from crushpost.pile import (inside_pile, pile_penetration, read_jack, relative_to_tip, tip_z,
                            tip_z_at)

HEADER = """\
# fix jack/pile jack: mode cyclic, v 1 m/s, depth 0.03 m, stroke 0.01 m (absolute)
# forces on the pile from the grains, + up (resisting the push); phase 0 push ...
# z_ref 0.0987654321 m: depth = z_ref - z of the cone apex; z_ref = keyword surface
# step time depth F_cone F_shaft F_head phase cycle v_next
"""


def test_read_jack_takes_z_ref_from_the_header(tmp_path):
    p = tmp_path / "jack.txt"
    p.write_text(HEADER + "100 1e-5 0.001 5.0 1.0 6.0 0 1 -1\n200 2e-5 0.002 7.0 1.5 8.5 0 1 -1\n")
    j = read_jack(p)
    assert j["z_ref"] == 0.0987654321
    assert j["step"].dtype == np.int64 and list(j["step"]) == [100, 200]
    assert list(j["depth"]) == [0.001, 0.002] and list(j["phase"]) == [0, 0]
    assert list(j["v_next"]) == [-1.0, -1.0]
    # a file written before the reference was: no z_ref
    p.write_text("# step time depth F_cone F_shaft F_head phase cycle v_next\n"
                 "100 1e-5 0.001 5.0 1.0 6.0 0 1 -1\n")
    assert read_jack(p)["z_ref"] is None


def test_tip_position_from_the_reference():
    # depth is measured from z_ref (the sand surface), not from the initial apex
    assert tip_z(0.01, 0.095) == pytest.approx(0.085, abs=1e-15)
    js = np.array([0, 100, 200, 300])
    jd = np.array([0.0, 1e-4, 2e-4, 1.5e-4])           # push, then unload
    z = tip_z_at([50, 100, 250, 400], js, jd, 0.1)
    np.testing.assert_allclose(z, 0.1 - np.array([0.5e-4, 1e-4, 1.75e-4, 1.5e-4]), rtol=0,
                               atol=1e-15)
    with pytest.raises(ValueError):
        tip_z_at([1], [10, 5], [0.0, 1.0], 0.0)


def test_relative_to_tip_measures_r_from_the_axis():
    R = 0.018
    h, r = relative_to_tip([3 * R, 0.0, -0.6 * R], [4 * R, -2 * R, 0.8 * R],
                           [0.1 + 2 * R, 0.1, 0.1 - R], 0.1, R)
    np.testing.assert_allclose(h, [2.0, 0.0, -1.0], atol=1e-12)
    np.testing.assert_allclose(r, [5.0, 2.0, 1.0], atol=1e-12)


def test_inside_pile_cone_and_shaft():
    t = math.tan(math.radians(30.0))            # cone radius per unit height
    h_base = 1.0 / t                            # sqrt(3): cone base
    # inside: on the axis above the apex, just inside the cone face, in the shaft
    h_in = np.array([0.5, 1.0, h_base + 2.0, 10.0])
    r_in = np.array([0.0, 0.99 * t, 0.5, 0.999])
    assert np.all(inside_pile(h_in, r_in))
    # outside: below the apex, just outside the cone face, beside the shaft
    h_out = np.array([-0.1, 1.0, h_base + 2.0, 0.0])
    r_out = np.array([0.0, 1.01 * t, 1.001, 0.0])
    assert not np.any(inside_pile(h_out, r_out))
    # the penetration is the distance to the nearest surface: on the axis at
    # height h in the cone, h sin 30; deep in the shaft, 1 - r
    assert pile_penetration(1.0, 0.0) == pytest.approx(0.5, abs=1e-15)
    assert pile_penetration(20.0, 0.25) == pytest.approx(0.75, abs=1e-15)
    # a tolerance excludes points barely inside
    assert not inside_pile(10.0, 0.999, tol=0.01)
