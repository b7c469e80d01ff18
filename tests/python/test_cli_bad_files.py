# SPDX-License-Identifier: GPL-2.0-or-later
"""Missing, empty, truncated and corrupt files given to the crushpost command
line: one line on stderr that names the file and what is wrong, exit status
1, no traceback; and crushpost.snapshot.read_snapshot on bad HDF5 files."""

import gzip
import os
import subprocess
import sys

import numpy as np
import pytest

from crushpost.cli import main


DUMP = ("ITEM: TIMESTEP\n100\nITEM: NUMBER OF ATOMS\n2\nITEM: BOX BOUNDS ff ff ff\n"
        "0 1\n0 1\n0 1\nITEM: ATOMS id type x y z radius\n1 1 0 0 0 0.001\n2 1 0 0 0 0.001\n")


@pytest.fixture
def files(tmp_path):
    """Bad files of every kind, by name."""
    f = {}

    def put(name, data):
        p = tmp_path / name
        if isinstance(data, bytes):
            p.write_bytes(data)
        else:
            p.write_text(data)
        f[name] = str(p)

    put("empty.txt", "")
    put("blank.txt", "\n  \n")
    # not UTF-8 text: a binary file of fixed content
    put("binary.bin", bytes(range(128, 256)) * 4)
    put("truncated.dump", DUMP[:DUMP.index("2 1 0 0 0")])
    put("header_cut.dump", "ITEM: TIMESTEP\n")
    put("not_a_dump.txt", "hello\n")
    put("good.dump", DUMP)
    put("words.txt", "h q_c\n0.1 2e6\n")
    put("two_points.txt", "0.1 2e6\n0.2 3e6\n")
    put("two_columns.txt", "0 0\n1 1\n")
    put("ragged.txt", "0 0 0\n1 1\n")
    put("events_bad.txt", "500 1e-4 4 0.002 0 0 0 1 0.9 sideways 0\n")
    put("jack_short.txt", "# fix jack/pile jack: mode monotonic\n# step time depth\n1 2\n")
    good_gz = gzip.compress(DUMP.encode())
    put("cut.dump.gz", good_gz[:len(good_gz) // 2])
    put("plain.dump.gz", DUMP)                 # not gzip-compressed
    put("no_thermo.log", "LIGGGHTS (Version 3.8)\nERROR: something\n")
    (tmp_path / "folder").mkdir()
    f["folder"] = str(tmp_path / "folder")
    f["missing"] = str(tmp_path / "missing.txt")
    return f


# (command line with {name} placeholders, bad file's name, words the message must hold)
CASES = [
    ("br {f}", "missing", "no such file"),
    ("br {f}", "empty.txt", "no snapshot"),
    ("br {f}", "binary.bin", "not a text file"),
    ("br {f}", "truncated.dump", "truncated"),
    ("br {f}", "header_cut.dump", "not a LAMMPS text dump"),
    ("br {f}", "not_a_dump.txt", "expected 'ITEM: TIMESTEP'"),
    ("br {f}", "folder", "is a folder"),
    ("br {f}", "cut.dump.gz", "truncated or corrupt gzip file"),
    ("br {f}", "plain.dump.gz", "not a gzip file"),
    ("br {good} --snapshot 5", "good.dump", "no snapshot 5 for --snapshot (the dump has 1)"),
    ("br {good} --initial {f}", "empty.txt", "no snapshot"),
    ("br {good} --events {f}", "missing", "no such file"),
    ("br {good} --events {f}", "events_bad.txt", "partner must be 'particle' or 'wall'"),
    ("br {good} --events {f}", "binary.bin", "not a text file"),
    ("fit-qc {f}", "missing", "no such file"),
    ("fit-qc {f}", "empty.txt", "empty file"),
    ("fit-qc {f}", "blank.txt", "empty file"),
    ("fit-qc {f}", "binary.bin", "not a text file"),
    ("fit-qc {f}", "words.txt", "not a table of h and q_c"),
    ("fit-qc {f}", "two_points.txt", "cannot fit q_c(h)"),
    ("fit-qc {f}", "folder", "is a folder"),
    ("fit-qc {f} --pile-radius 0.01", "jack_short.txt", "at least step, time and depth"),
    ("thermo {f}", "missing", "no such file"),
    ("thermo {f}", "empty.txt", "no thermo block found (empty file)"),
    ("thermo {f}", "no_thermo.log", "no thermo block found"),
    ("thermo {f}", "folder", "is a folder"),
    ("spheres --radius 0.01 --out {tmp}/s.in --centres-file {f}", "missing", "no such file"),
    ("spheres --radius 0.01 --out {tmp}/s.in --centres-file {f}", "empty.txt", "no centre"),
    ("spheres --radius 0.01 --out {tmp}/s.in --centres-file {f}", "binary.bin",
     "not a text file"),
    ("spheres --radius 0.01 --out {tmp}/s.in --centres-file {f}", "two_columns.txt",
     "expected three, x y z"),
    ("spheres --radius 0.01 --out {tmp}/s.in --centres-file {f}", "ragged.txt",
     "not a table of centres x y z"),
    # output paths: a folder that does not exist, a file where a folder must be
    ("spheres --radius 0.01 --centre 0 0 0 --out {f}/s.in", "missing", "No such file"),
    ("pile --radius 0.01 --shaft-length 0.1 --out {f}", "empty.txt", "File exists"),
]


@pytest.mark.parametrize("cmd, bad, words", CASES,
                         ids=["%s-%s" % (c.split()[0], b) for c, b, _ in CASES])
def test_bad_file_is_one_line_naming_it(files, tmp_path, capsys, cmd, bad, words):
    argv = cmd.format(f=files[bad], good=files["good.dump"], tmp=tmp_path).split()
    assert main(argv) == 1
    cap = capsys.readouterr()
    err = cap.err.strip().splitlines()
    assert len(err) == 1, cap.err                 # one line, no warnings, no traceback
    line = err[0]
    assert line.startswith("crushpost %s: error: " % argv[0]), line
    assert files[bad] in line, line              # names the file
    assert words in line, line                   # and what is wrong
    assert cap.out == ""


def test_dash_m_bad_file_no_traceback(files):
    env = dict(os.environ)
    res = subprocess.run([sys.executable, "-m", "crushpost", "br", files["binary.bin"]],
                         capture_output=True, text=True, env=env, timeout=60)
    assert res.returncode == 1
    assert "Traceback" not in res.stderr
    assert res.stderr.strip() == ("crushpost br: error: %s: not a text file (byte 0 is not "
                                  "UTF-8); expected a LAMMPS text dump" % files["binary.bin"])


def test_help_lists_the_commands():
    env = dict(os.environ)
    res = subprocess.run([sys.executable, "-m", "crushpost", "--help"],
                         capture_output=True, text=True, env=env, timeout=60)
    assert res.returncode == 0
    for command in ("br", "fit-qc", "thermo", "pile", "spheres"):
        assert "    %s " % command in res.stdout, res.stdout


# ---------------------------------------------------------------------------
# HDF5 snapshots (library reader)
# ---------------------------------------------------------------------------

def _snapshot_file(path):
    h5py = pytest.importorskip("h5py")
    with h5py.File(str(path), "w") as f:
        f.attrs["step"] = 10
        g = f.create_group("particles")
        g["id"] = np.arange(1, 201)
        g["x"] = np.zeros((200, 3))
        g["radius"] = np.full(200, 1e-3)


@pytest.mark.parametrize("kind", ["empty", "truncated", "garbage", "not_a_snapshot"])
def test_read_snapshot_bad_file_names_it(tmp_path, kind):
    from crushpost.snapshot import read_snapshot
    h5py = pytest.importorskip("h5py")
    good = tmp_path / "good_10.h5"
    _snapshot_file(good)
    data = good.read_bytes()
    bad = tmp_path / ("bad_%s_10.h5" % kind)
    if kind == "empty":
        bad.write_bytes(b"")
    elif kind == "truncated":
        bad.write_bytes(data[:len(data) // 2])
    elif kind == "garbage":
        bad.write_bytes(bytes(range(256)) * 8)
    else:
        with h5py.File(str(bad), "w") as f:
            f["other"] = np.zeros(3)
    with pytest.raises(ValueError) as exc:
        read_snapshot(bad)
    msg = str(exc.value)
    assert msg.startswith(str(bad) + ": "), msg
    assert len(msg.splitlines()) == 1, msg
    if kind == "truncated":
        assert "truncated" in msg
    if kind == "not_a_snapshot":
        assert "no 'particles' group" in msg
    assert read_snapshot(good)["particles"]["x"].shape == (200, 3)


def test_read_snapshot_missing_file(tmp_path):
    from crushpost.snapshot import read_snapshot
    pytest.importorskip("h5py")
    with pytest.raises(FileNotFoundError) as exc:
        read_snapshot(tmp_path / "nope_10.h5")
    assert exc.value.filename == str(tmp_path / "nope_10.h5")
    with pytest.raises(ValueError, match="is a folder"):
        read_snapshot(tmp_path)
