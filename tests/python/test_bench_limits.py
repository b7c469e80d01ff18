# SPDX-License-Identifier: GPL-2.0-or-later
"""The benchmarks that state a limit check it and exit 1 when it is missed
(issue 42 item 5): each script's limit_failures on small synthetic results,
on the committed results files (what the docs say of them), and the report
benchmark end to end on a small snapshot with a limit it cannot meet."""

import json
import statistics

import pytest

from conftest import REPO


@pytest.fixture(scope="module")
def benches(load_script):
    return {name: load_script("bench/%s/run.py" % name, "bench_%s_under_test" % name)
            for name in ("report", "break_cost", "crush_overhead", "stability_cost")}


def _committed(path):
    with open(REPO / path) as f:
        return json.load(f)


def test_report_limits(benches):
    m = benches["report"]
    assert m.LIMITS == {"total_s": 20.0, "peak_rss_MB": 2048.0}       # issue 10 item 7
    assert m.limit_failures({"total_s": 19.9, "peak_rss_MB": 2048.0}) == []
    bad = m.limit_failures({"total_s": 20.1, "peak_rss_MB": 100.0})
    assert len(bad) == 1 and bad[0].startswith("total_s")
    assert len(m.limit_failures({"total_s": 1.0, "peak_rss_MB": 2049.0})) == 1
    assert len(m.limit_failures({"total_s": float("nan")})) == 2      # NaN and missing fail
    # docs/studies/performance.md: 4.9 s and 0.52 GB, within the limits
    res = _committed("bench/report/results.json")
    assert m.limit_failures(res["median"]) == []


def test_break_cost_target(benches):
    m = benches["break_cost"]
    assert m.TARGET == {"crush_over_stock_mean": 0.9}                  # issue 13 item 3
    ok = {"np1": {"crush_over_stock_mean": 0.9}, "np2": {"crush_over_stock_mean": 1.2}}
    assert m.limit_failures(ok) == []
    bad = m.limit_failures({"np1": {"crush_over_stock_mean": 0.95},
                            "np2": {"crush_over_stock_mean": 0.899}})
    assert len(bad) == 1 and bad[0].startswith("np2")
    assert len(m.limit_failures({"np1": {}})) == 1
    # docs/studies/performance.md: met on instruction counts (0.913 at 1 and 2 ranks);
    # the wall-time run (noise at the 10 % level) missed it at 1 rank (0.882)
    assert m.limit_failures(_committed("bench/break_cost/results_callgrind.json")
                            ["summary_medians"]) == []
    wall = m.limit_failures(_committed("bench/break_cost/results.json")["summary_medians"])
    assert len(wall) == 1 and wall[0].startswith("np1")


def test_crush_overhead_target(benches):
    m = benches["crush_overhead"]
    assert m.TARGET == {"fix_share_from_other": 0.05}
    summ = {"1": {"fix_share_from_other": [0.01, 0.02, 0.2]},          # median 0.02
            "2": {"fix_share_from_other": [0.04, 0.06, 0.07]}}         # median 0.06
    bad = m.limit_failures(summ)
    assert len(bad) == 1 and bad[0].startswith("2 ranks")
    assert len(m.limit_failures({"1": {"fix_share_from_other": []}})) == 1
    # docs/studies/performance.md: after the margin skip (results_device.json, three
    # invocations) 2.1 % at 1 rank and 3.8 % at 2 ranks, median of 9 pairs;
    # before it (results.json, 2026-11-23) about 10 and 11 %
    dev = _committed("bench/crush_overhead/results_device.json")["invocations"]
    pooled = {k: {"fix_share_from_other": [x for inv in dev for x in inv["summary"][k]
                                           ["fix_share_from_other"]]} for k in ("1", "2")}
    assert [len(v["fix_share_from_other"]) for v in pooled.values()] == [9, 9]
    assert round(statistics.median(pooled["1"]["fix_share_from_other"]), 3) == 0.021
    assert round(statistics.median(pooled["2"]["fix_share_from_other"]), 3) == 0.038
    assert m.limit_failures(pooled) == []
    before = m.limit_failures(_committed("bench/crush_overhead/results.json")["summary"])
    assert len(before) == 2


def test_stability_cost_target(benches):
    m = benches["stability_cost"]
    assert m.limit_failures({"relative_cost_difference": 0.0099,
                             "relative_cost_own_functions": 0.005}) == []
    bad = m.limit_failures({"relative_cost_difference": 0.01, "relative_cost_own_functions": 0.0})
    assert len(bad) == 1 and bad[0].startswith("relative_cost_difference")
    # docs/stability.md: 0.536 %, below the 1 % target
    assert m.limit_failures(_committed("bench/stability_cost/results.json")) == []


def test_report_bench_exits_1_when_a_limit_is_missed(benches, tmp_path, monkeypatch):
    # a small snapshot (25,000 grains, 50,000 contacts, the 20,000 wall
    # contacts of the default) meets 20 s and 2 GB;
    # with a limit of 1 MB of memory it cannot, and the script exits 1 after
    # writing its results
    m = benches["report"]
    argv = ["--particles", "25000", "--contacts", "50000", "--repeat", "1"]
    assert m.main(argv + ["--out", str(tmp_path / "a.json")]) == 0
    monkeypatch.setitem(m.LIMITS, "peak_rss_MB", 1.0)
    assert m.main(argv + ["--out", str(tmp_path / "b.json")]) == 1
    res = json.loads((tmp_path / "b.json").read_text())
    assert res["limits"]["peak_rss_MB"] == 1.0 and res["median"]["peak_rss_MB"] > 1.0
