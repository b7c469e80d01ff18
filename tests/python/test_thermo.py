# SPDX-License-Identifier: GPL-2.0-or-later
"""Thermo blocks of a synthetic LIGGGHTS log with warnings and several runs."""

import numpy as np
import pytest

from crushpost.thermo import concat_blocks, parse_log, read_log, summarize

LOG = """LIGGGHTS (Version LIGGGHTS-PUBLIC 3.8.0, with the crushable-grain package)
Created 2 atoms
Setting up run at Mon Nov 23 00:32:17 2026

Memory usage per processor = 7.13336 Mbytes
    Step    Atoms         KinEng          c_qc 
       0        2              0          0.5 
      10        2        1.5e-05        0.75 
WARNING: Particle-wall contact lost (../fix_wall_gran.cpp:123)
WARNING: too many contacts here
      20        2        2.5e-05         1.25 
Loop time of 0.000645067 on 1 procs for 20 steps with 2 atoms

Pair  time (%) = 2.3956e-05 (3.71372)
Nlocal:    2 ave 2 max 2 min
Histogram: 1 0 0 0 0 0 0 0 0 0
Step Atoms KinEng v_h
20 2 2.5e-05 0.0
INFO: particle insertion: 0 particles inserted
30 3 3.5e-05 0.1
40 3 nan 0.2
Loop time of 0.1 on 1 procs for 20 steps with 3 atoms
Step Atoms KinEng
40 3 1
50 3 2
60 3
"""


def test_blocks_columns_and_values():
    blocks = parse_log(LOG)
    assert len(blocks) == 3
    b0, b1, b2 = blocks
    assert list(b0) == ["Step", "Atoms", "KinEng", "c_qc"]
    assert b0["Step"].dtype == np.int64
    assert b0["Step"].tolist() == [0, 10, 20]
    assert np.allclose(b0["c_qc"], [0.5, 0.75, 1.25])
    assert b1["Step"].tolist() == [20, 30, 40]
    assert np.isnan(b1["KinEng"][2]) and b1["v_h"][1] == 0.1
    # Third run was cut off (no Loop time, last line incomplete).
    assert b2["Step"].tolist() == [40, 50]
    assert b2["KinEng"].tolist() == [1.0, 2.0]


def test_concat_drops_repeated_steps_and_fills_nan(tmp_path):
    path = tmp_path / "log.liggghts"
    path.write_text(LOG)
    data = concat_blocks(read_log(path))
    assert data["Step"].tolist() == [0, 10, 20, 30, 40, 50]
    assert list(data) == ["Step", "Atoms", "KinEng", "c_qc", "v_h"]
    assert np.allclose(data["c_qc"][:3], [0.5, 0.75, 1.25])
    assert np.isnan(data["c_qc"][3:]).all()
    assert np.allclose(data["v_h"][3:5], [0.1, 0.2]) and np.isnan(data["v_h"][5])
    assert data["KinEng"][-1] == 2.0
    keep_all = concat_blocks(parse_log(LOG), drop_repeated_steps=False)
    assert keep_all["Step"].tolist() == [0, 10, 20, 20, 30, 40, 40, 50]
    assert concat_blocks([]) == {}


def test_summarize():
    rows = {r[0]: r[1:] for r in summarize(parse_log(LOG)[1])}
    n, first, last, lo, hi = rows["KinEng"]
    assert n == 3 and first == pytest.approx(2.5e-5) and np.isnan(last)
    assert lo == pytest.approx(2.5e-5) and hi == pytest.approx(3.5e-5)
