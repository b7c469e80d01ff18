# SPDX-License-Identifier: GPL-2.0-or-later
"""scripts/pvbatch, the wrapper that runs ParaView headless (issue 43), with
a stand-in for ParaView (CRUSH_PARAVIEW_ROOT/usr/bin/pvbatch, a shell
script that counts its runs): it runs under an X display of its own with
offscreen rendering and without the caller's PYTHONPATH, a run that aborts
with "bad X server connection" is tried again up to CRUSH_PV_TRIES times,
any other failure is not, and the exit status is the program's. The real
ParaView runs in tests/integration/test_paraview_state.py."""

import os
import shutil
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
WRAPPER = REPO / "scripts" / "pvbatch"

if shutil.which("xvfb-run") is None:
    pytest.fail("xvfb-run is missing: scripts/setup installs xvfb and xauth", pytrace=False)

# fails with MESSAGE (exit 134) while its run count is below GOOD_FROM
FAKE = r"""#!/bin/bash
n=$(( $(cat "$COUNT" 2>/dev/null || echo 0) + 1 ))
echo $n > "$COUNT"
echo "run $n display=${DISPLAY:-none} pythonpath=${PYTHONPATH:-unset} args=$*"
if [ "$n" -lt "$GOOD_FROM" ]; then
    echo "$MESSAGE" >&2
    exit 134
fi
exit 0
"""


def _fake_root(tmp_path, name="pvbatch"):
    root = tmp_path / "pv"
    (root / "usr" / "bin").mkdir(parents=True)
    fake = root / "usr" / "bin" / name
    fake.write_text(FAKE)
    fake.chmod(0o755)
    return root


def _run(tmp_path, root, good_from, message, tries=None, args=("state.py", "RUN")):
    env = dict(os.environ, CRUSH_PARAVIEW_ROOT=str(root), COUNT=str(tmp_path / "count"),
               GOOD_FROM=str(good_from), MESSAGE=message, PYTHONPATH="/nowhere",
               TMPDIR=str(tmp_path))
    if tries is not None:
        env["CRUSH_PV_TRIES"] = str(tries)
    res = subprocess.run([str(WRAPPER)] + list(args), capture_output=True, text=True, env=env,
                         timeout=300)
    count = int((tmp_path / "count").read_text()) if (tmp_path / "count").exists() else 0
    return res, count


def test_no_paraview_says_where_it_should_be(tmp_path):
    res, count = _run(tmp_path, tmp_path / "empty", 1, "")
    assert res.returncode == 127 and count == 0
    assert "scripts/setup" in res.stderr


def test_runs_under_a_display_offscreen_without_pythonpath(tmp_path):
    res, count = _run(tmp_path, _fake_root(tmp_path), 1, "")
    assert res.returncode == 0, res.stderr
    assert count == 1
    line = res.stdout.strip()
    assert "display=:" in line, line                    # xvfb-run's display
    assert "pythonpath=unset" in line, line
    assert "args=--force-offscreen-rendering state.py RUN" in line, line


def test_bad_x_connection_is_tried_again(tmp_path):
    res, count = _run(tmp_path, _fake_root(tmp_path), 2,
                      "ERROR: In vtkXOpenGLRenderWindow.cxx: bad X server connection.")
    assert res.returncode == 0, res.stderr
    assert count == 2
    assert "try 2 of 3" in res.stderr


def test_tries_end_with_the_programs_status(tmp_path):
    res, count = _run(tmp_path, _fake_root(tmp_path), 99, "bad X server connection", tries=2)
    assert res.returncode == 134
    assert count == 2


def test_other_failures_are_not_tried_again(tmp_path):
    res, count = _run(tmp_path, _fake_root(tmp_path), 99, "Traceback: NameError")
    assert res.returncode == 134 and count == 1
    assert "NameError" in res.stderr


def test_pvpython(tmp_path):
    res, count = _run(tmp_path, _fake_root(tmp_path, "pvpython"), 1, "",
                      args=("--pvpython", "x.py"))
    assert res.returncode == 0, res.stderr
    assert "args=x.py" in res.stdout            # pvpython: no offscreen option
