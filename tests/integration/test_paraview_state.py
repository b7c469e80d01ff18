# SPDX-License-Identifier: GPL-2.0-or-later
"""The ParaView state script (scripts/crushpost/paraview_state.py) under
ParaView itself, headless (issue 43): Debian's pvbatch, unpacked by
scripts/setup into build/paraview beside python3-vtk9, run offscreen under
Xvfb by scripts/pvbatch, on the VTK series of a small LIGGGHTS run written
by the decks' own block (inputs/vtk_dumps.in: post/grains_*.vtk,
post/meshes_*.vtk).

The run: 90 NE34-shaped grains dropped into a quarter of a cylindrical cell
(x, y >= 0, as the demo's 90-degree sector; mesh bottom, side and two
symmetry planes) under a cone pile held above them, fix crush/particle on,
three dumps.

Checks against what is known without ParaView:
a. the picture exists, is a PNG of the size asked for (1800 x 700), and is
   neither empty nor of one colour; it holds three views side by side (the
   lines ParaView draws between views: two full-height columns at 1/3 and
   2/3 of the width, no full-width row), and in each view more than 2 % of
   the pixels are not the background (grains, meshes, colour bar); against
   the picture of the same files with every grain's radius set to 0, more
   than 1 % of each view differs (the grains are drawn: a cut that kept the
   empty half y < 0 of the sector drew none);
b. the state file names the run's grain and mesh files (the reader's file
   list) and the three coloured arrays of the script's views;
c. crushpost report on the run folder renders the same picture into the
   report folder and report.html shows it.

ParaView runs one at a time (RUN_SERIAL in tests/CMakeLists.txt; the
wrapper also takes a lock and retries on "bad X server connection").
"""

import json
import math
import os
import shutil
import struct
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import harness  # noqa: E402
from harness import REPO  # noqa: E402

import pile_cell  # noqa: E402
from crushpost import paraview_state  # noqa: E402
from crushpost.meshes import (cylinder_triangles, plate_triangles, rectangle_triangles,  # noqa: E402
                              write_pile_stl, write_stl)
from crushpost.packing import ne34_diameters, rsa_cylinder, write_lammps_data  # noqa: E402

CTEST_TIMEOUT = 2200   # ctest's budget: the LIGGGHTS run (600 s), a render (600 s), the report (900 s)

PVBATCH = REPO / "scripts" / "pvbatch"
STATE_SCRIPT = REPO / "scripts" / "crushpost" / "paraview_state.py"
R_CELL = 0.04
H_RSA = 0.09
H_CELL = 0.15
N_GRAINS = 90
R_PILE = 0.006
DT = 2e-6
STEPS = 10000
VTK_EVERY = 5000
SIZE = (1800, 700)          # three views of 600 x 700 side by side


def deck():
    return f"""\
variable        inputs index {pile_cell.INPUTS}
variable        G_grain index {pile_cell.G_GRAIN!r}
include         ${{inputs}}/base.in
boundary        f f f
read_data       grains.data
include         ${{inputs}}/materials_ne34.in
neighbor        0.002 bin
neigh_modify    delay 0
timestep        {DT!r}
fix             grav all gravity {pile_cell.G_ACC!r} vector 0 0 -1
fix             bottom all mesh/surface/stress file bottom.stl type 3
fix             side all mesh/surface/stress file side.stl type 3
fix             cone all mesh/surface/stress file cone.stl type 2
fix             shaft all mesh/surface/stress file shaft.stl type 2
fix             sym_x all mesh/surface/stress file sym_x.stl type 4
fix             sym_y all mesh/surface/stress file sym_y.stl type 4
fix             walls all wall/gran model hertz tangential history mesh n_meshes 6 &
                meshes bottom side sym_x sym_y cone shaft
include         ${{inputs}}/contacts_local.in
variable        N equal {pile_cell.N_SCALE}
variable        seed equal 15485863
variable        crush_events string breakage_events.txt
include         ${{inputs}}/crushable_ne34.in
include         ${{inputs}}/integrate.in
variable        vtk_every equal {VTK_EVERY}
include         ${{inputs}}/vtk_dumps.in
thermo_style    custom step atoms ke
thermo_modify   lost error
thermo          500
run             {STEPS}
"""


def _run_pv(args, timeout=600):
    return subprocess.run([str(PVBATCH)] + [str(a) for a in args], capture_output=True,
                          text=True, timeout=timeout)


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    if not (REPO / "build" / "paraview" / "usr" / "bin" / "pvbatch").exists() and \
            "CRUSH_PARAVIEW_ROOT" not in os.environ:
        pytest.fail("no ParaView in build/paraview: run scripts/setup (docs/install.md, ParaView)")
    wd = tmp_path_factory.mktemp("paraview_run")
    rng = np.random.default_rng(20260613)
    d = ne34_diameters(N_GRAINS, pile_cell.N_SCALE, rng=rng)
    # a quarter cell (x, y >= 0), as the demo's 90-degree sector
    pos = rsa_cylinder(d, R_CELL, 0.0, H_RSA, rng=rng, sector_deg=90.0)
    L = 1.2 * R_CELL
    write_lammps_data(wd / "grains.data", pos, d, pile_cell.RHO,
                      (-L, L, -L, L, -0.005, 0.2), ntypes=4)
    write_stl(str(wd / "bottom.stl"), plate_triangles(1.1 * R_CELL, 0.0), "bottom")
    r_side = R_CELL / math.cos(math.pi / 32)
    write_stl(str(wd / "side.stl"), cylinder_triangles(r_side, 0.0, H_CELL, 8, phi0=0.0,
                                                       phi1=90.0), "side")
    h, zc = 0.55 * L, 0.5 * H_CELL
    write_stl(str(wd / "sym_x.stl"), rectangle_triangles(0, 0.0, (0.0, h, zc), h, zc), "sym_x")
    write_stl(str(wd / "sym_y.stl"), rectangle_triangles(1, 0.0, (h, 0.0, zc), zc, h), "sym_y")
    write_pile_stl(str(wd), R_PILE, 0.05, tip_z=H_RSA + 0.01, n_seg=16)
    res = harness.run_deck(deck(), wd, nprocs=1, timeout=600, check=True)
    out = wd / "pv"
    out.mkdir()
    png, state = out / "run.png", out / "run.pvsm"
    pv = _run_pv([STATE_SCRIPT, wd, "--png", png, "--state", state])
    # the same run with every grain of radius 0 (drawn as nothing): what
    # differs between the two pictures is the grains
    bare = wd / "no_grains"
    (bare / "post").mkdir(parents=True)
    for f in paraview_state.grain_files(str(wd)):
        _zero_radius(f, bare / "post" / Path(f).name)
    for f in paraview_state.mesh_files(str(wd)):
        shutil.copy(f, bare / "post")
    pv_bare = _run_pv([STATE_SCRIPT, bare, "--png", out / "no_grains.png"])
    return {"wd": wd, "res": res, "pv": pv, "png": png, "state": state, "pv_bare": pv_bare,
            "png_bare": out / "no_grains.png"}


def _zero_radius(src, dst):
    import vtk
    rd = vtk.vtkPolyDataReader()
    rd.SetFileName(str(src))
    rd.ReadAllScalarsOn()
    rd.ReadAllVectorsOn()
    rd.ReadAllFieldsOn()
    rd.Update()
    poly = rd.GetOutput()
    radius = poly.GetPointData().GetArray("radius")
    assert radius is not None and radius.GetNumberOfTuples() == poly.GetNumberOfPoints() > 0
    for i in range(radius.GetNumberOfTuples()):
        radius.SetValue(i, 0.0)
    wr = vtk.vtkPolyDataWriter()
    wr.SetFileName(str(dst))
    wr.SetInputData(poly)
    wr.Write()


def _png_size(path):
    head = Path(path).read_bytes()[:24]
    assert head[:8] == b"\x89PNG\r\n\x1a\n", path
    return struct.unpack(">II", head[16:24])


def _image(path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    img = plt.imread(str(path))                 # floats in [0, 1], H x W x 3 or 4
    return np.asarray(img[..., :3])


def test_the_run_wrote_the_series(run):
    grains = paraview_state.grain_files(str(run["wd"]))
    meshes = paraview_state.mesh_files(str(run["wd"]))
    steps = [int(Path(g).stem.split("_")[-1]) for g in grains]
    assert steps == list(range(0, STEPS + 1, VTK_EVERY))
    assert len(meshes) == len(grains)


def test_pvbatch_writes_a_picture_of_the_three_views(run):
    pv = run["pv"]
    assert pv.returncode == 0, pv.stdout + pv.stderr
    png = run["png"]
    assert png.is_file() and png.stat().st_size > 1000
    assert _png_size(png) == SIZE
    img = _image(png)
    assert img.shape[:2] == (SIZE[1], SIZE[0])
    assert float(img.std()) > 0.01
    assert len(np.unique((img * 255).round().astype(np.uint8).reshape(-1, 3), axis=0)) > 50
    # side by side: ParaView draws a light line between views, here two
    # full-height columns at a third and two thirds of the width, and no
    # full-width row (a view split top/bottom)
    light = img.min(axis=2) > 0.85
    cols = np.flatnonzero(light.all(axis=0))
    runs = np.split(cols, np.flatnonzero(np.diff(cols) > 1) + 1) if cols.size else []
    centres = [float(r.mean()) for r in runs]
    assert len(centres) == 2, centres
    assert abs(centres[0] - SIZE[0] / 3) <= 3 and abs(centres[1] - 2 * SIZE[0] / 3) <= 3, centres
    assert not light.all(axis=1).any()
    edges = [0] + [int(c) for c in centres] + [SIZE[0]]
    for k in range(3):
        panel = img[:, edges[k] + 4:edges[k + 1] - 4]     # the lines left out
        flat = (panel * 255).round().astype(np.uint8).reshape(-1, 3)
        colours, counts = np.unique(flat, axis=0, return_counts=True)
        background = colours[np.argmax(counts)]
        drawn = np.any(flat != background, axis=1).mean()
        # grains, meshes and the colour bar
        assert drawn > 0.02, (k, drawn)


def test_the_grains_are_in_the_picture(run):
    assert run["pv"].returncode == 0 and run["pv_bare"].returncode == 0, run["pv_bare"].stderr
    img, bare = _image(run["png"]), _image(run["png_bare"])
    assert bare.shape == img.shape
    differs = np.abs(img - bare).max(axis=2) > 0.02
    w = SIZE[0] // 3
    for k in range(3):
        # the grains of the half y >= 0 fill part of each view: the quarter
        # cell's ~90 grains cover several % of it (not 0: no grain drawn)
        frac = differs[:, k * w + 4:(k + 1) * w - 4].mean()
        assert frac > 0.01, (k, frac)


def test_state_names_the_run_files_and_arrays(run):
    assert run["pv"].returncode == 0, run["pv"].stderr
    text = run["state"].read_text()
    for f in paraview_state.grain_files(str(run["wd"])) + paraview_state.mesh_files(str(run["wd"])):
        assert f in text, f
    for name, _, _ in paraview_state.VIEWS:
        assert name in text, name


def test_report_renders_the_picture(run):
    wd = run["wd"]
    (wd / "summary.json").write_text(json.dumps({"R_pile_m": R_PILE, "N": pile_cell.N_SCALE,
                                                 "R_chamber_m": R_CELL, "sector_deg": 360}))
    out = wd / "report"
    rep = subprocess.run([sys.executable, "-m", "crushpost", "report", str(wd), "--out", str(out)],
                         capture_output=True, text=True, timeout=900)
    assert "Traceback" not in rep.stderr, rep.stderr
    png = out / "paraview.png"
    assert png.is_file(), rep.stderr
    assert _png_size(png) == SIZE
    assert float(_image(png).std()) > 0.01
    html = (out / "report.html").read_text()
    assert '<img src="paraview.png"' in html
    assert "ParaView picture skipped" not in html
