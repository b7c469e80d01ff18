# SPDX-License-Identifier: GPL-2.0-or-later
"""A symmetry plane of a chamber sector acts exactly as the mirror image of the
grain touching it (docs/model.md §4.4, issue: a grain pressed against a
plane of material type 3 broke at 22 % more platen force than against its
mirror grain).

Both scenes use the deck blocks of the chamber: inputs/materials_ne34.in
(4 atom types) and inputs/chamber_sym_<sector>.in, whose planes are meshes
of material type 4 (rigid, frictionless) written by
crushpost.chamber.symmetry_planes, in the deck's one mesh wall fix.

* plane: one NE34 grain (d = 39 d50 = 8.19 mm, N = 39, var 0) touching the
  symmetry plane y = 0 (chamber_sym_180.in), pressed against it by a steel
  platen (type 2) moving in -y at constant speed;
* mirror: the grain and its mirror image at -y, pressed together by two
  steel platens moving symmetrically (chamber_sym_360.in: no plane).

Independent answers (Hertz, docs/model.md §2.1): the plane contact at overlap
delta, R* = r, E* = E/(1 - nu^2), gives F = 4/3 E* sqrt(R*) delta^1.5; the
mirror contact at overlap 2 delta, R* = r/2, E* = E/(2(1 - nu^2)), gives the
same F; both have F_lim = (pi sigma_lim)^3 (3 R*/(4 E*))^2 with the same
R*/E*. The test asserts, to 1e-6 relative: the grain's path and the platen
force are the same in both scenes at every output step (so the force-overlap
curve is); the plane's force is the Hertz force of the rigid plane at the
dumped overlap; the break happens at the same step with the same F_n and
F_lim, equal to the analytic F_lim, on the plane and on the mirror contact.

With the old plane material (the grain's, type 3: -var E_rigid of the grain's E, or the
old primitive type-3 planes) the plane pushes with half the force at the same
overlap and the limit force is 4 times higher: this test fails.
"""

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import crush_decks as cd  # noqa: E402
import harness  # noqa: E402

from crushpost.chamber import symmetry_planes  # noqa: E402
from crushpost.materials import E_STEEL, NU_STEEL, RHO_GRAIN  # noqa: E402
from crushpost.meshes import rectangle_triangles, write_stl  # noqa: E402

N = 39
D = 39 * cd.D50               # the grain: 39 d50 at N = 39 = d50 of the chamber
R = 0.5 * D
SIGMA = cd.strength(D, N)     # var 0: f = 1
E_STAR_RIGID = cd.E_GRAIN / (1.0 - cd.NU_GRAIN ** 2)
E_STEEL_NE34 = E_STEEL                       # materials_ne34.in: G_steel 85 GPa, nu 0.2
E_STAR_STEEL = cd.effective_modulus(cd.E_GRAIN, cd.NU_GRAIN, E_STEEL_NE34, NU_STEEL)
F_LIM = cd.limit_force(SIGMA, R, E_STAR_RIGID)
SPEED = 0.5                   # platen speed, m/s
DT = 2e-7                     # 0.03 Rayleigh times of the grain
GAP = 0.02 * D                # platen gap at the start
HALF = 0.02                   # box half-width
X0, Z0 = 0.004, -0.004        # grain centre in x, z: inside one facet of the plane
EVERY = 100
TOL = 1e-6


def travel_to_break():
    """Platen travel until the plane contact reaches F_lim (quasi-static
    estimate: both contacts carry F_lim)."""
    return (GAP + cd.hertz_overlap(F_LIM, R, E_STAR_RIGID)
            + cd.hertz_overlap(F_LIM, R, E_STAR_STEEL))


STEP_BREAK = travel_to_break() / (SPEED * DT)
N_STEPS = int(0.93 * STEP_BREAK)     # the first run: the curve, no break yet

DECK = """\
variable inputs index {inputs}
variable sector index {sector}
include ${{inputs}}/base.in
boundary f f f
region box block -{h} {h} -{h} {h} -{h} {h} units box
create_box 4 box
include ${{inputs}}/materials_ne34.in
neighbor 0.0005 bin
neigh_modify delay 0
timestep {dt!r}
{atoms}
include ${{inputs}}/chamber_sym_${{sector}}.in
{platens}
fix walls all wall/gran model hertz tangential history mesh n_meshes $({n_platens}+v_n_sym) &
    meshes {platen_ids} ${{sym_meshes}}
{moves}
fix integrate all nve
fix crush all crush/particle sigma_lim0 {sigma0:g} m 10 d0 2e-3 scale {N} var 0 &
    d_comm {d_comm!r} seed 15485863 events events.txt
variable y1 equal y[1]
variable fy1 equal fy[1]
variable n_break equal f_crush[1]
thermo_style custom step atoms v_y1 v_fy1 f_top[2] {extra}
thermo_modify format float %.17g lost error
thermo {every}
run {steps}
# then in short runs until the grain breaks (at most 80 x 20 steps), and stop
# right after it: the fragments are not followed
variable k loop 80
label press
run 20
if "${{n_break}} > 0" then "jump SELF broken"
next k
jump SELF press
label broken
run 1
"""


def platen_stl(path, y, sign):
    """A square steel platen in the plane y, normal along sign * y."""
    write_stl(path, rectangle_triangles(1, y, (0.0, y, 0.0), 0.8 * HALF, 0.8 * HALF,
                                        normal_sign=sign), "platen")


def build(tmp, mirror):
    y_top = D + GAP                    # platen above the grain centred at y = r
    atoms = ("create_atoms 1 single {x} {y} {z} units box\nset atom 1 diameter {d} density {rho:g}\n"
             .format(x=X0, y=R, z=Z0, d=D, rho=RHO_GRAIN))
    platens = "fix top all mesh/surface/stress file top.stl type 2\n"
    moves = "fix mv_top all move/mesh mesh top linear 0 {v} 0\n".format(v=-SPEED)
    ids, extra = "top", "f_sym_y[2]"
    platen_stl(tmp / "top.stl", y_top, -1)
    if mirror:
        atoms += ("create_atoms 1 single {x} {y} {z} units box\n"
                  "set atom 2 diameter {d} density {rho:g}\n").format(x=X0, y=-R, z=Z0, d=D, rho=RHO_GRAIN)
        platens += "fix bot all mesh/surface/stress file bot.stl type 2\n"
        moves += "fix mv_bot all move/mesh mesh bot linear 0 {v} 0\n".format(v=SPEED)
        atoms += "variable y2 equal y[2]\n"
        ids, extra = "top bot", "f_bot[2] v_y2"
        platen_stl(tmp / "bot.stl", -y_top, 1)
    else:
        planes = symmetry_planes(180, 0.9 * HALF / 1.15, -0.9 * HALF, 0.9 * HALF, 0.9 * HALF)
        for name, tris in planes.items():
            write_stl(tmp / (name + ".stl"), tris, name)
    return DECK.format(inputs=harness.REPO / "inputs", sector=360 if mirror else 180,
                       h=HALF, dt=DT, atoms=atoms, platens=platens,
                       n_platens=len(ids.split()), platen_ids=ids, moves=moves, N=N,
                       d_comm=0.55 * D, extra=extra, every=EVERY, steps=N_STEPS, sigma0=cd.SIGMA0)


@pytest.fixture(scope="module")
def scenes(tmp_path_factory):
    out = {}
    for name, mirror in (("plane", False), ("mirror", True)):
        wd = tmp_path_factory.mktemp(name)
        res = cd.run(build(wd, mirror), wd, nprocs=1, timeout=300)
        out[name] = (res.thermo[0], cd.read_events(res.path("events.txt")))
    return out


def test_deck_uses_a_rigid_plane():
    """The plane material of materials_ne34.in is rigid to 1e-9 (E* of a
    grain-plane contact against the rigid limit)."""
    text = (harness.REPO / "inputs" / "materials_ne34.in").read_text()
    e_rigid = float(text.split("variable E_rigid")[1].split()[1])
    e_star = cd.effective_modulus(cd.E_GRAIN, cd.NU_GRAIN, e_rigid, cd.NU_GRAIN)
    assert abs(e_star - E_STAR_RIGID) / E_STAR_RIGID < 1e-9
    # the scene is quasi-static enough to break on the plane contact first
    assert cd.limit_force(SIGMA, R, E_STAR_STEEL) > 1.1 * F_LIM


def test_same_force_overlap_curve(scenes):
    plane, mirror = scenes["plane"][0], scenes["mirror"][0]
    keep = plane["Step"] > 0                 # not the setup row (mesh forces)
    assert keep.sum() > 20
    for col in ("v_y1", "v_fy1", "f_top[2]"):
        a, b = plane[col][keep], mirror[col][keep]
        scale = np.max(np.abs(a))
        np.testing.assert_allclose(a, b, rtol=TOL, atol=TOL * scale, err_msg=col)
    # the mirror stays a mirror
    np.testing.assert_allclose(mirror["v_y2"][keep], -mirror["v_y1"][keep], rtol=1e-12)
    # the plane's force is the rigid-plane Hertz force at the grain's overlap,
    # and the mirror pair's force at twice the overlap; both in the range of
    # the break force (the curve is tested where it matters)
    delta = R - plane["v_y1"][keep]
    F_plane = np.abs(plane["f_sym_y[2]"][keep])
    F_hertz = cd.hertz_force(delta, R, E_STAR_RIGID)
    on = delta > 0
    assert on.sum() > 10 and F_plane[on].max() > 0.5 * F_LIM
    np.testing.assert_allclose(F_plane[on], F_hertz[on], rtol=TOL)
    np.testing.assert_allclose(F_plane[on], cd.hertz_force(2 * delta[on], R / 2, E_STAR_RIGID / 2),
                               rtol=TOL)


def test_same_breaking_force(scenes):
    ev_plane, ev_mirror = scenes["plane"][1], scenes["mirror"][1]
    assert len(ev_plane) == 1, ev_plane
    assert len(ev_mirror) == 2, ev_mirror          # the grain and its image break together
    e = ev_plane[0]
    assert e.partner == "wall" and e.tag == 1
    assert e.F_lim == pytest.approx(F_LIM, rel=TOL)
    assert 1.0 <= e.F_n / F_LIM < 1.01
    for m in ev_mirror:
        assert m.partner == "particle"
        assert m.step == e.step
        assert m.F_lim == pytest.approx(e.F_lim, rel=TOL)
        assert m.F_n == pytest.approx(e.F_n, rel=TOL)
    print("break: F_lim %.6g N, plane F_n %.6g N, mirror F_n %.6g N, step %d (quasi-static "
          "estimate %.0f)" % (F_LIM, e.F_n, ev_mirror[0].F_n, e.step, STEP_BREAK))
