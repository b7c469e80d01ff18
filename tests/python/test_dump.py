# SPDX-License-Identifier: GPL-2.0-or-later
"""Text dump and crush event log readers on synthetic files."""

import gzip

import numpy as np
import pytest

from crushpost.dump import CRUSH_LOG_COLUMNS, iter_dump, read_crush_log, read_dump

DUMP = """ITEM: TIMESTEP
0
ITEM: NUMBER OF ATOMS
3
ITEM: BOX BOUNDS pp pp ff
-0.1 0.1
-0.2 0.2
0 0.5
ITEM: ATOMS id type x y z radius
3 1 0.01 0.02 0.03 0.001
1 1 -0.01 0.0 0.1 0.0015
2 2 0.0 0.0 0.2 0.002
ITEM: TIMESTEP
1000
ITEM: NUMBER OF ATOMS
2
ITEM: BOX BOUNDS xy xz yz pp pp pp
-0.1 0.1 0.01
-0.2 0.2 0.0
0 0.5 -0.02
ITEM: ATOMS id type x y z radius fx
5 1 1.0 2.0 3.0 0.004 -1e3
4 1 4.0 5.0 6.0 0.003 2.5e+2
"""


def test_read_dump(tmp_path):
    path = tmp_path / "dump.txt"
    path.write_text(DUMP)
    snaps = read_dump(path)
    assert [s["timestep"] for s in snaps] == [0, 1000]
    s0, s1 = snaps
    assert s0["n_atoms"] == 3 and s0["boundary"] == ["pp", "pp", "ff"]
    assert np.allclose(s0["box"], [[-0.1, 0.1], [-0.2, 0.2], [0, 0.5]])
    a = s0["atoms"]
    assert list(a) == ["id", "type", "x", "y", "z", "radius"]
    assert a["id"].dtype == np.int64 and a["id"].tolist() == [3, 1, 2]
    assert np.allclose(a["radius"], [0.001, 0.0015, 0.002])
    assert np.allclose(a["z"], [0.03, 0.1, 0.2])
    assert s1["box"].shape == (3, 3) and s1["box"][2, 2] == -0.02
    assert s1["boundary"] == ["pp", "pp", "pp"]
    assert np.allclose(s1["atoms"]["fx"], [-1000.0, 250.0])
    # gzip and the iterator give the same.
    gz = tmp_path / "dump.txt.gz"
    with gzip.open(gz, "wt") as fh:
        fh.write(DUMP)
    assert [s["atoms"]["x"].tolist() for s in iter_dump(gz)] == \
        [s["atoms"]["x"].tolist() for s in snaps]


def test_truncated_dump_raises(tmp_path):
    path = tmp_path / "dump.txt"
    path.write_text(DUMP[:DUMP.rindex("4 1 4.0")])
    with pytest.raises(ValueError, match="truncated"):
        read_dump(path)


CRUSH = """# step time parent_tag parent_diameter x y z F_n F_lim partner generation
200 2e-06 17 8.19e-03 0.1 0.2 0.3 150.5 150.0 particle 0

150 1.5e-06 4 3.39e-03 -0.1 0.0 0.5 90.0 89.9 wall 1
# a later comment
200 2e-06 9 8.0e-03 0.0 0.0 0.0 10 9.5 wall 0
"""


def test_read_crush_log(tmp_path):
    path = tmp_path / "crush.log"
    path.write_text(CRUSH)
    ev = read_crush_log(path)
    assert set(CRUSH_LOG_COLUMNS) < set(ev)
    # Sorted by step, stable among equal steps.
    assert ev["step"].tolist() == [150, 200, 200]
    assert ev["parent_tag"].tolist() == [4, 17, 9]
    assert ev["generation"].tolist() == [1, 0, 0]
    assert ev["partner"].tolist() == ["wall", "particle", "wall"]
    assert ev["partner_is_wall"].tolist() == [True, False, True]
    assert np.allclose(ev["F_n"], [90.0, 150.5, 10.0])
    assert np.allclose(ev["parent_diameter"], [3.39e-3, 8.19e-3, 8.0e-3])
    assert ev["time"][0] == 1.5e-6


def test_read_crush_log_energy_columns(tmp_path):
    """Files of `energy yes` carry 7 more columns; mixing is an error."""
    path = tmp_path / "crush.log"
    path.write_text("# header\n"
                    "15381 0.017 1 0.00819 0 0 0.0032 1.2e4 1.19e4 wall 0 "
                    "24.74 8.842 9.9e-07 5.2e-07 9.391 514.5 20\n")
    ev = read_crush_log(path)
    assert ev["E_el_before"].tolist() == [24.74]
    assert ev["v_max"].tolist() == [514.5]
    assert ev["n_steps"].dtype == np.int64 and ev["n_steps"].tolist() == [20]
    assert ev["partner_is_wall"].tolist() == [True]
    path.write_text(path.read_text() + "1 0.1 3 1e-3 0 0 0 1 1 wall 0\n")
    with pytest.raises(ValueError, match="expected 18 columns, got 11"):
        read_crush_log(path)


def test_crush_log_errors_and_empty(tmp_path):
    path = tmp_path / "crush.log"
    path.write_text("# only a header\n")
    ev = read_crush_log(path)
    assert ev["step"].size == 0 and ev["partner"].size == 0
    path.write_text("1 0.1 3 1e-3 0 0 0 1 1 floor 0\n")
    with pytest.raises(ValueError, match="partner"):
        read_crush_log(path)
    path.write_text("1 0.1 3 1e-3 0 0 0 1 1 wall\n")
    with pytest.raises(ValueError, match="columns"):
        read_crush_log(path)
