# SPDX-License-Identifier: GPL-2.0-or-later
"""Open a chamber run's VTK series in ParaView (issue 10 item 5).

Run it with ParaView's Python (not /usr/bin/python3)::

    scripts/pvbatch scripts/crushpost/paraview_state.py RUN_DIR [--state run.pvsm] [--png run.png]
    pvpython scripts/crushpost/paraview_state.py RUN_DIR [--state run.pvsm] [--png run.png]
    paraview --script=scripts/crushpost/paraview_state.py      # RUN_DIR from $CRUSH_RUN_DIR

scripts/pvbatch runs Debian's pvbatch, which scripts/setup unpacks into
build/paraview beside python3-vtk9, headless under Xvfb (docs/install.md,
"ParaView"); :func:`render` calls it from an ordinary Python (crushpost
report does, for the report's picture).

It reads the files the decks' vtk_dumps.in block writes into RUN_DIR/post/
(examples/cpt_demo/run.py --vtk particles): the grains
(``post/grains_<step>.vtk``: points with radius, the per-particle stress
components sp_xx ... sp_yz [Pa, compression positive], sigma_lim [Pa] and
generation) and the meshes (``post/meshes_<step>.vtk``: the chamber's walls
and the pile's cone and shaft, with their normal_stress_average [Pa]).
It builds three views side by side, with linked cameras, of the grains
(spheres of their own radius) cut by the vertical plane y = 0 through the
pile axis: the whole grains of the half y >= 0 (where the simulated sectors
of 180 and 90 degrees lie), seen from -y, coloured by

1. the mean stress p = (sp_xx + sp_yy + sp_zz) / 3 [kPa] ("p_kPa"),
2. the strength sigma_lim [MPa] ("sigma_lim_MPa"),
3. the generation (0: an original grain, 1: a fragment of one, ...),

each with the meshes (opacity 0.3, coloured by their normal stress). The
time slider steps through the series. ``--state FILE`` saves a ParaView
state file (File > Load State opens it in the GUI; it holds absolute
paths); ``--png FILE`` saves a picture of the three views side by side,
IMAGE_SIZE pixels. The colour range of each view is that of the last step
(a single value v: v to v + 1).

The module imports without ParaView: the file patterns and the arrays it
uses are constants that tests/integration/test_report_small.py checks
against the VTK files LIGGGHTS writes; tests/integration/test_paraview_state.py
runs it under ParaView.
"""

import glob
import os
import re
import sys

__all__ = ["GRAINS_GLOB", "MESHES_GLOB", "GRAIN_ARRAYS", "MESH_ARRAYS", "VIEWS", "IMAGE_SIZE",
           "grain_files", "mesh_files", "wrapper", "render", "main"]

#: the grains of every dump step (bounding-box files of the dump excluded)
GRAINS_GLOB = os.path.join("post", "grains_*.vtk")
#: all meshes of every dump step (dump mesh/vtk writes them into one file)
MESHES_GLOB = os.path.join("post", "meshes_*.vtk")
#: point arrays of the grains the script uses
GRAIN_ARRAYS = ("radius", "sp_xx", "sp_yy", "sp_zz", "sigma_lim", "generation")
#: cell arrays of the meshes the script uses
MESH_ARRAYS = ("normal_stress_average",)
#: (array shown, calculator function or None, title) of the three views
VIEWS = (("p_kPa", "(sp_xx+sp_yy+sp_zz)/3000", "mean stress p (kPa)"),
         ("sigma_lim_MPa", "sigma_lim/1000000", "strength sigma_lim (MPa)"),
         ("generation", None, "generation (0 = original grain)"))

#: cells of the layout that hold the three views, left to right
CELLS = (1, 5, 6)
#: size of the --png picture (width, height in pixels): the three views side by side
IMAGE_SIZE = (1800, 700)

_STEP = re.compile(r"_(\d+)\.vtk$")


def _series(run_dir, pattern, exclude=None):
    files = [f for f in glob.glob(os.path.join(glob.escape(run_dir), pattern))
             if _STEP.search(f) and not (exclude and exclude in os.path.basename(f))]
    return sorted(files, key=lambda f: int(_STEP.search(f).group(1)))


def grain_files(run_dir):
    """The grains' VTK files of a run, by step."""
    return _series(run_dir, GRAINS_GLOB, exclude="boundingBox")


def mesh_files(run_dir):
    """The meshes' VTK files of a run, by step."""
    return _series(run_dir, MESHES_GLOB)


def wrapper():
    """The command that runs ParaView headless: ``$CRUSH_PVBATCH`` if set,
    else scripts/pvbatch of this checkout (Debian's pvbatch, unpacked by
    scripts/setup into build/paraview, under Xvfb; docs/install.md)."""
    return os.environ.get("CRUSH_PVBATCH") or os.path.join(
        os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "pvbatch")


def render(run_dir, png=None, state=None, timeout=1800):
    """Run this script under ParaView (:func:`wrapper`) on ``run_dir`` from
    an ordinary Python: writes the picture ``png`` and/or the state file
    ``state``. Returns the subprocess.CompletedProcess (text output)."""
    import subprocess
    cmd = [wrapper(), os.path.abspath(__file__), os.path.abspath(run_dir)]
    if png:
        cmd += ["--png", os.path.abspath(png)]
    if state:
        cmd += ["--state", os.path.abspath(state)]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)


def _args(argv):
    import argparse
    ap = argparse.ArgumentParser(description="Open a chamber run's VTK series in ParaView.")
    ap.add_argument("run_dir", nargs="?", default=os.environ.get("CRUSH_RUN_DIR"),
                    help="the run's folder (default $CRUSH_RUN_DIR)")
    ap.add_argument("--state", help="save a ParaView state file (.pvsm)")
    ap.add_argument("--png", help="save a screenshot of the three views")
    # inside the ParaView GUI (--script) argv holds ParaView's own options
    a, _ = ap.parse_known_args(argv)
    if a.run_dir and a.run_dir.startswith("-"):
        a.run_dir = os.environ.get("CRUSH_RUN_DIR")
    if not a.run_dir:
        ap.error("give RUN_DIR (or set CRUSH_RUN_DIR)")
    return a


def main(argv=None):
    a = _args(sys.argv[1:] if argv is None else argv)
    grains, meshes = grain_files(a.run_dir), mesh_files(a.run_dir)
    if not grains:
        sys.stderr.write("paraview_state: no %s in %s (run the scene with --vtk particles)\n"
                         % (GRAINS_GLOB, a.run_dir))
        return 1
    import paraview.simple as pv

    g = pv.LegacyVTKReader(registrationName="grains", FileNames=grains)
    # a vertical cut through the pile axis: the whole grains of the half
    # y >= 0, where every sector the decks simulate lies (180: y >= 0; 90:
    # x, y >= 0), seen from -y (Invert 0 keeps the side the normal points to)
    clip = pv.Clip(registrationName="cut y=0", Input=g)
    clip.ClipType = "Plane"
    clip.ClipType.Origin = [0.0, 0.0, 0.0]
    clip.ClipType.Normal = [0.0, 1.0, 0.0]
    clip.Invert = 0
    clip.Crinkleclip = 1
    m = pv.LegacyVTKReader(registrationName="meshes", FileNames=meshes) if meshes else None
    # three cells side by side: split the whole (cell 0) at a third, then
    # its right part (cell 2) in halves: cells 1, 5 and 6 from left to right
    layout = pv.CreateLayout("chamber run")
    layout.SplitHorizontal(0, 1.0 / 3.0)
    layout.SplitHorizontal(2, 0.5)
    views, shown = [], []
    for cell, (name, function, title) in zip(CELLS, VIEWS):
        src = clip
        if function:
            src = pv.Calculator(registrationName=name, Input=clip)
            src.ResultArrayName = name
            src.Function = function
        glyph = pv.Glyph(registrationName="grains " + name, Input=src, GlyphType="Sphere")
        glyph.ScaleArray = ["POINTS", "radius"]
        glyph.ScaleFactor = 2.0            # the glyph sphere has radius 0.5
        glyph.GlyphMode = "All Points"
        glyph.GlyphType.ThetaResolution = 12
        glyph.GlyphType.PhiResolution = 8
        view = pv.CreateView("RenderView")
        layout.AssignView(cell, view)
        d = pv.Show(glyph, view)
        pv.ColorBy(d, ("POINTS", name))
        d.SetScalarBarVisibility(view, True)
        shown.append((src, name))
        lut = pv.GetColorTransferFunction(name)
        lut.ApplyPreset("Viridis (matplotlib)", True)
        bar = pv.GetScalarBar(lut, view)
        bar.Title = title
        bar.ComponentTitle = ""
        bar.HorizontalTitle = 1
        bar.WindowLocation = "Upper Right Corner"
        bar.ScalarBarLength = 0.4
        if m is not None:
            md = pv.Show(m, view)
            pv.ColorBy(md, ("CELLS", MESH_ARRAYS[0]))
            md.Opacity = 0.3
        view.OrientationAxesVisibility = 1
        view.CameraPosition = [0.0, -1.0, 0.0]
        view.CameraFocalPoint = [0.0, 0.0, 0.0]
        view.CameraViewUp = [0.0, 0.0, 1.0]
        pv.ResetCamera(view)
        views.append(view)
    for k, v in enumerate(views[1:], 1):
        pv.AddCameraLink(views[0], v, "camera%d" % k)
    scene = pv.GetAnimationScene()
    scene.UpdateAnimationUsingDataTimeSteps()
    scene.AnimationTime = scene.EndTime
    # colour ranges of the shown (last) step, not of the first one; a range
    # of one value (say, every grain of generation 0) is widened by 1
    # (ParaView would stretch it to float's largest number)
    if m is not None:
        shown.append((m, MESH_ARRAYS[0]))
    for src, name in shown:
        src.UpdatePipeline(scene.EndTime)
        info = (src.CellData if src is m else src.PointData)[name]
        lo, hi = info.GetRange() if info is not None else (0.0, 0.0)
        lo += 0.0                           # -0.0 -> 0.0
        pv.GetColorTransferFunction(name).RescaleTransferFunction(lo, hi if hi > lo else lo + 1.0)
    pv.SetActiveView(views[0])
    pv.Render()
    if a.state:
        pv.SaveState(a.state)
    if a.png:
        # the layout at the picture's size, so that text keeps its size
        layout.SetSize(*IMAGE_SIZE)
        pv.SaveScreenshot(a.png, layout, ImageResolution=list(IMAGE_SIZE))
    return 0


if __name__ == "__main__":
    status = main()
    if status:          # exit only on failure: inside the ParaView GUI exit would close it
        sys.exit(status)
