# SPDX-License-Identifier: GPL-2.0-or-later
"""bench/device/summarise_scaling_wall.py: medians per rank count and grid,
efficiency against the 1-rank median, and runs that were not static (a
neighbour-list build or a break in the timed steps) left out."""

import json

import pytest


@pytest.fixture(scope="module")
def summ(load_script):
    return load_script("bench/device/summarise_scaling_wall.py")


def run(np_, grid, rate, builds=0, breaks=0.0, rebuild_every=0, balance=None):
    var = {"rebuild_every": rebuild_every} if rebuild_every else {}
    if balance or (balance is None and grid == "8 1 2"):
        var["balance_cmd"] = "balance/grains"
    return {"np": np_, "proc_grid": grid, "atoms": 1000, "steps": 100, "loop_s": 1.0,
            "neighbor_builds_timed_run": builds, "n_break": breaks, "vars": var,
            "particle_steps_per_core_s": rate}


def write_call(folder, files):
    (folder / "json").mkdir(parents=True)
    for name, runs in files.items():
        (folder / "json" / (name + ".json")).write_text(json.dumps({"runs": runs}))


def test_medians_efficiency_and_dynamic_runs_left_out(summ, tmp_path):
    write_call(tmp_path / "c1", {
        "balanced_1": [run(16, "8 1 2", 1.0e6), run(1, "1 1 1", 2.0e6, balance=True)],
        "default_grid_1": [run(16, "* * 1", 0.8e6), run(1, "1 1 1", 1.0e6)]})
    write_call(tmp_path / "c2", {
        "balanced_1": [run(16, "8 1 2", 1.2e6), run(16, "8 1 2", 1.1e6),
                       run(16, "8 1 2", 9.0e6, builds=3)],          # relaxing: left out
        "default_grid_1": [run(16, "* * 1", 0.9e6, breaks=2.0),   # breaking: left out
                           run(1, "1 1 1", 3.0e6)]})
    runs = summ.load_runs([str(tmp_path / "c1"), str(tmp_path / "c2")])
    out = summ.summarise(runs)
    assert out["runs_not_static"] == 2
    # the 1-rank runs of both kinds of invocation count as one group
    assert out["rate_1_rank_median"] == pytest.approx(2.0e6)
    rows = {(r["np"], r["proc_grid"], r["balance_grains"]): r for r in out["rows"]}
    assert set(rows) == {(1, "1 1 1", False), (16, "8 1 2", True), (16, "* * 1", False)}
    bal = rows[(16, "8 1 2", True)]
    assert bal["n_runs"] == 3 and bal["rate_median"] == pytest.approx(1.1e6)
    assert bal["efficiency_vs_1_rank"] == pytest.approx(0.55)
    dflt = rows[(16, "* * 1", False)]
    assert dflt["n_runs"] == 1 and dflt["rate_median"] == pytest.approx(0.8e6)


def test_forced_rebuilds_count_others_do_not(summ, tmp_path):
    write_call(tmp_path / "c", {"default_grid_1": [
        run(16, "* * 1", 1.0e6, builds=5, rebuild_every=20),     # as asked: counted
        run(16, "* * 1", 2.0e6, builds=6, rebuild_every=20),     # one more: left out
        run(1, "1 1 1", 2.0e6, builds=5, rebuild_every=20)]})
    out = summ.summarise(summ.load_runs([str(tmp_path / "c")]))
    assert out["runs_not_static"] == 1
    rows = {r["np"]: r for r in out["rows"]}
    assert rows[16]["n_runs"] == 1 and rows[16]["efficiency_vs_1_rank"] == pytest.approx(0.5)


def test_folder_without_results_named(summ, tmp_path):
    (tmp_path / "empty").mkdir()
    with pytest.raises(SystemExit, match="empty.*results.tgz"):
        summ.load_runs([str(tmp_path / "empty")])
