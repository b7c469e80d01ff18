# SPDX-License-Identifier: GPL-2.0-or-later
"""The event log fix crush/particle writes (src_liggghts_plugin/
fix_crush_particle.cpp) against its one Python definition, crushpost.formats
(issue "One topic per file", item 4): a tiny crushing deck (one 1 mm grain
pressed by a platen until it breaks, the n1_mesh stack of
test_crush_single_grain.py), with and without ``energy yes``; the header's
title and column names are those of crushpost.formats, every event line has
that many words, and crushpost.dump.read_crush_log reads it by them."""

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import crush_decks as cd  # noqa: E402
from test_crush_single_grain import CASES, Stack  # noqa: E402

from crushpost import formats  # noqa: E402
from crushpost.dump import read_crush_log  # noqa: E402


def _case(energy):
    base = CASES["n1_mesh"]
    if not energy:
        return base
    return Stack("n1_mesh_energy", base.d, N=base.N, top=base.top, bottom=base.bottom,
                 crush_extra="energy yes energy_window 10")


@pytest.mark.parametrize("energy", [False, True], ids=["plain", "energy"])
def test_event_log_matches_formats(tmp_path, energy):
    case = _case(energy)
    res = cd.run(case.deck(), tmp_path, files={"plate.stl": case.write_stl})
    path = Path(res.path("events.txt"))
    lines = path.read_text().splitlines()
    fix_id, names = formats.event_log_header(lines[:2])
    assert fix_id == "crush"
    expect = formats.EVENT_LOG_COLUMNS + (formats.EVENT_LOG_ENERGY_COLUMNS if energy else ())
    assert names == expect, "header of %s: %s; crushpost.formats: %s" % (path, names, expect)
    data = [ln.split() for ln in lines[2:] if ln.strip() and not ln.startswith("#")]
    assert len(data) == 1, data                          # the grain breaks once
    assert all(len(w) == len(names) for w in data)
    assert formats.event_log_columns(len(data[0])) == names
    ev = read_crush_log(path)
    for k, name in enumerate(names):
        col = ev[name]
        if name == "partner":
            assert col[0] in formats.EVENT_LOG_PARTNERS
        elif name in formats.EVENT_LOG_INT_COLUMNS:
            assert col.dtype == np.int64 and col[0] == int(data[0][k])
        else:
            assert col[0] == float(data[0][k])
    assert ev["parent_diameter"][0] == pytest.approx(case.d[0])
