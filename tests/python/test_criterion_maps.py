# SPDX-License-Identifier: GPL-2.0-or-later
"""The criterion-readings study's figures (bench/criterion_readings/run.py
--table): the events kept from each chamber piece's report and the split
into penetration events, the maps, and the oedometer and triaxial curves,
on synthetic records with known answers."""

import json

import numpy as np
import pytest

R = 0.018      # m, a pile radius that is not 1: the tip depth is converted


@pytest.fixture(scope="module")
def cr(load_script):
    return load_script("bench/criterion_readings/run.py")


def _report(root, name, h, r, tip_depth_m):
    import h5py
    run = root / name
    (run / "report").mkdir(parents=True)
    (run / "summary.json").write_text(json.dumps({"R_pile_m": R}))
    with h5py.File(run / "report" / "fields.h5", "w") as f:
        g = f.create_group("breakage/events")
        g["h_over_R"] = np.asarray(h, dtype=float)
        g["r_over_R"] = np.asarray(r, dtype=float)
        g["tip_depth"] = np.asarray(tip_depth_m, dtype=float)


def test_events_are_kept_in_radii_and_penetration_needs_the_tip_below_2R(cr, tmp_path):
    # five events: at switch-on (tip at the surface), at entry (tip 1.5 R
    # deep), three during penetration, of which two in the zone
    h = [-3.0, 0.5, -1.0, 1.0, -7.0]
    r = [6.0, 1.2, 1.1, 2.5, 0.5]
    tip = np.array([0.0, 1.5, 2.5, 4.0, 10.0]) * R
    _report(tmp_path, "chamber_printed_seed2024", h, r, tip)
    path = tmp_path / "events.json"
    data = cr.collect_events(["chamber_printed_seed2024", "chamber_peak_seed2024"],
                             root=str(tmp_path), path=str(path))
    assert list(data) == ["chamber_printed_seed2024"]        # the missing piece is skipped
    ev = json.loads(path.read_text())["chamber_printed_seed2024"]
    assert ev["tip_depth_over_R"] == [0.0, 1.5, 2.5, 4.0, 10.0]
    hp, rp, n_other = cr.penetration_events(ev)
    assert n_other == 2
    assert hp.tolist() == [-1.0, 1.0, -7.0] and rp.tolist() == [1.1, 2.5, 0.5]
    # break_zones counts the same events as penetration and in the zone
    from crushpost.pile import break_zones
    z = break_zones(np.array(h), np.array(r), tip / R, np.array([True, False, False, False, False]))
    assert z["penetration"] == hp.size and z["in_zone"] == 2


def test_a_piece_without_a_break_keeps_an_empty_map(cr, tmp_path):
    # the report of crushable grains that never broke has zones (all 0) and
    # no events: an empty entry, drawn as a panel; a report without zones
    # (unbreakable grains, or older) is skipped
    import h5py
    for name, n_events in (("chamber_truncated_0.5_seed2024", 0), ("chamber_sliding_seed2024", None)):
        run = tmp_path / name
        (run / "report").mkdir(parents=True)
        (run / "summary.json").write_text(json.dumps({"R_pile_m": R}))
        with h5py.File(run / "report" / "fields.h5", "w") as f:
            if n_events is not None:
                f["breakage/zones/n_events"] = n_events
    data = cr.collect_events(["chamber_truncated_0.5_seed2024", "chamber_sliding_seed2024"],
                             root=str(tmp_path), path=str(tmp_path / "events.json"))
    assert data == {"chamber_truncated_0.5_seed2024": {"h_over_R": [], "r_over_R": [],
                                                       "tip_depth_over_R": []}}
    assert cr.draw_maps(data, path=str(tmp_path / "maps.png")) == ["truncated_0.5"]


def test_maps_pool_the_seeds_of_a_reading(cr, tmp_path):
    events = {"chamber_printed_seed2024": {"h_over_R": [-1.0], "r_over_R": [1.0],
                                           "tip_depth_over_R": [3.0]},
              "chamber_printed_seed2025": {"h_over_R": [-8.0], "r_over_R": [1.0],
                                           "tip_depth_over_R": [4.0]},
              "chamber_peak_seed2025": {"h_over_R": [], "r_over_R": [], "tip_depth_over_R": []}}
    png = tmp_path / "maps.png"
    assert cr.draw_maps(events, path=str(png)) == ["printed", "peak"]
    assert png.stat().st_size > 1000


def test_oedometer_curves_drawn_only_for_records_that_keep_one(cr, tmp_path):
    # printed and peak keep a curve, weibull's record predates it, sliding's
    # curve is empty (never reached 0.1 MPa): two readings drawn, in READINGS order
    curve = {"sigma_v_MPa": [0.1, 1.0, 10.0], "e_core": [None, 0.6, 0.5], "Br": [None, 0.0, 0.1]}
    runs = {"oedometer_peak": {"metrics": {"loading_curve": curve}},
            "oedometer_printed": {"metrics": {"loading_curve": curve}},
            "oedometer_weibull": {"metrics": {"Br_at_30MPa": 0.1}},
            "oedometer_sliding": {"metrics": {"loading_curve": {"sigma_v_MPa": [], "e_core": [],
                                                                "Br": []}}}}
    png = tmp_path / "oedo.png"
    assert cr.draw_oedometer_curves({"runs": runs}, path=str(png)) == ["printed", "peak"]
    assert png.stat().st_size > 1000
    assert cr.draw_oedometer_curves({"runs": {}}, path=str(tmp_path / "none.png")) == []


def test_triaxial_curves_drawn_for_each_reading_with_a_curve(cr, tmp_path):
    # peak has a curve for seed 2025 only, printed for both, weibull none
    curve = {"eps_a": [0.0, 0.005, 0.01], "eta": [0.0, 0.8, 1.1], "eps_v": [0.0, 0.001, 0.0],
             "Br": [0.0, 0.0, 0.0]}
    runs = {"triaxial_printed": {"metrics": {"shear_curve": curve}},
            "triaxial_printed_seed2025": {"metrics": {"shear_curve": curve}},
            "triaxial_peak_seed2025": {"metrics": {"shear_curve": curve}},
            "triaxial_weibull": {"metrics": {"phi_cs_deg": 33.0}}}
    png = tmp_path / "tri.png"
    assert cr.draw_triaxial_curves({"runs": runs}, path=str(png)) == ["printed", "peak"]
    assert png.stat().st_size > 1000
    assert cr.draw_triaxial_curves({"runs": {}}, path=str(tmp_path / "none.png")) == []


def test_remeasure_replaces_only_the_metrics_and_says_when(cr, tmp_path, monkeypatch):
    # a done chamber piece measured again from its run folder: the record's
    # other fields stay, its metrics are today's report's, a stamp says so;
    # a piece whose folder is not here is left alone, with the reason
    results = tmp_path / "results.json"
    old = {"name": "chamber_truncated_0.5_seed2024", "wall_s": 3346.0,
           "metrics": {"events_in_zone": None, "qc_steady_MPa": 17.5}}
    results.write_text(json.dumps({"runs": {old["name"]: old}}))
    monkeypatch.setattr(cr, "RESULTS", str(results))
    monkeypatch.setattr(cr, "ROOT", str(tmp_path))
    piece = {"name": old["name"], "scene": "chamber"}
    assert cr.remeasure(piece).startswith("not remeasured: no ")
    run = tmp_path / old["name"]
    run.mkdir()
    (run / "summary.json").write_text(json.dumps({"qc_steady_MPa": 17.5}))
    seen = []

    def fake(out, summ):
        seen.append((out, summ))
        return {"events_in_zone": 0, "qc_steady_MPa": 17.5}, None
    monkeypatch.setattr(cr.evr, "chamber_report_metrics", fake)
    assert cr.remeasure(piece) == "remeasured"
    assert seen == [(str(run), {"qc_steady_MPa": 17.5})]
    rec = json.loads(results.read_text())["runs"][old["name"]]
    assert rec["metrics"] == {"events_in_zone": 0, "qc_steady_MPa": 17.5}
    assert rec["wall_s"] == 3346.0 and set(rec["remeasured"]) == {"date", "commit"}
    monkeypatch.setattr(cr.evr, "chamber_report_metrics", lambda out, summ: (None, "no fields"))
    assert cr.remeasure(piece) == "not remeasured: no fields"
