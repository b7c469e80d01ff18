# SPDX-License-Identifier: GPL-2.0-or-later
"""crushpost.snapshot on synthetic files written with h5py in the layout of
fix snapshot/hdf5 (docs/fix_snapshot_hdf5.md), with known answers."""

import math

import numpy as np
import pytest

h5py = pytest.importorskip("h5py")

from crushpost.snapshot import (contact_rows, list_snapshots, read_snapshot,  # noqa: E402
                                read_snapshots, snapshot_particle_stress, write_snapshot)


def _str_attr(obj, name, s):
    obj.attrs.create(name, np.bytes_(s))


def write_synthetic(path, step=1200, contacts=True, walls=True, empty_pp=False):
    """Three grains: ids 2 and 5 (r = 1) touch along x, the contact point at
    x = 0.9 and a force of 10 N pushing 2 in -x; grain 9 (r = 0.5) touches
    mesh 1 ('shaft') at z = 4.6 with 3 N upward."""
    with h5py.File(path, "w") as f:
        f.attrs["step"] = np.int64(step)
        f.attrs["time"] = 2.4e-3
        f.attrs["dt"] = 2e-6
        _str_attr(f, "trigger", "f_jack[6]")
        f.attrs["trigger_old"] = 0.0
        f.attrs["trigger_new"] = 1.0
        f.attrs["snapshot"] = np.int64(3)
        _str_attr(f, "fix", "snap")
        _str_attr(f, "group", "all")
        g = f.create_group("particles")
        g.attrs["count"] = np.int64(3)
        g["id"] = np.array([2, 5, 9], dtype=np.int64)
        g["type"] = np.array([1, 1, 1], dtype=np.int32)
        g["x"] = np.array([[0.0, 0, 0], [1.8, 0, 0], [0, 0, 5.0]])
        g["v"] = np.array([[0.1, 0, 0], [0, 0.2, 0], [0, 0, -0.3]])
        g["radius"] = np.array([1.0, 1.0, 0.5])
        gv = g.create_group("values")
        gv["f_crush[1]"] = np.array([1e9, 2e9, 3e9])
        gv["c_stress"] = np.arange(18, dtype=float).reshape(3, 6)
        if not contacts:
            return
        c = f.create_group("contacts")
        pp = c.create_group("pp")
        if empty_pp:
            pp["id"] = np.zeros(0, dtype=np.int64)
            for k in ("contact_point", "force", "force_normal", "overlap"):
                pp[k] = np.zeros(0)
        else:
            pp["id"] = np.array([[2, 5]], dtype=np.int64)
            pp["contact_point"] = np.array([[0.9, 0, 0]])
            pp["force"] = np.array([[-10.0, 0, 0]])
            pp["force_normal"] = np.array([[-10.0, 0, 0]])
            pp["overlap"] = np.array([0.2])
        if walls:
            pw = c.create_group("pw")
            _str_attr(pw, "meshes", "cone shaft")
            _str_attr(pw, "wall_fix", "pile")
            pw["id"] = np.array([9], dtype=np.int64)
            pw["mesh"] = np.array([1], dtype=np.int32)
            pw["triangle"] = np.array([17], dtype=np.int64)
            pw["contact_point"] = np.array([[0, 0, 4.6]])
            pw["force"] = np.array([[0, 0, 3.0]])
            pw["force_normal"] = np.array([[0, 0, 3.0]])
            pw["overlap"] = np.array([0.1])


def test_read_snapshot_fields(tmp_path):
    path = tmp_path / "snap_1200.h5"
    write_synthetic(path)
    s = read_snapshot(path)
    assert s["step"] == 1200 and s["snapshot"] == 3
    assert s["time"] == pytest.approx(2.4e-3) and s["dt"] == pytest.approx(2e-6)
    assert s["trigger"] == "f_jack[6]" and s["fix"] == "snap" and s["group"] == "all"
    assert (s["trigger_old"], s["trigger_new"]) == (0.0, 1.0)
    p = s["particles"]
    assert p["id"].tolist() == [2, 5, 9]
    assert p["x"].shape == (3, 3) and p["v"][2, 2] == -0.3
    assert p["values"]["f_crush[1]"].tolist() == [1e9, 2e9, 3e9]
    assert p["values"]["c_stress"].shape == (3, 6)
    pp, pw = s["contacts"]["pp"], s["contacts"]["pw"]
    assert pp["id"].tolist() == [[2, 5]]
    assert pp["force"].shape == (1, 3)
    assert pw["meshes"] == ["cone", "shaft"] and pw["wall_fix"] == "pile"
    assert pw["meshes"][pw["mesh"][0]] == "shaft" and pw["triangle"][0] == 17


def test_without_contacts_and_walls(tmp_path):
    write_synthetic(tmp_path / "a_1.h5", contacts=False)
    assert read_snapshot(tmp_path / "a_1.h5")["contacts"] is None
    write_synthetic(tmp_path / "b_1.h5", walls=False, empty_pp=True)
    s = read_snapshot(tmp_path / "b_1.h5")
    assert s["contacts"]["pw"] is None
    # empty data sets come back with their row shapes
    assert s["contacts"]["pp"]["id"].shape == (0, 2)
    assert s["contacts"]["pp"]["force"].shape == (0, 3)
    with pytest.raises(ValueError, match="without contacts"):
        snapshot_particle_stress(read_snapshot(tmp_path / "a_1.h5"))


def _same(a, b, where="snapshot"):
    assert type(a) is type(b) or (np.isscalar(a) and np.isscalar(b)), where
    if isinstance(a, dict):
        assert sorted(a) == sorted(b), where
        for k in a:
            if k != "path":
                _same(a[k], b[k], where + "/" + k)
    elif isinstance(a, np.ndarray):
        assert a.dtype == b.dtype and a.shape == b.shape and np.array_equal(a, b), where
    else:
        assert a == b, where


@pytest.mark.parametrize("kw", [{}, {"contacts": False}, {"walls": False, "empty_pp": True}])
def test_write_snapshot_round_trip(tmp_path, kw):
    """write_snapshot writes what read_snapshot read, bit for bit (the file
    written by the independent h5py writer above is the reference)."""
    write_synthetic(tmp_path / "a_1200.h5", **kw)
    first = read_snapshot(tmp_path / "a_1200.h5")
    write_snapshot(tmp_path / "b_1200.h5", first)
    _same(first, read_snapshot(tmp_path / "b_1200.h5"))


def test_list_snapshots_orders_by_step(tmp_path):
    for step in (25000, 900, 12000):
        write_synthetic(tmp_path / ("run_%d.h5" % step), step=step)
    write_synthetic(tmp_path / "run_other_5.h5", step=5)      # another prefix
    (tmp_path / "run_notes.txt").write_text("x")
    found = list_snapshots(tmp_path / "run")
    assert [s for s, _ in found] == [900, 12000, 25000]
    assert [p.name for _, p in found] == ["run_900.h5", "run_12000.h5", "run_25000.h5"]
    assert [s["step"] for s in read_snapshots(tmp_path / "run")] == [900, 12000, 25000]
    assert list_snapshots(tmp_path / "nothing") == []


def test_particle_stress_known_answer(tmp_path):
    write_synthetic(tmp_path / "s_1.h5")
    s = read_snapshot(tmp_path / "s_1.h5")
    sig = snapshot_particle_stress(s)
    v1 = 4.0 / 3.0 * math.pi
    v9 = 4.0 / 3.0 * math.pi * 0.5 ** 3
    exp = np.zeros((3, 3, 3))
    # grain 2: s = +0.9 x, F = -10 x; grain 5: s = -0.9 x, F = +10 x
    exp[0, 0, 0] = 9.0 / v1
    exp[1, 0, 0] = 9.0 / v1
    # grain 9 on the wall: s = -0.4 z, F = +3 z
    exp[2, 2, 2] = 1.2 / v9
    np.testing.assert_allclose(sig, exp, rtol=1e-12, atol=1e-15)
    no_walls = snapshot_particle_stress(s, walls=False)
    assert np.all(no_walls[2] == 0.0)
    np.testing.assert_allclose(no_walls[:2], exp[:2], rtol=1e-12)


def test_contact_rows(tmp_path):
    write_synthetic(tmp_path / "s_1.h5")
    s = read_snapshot(tmp_path / "s_1.h5")
    assert contact_rows(s, [9, 2, 5]).tolist() == [2, 0, 1]
    with pytest.raises(ValueError):
        contact_rows(s, [3])
