# SPDX-License-Identifier: GPL-2.0-or-later
"""Deck-level tests of `fix servo/radial` (docs/model.md §4.4, issue 5
item 1): the lateral wall of a small chamber servo-controlled to a radial
stress, then held at a fixed radius by `unfix`.

Scene: about 260 NE34 grains at N = 39 (unbreakable, Hertz-Mindlin, local
damping 0.2), placed loose by random sequential addition in a cylinder of
radius 4.5 d50 and height 5 d50 between a fixed bottom plate and a top plate
(both frictionless); the chamber wall is a frictionless STL cylinder of 48
vertical strips (particle-wall stiffness = particle stiffness, material type
3), taller than the sample, with its axis off the box centre so that at 2
ranks (box split at x = 0) wall elements change rank as the wall moves.

1. Preparation, grains frictionless (as inputs/prepare_expand.in does),
   target 76 kPa: the packing is loose, so the wall moves in (v_r < 0, R
   drops by more than 10 %) until the grains jam and carry the target. A
   frictionless packing under a stress that is not isotropic keeps creeping,
   so the wall keeps closing slowly: the stress averaged over the last 4000
   steps is within 10 % of the target (a few % below, by the creep rate over
   the gain).
2. Grain friction on; the top plate pushes the packing down by 2 % of its
   height: the packing pushes harder than the target and the wall moves out
   (R grows by more than 0.1 mm); the sample height is an equal-style
   variable that follows the plate. The plate stops and the radial stress
   averaged over the last 4000 steps is within 5 % of 76 kPa.
3. `unfix`, a phase with no servo: a new servo defined after it finds the
   radius the first one left.

At every output row the reported velocity obeys the control law
v_r = clip(K (sigma_r - target), -vmax, vmax), and the measured stress agrees
within 0.5 % with an independent one: the radial components of the wall
forces on the grains (fix wall/gran store_force; the frictionless plates push
along z only) over the wall's perimeter times the sample height. Both rank
counts run the same deck; their first rows (before the chaotic grain
dynamics lets round-off grow) agree to 1e-7. Bad input stops with an error
naming the keyword and the allowed range.
"""

import math
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import harness  # noqa: E402

from crushpost.materials import RHO_GRAIN  # noqa: E402
from crushpost.meshes import cylinder_triangles, plate_triangles, write_stl  # noqa: E402
from crushpost.packing import D50_NE34, ne34_diameters, rsa_cylinder, write_lammps_data  # noqa: E402

N = 39
D50 = D50_NE34 * N
R0 = 4.5 * D50             # initial wall radius
H = 5.0 * D50              # sample height (fixed plates at z = 0 and H)
SOLID_FRACTION0 = 0.28     # loose random sequential addition
AXIS = (0.006, -0.004)     # chamber axis, off the box centre
N_SEG = 48
PACKING_SEED = 7
RHO = RHO_GRAIN

T1, K1, VMAX1 = 76e3, 1e-5, 1.0      # target (Pa), gain (m/s per Pa), vmax (m/s)
STEPS1 = 26000                       # 1. preparation
V_PLATE, STEPS_PRESS = 0.1, 8000     # 2. top plate pushed down 0.8 mm (2 % of H)
STEPS_SETTLE = 8000                  #    then stopped
STEPS_HOLD = 500                     # 3. no servo
THERMO = 250
SETTLED = 4000                       # steps averaged at the end of a phase
TOL = 0.05                           # servo error, time-averaged, settled packing
PREP_TOL = 0.10                      # same, frictionless packing still creeping
STRESS_CHECK_TOL = 0.005             # measured vs independent stress, of the target
DT = 1e-6

DECK = """\
variable inputs index {inputs}
variable D_loc  index 0.2
include ${{inputs}}/base.in
boundary f f f
processors * 1 1
read_data grains.data
include ${{inputs}}/materials_ne34.in
neighbor 0.002 bin
neigh_modify delay 0
timestep {dt!r}
fix bottom  all wall/gran model hertz tangential history primitive type 3 zplane 0.0
fix top     all mesh/surface file plate.stl type 3 move 0 0 {H!r}
fix chamber all mesh/surface/stress file chamber.stl type 3
fix mesh_walls all wall/gran model hertz tangential history mesh n_meshes 2 meshes top chamber &
    store_force yes
include ${{inputs}}/integrate.in

# sample height: H, then the top plate comes down at V_PLATE for STEPS_PRESS steps
variable n_press equal (step-{steps1})*(step>{steps1})*(step<={steps1}+{steps_press})+{steps_press}*(step>{steps1}+{steps_press})
variable Hs equal {H!r}-{v_plate!r}*dt*v_n_press

# independent check of the measured stress: the radial wall force on the
# grains (the frictionless plates push along z only) over the polygon's
# perimeter times the height
variable dxa atom x-{x0!r}
variable dya atom y-{y0!r}
variable fr  atom (f_force_mesh_walls[1]*v_dxa+f_force_mesh_walls[2]*v_dya)/sqrt(v_dxa*v_dxa+v_dya*v_dya)
compute  Fr all reduce sum v_fr
variable sig_wall equal -c_Fr/(2*{n_seg}*f_servo[1]*sin(PI/{n_seg})*v_Hs)

# 1. preparation: the wall closes in on the loose packing (frictionless grains,
#    as in inputs/prepare_expand.in: a dense packing without locked-in stress)
variable mu_grain_now equal 0.0
include ${{inputs}}/friction_ne34.in
fix servo all servo/radial mesh chamber target {T1!r} gain {K1!r} vmax {VMAX1!r} &
    height v_Hs axis {x0!r} {y0!r}
thermo_style custom step f_servo[1] f_servo[2] f_servo[3] v_Hs v_sig_wall
thermo_modify format float %.12g lost error
thermo {thermo}
run {steps1}

# 2. grain friction back on; the packing is pushed vertically: it pushes
#    harder on the wall, which opens
variable mu_grain_now equal ${{mu_grain}}
include ${{inputs}}/friction_ne34.in
fix press all move/mesh mesh top linear 0 0 -{v_plate!r}
run {steps_press}
unfix press
run {steps_settle}

# 3. hold: no servo, the wall stands still; a new servo reads its radius
unfix servo
thermo_style custom step ke
thermo_modify lost error
run {steps_hold}
fix servo all servo/radial mesh chamber target {T1!r} gain {K1!r} height v_Hs axis {x0!r} {y0!r}
thermo_style custom step f_servo[1] f_servo[2] f_servo[3] v_Hs
thermo_modify format float %.12g lost error
run 0
"""


@pytest.fixture(scope="module")
def scene(tmp_path_factory):
    """Grains and chamber mesh, written once for every run of this module."""
    d = tmp_path_factory.mktemp("servo_scene")
    rng = np.random.default_rng(PACKING_SEED)
    diam = ne34_diameters(2000, N, rng=rng)
    n = int(np.searchsorted(np.cumsum(np.pi / 6 * diam ** 3),
                            SOLID_FRACTION0 * math.pi * R0 * R0 * H))
    diam = diam[:n]
    pos = rsa_cylinder(diam, R0, 0.0, H, rng=rng)
    pos[:, 0] += AXIS[0]
    pos[:, 1] += AXIS[1]
    L = 1.3 * R0 + max(abs(AXIS[0]), abs(AXIS[1]))
    write_lammps_data(str(d / "grains.data"), pos, diam, RHO,
                      (-L, L, -L, L, -0.3 * H, 1.3 * H), ntypes=4)
    write_stl(str(d / "chamber.stl"),
              cylinder_triangles(R0, -0.1 * H, 1.1 * H, N_SEG, center=AXIS), "chamber")
    write_stl(str(d / "plate.stl"), plate_triangles(R0 + 0.01), "plate")
    return d


_RUNS = {}


def servo_run(scene, tmp_path_factory, nprocs):
    """The three-phase deck at `nprocs` ranks, run once per session."""
    if nprocs not in _RUNS:
        work = tmp_path_factory.mktemp("servo_np%d" % nprocs)
        for name in ("grains.data", "chamber.stl", "plate.stl"):
            (work / name).write_bytes((scene / name).read_bytes())
        deck = DECK.format(inputs=harness.REPO / "inputs", H=H, T1=T1, K1=K1, VMAX1=VMAX1,
                           x0=AXIS[0], y0=AXIS[1], n_seg=N_SEG, dt=DT, thermo=THERMO, steps1=STEPS1,
                           v_plate=V_PLATE, steps_press=STEPS_PRESS,
                           steps_settle=STEPS_SETTLE, steps_hold=STEPS_HOLD)
        res = harness.run_deck(deck, work, nprocs=nprocs, timeout=400, check=True)
        blocks = res.thermo
        assert len(blocks) == 5, res.summary()
        _RUNS[nprocs] = blocks
    return _RUNS[nprocs]


def columns(block):
    return block["Step"], block["f_servo[1]"], block["f_servo[2]"], block["f_servo[3]"]


def control_law(sigma, target, gain, vmax):
    return np.clip(gain * (sigma - target), -vmax, vmax)


def settled_mean(step, sigma):
    """Time average over the last SETTLED steps of a phase."""
    return float(np.mean(sigma[step >= step[-1] - SETTLED]))


def check_servo_block(block, target, gain, vmax):
    """Control law and the independent stress at every row of a servo phase."""
    step, R, sigma, v_r = columns(block)
    np.testing.assert_allclose(v_r, control_law(sigma, target, gain, vmax), rtol=1e-8, atol=1e-12)
    np.testing.assert_allclose(block["v_sig_wall"], sigma, rtol=0.0, atol=STRESS_CHECK_TOL * target)


@pytest.mark.parametrize("nprocs", [1, 2])
def test_wall_closes_on_loose_packing(scene, tmp_path_factory, nprocs):
    block = servo_run(scene, tmp_path_factory, nprocs)[0]
    step, R, sigma, v_r = columns(block)
    assert R[0] == pytest.approx(R0, rel=1e-9)
    # softer than the target: the wall moves in, a long way
    assert v_r[1] < 0.0 and R[1] < R[0]
    assert R[-1] < 0.9 * R0
    mean = settled_mean(step, sigma)
    print("servo/radial np=%d preparation (frictionless, creeping): target %g Pa, "
          "mean of the last %d steps %.1f Pa (%+.2f %%)"
          % (nprocs, T1, SETTLED, mean, 100.0 * (mean - T1) / T1))
    assert abs(mean - T1) < PREP_TOL * T1, (mean, T1)
    check_servo_block(block, T1, K1, VMAX1)


@pytest.mark.parametrize("nprocs", [1, 2])
def test_wall_opens_when_packing_pushes_harder_and_settles_on_target(scene, tmp_path_factory,
                                                                     nprocs):
    blocks = servo_run(scene, tmp_path_factory, nprocs)
    _, R1, sigma1, _ = columns(blocks[0])
    press, settle = blocks[1], blocks[2]
    step, R, sigma, v_r = columns(press)
    assert press["v_Hs"][-1] == pytest.approx(H - V_PLATE * DT * STEPS_PRESS, rel=1e-9)
    assert R[0] == pytest.approx(R1[-1], rel=1e-10)
    # the set-up of a run measures the same stress as the end of the last
    # step (same grain positions, frictionless wall): at 2 ranks this needs
    # the forces held by ghost elements, which set-up leaves unsummed
    assert sigma[0] == pytest.approx(sigma1[-1], rel=1e-9)
    # pushed vertically, the packing pushes harder on the wall: it moves out
    assert np.mean(v_r) > 0.0
    assert R[-1] - R[0] > 1e-4, (R[0], R[-1])
    check_servo_block(press, T1, K1, VMAX1)
    # the plate stops: the servo settles on the target
    step, R, sigma, v_r = columns(settle)
    mean = settled_mean(step, sigma)
    print("servo/radial np=%d settled: target %g Pa, mean of the last %d steps %.1f Pa (%+.3f %%)"
          % (nprocs, T1, SETTLED, mean, 100.0 * (mean - T1) / T1))
    assert abs(mean - T1) < TOL * T1, (mean, T1)
    check_servo_block(settle, T1, K1, VMAX1)


@pytest.mark.parametrize("nprocs", [1, 2])
def test_unfix_holds_radius(scene, tmp_path_factory, nprocs):
    blocks = servo_run(scene, tmp_path_factory, nprocs)
    _, R_before, _, _ = columns(blocks[2])
    _, R_after, _, v_r = columns(blocks[4])
    assert "f_servo[1]" not in blocks[3]
    # after a servo-free phase a new servo finds the radius the old one left
    assert R_after[0] == pytest.approx(R_before[-1], rel=1e-10)
    # default vmax = gain * target
    assert abs(v_r[0]) <= K1 * T1


def test_same_start_at_one_and_two_ranks(scene, tmp_path_factory):
    b1 = servo_run(scene, tmp_path_factory, 1)[0]
    b2 = servo_run(scene, tmp_path_factory, 2)[0]
    s1, R1, sig1, v1 = columns(b1)
    s2, R2, sig2, v2 = columns(b2)
    early = s1 <= 2500
    assert np.array_equal(s1[early], s2[early])
    # at set-up (row 0) the stress includes the forces held by ghost elements
    assert sig1[0] > 0.0
    np.testing.assert_allclose(R2[early], R1[early], rtol=1e-10)
    np.testing.assert_allclose(sig2[early], sig1[early], rtol=1e-7, atol=1e-6)
    np.testing.assert_allclose(v2[early], v1[early], rtol=1e-7, atol=1e-12)


# ---------------------------------------------------------------------------
# bad input
# ---------------------------------------------------------------------------

ERR_HEAD = """\
variable inputs index {inputs}
include ${{inputs}}/base.in
boundary {boundary}
region box block -0.05 0.05 -0.05 0.05 -0.01 0.06 units box
create_box 4 box
create_atoms 1 single 0.006 -0.004 0.02 units box
set atom 1 diameter 0.008 density """ + "%g" % RHO_GRAIN + """
include ${{inputs}}/materials_ne34.in
neighbor 0.002 bin
neigh_modify delay 0
timestep 1e-6
fix chamber all mesh/surface/stress file chamber.stl type 3
"""
WALL = "fix chamber_wall all wall/gran model hertz tangential history mesh n_meshes 1 meshes chamber\n"
OK_ARGS = "mesh chamber target 76e3 gain 1e-6 height 0.04 axis %r %r" % AXIS

ERROR_CASES = {
    "no_target": (WALL + "fix s all servo/radial mesh chamber gain 1e-6 height 0.04\n",
                  "missing required keyword 'target'"),
    "gain_negative": (WALL + "fix s all servo/radial mesh chamber target 76e3 gain -1 height 0.04\n",
                      "keyword 'gain' must be > 0 (m/s per Pa)"),
    "vmax_not_number": (WALL + "fix s all servo/radial %s vmax fast\n" % OK_ARGS,
                        "value 'fast' of keyword 'vmax' is not a number; allowed: > 0 (m/s)"),
    "height_zero": (WALL + "fix s all servo/radial mesh chamber target 76e3 gain 1e-6 height 0\n",
                    "keyword 'height' must be > 0 (m)"),
    "unknown_keyword": (WALL + "fix s all servo/radial %s speed 2\n" % OK_ARGS,
                        "unknown keyword 'speed'; expected mesh, target, gain, vmax, height, axis"),
    "sector_too_wide": (WALL + "fix s all servo/radial %s sector 400\n" % OK_ARGS,
                        "keyword 'sector' must be > 0 and <= 360 (degrees), got 400"),
    "mesh_missing": (WALL + "fix s all servo/radial mesh nope target 76e3 gain 1e-6 height 0.04\n",
                     "no fix with ID 'nope' given to keyword 'mesh'"),
    "mesh_not_stress": ("fix plain all mesh/surface file chamber.stl type 3\n" + WALL +
                        "fix s all servo/radial mesh plain target 76e3 gain 1e-6 height 0.04\n",
                        "is not a fix mesh/surface/stress"),
    "height_variable_atom": (WALL + "variable ha atom z\nfix s all servo/radial mesh chamber "
                             "target 76e3 gain 1e-6 height v_ha\nrun 0\n",
                             "given to keyword 'height' must be equal-style"),
    "height_variable_negative": (WALL + "variable hn equal -0.04\nfix s all servo/radial mesh "
                                 "chamber target 76e3 gain 1e-6 height v_hn axis %r %r\nrun 0\n" % AXIS,
                                 "the sample height must be > 0"),
    "axis_off_wall_centre": (WALL + "fix s all servo/radial mesh chamber target 76e3 gain 1e-6 "
                             "height 0.04 axis 0.01 0\nrun 0\n",
                             "are not on one circle about the axis"),
    "not_a_cylinder": ("fix plate all mesh/surface/stress file plate.stl type 3\n" +
                       "fix plate_wall all wall/gran model hertz tangential history mesh "
                       "n_meshes 1 meshes plate\n" +
                       "fix s all servo/radial mesh plate target 76e3 gain 1e-6 height 0.04\nrun 0\n",
                       "is not a cylinder of vertical facets"),
    "before_wall": ("fix s all servo/radial %s\n" % OK_ARGS + WALL + "run 0\n",
                    "define it after fix wall/gran 'chamber_wall'"),
    "two_servos": (WALL + "fix s all servo/radial %s\nfix s2 all servo/radial %s\nrun 0\n"
                   % (OK_ARGS, OK_ARGS), "both servo mesh 'chamber'"),
    "move_mesh_too": (WALL + "fix mv all move/mesh mesh chamber linear 0 0 0.1\n"
                      "fix s all servo/radial %s\n" % OK_ARGS, "also moves mesh 'chamber'"),
    "periodic": (WALL + "fix s all servo/radial %s\n" % OK_ARGS, "needs a non-periodic box"),
}


@pytest.mark.parametrize("case", sorted(ERROR_CASES))
def test_bad_input_is_an_error(scene, tmp_path, case):
    body, message = ERROR_CASES[case]
    for name in ("chamber.stl", "plate.stl"):
        (tmp_path / name).write_bytes((scene / name).read_bytes())
    boundary = "p p f" if case == "periodic" else "f f f"
    deck = ERR_HEAD.format(inputs=harness.REPO / "inputs", boundary=boundary) + body
    harness.expect_error(deck, tmp_path, message, timeout=120)
