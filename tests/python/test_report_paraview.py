# SPDX-License-Identifier: GPL-2.0-or-later
"""crushpost report's ParaView picture (issue 43), with a stand-in for
scripts/pvbatch (CRUSH_PVBATCH, a shell script that logs its arguments and
copies a known PNG to its --png argument): a run with a VTK series gets
paraview.png from paraview_state.py run on the run folder, shown in
report.html; a run without one, or a ParaView that fails, gets a line
saying why, and the rest of the report. The real ParaView draws it in
tests/integration/test_paraview_state.py."""

import json
import os
import subprocess
import sys

import pytest

pytest.importorskip("h5py")

from crushpost import paraview_state  # noqa: E402

FAKE = r"""#!/bin/bash
printf '%s\n' "$@" > "$ARGS_LOG"
[ -n "${FAIL:-}" ] && { echo "pvbatch: no ParaView in /x" >&2; exit 127; }
while [ $# -gt 0 ]; do
    [ "$1" = "--png" ] && cp "$PNG_IN" "$2"
    shift
done
"""


def _run_folder(base, vtk=True):
    run = base / "run"
    (run / "post").mkdir(parents=True)
    (run / "summary.json").write_text(json.dumps({"R_pile_m": 0.006, "N": 39}))
    if vtk:
        for step in (0, 500, 1000):
            (run / "post" / ("grains_%d.vtk" % step)).write_text("# vtk DataFile\n")
            (run / "post" / ("meshes_%d.vtk" % step)).write_text("# vtk DataFile\n")
        (run / "post" / "grains_boundingBox_0.vtk").write_text("# vtk DataFile\n")
    return run


def _report(tmp_path, run, fail=False):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    png_in = tmp_path / "known.png"
    plt.imsave(str(png_in), [[0.0, 1.0], [1.0, 0.0]], cmap="gray")
    fake = tmp_path / "fake_pvbatch"
    fake.write_text(FAKE)
    fake.chmod(0o755)
    env = dict(os.environ, CRUSH_PVBATCH=str(fake), ARGS_LOG=str(tmp_path / "args"),
               PNG_IN=str(png_in))
    if fail:
        env["FAIL"] = "1"
    out = tmp_path / "report"
    res = subprocess.run([sys.executable, "-m", "crushpost", "report", str(run), "--out", str(out)],
                         capture_output=True, text=True, env=env, timeout=300)
    assert "Traceback" not in res.stderr, res.stderr
    args = (tmp_path / "args").read_text().splitlines() if (tmp_path / "args").exists() else None
    return res, out, args, png_in


def test_the_picture_is_made_and_shown(tmp_path):
    run = _run_folder(tmp_path)
    res, out, args, png_in = _report(tmp_path, run)
    assert args == [os.path.abspath(paraview_state.__file__), str(run.resolve()),
                    "--png", str((out / "paraview.png").resolve()),
                    "--state", str((out / "paraview.pvsm").resolve())]
    assert (out / "paraview.png").read_bytes() == png_in.read_bytes()
    html = (out / "report.html").read_text()
    assert '<img src="paraview.png"' in html
    assert "grains_1000.vtk" in html            # the step shown: the last one
    assert "ParaView picture skipped" not in html


def test_no_vtk_series_says_so(tmp_path):
    run = _run_folder(tmp_path, vtk=False)
    res, out, args, _ = _report(tmp_path, run)
    assert args is None                          # ParaView not started
    assert not (out / "paraview.png").exists()
    html = (out / "report.html").read_text()
    assert "ParaView picture skipped: no " in html and "--vtk particles" in html
    assert "ParaView picture skipped" in res.stderr


def test_a_failing_paraview_says_why_and_the_report_goes_on(tmp_path):
    run = _run_folder(tmp_path)
    res, out, args, _ = _report(tmp_path, run, fail=True)
    assert args is not None
    assert not (out / "paraview.png").exists()
    html = (out / "report.html").read_text()
    assert "exited 127: pvbatch: no ParaView in /x" in html
    assert '<img src="paraview.png"' not in html
    assert (out / "fields.h5").exists()
