# SPDX-License-Identifier: GPL-2.0-or-later
"""Chamber sectors (issue 5 item 1): a quarter of the calibration chamber,
grains in x, y >= 0 between the rigid frictionless symmetry planes x = 0 and
y = 0 (inputs/chamber_sym_90.in: planar meshes of material type 4 written by
crushpost.chamber.symmetry_planes, in the deck's one mesh wall fix), with the
keyword `sector 90` of fix servo/radial and fix jack/pile.

Scene: about 260 NE34 grains at N = 39 (unbreakable, local damping 0.2)
placed loose by random sequential addition in the quarter cylinder of radius
9 d50 (the same grain count as the full cylinder of 4.5 d50 of
test_servo_radial.py) and height 5 d50, between a fixed bottom plane and a top
plate; the lateral wall is the arc -7.5 ... 97.5 degrees of a strip cylinder
(the sector plus one strip each side, as crushpost.chamber writes it).

1. Servo, frictionless grains, target 76 kPa, `sector 90`: the wall closes in
   (R drops by more than 10 %; the quarter of radius 9 d50 has twice as far
   to close as the full cylinder of 4.5 d50), the stress averaged over the last 4000 steps
   is within 10 % of the target (a frictionless packing creeps, as in
   test_servo_radial.py), and every 1000 steps the reported stress agrees
   within 0.5 % of the target with an independent one: the radial components
   of the lateral wall's contact forces on the grains (compute
   wall/gran/local, the rows of the lateral mesh; the planes are in the same
   wall fix) over the quarter arc (pi/2) R times the sample height. Without
   the keyword the stress would be that over the whole 105 degree mesh, 14 %
   lower. The planes carry the hoop force: their forces push the grains
   into the quarter (+x on x = 0, +y on y = 0) and nothing else.
2. The top plate is removed and a cone pile (R = 2.2 d50) is pushed 2 d50
   into the quarter packing by fix jack/pile with `sector 90`: at every row
   the cone, shaft and head forces it reports are 4 times the totals of the
   mesh fixes (f_cone[3], f_shaft[3]), the grains do resist the push, and the
   time series file names the sector.
"""

import math
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import harness  # noqa: E402

from crushpost.chamber import symmetry_planes  # noqa: E402
from crushpost.materials import RHO_GRAIN  # noqa: E402
from crushpost.meshes import cylinder_triangles, plate_triangles, write_pile_stl, write_stl  # noqa: E402
from crushpost.packing import D50_NE34, ne34_diameters, rsa_cylinder, write_lammps_data  # noqa: E402

N = 39
D50 = D50_NE34 * N
R0 = 9.0 * D50
H = 5.0 * D50
SOLID_FRACTION0 = 0.28
SECTOR = 90.0
PACKING_SEED = 10007
RHO = RHO_GRAIN
T1, K1, VMAX1 = 76e3, 1e-5, 1.0
STEPS1 = 60000
R_PILE = 0.018
V_PUSH, DEPTH = 1.0, 2.0 * D50
THERMO = 250
SETTLED = 4000
PREP_TOL = 0.10
STRESS_CHECK_TOL = 0.005
WALL_EVERY = 1000        # steps between the wall-contact dumps of the servo phase
DT = 1e-6

DECK = """\
variable inputs index {inputs}
variable D_loc  index 0.2
include ${{inputs}}/base.in
boundary f f f
processors 1 1 1
read_data grains.data
include ${{inputs}}/materials_ne34.in
neighbor 0.002 bin
neigh_modify delay 0
timestep {dt!r}
fix bottom  all wall/gran model hertz tangential history primitive type 3 zplane 0.0
fix top     all mesh/surface file plate.stl type 3 move 0 0 {H!r}
fix chamber all mesh/surface/stress file chamber.stl type 3
fix cone    all mesh/surface/stress file cone.stl type 2
fix shaft   all mesh/surface/stress file shaft.stl type 2
include ${{inputs}}/chamber_sym_90.in
fix mesh_walls all wall/gran model hertz tangential history mesh n_meshes $(2+v_n_sym) &
    meshes top chamber ${{sym_meshes}}
include ${{inputs}}/integrate.in
# the wall contacts (mesh index in mesh_walls: 0 top, 1 chamber, 2 sym_x, 3 sym_y)
compute wgl all wall/gran/local pos id force
dump wl all local {wall_every} walls.*.txt c_wgl[1] c_wgl[2] c_wgl[3] c_wgl[4] c_wgl[5] c_wgl[6] &
    c_wgl[7] c_wgl[8] c_wgl[9] c_wgl[10] c_wgl[11] c_wgl[12]
dump_modify wl format "%.12g %.12g %.12g %.12g %.12g %.12g %.12g %.12g %.12g %.12g %.12g %.12g"

variable Hs equal {H!r}

# 1. servo on the quarter chamber, frictionless grains
variable mu_grain_now equal 0.0
include ${{inputs}}/friction_ne34.in
fix servo all servo/radial mesh chamber target {T1!r} gain {K1!r} vmax {VMAX1!r} &
    height v_Hs sector {sector!r}
thermo_style custom step f_servo[1] f_servo[2] f_servo[3]
thermo_modify format float %.12g lost error
thermo {thermo}
run {steps1}

# 2. the lateral wall held, the top plate removed, the pile pushed in
# (LIGGGHTS unfixes a wall fix only without its wall/gran/local)
unfix servo
undump wl
uncompute wgl
unfix mesh_walls
unfix top
fix mesh_walls all wall/gran model hertz tangential history mesh n_meshes $(3+v_n_sym) &
    meshes chamber cone shaft ${{sym_meshes}}
unfix damping
fix damping all damp/local alpha ${{D_loc}}
fix jack all jack/pile cone cone shaft shaft mode monotonic v {v_push!r} depth {depth!r} &
    sector {sector!r} file jack.txt every 100
variable zero equal 0
variable vz   equal f_jack[1]
fix mv_cone  all move/mesh mesh cone  linear/variable v_zero v_zero v_vz
fix mv_shaft all move/mesh mesh shaft linear/variable v_zero v_zero v_vz
thermo_style custom step f_jack[2] f_jack[3] f_jack[4] f_jack[5] f_cone[3] f_shaft[3]
thermo_modify format float %.15g lost error
run {steps2}
"""


@pytest.fixture(scope="module")
def sector_run(tmp_path_factory):
    work = tmp_path_factory.mktemp("sector")
    rng = np.random.default_rng(PACKING_SEED)
    diam = ne34_diameters(2000, N, rng=rng)
    n = int(np.searchsorted(np.cumsum(np.pi / 6 * diam ** 3),
                            SOLID_FRACTION0 * (SECTOR / 360.0) * math.pi * R0 * R0 * H))
    diam = diam[:n]
    pos = rsa_cylinder(diam, R0, 0.0, H, rng=rng, sector_deg=SECTOR)
    tip_z0 = H + 0.25 * D50
    pile = write_pile_stl(str(work), R_PILE, shaft_length=DEPTH + 0.5 * H, tip_z=tip_z0, n_seg=24)
    L = 1.3 * R0
    write_lammps_data(str(work / "grains.data"), pos, diam, RHO,
                      (-L, L, -L, L, -0.3 * H, pile["z_top"] + 0.1 * H), ntypes=4)
    write_stl(str(work / "chamber.stl"),
              cylinder_triangles(R0, -0.1 * H, 1.1 * H, 14, phi0=-7.5, phi1=97.5), "chamber")
    write_stl(str(work / "plate.stl"), plate_triangles(R0 + 0.01), "plate")
    for name, tris in symmetry_planes(90, R0, -0.1 * H, 1.1 * H, 0.5 * R0).items():
        write_stl(str(work / (name + ".stl")), tris, name)
    steps2 = int(1.1 * (DEPTH / (V_PUSH * DT)))
    deck = DECK.format(inputs=harness.REPO / "inputs", H=H, T1=T1, K1=K1, VMAX1=VMAX1, dt=DT,
                       thermo=THERMO, steps1=STEPS1, sector=SECTOR, v_push=V_PUSH, depth=DEPTH,
                       steps2=steps2, wall_every=WALL_EVERY)
    res = harness.run_deck(deck, work, nprocs=1, timeout=400, check=True)
    blocks = res.thermo
    assert len(blocks) == 2, res.summary()
    return {"n": n, "servo": blocks[0], "jack": blocks[1], "work": work}


def test_packing_lies_in_the_quarter(sector_run):
    data = np.loadtxt(sector_run["work"] / "grains.data", skiprows=11)
    r = 0.5 * data[:, 2]
    assert np.all(data[:, 4] >= r) and np.all(data[:, 5] >= r)
    assert np.all(np.hypot(data[:, 4], data[:, 5]) + r <= R0 * (1 + 1e-12))


def test_sector_servo_closes_and_measures_stress_over_the_arc(sector_run):
    b = sector_run["servo"]
    step, R, sigma, v_r = b["Step"], b["f_servo[1]"], b["f_servo[2]"], b["f_servo[3]"]
    assert R[0] == pytest.approx(R0, rel=1e-9)
    assert v_r[1] < 0.0 and R[-1] < 0.9 * R0
    mean = float(np.mean(sigma[step >= step[-1] - SETTLED]))
    print("quarter chamber servo: target %g Pa, mean of the last %d steps %.1f Pa (%+.2f %%)"
          % (T1, SETTLED, mean, 100.0 * (mean - T1) / T1))
    assert abs(mean - T1) < PREP_TOL * T1, (mean, T1)
    np.testing.assert_allclose(v_r, np.clip(K1 * (sigma - T1), -VMAX1, VMAX1), rtol=1e-8, atol=1e-12)
    # independent: the lateral wall's contact forces on the grains over the quarter arc
    row = {int(s): k for k, s in enumerate(step)}
    checked = 0
    for path in sector_run["work"].glob("walls.*.txt"):
        st = int(path.name.split(".")[1])
        if st == 0 or st not in row:
            continue                      # the setup row of the servo's stress
        w = read_local(path, 12)
        mesh, xp, f = w[:, 6].astype(int), w[:, 3:6], w[:, 9:12]
        side = mesh == 1
        rho = np.hypot(xp[side, 0], xp[side, 1])
        f_r = (f[side, 0] * xp[side, 0] + f[side, 1] * xp[side, 1]) / rho
        sig_wall = -f_r.sum() / (SECTOR / 180.0 * math.pi * R[row[st]] * H)
        assert abs(sig_wall - sigma[row[st]]) < STRESS_CHECK_TOL * T1, (st, sig_wall, sigma[row[st]])
        # the planes push the grains into the quarter, normal to themselves
        for k, axis in ((2, 0), (3, 1)):
            on = mesh == k
            assert np.all(f[on, axis] >= 0.0)
            assert np.abs(np.delete(f[on], axis, axis=1)).max(initial=0.0) <= 1e-9 * max(
                1.0, np.abs(f[on, axis]).max(initial=0.0))
        checked += 1
    assert checked >= STEPS1 // WALL_EVERY - 2, checked


def read_local(path, ncol):
    """Rows of a one-frame `dump local` file."""
    lines = path.read_text().splitlines()
    k = next(i for i, s in enumerate(lines) if s.startswith("ITEM: ENTRIES"))
    rows = [list(map(float, s.split())) for s in lines[k + 1:] if s.strip()]
    return np.array(rows, dtype=float).reshape(-1, ncol)


def test_jack_reports_whole_pile_forces(sector_run):
    b = sector_run["jack"]
    f = 360.0 / SECTOR
    scale = max(1.0, float(np.max(np.abs(b["f_cone[3]"]))))
    np.testing.assert_allclose(b["f_jack[3]"], f * b["f_cone[3]"], rtol=1e-10, atol=1e-12 * scale)
    np.testing.assert_allclose(b["f_jack[4]"], f * b["f_shaft[3]"], rtol=1e-10, atol=1e-12 * scale)
    np.testing.assert_allclose(b["f_jack[5]"], f * (b["f_cone[3]"] + b["f_shaft[3]"]),
                               rtol=1e-10, atol=1e-12 * scale)
    assert b["f_jack[2]"][-1] == pytest.approx(DEPTH, rel=1e-9)
    assert np.max(b["f_cone[3]"]) > 1.0          # the grains resist the push (N)
    head = (sector_run["work"] / "jack.txt").read_text().splitlines()[0]
    assert "sector 90" in head
