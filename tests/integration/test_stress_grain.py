# SPDX-License-Identifier: GPL-2.0-or-later
"""`compute stress/grain`: the per-particle stress of docs/model.md §4.7,
sigma_p = -(1/V_p) sum_c s^c (x) F^c over every contact, walls included
(docs/compute_stress_grain.md), as the chamber decks define it
(inputs/contacts_local.in: c_sigma_p from c_pgl and c_wgl).

1. One grain squeezed between two steel mesh plates (no gravity, no damping):
   at every output step sigma_zz = 3 [(r - d_t) F_t + (r - d_b) F_b] / (4 pi r^3)
   with the Hertz forces F of the overlaps d from the dumped position and the
   top plate's position (docs/model.md §2.1; E* of grain and steel), to 1e-9;
   that is 3 F / (2 pi r^2) to first order in d/r (within 3 % here); every
   other component (skew part included) is zero.
   The same with a fragment (r_s = 0.23 r, the small Apollonian fragment) on
   the grain: each one's sigma_zz = 3 sum_c |s_c| F_c / (4 pi r^3) with |s_c|
   the distance to the plate, or to the pair's contact point
   c = (r_j x_i + r_i x_j)/(r_i + r_j) (LIGGGHTS' point). The pair virial
   (half the branch vector) would read the fragment 1.8 times higher.
2. A closed box: about 130 NE34 grains (N = 39) grown by fix adapt inside six
   frictionless mesh plates, then run without damping or gravity. The
   contact terms of a pair cancel in the sum over grains (same contact point,
   opposite forces), so exactly
       sum_p V_p sigma_p = -(sum_walls x_c (x) F_w - sum_p x_p (x) f_p),
   x_c, F_w the wall contacts (dump local of c_wgl), f_p the force on grain p
   (the sum of its contact forces: nothing else acts), all 9 components to
   1e-9 of their scale; its diagonal is also checked against the plates'
   own force totals (mesh/surface/stress) times their positions.
3. The same box at 1 and 2 MPI ranks (the x = 0 subdomain boundary cuts the
   box): the per-grain stresses agree to 1e-9 at the first output and stay
   within 1e-6 after 200 steps (round-off of the force sums grows).
4. fix snapshot/hdf5 in the same deck writes c_sigma_p and the contacts: the
   stress crushpost.snapshot.snapshot_particle_stress computes from the
   snapshot's contacts (walls included) equals the compute's, to 1e-10.

Each check fails on the old block (compute stress/atom pair: half the branch
vector, no walls): 1 reads zero (no pair contacts), 2 misses the wall terms.
"""

import math
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import crush_decks as cd  # noqa: E402
import harness  # noqa: E402

from crushpost.materials import E_STEEL, NU_STEEL, RHO_GRAIN  # noqa: E402
from crushpost.meshes import axis_plate_triangles, plate_triangles, write_stl  # noqa: E402
from crushpost.packing import D50_NE34, ne34_diameters, rsa_box, write_lammps_data  # noqa: E402

INPUTS = harness.REPO / "inputs"
N = 39
D50 = D50_NE34 * N
E_STEEL_NE34 = E_STEEL                       # materials_ne34.in: G_steel 85 GPa, nu 0.2
E_STAR_STEEL = cd.effective_modulus(cd.E_GRAIN, cd.NU_GRAIN, E_STEEL_NE34, NU_STEEL)
STRESS_COLS = " ".join("c_sigma_p[%d]" % k for k in range(1, 10))
DUMP_FMT = "%d" + " %.17g" * 16


def full_tensor(cols):
    """(n, 3, 3) tensors from the 9 columns of stress/grain (symmetric part
    xx yy zz xy xz yz, then skew xy xz yz)."""
    c = np.asarray(cols, dtype=float).reshape(-1, 9)
    t = np.empty((len(c), 3, 3))
    t[:, 0, 0], t[:, 1, 1], t[:, 2, 2] = c[:, 0], c[:, 1], c[:, 2]
    for (a, b), sym, skew in (((0, 1), 3, 6), ((0, 2), 4, 7), ((1, 2), 5, 8)):
        t[:, a, b] = c[:, sym] + c[:, skew]
        t[:, b, a] = c[:, sym] - c[:, skew]
    return t


def stress_of(frame):
    return full_tensor(np.column_stack([frame["c_sigma_p[%d]" % k] for k in range(1, 10)]))


# ---------------------------------------------------------------------------
# 1. one grain between two plates
# ---------------------------------------------------------------------------

R1 = 0.5 * D50
R_FRAG = 0.230093 * R1             # the small fragment of an Apollonian break
X1, Y1 = 0.0031, -0.0017           # off the axis and off the plates' diagonals
V_PLATE = 0.2
DT1 = 2e-7
STEPS1 = 3000
EVERY1 = 300
PRESS = 1e-6                       # the plates' total overlap at the start

SINGLE = """\
variable inputs index {inputs}
include ${{inputs}}/base.in
boundary f f f
region box block -0.02 0.02 -0.02 0.02 -0.001 0.025 units box
create_box 4 box
include ${{inputs}}/materials_ne34.in
neighbor 0.0005 bin
neigh_modify delay 0
timestep {dt!r}
{atoms}
fix bottom all mesh/surface/stress file bottom.stl type 2
fix top    all mesh/surface/stress file top.stl type 2 reference_point 0 0 {ztop!r}
fix walls  all wall/gran model hertz tangential history mesh n_meshes 2 meshes bottom top
fix mv all move/mesh mesh top linear 0 0 {v!r}
fix integrate all nve
include ${{inputs}}/contacts_local.in
variable ztop equal f_top[9]
thermo_style custom step v_ztop
thermo_modify format float %.17g lost error
thermo {every}
dump d all custom {every} grain.*.txt id radius x y z fx fy fz {cols}
dump_modify d format "{fmt}" sort id
run {steps}
"""

STACKS = {"grain": [R1], "fragment_on_grain": [R1, R_FRAG]}


def run_stack(wd, radii):
    """The stack of `radii` between the two plates, run in the folder `wd`:
    (radii, frames, z_top_at) as test_stack_between_plates checks it (also
    the smoke run of test_install_tree.py)."""
    write_stl(wd / "bottom.stl", plate_triangles(0.015, 0.0), "bottom")
    # touching, then the plates' overlap PRESS shared out
    z = np.cumsum(2 * np.array(radii)) - np.array(radii) - PRESS / (2 * len(radii))
    z_top = 2 * sum(radii) - PRESS
    write_stl(wd / "top.stl", plate_triangles(0.015, z_top), "top")
    atoms = "".join("create_atoms 1 single {x!r} {y!r} {z!r} units box\n"
                    "set atom {k} diameter {d!r} density {rho:g}\n"
                    .format(x=X1, y=Y1, z=zk, k=k + 1, d=2 * rk, rho=RHO_GRAIN)
                    for k, (rk, zk) in enumerate(zip(radii, z)))
    deck = SINGLE.format(inputs=INPUTS, dt=DT1, atoms=atoms, ztop=z_top, v=-V_PLATE,
                         every=EVERY1, cols=STRESS_COLS, fmt=DUMP_FMT, steps=STEPS1)
    res = cd.run(deck, wd, nprocs=1, timeout=120)
    frames = [harness.read_dump(p)[0] for p in sorted(wd.glob("grain.*.txt"),
                                                      key=lambda p: int(p.name.split(".")[1]))]
    th = res.thermo[0]
    z_top_at = dict(zip(th["Step"].astype(int), th["v_ztop"]))
    return np.array(radii), frames, z_top_at


@pytest.fixture(scope="module", params=sorted(STACKS))
def stack(request, tmp_path_factory):
    return run_stack(tmp_path_factory.mktemp(request.param), STACKS[request.param])


def stack_stress_zz(radii, z, z_top):
    """sigma_zz of each grain of a vertical stack between the plate z = 0 and
    the plate z_top: 3 sum_c |s_c| F_c / (4 pi r^3), Hertz forces (docs/model.md
    §2.1), s_c to the plate or to LIGGGHTS' pair contact point."""
    n = len(radii)
    out = np.zeros(n)
    # bottom and top plates
    for k, gap in ((0, z[0]), (n - 1, z_top - z[-1])):
        d = radii[k] - gap
        out[k] += gap * float(cd.hertz_force(d, radii[k], E_STAR_STEEL))
    for k in range(n - 1):
        dist = z[k + 1] - z[k]
        d = radii[k] + radii[k + 1] - dist
        E_pair = 0.5 * cd.E_GRAIN / (1 - cd.NU_GRAIN ** 2)
        F = float(cd.hertz_force(d, cd.effective_radius(radii[k], radii[k + 1]), E_pair))
        for g in (k, k + 1):
            out[g] += dist * radii[g] / (radii[k] + radii[k + 1]) * F
    return 3.0 * out / (4.0 * math.pi * radii ** 3)


def test_stack_between_plates(stack):
    radii, frames, z_top_at = stack
    checked = 0
    for fr in frames[1:]:                 # not the setup frame (mesh reference)
        z = fr["z"]
        sig = stress_of(fr)
        expect = stack_stress_zz(radii, z, z_top_at[fr.timestep])
        assert np.all(expect > 0)
        np.testing.assert_allclose(sig[:, 2, 2], expect, rtol=1e-9)
        others = sig.copy()
        others[:, 2, 2] = 0.0
        assert np.abs(others).max() < 1e-12 * sig[:, 2, 2].min(), sig
        if len(radii) == 1:
            # first order in d/r: 3 F / (2 pi r^2), F the mean plate force
            F = np.mean([float(cd.hertz_force(r - g, r, E_STAR_STEEL))
                         for r, g in ((radii[0], z[0]), (radii[0], z_top_at[fr.timestep] - z[0]))])
            approx = 3.0 * F / (2.0 * math.pi * radii[0] ** 2)
            assert abs(sig[0, 2, 2] - approx) < 0.03 * approx
        checked += 1
    assert checked >= 5
    print("stack %s: sigma_zz %s Pa at the last output" % (radii, sig[:, 2, 2]))


# ---------------------------------------------------------------------------
# 2.-4. the closed box
# ---------------------------------------------------------------------------

L = 5.0 * D50
BOX_SEED = 10007
DT = 1.5e-7
EVERY = 100
STEPS = 200
SNAP_STEP = 100

PREP = """\
variable inputs index {inputs}
include ${{inputs}}/base.in
boundary f f f
read_data grains.data
include ${{inputs}}/materials_ne34.in
neighbor 0.0008 bin
neigh_modify delay 0
timestep {dt!r}
{plates}
fix walls all wall/gran model hertz tangential history mesh n_meshes 6 meshes xm xp ym yp zm zp
fix integrate all nve
fix damping all damp/local alpha 0.5
# grow the grains back to their size (x 1.25) in 3000 steps
variable growth atom {g!r}
fix grow all adapt 20 atom diameter v_growth scale yes
thermo_style custom step atoms ke
thermo_modify lost error
thermo 1000
run 3000
unfix grow
run 1000
write_data box.data
"""

MEASURE = """\
variable inputs index {inputs}
include ${{inputs}}/base.in
boundary f f f
{processors}
read_data box.data
include ${{inputs}}/materials_ne34.in
neighbor 0.0008 bin
neigh_modify delay 0
timestep {dt!r}
{plates}
fix walls all wall/gran model hertz tangential history mesh n_meshes 6 meshes xm xp ym yp zm zp
fix integrate all nve
include ${{inputs}}/contacts_local.in
variable trig equal step>={snap}
fix snap all snapshot/hdf5 file snap trigger v_trig contacts yes pair_local pgl &
    wall_local wgl values c_sigma_p
thermo_style custom step atoms ke f_xm[1] f_xp[1] f_ym[2] f_yp[2] f_zm[3] f_zp[3]
thermo_modify format float %.17g lost error
thermo {every}
dump d all custom {every} grains.*.txt id radius x y z fx fy fz {cols}
dump_modify d format "{fmt}" sort id
dump w all local {every} walls.*.txt c_wgl[1] c_wgl[2] c_wgl[3] c_wgl[16] c_wgl[17] c_wgl[18]
dump_modify w format "%.17g %.17g %.17g %.17g %.17g %.17g"
run {steps}
"""


def plates_text(workdir):
    lines = []
    for axis, name in enumerate("xyz"):
        for sign, tag in ((-1, "m"), (1, "p")):
            mid = name + tag
            write_stl(workdir / (mid + ".stl"), axis_plate_triangles(0.6 * L, axis, sign * L / 2), mid)
            lines.append("fix %s all mesh/surface/stress file %s.stl type 3" % (mid, mid))
    return "\n".join(lines)


@pytest.fixture(scope="module")
def box_data(tmp_path_factory):
    wd = tmp_path_factory.mktemp("box_prep")
    rng = np.random.default_rng(BOX_SEED)
    d = ne34_diameters(1000, N, rng=rng)
    n = int(np.searchsorted(np.cumsum(np.pi / 6 * d ** 3), 0.30 * L ** 3))
    d = d[:n] * 0.8
    pos = rsa_box(d, [-L / 2] * 3, [L / 2] * 3, rng=rng)
    B = 0.7 * L
    write_lammps_data(wd / "grains.data", pos, d, RHO_GRAIN, (-B, B, -B, B, -B, B), ntypes=4)
    deck = PREP.format(inputs=INPUTS, dt=DT, plates=plates_text(wd), g=1.25 ** (1.0 / 150))
    cd.run(deck, wd, nprocs=1, timeout=300)
    return wd / "box.data", n


def read_local(path, ncol):
    lines = Path(path).read_text().splitlines()
    k = next(i for i, s in enumerate(lines) if s.startswith("ITEM: ENTRIES"))
    rows = [list(map(float, s.split())) for s in lines[k + 1:] if s.strip()]
    return np.array(rows, dtype=float).reshape(-1, ncol)


_BOX = {}


def box_run(box_data, tmp_path_factory, nprocs):
    if nprocs not in _BOX:
        wd = tmp_path_factory.mktemp("box_np%d" % nprocs)
        data, n = box_data
        (wd / "box.data").write_text(data.read_text())
        deck = MEASURE.format(inputs=INPUTS, dt=DT, plates=plates_text(wd),
                              processors="processors 2 1 1" if nprocs == 2 else "",
                              snap=SNAP_STEP, every=EVERY, cols=STRESS_COLS, fmt=DUMP_FMT,
                              steps=STEPS)
        res = cd.run(deck, wd, nprocs=nprocs, timeout=300)
        frames = {}
        for p in wd.glob("grains.*.txt"):
            fr = harness.read_dump(p)[0]
            frames[fr.timestep] = fr
        _BOX[nprocs] = {"wd": wd, "res": res, "frames": frames, "n": n}
    return _BOX[nprocs]


@pytest.mark.parametrize("nprocs", [1, 2])
def test_box_sum_equals_boundary_virial(box_data, tmp_path_factory, nprocs):
    run = box_run(box_data, tmp_path_factory, nprocs)
    th = run["res"].thermo[0]
    rows = {int(s): k for k, s in enumerate(th["Step"])}
    for step, fr in sorted(run["frames"].items()):
        assert len(fr) == run["n"]
        vol = 4.0 / 3.0 * np.pi * fr["radius"] ** 3
        lhs = np.einsum("p,pij->ij", vol, stress_of(fr))
        w = read_local(run["wd"] / ("walls.%d.txt" % step), 6)
        cp, fw = w[:, 0:3], w[:, 3:6]
        x = np.column_stack([fr["x"], fr["y"], fr["z"]])
        f = np.column_stack([fr["fx"], fr["fy"], fr["fz"]])
        boundary = np.einsum("ci,cj->ij", cp, fw)
        net = np.einsum("pi,pj->ij", x, f)
        rhs = -(boundary - net)
        scale = np.abs(np.einsum("ci,cj->cij", cp, fw)).sum() + np.abs(
            np.einsum("pi,pj->pij", x, f)).sum()
        np.testing.assert_allclose(lhs, rhs, rtol=0, atol=1e-9 * scale)
        assert np.abs(np.diag(lhs)).min() > 1e-3 * scale   # the grains are loaded
        if step > 0:      # the plates' own totals (not the setup row), force on the mesh
            k = rows[step]
            plate = np.array([L / 2 * (th["f_xm[1]"][k] - th["f_xp[1]"][k]),
                              L / 2 * (th["f_ym[2]"][k] - th["f_yp[2]"][k]),
                              L / 2 * (th["f_zm[3]"][k] - th["f_zp[3]"][k])])
            # x_c F_w on the plate at +L/2 is L/2 times minus the force on it
            np.testing.assert_allclose(np.diag(boundary), plate, rtol=1e-9)
    print("box (%d ranks): sum V_p sigma_p diagonal %s N m at step %d"
          % (nprocs, np.diag(lhs), step))


def test_box_one_and_two_ranks(box_data, tmp_path_factory):
    a = box_run(box_data, tmp_path_factory, 1)["frames"]
    b = box_run(box_data, tmp_path_factory, 2)["frames"]
    assert sorted(a) == sorted(b)
    for step in sorted(a):
        sa, sb = stress_of(a[step]), stress_of(b[step])
        np.testing.assert_array_equal(a[step]["id"], b[step]["id"])
        scale = np.abs(sa).max()
        tol = 1e-9 if step == 0 else 1e-6
        np.testing.assert_allclose(sb, sa, rtol=0, atol=tol * scale, err_msg="step %d" % step)
        print("step %d: 1 vs 2 ranks, largest difference %.3g of the largest stress"
              % (step, np.abs(sb - sa).max() / scale))


@pytest.mark.parametrize("nprocs", [1, 2])
def test_snapshot_stress_equals_compute(box_data, tmp_path_factory, nprocs):
    from crushpost.snapshot import list_snapshots, read_snapshot, snapshot_particle_stress

    run = box_run(box_data, tmp_path_factory, nprocs)
    snaps = list_snapshots(run["wd"] / "snap")
    assert [s for s, _ in snaps] == [SNAP_STEP]
    snap = read_snapshot(snaps[0][1])
    assert len(snap["contacts"]["pw"]["id"]) > 0           # wall contacts are there
    mine = snapshot_particle_stress(snap)
    comp = full_tensor(snap["particles"]["values"]["c_sigma_p"])
    scale = np.abs(comp).max()
    np.testing.assert_allclose(mine, comp, rtol=0, atol=1e-10 * scale)
    # and it is the dump's at that step
    fr = run["frames"][SNAP_STEP]
    np.testing.assert_allclose(stress_of(fr), comp, rtol=0, atol=1e-12 * scale)
