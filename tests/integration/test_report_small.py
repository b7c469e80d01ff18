# SPDX-License-Identifier: GPL-2.0-or-later
"""``python3 -m crushpost report`` on a real LIGGGHTS run (issue 10 items 1-5):
a small cell of NE34-shaped grains settled under 100 g (tests/integration/
pile_cell.py), a cone pile jacked in cyclically at 2 MPI ranks with weak
grains that break under it, HDF5 snapshots at the prepared state and at the
end of every push and pause, measurement spheres, and the VTK series for
ParaView.

Checks against independent answers:
a. the report runs on the folder and makes every figure; its states are
   the snapshots, with the kinds that jack.txt's phases give;
b. the per-particle stress the report computes from the snapshot's
   contacts (pair and wall) equals LIGGGHTS' own compute stress/grain
   written into the snapshot (c_sigma_p, symmetric part);
c. the Br of the whole sample from the last snapshot and the event log
   (crushpost.fields.cell_breakage) equals the fix's Br in the log;
d. the solid volume of the rings adds up to the grains' volume inside the
   grid;
e. the VTK files hold the arrays the ParaView script
   (crushpost/paraview_state.py) names, one value per grain (the atom count
   of the log at that step) and the meshes' cells (the STL triangles);
   the script itself runs under ParaView in test_paraview_state.py.
f. the strengths and generations of the VTK files and of the snapshots are
   the fix's own per-atom values (a dump of f_crush[1], f_crush[2]):
   fragments have generation 1 or more, original grains 0, and the
   strengths follow the drawn scatter (mean 1, sd 0.36).
"""

import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import harness  # noqa: E402

import pile_cell  # noqa: E402
from crushpost import paraview_state  # noqa: E402
from crushpost.materials import D50  # noqa: E402
from crushpost.dump import read_crush_log  # noqa: E402
from crushpost.fields import cell_breakage  # noqa: E402
from crushpost.meshes import (cylinder_triangles, plate_triangles, read_stl,  # noqa: E402
                              write_pile_stl, write_stl)
from crushpost.rings import ring_fields  # noqa: E402
from crushpost.snapshot import list_snapshots, read_snapshot, snapshot_particle_stress  # noqa: E402
from crushpost.spheres import write_sphere_block  # noqa: E402
from crushpost.thermo import read_log  # noqa: E402

h5py = pytest.importorskip("h5py")
vtk = pytest.importorskip("vtk")

R_CELL = 0.03
H_PACK = 0.035
H_RSA = 0.075
DT = 2e-6
SETTLE_STEPS = 15000
R_PILE = 0.006
N_SEG = 16
SHAFT_LENGTH = 0.06
N_SCALE = 39
# weak grains (sigma_lim0 8e7 Pa instead of the calibrated 1.9 GPa): a few break when the fix
# starts, about ten more while the cone goes in (5e7: the cell collapses)
SIGMA_LIM0 = 8e7
# strokes of 7 mm: the cone meets the grains after about 4.5 mm (the weakest
# grains under it break when the fix starts)
V, S, VU, T_PAUSE, ZERO_TOL = 0.5, 0.007, 0.5, 2e-4, 0.05
DEPTH = 2 * S
VTK_EVERY = 4000


N_SEG_SIDE = 64


def write_cell_meshes(wd):
    """The cell's bottom and side as meshes (compute stress/grain needs every
    wall's contacts, which primitive walls do not list): a plate at z = 0 and
    a polygon circumscribed about the settling cylinder."""
    write_stl(str(wd / "bottom.stl"), plate_triangles(1.1 * R_CELL, 0.0), "bottom")
    r_side = R_CELL / math.cos(math.pi / N_SEG_SIDE)
    write_stl(str(wd / "side.stl"), cylinder_triangles(r_side, 0.0, 0.15, N_SEG_SIDE), "side")


def jack_deck():
    return f"""\
variable        inputs index {pile_cell.INPUTS}
variable        G_grain index {pile_cell.G_GRAIN!r}
include         ${{inputs}}/base.in
boundary        f f f
read_data       settled.data
include         ${{inputs}}/materials_ne34.in
neighbor        0.002 bin
neigh_modify    delay 0
timestep        {DT!r}
fix             grav all gravity {pile_cell.G_ACC!r} vector 0 0 -1
fix             bottom all mesh/surface/stress file bottom.stl type 3
fix             side all mesh/surface/stress file side.stl type 3
fix             cone all mesh/surface/stress file cone.stl type 2
fix             shaft all mesh/surface/stress file shaft.stl type 2
fix             walls all wall/gran model hertz tangential history mesh n_meshes 4 &
                meshes bottom side cone shaft
include         ${{inputs}}/contacts_local.in
variable        N equal {N_SCALE}
variable        d50 equal {D50!r}*${{N}}
fix             crush all crush/particle sigma_lim0 {SIGMA_LIM0!r} m 10 d0 2e-3 scale ${{N}} &
                var 0.36 d_comm $(0.55*v_d50) seed 15485863 br d_max $(0.27e-3*v_N) &
                d_min $(0.01e-3*v_N) omega 2.6 events breakage_events.txt
variable        n_break equal f_crush[1]
variable        fines equal f_crush[3]
variable        Br equal f_crush[5]
compute         crush_atom all crush/atom crush
variable        sigma_lim atom c_crush_atom[1]
variable        generation atom c_crush_atom[2]
variable        mass_true atom c_crush_atom[3]
variable        utilisation atom c_crush_atom[4]
variable        m_atom atom v_mass_true
compute         M_grains all reduce sum v_m_atom
include         ${{inputs}}/integrate.in
include         ${{inputs}}/snapshot_prep.in
fix             jack all jack/pile cone cone shaft shaft mode cyclic v {V} stroke {S} &
                v_unload {VU} pause {T_PAUSE} depth {DEPTH} zero_tol {ZERO_TOL} file jack.txt every 20
variable        zero equal 0
variable        vz equal f_jack[1]
fix             mv_cone all move/mesh mesh cone linear/variable v_zero v_zero v_vz
fix             mv_shaft all move/mesh mesh shaft linear/variable v_zero v_zero v_vz
variable        qc equal f_jack[3]/(PI*{R_PILE!r}^2)
variable        phase equal f_jack[6]
variable        vtk_every equal {VTK_EVERY}
include         ${{inputs}}/snapshots_hdf5.in
include         ${{inputs}}/vtk_dumps.in
# the fix's own per-atom array at the VTK steps, the reference for the
# strengths and generations that the snapshots and VTK files carry
dump            fix_ref all custom ${{vtk_every}} post/fix_*.txt id radius f_crush[1] f_crush[2]
dump_modify     fix_ref sort id format "%d %.17g %.17g %.17g"
include         spheres.in
thermo_style    custom step time atoms f_jack[2] v_qc f_jack[4] f_jack[6] v_n_break v_fines v_Br c_M_grains
thermo_modify   lost error format float %.15g
thermo          200
label           jacking
run             2000
if              "${{phase}} < 3" then "jump SELF jacking"
print           "CELL done"
"""


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    wd = tmp_path_factory.mktemp("report_cell")
    _, atoms = pile_cell.settle(wd, R_CELL, H_PACK, H_RSA, DT, SETTLE_STEPS, seed=20240613,
                                z_box_top=0.16)
    # the apex 0.1 mm above the highest grain top over the cone's footprint
    r = 0.5 * atoms[:, 2]
    rho = np.hypot(atoms[:, 4], atoms[:, 5])
    near = rho < R_PILE + r
    z_top = float(np.max((atoms[:, 6] + r)[near]))
    write_pile_stl(str(wd), R_PILE, SHAFT_LENGTH, tip_z=z_top + 1e-4, n_seg=N_SEG)
    write_cell_meshes(wd)
    # two measurement spheres beside the pile path
    write_sphere_block(str(wd / "spheres.in"), [[0.015, 0.0, z_top - 0.008],
                                                [0.0, 0.015, z_top - 0.016]],
                       0.005, 100, "spheres.txt")
    res = harness.run_deck(jack_deck(), wd, nprocs=2, timeout=600, check=True)
    # the driver's summary.json, the part the report reads
    (wd / "summary.json").write_text(
        '{"R_pile_m": %r, "N": %d, "R_chamber_m": %r, "sector_deg": 360, "mode": "cyclic"}'
        % (R_PILE, N_SCALE, R_CELL))
    if harness.LOG_NAME != "log.liggghts":
        (wd / "log.liggghts").write_text(res.log)
    out = wd / "report"
    env = dict(os.environ)
    rep = subprocess.run([sys.executable, "-m", "crushpost", "report", str(wd), "--out", str(out),
                          "--ring-height", "0.01", "--ring-width", "0.006", "--min-grains", "10",
                          "--history-r", "2", "3"],
                         capture_output=True, text=True, env=env, timeout=600)
    return {"wd": wd, "out": out, "rep": rep, "res": res}


def test_report_runs_and_makes_every_figure(run):
    rep = run["rep"]
    assert rep.returncode == 0, rep.stderr
    assert "Traceback" not in rep.stderr
    made = set(os.listdir(run["out"]))
    for name in ("qc_depth.png", "initial_state.png", "stress_push1.png", "stress_pause1.png",
                 "stress_push2.png", "radial_profiles.png", "stress_history.png", "rotation.png",
                 "br_bands.png", "psd.png", "radial_increments.png", "breakage_density.png",
                 "spheres_q_over_p.png", "report.html", "fields.h5"):
        assert name in made, (name, rep.stderr)
    with h5py.File(run["out"] / "fields.h5", "r") as f:
        kinds = [k.decode() for k in f["states/kind"][()]]
        steps = f["states/step"][()]
    jack = np.loadtxt(run["wd"] / "jack.txt", comments="#", ndmin=2)
    # the jack snapshots are the steps where the phase leaves push or pause
    phase = jack[:, 6].astype(int)
    left = [(int(jack[k, 0]), int(phase[k - 1])) for k in range(1, len(phase))
            if phase[k] != phase[k - 1] and phase[k - 1] in (0, 2)]
    assert kinds[0] == "initial"
    assert [(int(s), k) for s, k in zip(steps[1:], kinds[1:])] == [
        (s, "push_end" if p == 0 else "pause_end") for s, p in left]


def test_particle_stress_equals_compute_stress_grain(run):
    for _, path in list_snapshots(run["wd"] / "snapshots" / "jack")[-1:] + \
            list_snapshots(run["wd"] / "snapshots" / "prep"):
        snap = read_snapshot(path)
        sig = snapshot_particle_stress(snap)
        sym = 0.5 * (sig + np.swapaxes(sig, 1, 2))
        lig = snap["particles"]["values"]["c_sigma_p"]       # xx yy zz xy xz yz, skew ...
        comp = np.stack([sym[:, 0, 0], sym[:, 1, 1], sym[:, 2, 2], sym[:, 0, 1], sym[:, 0, 2],
                         sym[:, 1, 2]], axis=1)
        scale = np.abs(lig[:, :6]).max()
        assert scale > 0
        assert np.allclose(comp, lig[:, :6], rtol=1e-6, atol=1e-9 * scale), path


def test_sample_br_equals_the_fix(run):
    wd = run["wd"]
    last = read_snapshot(list_snapshots(wd / "snapshots" / "jack")[-1][1])
    ev = read_crush_log(wd / "breakage_events.txt")
    prep_step = list_snapshots(wd / "snapshots" / "prep")[0][0]
    assert np.sum(ev["step"] > prep_step) >= 3, "the weak grains should break under the cone"
    blocks = [b for b in read_log(wd / "log.liggghts") if "Br" in b]
    step_end, br_log = blocks[-1]["Step"][-1], blocks[-1]["Br"][-1]
    # the fix's Br at the end counts every event against the grading when
    # the fix was created (settled.data); the snapshot has the grains at its
    # step: no event may fall between it and the end
    assert np.all(ev["step"] <= last["step"]), (last["step"], step_end)
    d0 = pile_cell.data_atoms(wd / "settled.data")[:, 2]
    d1 = 2 * last["particles"]["radius"]
    br, _, _ = cell_breakage(np.zeros(d1.size, int), d1, np.zeros(d0.size, int), d0, 1,
                             0.01e-3 * N_SCALE, 0.27e-3 * N_SCALE, np.zeros(ev["step"].size, int),
                             ev["parent_diameter"])
    assert br_log > 0
    assert br[0] == pytest.approx(br_log, rel=1e-10)


def test_ring_solid_volume_adds_up(run):
    snap = read_snapshot(list_snapshots(run["wd"] / "snapshots" / "prep")[0][1])
    x, r = snap["particles"]["x"], snap["particles"]["radius"]
    r_edges = np.linspace(0.0, R_CELL + 0.01, 7)
    z_edges = np.linspace(-0.01, 0.2, 9)
    rf = ring_fields(None, x, r, r_edges, z_edges)
    assert rf["V_solid"].sum() == pytest.approx(np.sum(4 / 3 * np.pi * r ** 3), rel=1e-9)
    assert rf["n_grains"].sum() == len(r)


def _read_vtk(path):
    rd = vtk.vtkPolyDataReader()
    rd.SetFileName(str(path))
    rd.ReadAllScalarsOn()
    rd.ReadAllVectorsOn()
    rd.ReadAllFieldsOn()
    rd.Update()
    return rd.GetOutput()


def _point_array(pd, name):
    """A VTK point-data array as a numpy array (one value per grain)."""
    arr = pd.GetArray(name)
    return np.array([arr.GetValue(i) for i in range(arr.GetNumberOfTuples())])


def test_strengths_and_generations_are_the_fixs_per_atom_values(run):
    """The strength and generation that the VTK files and the HDF5 snapshots
    carry for each grain (atom variables over compute crush/atom) are the
    fix's own per-atom values (its array f_crush[1], f_crush[2], dumped at
    the VTK steps); fragments (new tags) have generation 1 or more and the
    original grains 0; and the strengths follow the drawn scatter,
    f = sigma_lim / (sigma_lim0 (d / (N d0))^(-3/m)) ~ Normal(1, 0.36)."""
    wd = run["wd"]
    ref = {f.timestep: f for f in harness.read_dumps(wd / "post", "fix_*.txt")}
    n0 = int(max(pile_cell.data_atoms(wd / "settled.data")[:, 0]))
    grains = paraview_state.grain_files(str(wd))
    assert grains and set(int(Path(g).stem.split("_")[-1]) for g in grains) <= set(ref)
    for gpath in grains:
        f = ref[int(Path(gpath).stem.split("_")[-1])]
        pd = _read_vtk(gpath).GetPointData()
        col = {name: _point_array(pd, name) for name in ("id", "sigma_lim", "generation")}
        order = np.argsort(col["id"], kind="stable")
        assert np.array_equal(col["id"][order], f["id"])
        np.testing.assert_allclose(col["sigma_lim"][order], f["f_crush[1]"], rtol=1e-6)
        assert np.array_equal(col["generation"][order], f["f_crush[2]"])
    steps = sorted(ref)
    for _, path in list_snapshots(wd / "snapshots" / "jack"):
        snap = read_snapshot(path)
        p = snap["particles"]
        f = ref[steps[min(np.searchsorted(steps, snap["step"]), len(steps) - 1)]]
        # grains still there, unbroken, at the next reference step
        common, i_s, i_r = np.intersect1d(p["id"], f["id"].astype(np.int64), return_indices=True)
        same = p["radius"][i_s] == f["radius"][i_r]
        assert np.count_nonzero(same) > 0.9 * len(p["id"])
        np.testing.assert_array_equal(p["values"]["v_sigma_lim"][i_s][same], f["f_crush[1]"][i_r][same])
        np.testing.assert_array_equal(p["values"]["v_generation"][i_s][same], f["f_crush[2]"][i_r][same])
    last = ref[steps[-1]]
    fragment = last["id"] > n0
    assert np.count_nonzero(fragment) >= 13, "the test needs breaks"
    assert np.array_equal(last["f_crush[2]"] >= 1, fragment)
    assert np.count_nonzero(last["f_crush[2]"] == 1) > 0
    fac = last["f_crush[1]"] / (SIGMA_LIM0 * (2 * last["radius"] / (N_SCALE * 2e-3)) ** (-0.3))
    assert abs(fac.mean() - 1) < 4 * 0.36 / math.sqrt(fac.size) + 0.01
    assert fac.std(ddof=1) == pytest.approx(0.36, rel=0.15)
    assert fac.min() > 0


def test_vtk_files_hold_what_the_paraview_script_uses(run):
    wd = run["wd"]
    grains = paraview_state.grain_files(str(wd))
    meshes = paraview_state.mesh_files(str(wd))
    assert len(grains) >= 2 and len(meshes) == len(grains)
    assert not any("boundingBox" in g for g in grains)
    blocks = read_log(wd / "log.liggghts")
    atoms_at = {int(s): int(a) for b in blocks if "Atoms" in b
                for s, a in zip(b["Step"], b["Atoms"])}
    n_tri = sum(len(read_stl(wd / name)[0]) for name in ("bottom.stl", "side.stl", "cone.stl",
                                                         "shaft.stl"))
    for gpath, mpath in zip(grains, meshes):
        step = int(Path(gpath).stem.split("_")[-1])
        g = _read_vtk(gpath)
        pd = g.GetPointData()
        names = {pd.GetArrayName(i) for i in range(pd.GetNumberOfArrays())}
        assert set(paraview_state.GRAIN_ARRAYS) <= names, names
        for name in paraview_state.GRAIN_ARRAYS:
            assert pd.GetArray(name).GetNumberOfTuples() == g.GetNumberOfPoints()
        if step in atoms_at:
            assert g.GetNumberOfPoints() == atoms_at[step]
        gen = _point_array(pd, "generation")
        assert np.all(gen >= 0) and np.all(gen == np.round(gen))
        # per grain, not one global number for all (an atom variable f_crush[1]
        # read the fix's global vector: every grain had the run's event count)
        sig = _point_array(pd, "sigma_lim")
        assert np.unique(sig).size > 0.9 * sig.size, np.unique(sig)[:5]
        assert np.count_nonzero(gen == 0) > 0.5 * gen.size
        m = _read_vtk(mpath)
        cd = m.GetCellData()
        assert set(paraview_state.MESH_ARRAYS) <= {cd.GetArrayName(i)
                                                   for i in range(cd.GetNumberOfArrays())}
        # the meshes the deck has: bottom, side, cone and shaft
        assert m.GetNumberOfCells() == n_tri
    # the script's calculator functions use arrays the grains have
    for name, function, _ in paraview_state.VIEWS:
        if function:
            used = set(w for w in __import__("re").findall(r"[A-Za-z_]\w*", function))
            assert used <= names, (name, used)
        else:
            assert name in names
