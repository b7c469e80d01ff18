# SPDX-License-Identifier: GPL-2.0-or-later
"""crushpost.restart: a chamber run in parts, merged as if it had not stopped
(synthetic series with known answers)."""

import json

import numpy as np
import pytest

from crushpost import restart as rs


def series(steps, tag, header="# z_ref 0.1 m\n# step value\n"):
    return header + "".join("%d %s%d\n" % (s, tag, s) for s in steps)


def rows(text):
    return [ln for ln in text.splitlines() if not ln.startswith("#")]


def test_part_names():
    assert rs.part_name("jack.txt", 2) == "jack.part2.txt"
    assert rs.part_name("log.liggghts", 0) == "log.part0.liggghts"
    assert rs.part_name("breakage_events.txt", 11) == "breakage_events.part11.txt"


def test_keep_before_drops_the_lost_work_and_prefers_the_next_part_at_its_step():
    steps = np.array([0, 2, 4, 6, 6, 8, 10])
    # the next part writes no row at its start: the rows at 6 stay
    assert rs.keep_before(steps, 6, [8, 10]).tolist() == [1, 1, 1, 1, 1, 0, 0]
    # it writes step 6 again: its row replaces both of the earlier run's
    assert rs.keep_before(steps, 6, [6, 8]).tolist() == [1, 1, 1, 0, 0, 0, 0]


def test_merge_of_two_parts_is_the_run_without_the_lost_work():
    first = series(range(0, 12, 2), "a")          # killed after step 10
    second = series(range(8, 16, 2), "b", header="# z_ref 0.1 m (restart)\n")  # from step 6
    merged = rs.merge_series_text([first, second], [6])
    assert merged.startswith("# z_ref 0.1 m\n# step value\n")
    assert rows(merged) == ["0 a0", "2 a2", "4 a4", "6 a6", "8 b8", "10 b10", "12 b12", "14 b14"]


def test_merge_keeps_several_events_of_one_step_and_chains_parts():
    first = "# events\n3 x\n5 x\n5 y\n7 x\n9 x\n"
    second = "9 p\n11 p\n13 p\n"                   # from step 5: 7 and 9 were lost
    third = "12 q\n14 q\n"                         # from step 11: 13 was lost
    merged = rs.merge_series_text([first, second, third], [5, 11])
    assert rows(merged) == ["3 x", "5 x", "5 y", "9 p", "11 p", "12 q", "14 q"]


def test_merge_refuses_a_part_that_starts_before_its_restart_step():
    with pytest.raises(rs.RestartError, match="from step 6 has a row at step 4"):
        rs.merge_series_text([series([0, 2, 4, 6], "a"), series([4, 8], "b")], [6])
    with pytest.raises(rs.RestartError, match="2 parts need 1 restart steps"):
        rs.merge_series_text([series([0], "a"), series([2], "b")], [])


def test_merge_of_an_empty_part():
    merged = rs.merge_series_text([series([0, 2, 4], "a"), "# header only\n"], [2])
    assert rows(merged) == ["0 a0", "2 a2"]


def test_latest_restart_names_what_is_wrong(tmp_path):
    with pytest.raises(rs.RestartError, match="wrote no restart file"):
        rs.latest_restart(str(tmp_path))
    (tmp_path / "restart").mkdir()
    (tmp_path / "restart" / "latest.txt").write_text("restart/jack_0.restart\n")
    with pytest.raises(rs.RestartError, match="expected 'STEP FILE'"):
        rs.latest_restart(str(tmp_path))
    (tmp_path / "restart" / "latest.txt").write_text("120000 restart/jack_1.restart\n")
    with pytest.raises(rs.RestartError, match="jack_1.restart, which does not exist"):
        rs.latest_restart(str(tmp_path))
    (tmp_path / "restart" / "jack_1.restart").write_bytes(b"\0")
    step, path = rs.latest_restart(str(tmp_path))
    assert step == 120000 and path.endswith("restart/jack_1.restart")


def test_merge_parts_writes_the_series_and_the_whole_log(tmp_path):
    (tmp_path / "restart").mkdir()
    rs.write_parts(str(tmp_path), [{"part": 1, "step": 6, "restart_file": "restart/jack_0.restart",
                                    "started": 0.0, "wall_s": 5.0}])
    (tmp_path / "jack.part0.txt").write_text(series(range(0, 12, 2), "a"))
    (tmp_path / "jack.part1.txt").write_text(series(range(8, 12, 2), "b"))
    (tmp_path / "log.part0.liggghts").write_text("first\n")
    (tmp_path / "log.part1.liggghts").write_text("second\n")
    written = rs.merge_parts(str(tmp_path))
    assert written == ["jack.txt", "log.liggghts"]      # no events or spheres in part 0
    assert rows((tmp_path / "jack.txt").read_text()) == ["0 a0", "2 a2", "4 a4", "6 a6", "8 b8",
                                                         "10 b10"]
    log = (tmp_path / "log.liggghts").read_text().splitlines()
    assert log[0] == "first" and log[-1] == "second"
    assert "part 1 goes on from restart/jack_0.restart at step 6" in log[1]
    assert rs.part_walls(str(tmp_path), rs.read_parts(str(tmp_path))) == [5.0]
    # a part's series missing
    (tmp_path / "breakage_events.part0.txt").write_text("1 x\n")
    with pytest.raises(rs.RestartError, match="breakage_events.part1.txt"):
        rs.merge_parts(str(tmp_path))


def test_parts_file_checked(tmp_path):
    (tmp_path / "restart").mkdir()
    assert rs.read_parts(str(tmp_path)) == []
    (tmp_path / "restart" / "parts.json").write_text(json.dumps([{"part": 2, "step": 1}]))
    with pytest.raises(rs.RestartError, match="parts \\[2\\], expected 1..1"):
        rs.merge_parts(str(tmp_path))
    (tmp_path / "restart" / "parts.json").write_text("{")
    with pytest.raises(rs.RestartError, match="not JSON"):
        rs.read_parts(str(tmp_path))


def test_stale_snapshots():
    snaps = [(100, "s/jack_100.h5"), (250, "s/jack_250.h5"), (300, "s/jack_300.h5")]
    assert rs.stale_snapshots(snaps, 250) == ["s/jack_300.h5"]


def test_clear_parts_removes_only_what_resuming_reads(tmp_path):
    (tmp_path / "restart").mkdir()
    (tmp_path / "restart" / "latest.txt").write_text("10 restart/jack_0.restart\n")
    for name in ("jack.part0.txt", "log.part3.liggghts", "spheres.part1.in", "jack.txt",
                 "jack.partial.txt", "log.liggghts", "summary.json"):
        (tmp_path / name).write_text("x")
    rs.clear_parts(str(tmp_path))
    assert sorted(p.name for p in tmp_path.iterdir()) == ["jack.partial.txt", "jack.txt",
                                                          "log.liggghts", "summary.json"]


def thermo_log(steps):
    rows = "".join("%8d %8d\n" % (s, 100) for s in steps)
    return "Setting up run\n    Step    Atoms \n%sLoop time of 1 on 1 procs for 10 steps\n" % rows


def test_merge_parts_command_infers_the_parts_of_a_run_resumed_by_hand(tmp_path):
    from crushpost.cli import main

    (tmp_path / "log.part0.liggghts").write_text(thermo_log([0, 10, 20, 30]))
    (tmp_path / "log.part1.liggghts").write_text(thermo_log([20, 30, 40]))
    (tmp_path / "jack.part0.txt").write_text(series([10, 20, 30], "a"))
    (tmp_path / "jack.part1.txt").write_text(series([30, 40], "b"))
    assert main(["merge-parts", str(tmp_path)]) == 0
    assert rows((tmp_path / "jack.txt").read_text()) == ["10 a10", "20 a20", "30 b30", "40 b40"]
    assert rs.read_parts(str(tmp_path))[0]["step"] == 20
    empty = tmp_path / "empty"
    empty.mkdir()
    assert main(["merge-parts", str(empty)]) == 1       # "no log.part1.liggghts: no part to merge"


def test_part_files():
    assert rs.part_files(0) == {"log": "log.liggghts", "jack": "jack.txt",
                                "events": "breakage_events.txt", "spheres": "spheres.txt"}
    assert rs.part_files(3)["events"] == "breakage_events.part3.txt"


def killed_run(out):
    """A run folder as a killed jacking run leaves it: two restart files in
    turn, latest.txt naming the complete one, a claim and a snapshot."""
    (out / "restart").mkdir(parents=True)
    (out / "restart" / "jack_0.restart").write_bytes(b"\x00complete" * 100)
    (out / "restart" / "jack_1.restart").write_bytes(b"half written")
    (out / "restart" / "latest.txt").write_text("200001 restart/jack_0.restart\n")
    (out / "snapshots").mkdir()
    (out / "snapshots" / "prep_5000.h5").write_bytes(b"h5")
    (out / "jack.txt").write_text(series([0, 100000, 200000], "a"))
    (out / "log.liggghts").write_text("Step Atoms\n")
    (out / "running.pid").write_text("12345\n")
    (out / "restart_forced_liggghts_200043.data").write_bytes(b"signal")
    import os
    os.utime(out / "log.liggghts", (1.7e9, 1.7e9))


def test_carry_round_trip_keeps_what_resuming_reads_and_the_log_time(tmp_path):
    killed_run(tmp_path / "a")
    assert rs.carry_members(tmp_path / "a") == [
        "jack.txt", "log.liggghts", "restart/jack_0.restart", "restart/latest.txt",
        "snapshots/prep_5000.h5"]
    archive = str(tmp_path / "carry" / "a.tar.xz")
    assert rs.pack_carry(str(tmp_path / "a"), archive) == 200001
    assert rs.carry_step(archive) == 200001
    assert rs.unpack_carry(archive, str(tmp_path / "b")) == 200001
    b = tmp_path / "b"
    assert rs.latest_restart(str(b))[0] == 200001
    assert (b / "restart" / "jack_0.restart").read_bytes() == b"\x00complete" * 100
    assert not (b / "restart" / "jack_1.restart").exists()
    assert not (b / "running.pid").exists()
    assert (b / "jack.txt").read_text() == (tmp_path / "a" / "jack.txt").read_text()
    # a killed part's wall time ends at its log's last change (part_walls)
    assert (b / "log.liggghts").stat().st_mtime == 1.7e9


def test_carry_refuses_a_complete_run_and_never_overwrites_a_run(tmp_path):
    killed_run(tmp_path / "a")
    archive = str(tmp_path / "a.tar.xz")
    rs.pack_carry(str(tmp_path / "a"), archive)
    with pytest.raises(rs.RestartError, match="holds a run of its own"):
        rs.unpack_carry(archive, str(tmp_path / "a"))
    (tmp_path / "a" / "summary.json").write_text("{}")
    with pytest.raises(rs.RestartError, match="the run is complete"):
        rs.pack_carry(str(tmp_path / "a"), str(tmp_path / "b.tar.xz"))
    with pytest.raises(rs.RestartError, match="no such file"):
        rs.pack_carry(str(tmp_path / "empty"), str(tmp_path / "c.tar.xz"))


def test_carry_rejects_a_file_that_is_not_a_carry_or_leaves_the_folder(tmp_path):
    import io
    import tarfile
    bogus = tmp_path / "bogus.tar.xz"
    bogus.write_text("not a tar")
    with pytest.raises(rs.RestartError, match="bogus.tar.xz: not a carried run"):
        rs.carry_step(str(bogus))
    evil = str(tmp_path / "evil.tar.xz")
    with tarfile.open(evil, "w:xz") as tar:
        for name, data in (("restart/latest.txt", b"7 restart/jack_0.restart\n"),
                           ("../outside.txt", b"x")):
            info = tarfile.TarInfo(name)
            info.size = len(data)
            tar.addfile(info, io.BytesIO(data))
    with pytest.raises(rs.RestartError, match=r"\.\./outside\.txt are not plain files"):
        rs.unpack_carry(evil, str(tmp_path / "out"))
    assert not (tmp_path / "outside.txt").exists()


def test_study_carries_killed_pieces_and_unpacks_only_where_no_run_is(tmp_path, load_script):
    evr = load_script("bench/error_vs_runtime/run.py", "evr_run")
    root, carry = tmp_path / "work", tmp_path / "carry"
    killed_run(root / "killed")
    (root / "done" / "restart").mkdir(parents=True)       # finished: not carried
    (root / "done" / "restart" / "latest.txt").write_text("9 restart/jack_0.restart\n")
    (root / "done" / "summary.json").write_text("{}")
    packed = evr.carry_out(str(root), ["killed", "done", "never_run"], str(carry))
    assert [(n, s) for n, s, _ in packed] == [("killed", 200001)]
    # a new machine: the folder is not there; it is laid out from the carry
    fresh = tmp_path / "fresh"
    assert evr.carry_in(str(fresh / "killed"), "killed", str(carry)) == 200001
    assert evr.resumable(str(fresh / "killed"))
    # a folder that can go on by itself is left alone (its run may be further on)
    assert evr.carry_in(str(root / "killed"), "killed", str(carry)) is None
    assert evr.carry_in(str(fresh / "other"), "other", str(carry)) is None
