# SPDX-License-Identifier: GPL-2.0-or-later
"""crushpost compare on two synthetic run folders with known answers."""

import json

import h5py
import pytest

from crushpost.cli import main
from crushpost.compare import compare, read_run


def _run(tmp_path, name, qc, zones=None, head=None):
    d = tmp_path / name
    d.mkdir()
    s = {"qc_steady_MPa": qc, "n_break_events": 0 if zones is None else zones["n_events"],
         "fines_mass_fraction": 0.0}
    if zones is not None:
        s["break_zones"] = zones
    (d / "summary.json").write_text(json.dumps(s))
    if head is not None:
        (d / "report").mkdir()
        with h5py.File(d / "report" / "fields.h5", "w") as f:
            g = f.create_group("headline")
            for k, v in head.items():
                g.attrs[k] = v
    return d


ZONES = {"n_events": 40, "switch_on": 4, "entry": 2, "penetration": 34, "in_zone": 30,
         "along_shaft": 0, "beyond_5R_below": 1, "elsewhere": 3, "fraction_in_zone": 30 / 34}


def test_ratio_and_differences(tmp_path, capsys):
    a = _run(tmp_path, "unbreakable", 30.0)
    b = _run(tmp_path, "crushable", 20.0, ZONES, head={"Br_penetrated_1_2R": 0.25})
    rows, ratio = compare(read_run(a), read_run(b))
    assert ratio == pytest.approx(1.5)
    r = {row[0]: row for row in rows}
    assert r["events_in_zone"][2] == 30 and r["events_in_zone"][1] is None
    assert r["Br_penetrated_1_2R"][2] == 0.25
    assert r["n_break_events"][4] == -40
    assert main(["compare", str(a), str(b), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["qc_ratio"] == pytest.approx(1.5)
    assert out["rows"]["fraction_in_zone"]["b"] == pytest.approx(30 / 34)
    assert main(["compare", str(a), str(b)]) == 0
    assert "qc_steady_MPa" in capsys.readouterr().out


def test_missing_summary_names_the_file(tmp_path, capsys):
    a = _run(tmp_path, "a", 10.0)
    assert main(["compare", str(a), str(tmp_path / "nowhere")]) == 1
    assert "nowhere/summary.json: no such file" in capsys.readouterr().err
    bad = tmp_path / "bad"
    bad.mkdir()
    (bad / "summary.json").write_text("{not json")
    assert main(["compare", str(a), str(bad)]) == 1
    assert "bad/summary.json: not JSON" in capsys.readouterr().err
