# SPDX-License-Identifier: GPL-2.0-or-later
"""crushpost.runner: the mpirun command line of the example drivers."""

from crushpost.runner import mpirun_command


def test_command_line_order_and_values():
    cmd = mpirun_command("in.x", {"N": 39.0, "dt": 1.5e-7, "grain_model": "unbreakable", "n": 3},
                         np=2, binary="/b/liggghts", as_root=False)
    # unbound: side-by-side 1-rank runs must not all be bound to core 0
    assert cmd[:6] == ["mpirun", "--oversubscribe", "--bind-to", "none", "-np", "2"]
    assert cmd[6:15] == ["/b/liggghts", "-in", "in.x", "-log", "log.liggghts",
                         "-echo", "none", "-screen", "none"]
    pairs = dict(zip(cmd[16::3], cmd[17::3]))
    assert cmd[15::3] == ["-var"] * 4
    # floats keep all their digits
    assert pairs == {"N": "39.0", "dt": "1.5e-07", "grain_model": "unbreakable", "n": "3"}
    assert float(pairs["dt"]) == 1.5e-7


def test_root_flag():
    assert mpirun_command("d", {}, as_root=True, binary="b")[1] == "--allow-run-as-root"
    assert "--allow-run-as-root" not in mpirun_command("d", {}, as_root=False, binary="b")


def test_log_name_and_snapshot_tree(tmp_path, monkeypatch):
    import os

    from crushpost.runner import REPO, snapshot_tree

    cmd = mpirun_command("d", {}, binary="b", log="log.part2.liggghts", as_root=False)
    assert cmd[cmd.index("-log") + 1] == "log.part2.liggghts"
    tree = snapshot_tree(str(tmp_path), ("inputs", "scripts/crushpost"))
    assert os.path.dirname(tree) == str(tmp_path) and os.path.basename(tree).startswith("_tree_")
    for name in ("pile_jacking.in", "chamber_resume.in"):
        with open(os.path.join(REPO, "inputs", name)) as a, open(os.path.join(tree, "inputs", name)) as b:
            assert a.read() == b.read()
    assert os.path.exists(os.path.join(tree, "scripts", "crushpost", "restart.py"))
    assert not any("__pycache__" in d for d, _, _ in os.walk(tree))
    # two copies in the same second (the clock held) get their own folders
    import crushpost.runner

    monkeypatch.setattr(crushpost.runner.time, "time", lambda: 1.8e9)
    first = snapshot_tree(str(tmp_path), ("inputs",))
    assert snapshot_tree(str(tmp_path), ("inputs",)) != first


def test_copies_of_gone_owners_are_pruned_and_a_call_removes_its_own(tmp_path, dead_pid):
    import os

    from crushpost.runner import prune_trees, remove_tree, snapshot_tree

    mine = snapshot_tree(str(tmp_path), ("inputs",))
    with open(os.path.join(mine, "owner.pid")) as f:
        assert int(f.read()) == os.getpid()
    # a copy of another live process (a study running side by side): kept
    alive = snapshot_tree(str(tmp_path), ("inputs",))
    with open(os.path.join(alive, "owner.pid"), "w") as f:
        f.write("%d\n" % os.getppid())
    # a copy whose owner has exited (a study killed at a restart point)
    gone = snapshot_tree(str(tmp_path), ("inputs",))
    with open(os.path.join(gone, "owner.pid"), "w") as f:
        f.write("%d\n" % dead_pid)
    # a copy without an owner file (an older version's, maybe running): kept
    legacy = os.path.join(str(tmp_path), "_tree_1_legacy")
    os.makedirs(legacy)
    other = os.path.join(str(tmp_path), "chamber_run")   # not a copy: kept
    os.makedirs(other)
    with open(os.path.join(other, "owner.pid"), "w") as f:
        f.write("%d\n" % dead_pid)
    assert prune_trees(str(tmp_path)) == [gone]
    assert sorted(os.listdir(str(tmp_path))) == sorted(
        os.path.basename(d) for d in (mine, alive, legacy, other))
    # the next copy prunes before it copies
    with open(os.path.join(legacy, "owner.pid"), "w") as f:
        f.write("%d\n" % dead_pid)
    third = snapshot_tree(str(tmp_path), ("inputs",))
    assert not os.path.exists(legacy) and os.path.isdir(third) and os.path.isdir(mine)
    remove_tree(mine)
    remove_tree(None)
    remove_tree(other)           # not a copy's name: left alone
    assert sorted(os.listdir(str(tmp_path))) == sorted(
        os.path.basename(d) for d in (alive, third, other))


def test_a_failed_run_names_its_log_and_last_error(tmp_path, capsys):
    import pytest

    from crushpost.runner import log_errors, stop_on_failure

    log = tmp_path / "log.liggghts"
    log.write_text("LIGGGHTS (Version ...)\nERROR: first\nthermo ...\n"
                   "ERROR: fix check/stability: unstable at step 7, signal 'move'\n")
    assert log_errors(str(log)) == ["first", "fix check/stability: unstable at step 7, signal 'move'"]
    assert log_errors(str(tmp_path / "missing")) == []
    with pytest.raises(SystemExit) as exc:
        stop_on_failure("oedometer", 3, str(log))
    assert exc.value.code == 3
    err = capsys.readouterr().err.splitlines()
    assert err == ["oedometer: LIGGGHTS failed (exit 3); see %s" % log,
                   "oedometer: fix check/stability: unstable at step 7, signal 'move'"]
    log.write_text("ERROR: Unknown command: PREPARATION FAILED (radius expansion, 6 cycles): ...\n")
    with pytest.raises(SystemExit):
        stop_on_failure("cpt", 1, str(log))
    assert capsys.readouterr().err.splitlines()[1] == "cpt: PREPARATION FAILED (radius expansion, 6 cycles): ..."
