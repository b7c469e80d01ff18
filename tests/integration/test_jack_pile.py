# SPDX-License-Identifier: GPL-2.0-or-later
"""Deck-level tests of `fix jack/pile`, the jacking controller of the pile
(docs/model.md §4.5), driving the cone and shaft meshes written by
crushpost.meshes through stock `fix move/mesh ... linear/variable`.

a. No grains (1 and 2 MPI ranks): the head force is exactly zero and the
   kinematics are exact. Monotonic: depth = V t during the push (every full
   step moves V dt, slope V to 1e-9), the last step lands on the target, then
   the pile stands still. Cyclic: every unload lasts zero steps (head force
   0 <= zero_tol), every pause ceil(T / dt) steps, strokes end at S, 2 S and
   the target; `surface` shifts the depth reference. A run continued from a
   restart file writes the same series as an uninterrupted one.
b. 482 NE34-shaped grains (N = 39) settled in a frictionless cylinder under
   100 g (a centrifuge-like body force gives quasi-static stresses in a box
   this small), steel pile (type 2, tan delta = 0.5 with the grains, R = 6 mm),
   cyclic jacking for 3 strokes, with the pile held still in the pauses and
   with pause_servo: the phases repeat push -> unload -> pause; pushes end
   exactly at S, 2 S, 3 S; the depth changes by -v dt every step (V while
   pushing, VU while unloading, 0 or the servo velocity while paused); every
   unload ends on the first step with head force <= zero_tol; the head force
   stays within the stated tolerance of zero through every pause (held: 1 %
   of the peak push load; servo: zero_tol); head = cone + shaft.
c. Monotonic jacking into the same grains: depth against time has slope V
   (relative 1e-9) during the push, and the target depth is reached exactly.
d. Bad input (negative or zero stroke, zero velocity, unknown mode, missing
   or wrong meshes, ...) stops with an error naming the keyword and its
   allowed range; meshes not moved with the controller's velocity stop with
   an error naming the deck lines. Error decks run concurrently (each spends
   ~2 s in MPI shutdown).
"""

import math
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import harness  # noqa: E402
from harness import REPO  # noqa: E402

from crushpost.materials import RHO_GRAIN  # noqa: E402
from crushpost.meshes import write_pile_stl  # noqa: E402
import pile_cell  # noqa: E402

INPUTS = REPO / "inputs"
PHASE_PUSH, PHASE_UNLOAD, PHASE_PAUSE, PHASE_DONE = 0, 1, 2, 3
COLUMNS = ["step", "time", "depth", "F_cone", "F_shaft", "F_head", "phase", "cycle", "v_next"]

R_PILE = 0.006             # m: a small pile, 1.5 d50 wide
N_SEG = 16
SHAFT_LENGTH = 0.07


def read_series(path):
    """The time series file of the fix as a dict of columns."""
    return pile_cell.read_series(path, COLUMNS)


def write_pile(workdir, tip_z):
    return write_pile_stl(str(workdir), R_PILE, SHAFT_LENGTH, tip_z=tip_z, n_seg=N_SEG)


MOVE_LINES = """\
variable        zero equal 0
variable        vz equal f_jack[1]
fix             mv_cone all move/mesh mesh cone linear/variable v_zero v_zero v_vz
fix             mv_shaft all move/mesh mesh shaft linear/variable v_zero v_zero v_vz
"""

# ---------------------------------------------------------------------------
# a. no grains: exact kinematics, zero head force
# ---------------------------------------------------------------------------

DT_A = 1e-5
TIP_A = 0.05


def deck_empty(jack_args, nsteps, move=True, processors=""):
    return f"""\
variable        inputs index {INPUTS}
include         ${{inputs}}/base.in
atom_modify     sort 0 0.0     # no atoms: nothing to sort
boundary        f f f
{processors}
region          box block -0.02 0.02 -0.02 0.02 0.0 0.2 units box
create_box      4 box
include         ${{inputs}}/materials_ne34.in
neighbor        0.002 bin
neigh_modify    delay 0
timestep        {DT_A!r}
fix             cone all mesh/surface/stress file cone.stl type 2
fix             shaft all mesh/surface/stress file shaft.stl type 2
fix             pile all wall/gran model hertz tangential history mesh n_meshes 2 meshes cone shaft
fix             jack all jack/pile cone cone shaft shaft {jack_args}
{MOVE_LINES if move else ""}
fix             integ all nve
thermo_style    custom step time f_jack[1] f_jack[2] f_jack[3] f_jack[4] f_jack[5] f_jack[6] f_jack[7]
thermo_modify   format float %.17g lost error
thermo          1
run             {nsteps}
"""


def run_empty(tmp_path, jack_args, nsteps, nprocs=1, **kw):
    write_pile(tmp_path, TIP_A)
    procs = "processors * 1 1" if nprocs > 1 else ""
    res = harness.run_deck(deck_empty(jack_args, nsteps, processors=procs, **kw), tmp_path,
                           nprocs=nprocs, timeout=120, check=True)
    return res, read_series(tmp_path / "jack.txt")


@pytest.mark.parametrize("nprocs", [1, 2])
def test_empty_monotonic_exact(tmp_path, nprocs):
    V, D = 0.5, 0.012341
    n_full = int(math.floor(D / (V * DT_A)))          # 2468 full steps, then 0.2 of one
    assert D / (V * DT_A) - n_full == pytest.approx(0.2)
    nsteps = n_full + 50
    res, s = run_empty(tmp_path, f"mode monotonic v {V} depth {D} file jack.txt every 1",
                       nsteps, nprocs)
    step, depth = s["step"], s["depth"]
    assert np.array_equal(step, np.arange(1, nsteps + 1))
    # exactly zero force on both meshes
    for c in ("F_cone", "F_shaft", "F_head"):
        assert np.all(s[c] == 0.0), c
    # full push steps: depth = V t exactly (to round-off of the mesh nodes)
    t = s["time"]
    k = n_full - 1
    np.testing.assert_allclose(depth[:n_full], V * step[:n_full] * DT_A, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(t[:n_full], step[:n_full] * DT_A, rtol=1e-12)
    slope = np.diff(depth[:n_full]) / np.diff(t[:n_full])
    np.testing.assert_allclose(slope, V, rtol=1e-9)
    assert np.all(s["phase"][:k] == PHASE_PUSH)
    # the last step lands on the target; then done, standing still
    assert depth[n_full] == pytest.approx(D, abs=1e-14)
    # the last step covers the remaining 0.2 of a step (up to the round-off of
    # the mesh positions accumulated over the push, ~1e-14 m)
    assert -s["v_next"][n_full - 1] * DT_A == pytest.approx(0.2 * V * DT_A, abs=2e-14)
    assert np.all(s["phase"][n_full:] == PHASE_DONE)
    assert np.all(depth[n_full:] == depth[n_full])
    assert np.all(s["v_next"][n_full:] == 0.0)
    assert np.all(s["cycle"] == 1)
    # the thermo output is the same global vector (f_jack[1..7])
    blk = res.thermo[-1]
    np.testing.assert_allclose(blk["f_jack[2]"][1:], depth, rtol=1e-10, atol=1e-15)
    np.testing.assert_allclose(blk["f_jack[1]"][1:], s["v_next"], rtol=1e-10, atol=1e-15)
    assert blk["f_jack[1]"][0] == -V and blk["f_jack[2]"][0] == 0.0
    assert np.all(blk["f_jack[5]"] == 0.0)


@pytest.mark.parametrize("nprocs", [1, 2])
def test_empty_cyclic_exact(tmp_path, nprocs):
    V, S, VU, T, D = 0.5, 0.004, 0.05, 2.05e-4, 0.01
    # surface 2 mm below the tip: depth starts at -0.002, strokes end at 4, 8, 10 mm
    z_surf = TIP_A - 0.002
    args = (f"mode cyclic v {V} stroke {S} v_unload {VU} pause {T} depth {D} "
            f"surface {z_surf!r} file jack.txt every 1")
    n_pause = math.ceil(T / DT_A)                     # 21 steps standing still
    pushes = [0.006, S, D - 2 * S]                     # lengths of the three strokes
    n_push = [round(p / (V * DT_A)) for p in pushes]   # 1200, 800, 400
    nsteps = sum(n_push) + 2 * n_pause + 30
    res, s = run_empty(tmp_path, args, nsteps, nprocs)
    assert np.all(s["F_head"] == 0.0) and np.all(s["F_cone"] == 0.0)
    depth, phase, cycle, v = s["depth"], s["phase"], s["cycle"], s["v_next"]
    # reconstruct the exact schedule: push, (zero-step unload), pause, ...
    exp_depth, exp_phase, exp_cycle = [], [], []
    d = -0.002
    for k, n in enumerate(n_push):
        for i in range(n):
            d = -0.002 + (sum(pushes[:k]) + (i + 1) * V * DT_A)
            exp_depth.append(d)
            last = i == n - 1
            exp_phase.append((PHASE_DONE if k == 2 else PHASE_PAUSE) if last else PHASE_PUSH)
            exp_cycle.append(k + 1)
        if k < 2:
            for i in range(n_pause):
                exp_depth.append(d)
                exp_phase.append(PHASE_PUSH if i == n_pause - 1 else PHASE_PAUSE)
                exp_cycle.append(k + 2 if i == n_pause - 1 else k + 1)
    while len(exp_depth) < nsteps:
        exp_depth.append(d)
        exp_phase.append(PHASE_DONE)
        exp_cycle.append(3)
    np.testing.assert_allclose(depth, exp_depth, rtol=0, atol=1e-14)
    assert np.array_equal(phase, exp_phase)
    assert np.array_equal(cycle, exp_cycle)
    # stroke ends: S, 2 S and the target, measured from the surface
    ends = depth[np.nonzero((phase != PHASE_PUSH) & (np.roll(phase, 1) == PHASE_PUSH))[0]]
    np.testing.assert_allclose(ends, [S, 2 * S, D], atol=1e-14)
    # no unload step ever happened (never moving up)
    assert np.all(v <= 0.0)


RESTART_PILE = """\
include         ${{inputs}}/materials_ne34.in
neighbor        0.002 bin
neigh_modify    delay 0
timestep        {dt!r}
fix             cone all mesh/surface/stress file cone.stl type 2
fix             shaft all mesh/surface/stress file shaft.stl type 2
fix             pile all wall/gran model hertz tangential history mesh n_meshes 2 meshes cone shaft
fix             jack all jack/pile cone cone shaft shaft {args} file {out} every 1
""" + MOVE_LINES + """\
fix             integ all nve
"""

RESTART_HEAD = f"""\
variable        inputs index {INPUTS}
include         ${{inputs}}/base.in
boundary        f f f
"""

# one far-away grain: LIGGGHTS needs an atom type in use for a second run
RESTART_BOX = f"""\
region          box block -0.02 0.02 -0.02 0.02 0.0 0.2 units box
create_box      4 box
create_atoms    1 single 0.015 0.015 0.19 units box
set             atom 1 diameter 0.001 density {RHO_GRAIN:g}
"""


def test_restart_continues_exactly(tmp_path):
    # a cyclic run interrupted in the middle of the second stroke and continued
    # from a restart file writes the same series (step, time, depth, phase,
    # cycle, velocity) as one uninterrupted run
    args = "mode cyclic v 0.5 stroke 0.004 v_unload 0.05 pause 2.05e-4 depth 0.01"
    pile = lambda out: RESTART_PILE.format(dt=DT_A, args=args, out=out)  # noqa: E731
    write_pile(tmp_path, TIP_A)
    full = RESTART_HEAD + RESTART_BOX + pile("full.txt") + "run 1210\nrun 1300\n"
    part1 = RESTART_HEAD + RESTART_BOX + pile("a.txt") + "run 1210\nwrite_restart r.restart\n"
    part2 = RESTART_HEAD + "read_restart r.restart\n" + pile("b.txt") + "run 1300\n"
    for deck in (full, part1, part2):
        harness.run_deck(deck, tmp_path, timeout=60, check=True)
    f = read_series(tmp_path / "full.txt")
    a, b = read_series(tmp_path / "a.txt"), read_series(tmp_path / "b.txt")
    assert a["phase"][-1] == PHASE_PUSH and a["cycle"][-1] == 2   # stopped mid-stroke 2
    assert f["phase"][-1] == PHASE_DONE
    for c in COLUMNS:
        np.testing.assert_array_equal(np.concatenate([a[c], b[c]]), f[c], err_msg=c)


# ---------------------------------------------------------------------------
# b., c. grains settled under gravity, pile jacked in
# ---------------------------------------------------------------------------

R_CELL = 0.035
H_PACK = 0.045             # estimated settled height
H_RSA = 0.085
DT_B = 2e-6
SETTLE_STEPS = 30000


def header_grains(data_file):
    return pile_cell.header(data_file, R_CELL, DT_B)


@pytest.fixture(scope="module")
def settled(tmp_path_factory):
    """A few hundred NE34-shaped grains (N = 39) settled in a frictionless
    cylinder; returns (folder, number of grains, z of the highest grain top
    in the way of the pile)."""
    wd = tmp_path_factory.mktemp("settle")
    res, atoms = pile_cell.settle(wd, R_CELL, H_PACK, H_RSA, DT_B, SETTLE_STEPS, seed=20240611,
                                  z_box_top=0.2)
    n = len(atoms)
    ke = res.thermo[-1]["KinEng"]
    assert ke[-1] < 1e-3 * ke.max(), ke                # settled
    # top of the grains in the pile's way (centres within R_PILE + r of the axis)
    r = 0.5 * atoms[:, 2]
    near = np.hypot(atoms[:, 4], atoms[:, 5]) < R_PILE + r
    ztop = float(np.max(atoms[near, 6] + r[near]))
    return wd, n, ztop


def deck_jack(jack_args, max_chunks):
    return header_grains("settled.data") + f"""\
include         ${{inputs}}/unbreakable.in
fix             cone all mesh/surface/stress file cone.stl type 2
fix             shaft all mesh/surface/stress file shaft.stl type 2
fix             pile all wall/gran model hertz tangential history mesh n_meshes 2 meshes cone shaft
include         ${{inputs}}/integrate.in
fix             jack all jack/pile cone cone shaft shaft {jack_args} file jack.txt every 1
{MOVE_LINES}
variable        phase equal f_jack[6]
thermo_style    custom step atoms f_jack[2] f_jack[3] f_jack[4] f_jack[5] f_jack[6] f_jack[7]
thermo_modify   lost error
thermo          2000
variable        chunk loop {max_chunks}
label           chunks
run             2000
if              "${{phase}} == 3" then "jump SELF finished"
next            chunk
jump            SELF chunks
label           finished
print           "JACK DONE"
"""


def run_jack(settled, tmp_path, jack_args, max_chunks=40, nprocs=1):
    wd, n, ztop = settled
    (tmp_path / "settled.data").write_text((wd / "settled.data").read_text())
    write_pile(tmp_path, ztop + 2e-4)                   # tip just above the grains
    res = harness.run_deck(deck_jack(jack_args, max_chunks), tmp_path, nprocs=nprocs,
                           timeout=300, check=True)
    assert "JACK DONE" in res.log, res.summary()
    return res, read_series(tmp_path / "jack.txt")


V_B, S_B, VU_B, T_B, D_B = 0.25, 0.006, 0.1, 1e-3, 0.018
ZERO_TOL_B = 0.05          # N: unload ends at head force <= 0.05 N
SERVO_B = 2.0              # m/s per N: pause_servo of the load-controlled pause


@pytest.fixture(scope="module", params=["hold", "servo"])
def cyclic_run(settled, tmp_path_factory, request):
    """Cyclic jacking with the pile held still in the pauses (default), and
    with the head force servo-controlled to zero (pause_servo)."""
    wd = tmp_path_factory.mktemp("cyclic_" + request.param)
    args = (f"mode cyclic v {V_B} stroke {S_B} v_unload {VU_B} pause {T_B} depth {D_B} "
            f"zero_tol {ZERO_TOL_B}")
    if request.param == "servo":
        args += f" pause_servo {SERVO_B}"
    res, s = run_jack(settled, wd, args)
    return request.param, res, s


def segments(phase):
    """(phase, first index, last index) of each run of equal phases."""
    out = []
    start = 0
    for i in range(1, len(phase) + 1):
        if i == len(phase) or phase[i] != phase[start]:
            out.append((int(phase[start]), start, i - 1))
            start = i
    return out


def test_cyclic_phase_sequence_and_stroke_ends(cyclic_run):
    mode, res, s = cyclic_run
    phase, depth, cycle = s["phase"], s["depth"], s["cycle"]
    seq = [p for p, a, b in segments(phase)]
    assert seq == [0, 1, 2, 0, 1, 2, 0, 3], seq
    cyc = [int(cycle[a]) for p, a, b in segments(phase)]
    assert cyc == [1, 1, 1, 2, 2, 2, 3, 3], cyc
    # each push ends (the record where the phase leaves push) exactly at k S
    ends = [depth[a] for p, a, b in segments(phase) if p in (PHASE_UNLOAD, PHASE_DONE)]
    np.testing.assert_allclose(ends, [S_B, 2 * S_B, 3 * S_B], rtol=0, atol=1e-12)
    assert 3 * S_B == pytest.approx(D_B)
    # after done the pile stands still at the target
    a = segments(phase)[-1][1]
    assert np.all(s["v_next"][a:] == 0.0)
    assert np.all(depth[a:] == depth[a])
    print("cyclic: %d steps, stroke ends %s" % (len(depth), ends))


def test_cyclic_kinematics(cyclic_run):
    mode, res, s = cyclic_run
    phase, depth, v, head = s["phase"], s["depth"], s["v_next"], s["F_head"]
    # the depth change of step n is -v_next of step n-1 times dt
    dd = np.diff(depth)
    np.testing.assert_allclose(dd, -v[:-1] * DT_B, rtol=1e-9, atol=1e-9 * V_B * DT_B)
    # while pushing: -V (full steps); while unloading +VU
    prev = phase[:-1]
    full = (prev == PHASE_PUSH) & (phase[1:] == PHASE_PUSH)
    np.testing.assert_allclose(dd[full] / DT_B, V_B, rtol=1e-9)
    np.testing.assert_allclose(dd[prev == PHASE_UNLOAD] / DT_B, -VU_B, rtol=1e-9)
    # paused: standing still, or the servo velocity G F_head (at most VU)
    paused = phase == PHASE_PAUSE
    if mode == "hold":
        assert np.all(dd[prev == PHASE_PAUSE] == 0.0)
        assert np.all(v[paused] == 0.0)
    else:
        # (F_head is written with 10 digits)
        np.testing.assert_allclose(v[paused], np.clip(SERVO_B * head[paused], -VU_B, VU_B),
                                   rtol=1e-9, atol=1e-18)
    # pauses last ceil(T / dt) steps
    for p, a, b in segments(phase):
        if p == PHASE_PAUSE:
            assert b - a + 1 == math.ceil(T_B / DT_B - 1e-6), (a, b)


# Stated tolerances of the zero-load pauses (docs/fix_jack_pile.md):
# - every pause starts on the first step with F_head <= zero_tol, after an
#   unload that had F_head > zero_tol on every step;
# - holding the position, grains relaxing against the still pile may reload
#   it: |F_head| stays below 1 % of the peak push load throughout the pause;
# - with pause_servo the head load is held at zero: |F_head| <= zero_tol
#   on every step of the pause.
PAUSE_TOL_HOLD = 0.01      # x peak head force while pushing


def test_cyclic_pauses_at_zero_head_load(cyclic_run):
    mode, res, s = cyclic_run
    phase, head = s["phase"], s["F_head"]
    np.testing.assert_allclose(head, s["F_cone"] + s["F_shaft"], rtol=1e-9, atol=1e-12)
    peak = np.max(head[phase == PHASE_PUSH])
    assert peak > 100 * ZERO_TOL_B
    tol = PAUSE_TOL_HOLD * peak if mode == "hold" else ZERO_TOL_B
    report = []
    for p, a, b in segments(phase):
        if p == PHASE_UNLOAD:
            # unloading until the first step at or below the tolerance
            assert np.all(head[a:b + 1] > ZERO_TOL_B)
        if p == PHASE_PAUSE:
            # entered on the first step with F_head <= zero_tol ...
            assert head[a] <= ZERO_TOL_B
            # ... and within the stated tolerance of zero all through the pause
            # (records a .. b+1: the force before and after every paused step)
            window = head[a:b + 2]
            report.append((head[a], np.min(window), np.max(window)))
            assert np.max(np.abs(window)) <= tol, (mode, tol, window)
    assert len(report) == 2
    print("%s: peak push head force %.4g N; pauses (entry, min, max F_head): %s"
          % (mode, peak, report))


def test_cyclic_pile_carries_load_while_pushing(cyclic_run):
    mode, res, s = cyclic_run
    phase, cone, shaft = s["phase"], s["F_cone"], s["F_shaft"]
    segs = segments(phase)
    for p, a, b in segs:
        if p == PHASE_PUSH:
            # the soil resists the push: the cone carries a clear upward load
            assert np.mean(cone[a:b + 1]) > 0.0
    # the shaft enters the grains in the later strokes: friction resists the push
    last_push = [(a, b) for p, a, b in segs if p == PHASE_PUSH][-1]
    assert np.max(shaft[last_push[0]:last_push[1] + 1]) > 0.0
    # unloading relieves the cone: lower head force at the end than at the start
    for p, a, b in segs:
        if p == PHASE_UNLOAD:
            assert s["F_head"][b] < s["F_head"][a]


def test_monotonic_into_grains(settled, tmp_path):
    D = 0.012
    res, s = run_jack(settled, tmp_path, f"mode monotonic v {V_B} depth {D}")
    phase, depth, t = s["phase"], s["depth"], s["time"]
    push = np.nonzero(phase == PHASE_PUSH)[0]
    assert len(push) > 1000
    # depth against time during the push: slope V (relative 1e-9)
    slope = np.diff(depth[push]) / np.diff(t[push])
    np.testing.assert_allclose(slope, V_B, rtol=1e-9)
    fit = np.polyfit(t[push] - t[push[0]], depth[push], 1)
    assert fit[0] == pytest.approx(V_B, rel=1e-9)
    # target reached exactly; done for the rest of the run
    done = np.nonzero(phase == PHASE_DONE)[0]
    assert done[0] == push[-1] + 1
    assert depth[done[0]] == pytest.approx(D, abs=1e-12)
    assert np.all(depth[done] == depth[done[0]])
    assert np.all(s["cycle"] == 1)
    assert np.max(s["F_cone"]) > 0.0


# ---------------------------------------------------------------------------
# d. bad input
# ---------------------------------------------------------------------------
# A run that ends in error->all spends ~2 s in MPI shutdown; the error decks
# are therefore run concurrently once (they use almost no CPU) and each case
# checks its own result.

GOOD_CYCLIC = "mode cyclic v 0.5 stroke 0.004 v_unload 0.05 pause 1e-4 depth 0.01"

BAD_INPUT = [
    ("negative_stroke", "mode cyclic v 0.5 stroke -0.004 v_unload 0.05 pause 1e-4 depth 0.01",
     "keyword 'stroke' must be > 0 (m), got -0.004"),
    ("zero_stroke", "mode cyclic v 0.5 stroke 0 v_unload 0.05 pause 1e-4 depth 0.01",
     "keyword 'stroke' must be > 0 (m), got 0"),
    ("zero_velocity", "mode monotonic v 0 depth 0.01",
     "keyword 'v' (push velocity) must be > 0 (m/s), got 0"),
    ("negative_velocity", "mode monotonic v -0.5 depth 0.01",
     "keyword 'v' (push velocity) must be > 0 (m/s), got -0.5"),
    ("nan_velocity", "mode cyclic v nan stroke 0.004 v_unload 0.05 pause 1e-4 depth 0.01",
     "keyword 'v' (push velocity) must be > 0 (m/s), got nan"),
    ("zero_depth", "mode monotonic v 0.5 depth 0",
     "keyword 'depth' (target tip depth) must be > 0 (m), got 0"),
    ("negative_depth", "mode cyclic v 0.5 stroke 0.004 v_unload 0.05 pause 1e-4 depth -1",
     "keyword 'depth' (target tip depth) must be > 0 (m), got -1"),
    ("zero_unload_velocity", "mode cyclic v 0.5 stroke 0.004 v_unload 0 pause 1e-4 depth 0.01",
     "keyword 'v_unload' (upward unloading velocity) must be > 0 (m/s), got 0"),
    ("negative_pause", "mode cyclic v 0.5 stroke 0.004 v_unload 0.05 pause -1 depth 0.01",
     "keyword 'pause' (duration) must be >= 0 (s), got -1"),
    ("negative_zero_tol", GOOD_CYCLIC + " zero_tol -1",
     "keyword 'zero_tol' (head force tolerance) must be >= 0 (N), got -1"),
    ("unknown_mode", "mode sideways v 0.5 depth 0.01",
     "keyword 'mode' must be 'monotonic' or 'cyclic', got 'sideways'"),
    ("missing_mode", "v 0.5 depth 0.01", "missing required keyword 'mode' (monotonic or cyclic)"),
    ("missing_v", "mode monotonic depth 0.01", "missing required keyword 'v'"),
    ("missing_depth", "mode monotonic v 0.5", "missing required keyword 'depth'"),
    ("non_numeric", "mode monotonic v abc depth 0.01",
     "value 'abc' of keyword 'v' is not a number; allowed: > 0 (m/s)"),
    ("cyclic_without_stroke", "mode cyclic v 0.5 v_unload 0.05 pause 1e-4 depth 0.01",
     "mode cyclic needs keyword 'stroke' (> 0, m)"),
    ("cyclic_without_pause", "mode cyclic v 0.5 stroke 0.004 v_unload 0.05 depth 0.01",
     "mode cyclic needs keyword 'pause' (>= 0, s)"),
    ("stroke_in_monotonic", "mode monotonic v 0.5 depth 0.01 stroke 0.004",
     "keyword 'stroke' applies to mode cyclic only"),
    ("bad_strokes", GOOD_CYCLIC + " strokes sideways",
     "keyword 'strokes' must be 'absolute' or 'relative'"),
    ("every_fraction", GOOD_CYCLIC + " every 2.5", "keyword 'every' must be an integer >= 1"),
    ("unknown_keyword", GOOD_CYCLIC + " speed 3", "unknown keyword 'speed'; expected cone, shaft"),
    ("missing_value", GOOD_CYCLIC + " surface", "keyword 'surface' needs a value"),
    ("sector_zero", GOOD_CYCLIC + " sector 0",
     "keyword 'sector' (simulated sector of the chamber) must be > 0 and <= 360 (degrees), got 0"),
    ("sector_too_wide", GOOD_CYCLIC + " sector 400", "must be > 0 and <= 360 (degrees), got 400"),
]

ERROR_MESHES = pile_cell.EMPTY_BOX + """\
fix             cone all mesh/surface/stress file cone.stl type 2
fix             plain all mesh/surface file shaft.stl type 2
fix             pile all wall/gran model hertz tangential history mesh n_meshes 2 meshes cone plain
fix             integ all nve
fix             jack all jack/pile {mesh_args} mode monotonic v 0.5 depth 0.01
run             1
"""

BAD_MESHES = [
    ("no_cone", "shaft plain", "missing required keyword 'cone'"),
    ("no_shaft", "cone cone", "missing required keyword 'shaft'"),
    ("same_mesh", "cone cone shaft cone",
     "keywords 'cone' and 'shaft' name the same fix 'cone'"),
    ("unknown_shaft", "cone cone shaft nosuch", "keyword 'shaft': no fix with ID 'nosuch'"),
    ("unknown_cone", "cone nosuch shaft plain", "keyword 'cone': no fix with ID 'nosuch'"),
    ("not_stress", "cone cone shaft plain",
     "keyword 'shaft': fix 'plain' (mesh/surface) is not a fix mesh/surface/stress"),
    ("not_a_mesh", "cone integ shaft plain",
     "keyword 'cone': fix 'integ' (nve) is not a fix mesh/surface/stress"),
]

MOVE_CONE_ONLY = ("variable zero equal 0\nvariable vz equal f_jack[1]\n"
                  "fix mv all move/mesh mesh cone linear/variable v_zero v_zero v_vz\n")

BAD_MOTION = [
    ("not_moved", deck_empty("mode monotonic v 0.5 depth 0.01", 5, move=False),
     "the cone mesh (fix cone) moved by 0 m in step 1 but the controller commanded -5e-06 m"),
    ("shaft_not_moved", deck_empty("mode monotonic v 0.5 depth 0.01", 5, move=False).replace(
        "fix             integ all nve", MOVE_CONE_ONLY + "fix integ all nve"),
     "the shaft mesh (fix shaft) moved by 0 m in step 1"),
    # the stock syntax needs three variables: a plain 0 is not accepted
    ("constant_component", deck_empty("mode monotonic v 0.5 depth 0.01", 5, move=False).replace(
        "fix             integ all nve",
        "variable vz equal f_jack[1]\n"
        "fix mv all move/mesh mesh cone linear/variable 0 0 v_vz\nfix integ all nve"),
     "Variable name 1 for fix move/mesh linear/variable does not exist"),
]


@pytest.fixture(scope="module")
def error_runs(tmp_path_factory):
    cases = {}
    for name, args, pattern in BAD_INPUT:
        cases["input_" + name] = (deck_empty(args, 1), pattern)
    for name, args, pattern in BAD_MESHES:
        cases["mesh_" + name] = (ERROR_MESHES.format(inputs=INPUTS, mesh_args=args), pattern)
    for name, deck, pattern in BAD_MOTION:
        cases["motion_" + name] = (deck, pattern)
    return pile_cell.run_error_cases(cases, tmp_path_factory, lambda wd: write_pile(wd, TIP_A))


def _check_error(error_runs, key, pattern, source="fix jack/pile"):
    res = error_runs[key]
    if isinstance(res, Exception):
        raise res
    assert any(pattern in e and source in e for e in res.errors), res.errors


@pytest.mark.parametrize("name, args, expected", BAD_INPUT, ids=[c[0] for c in BAD_INPUT])
def test_bad_input(error_runs, name, args, expected):
    _check_error(error_runs, "input_" + name, expected)


@pytest.mark.parametrize("name, args, expected", BAD_MESHES, ids=[c[0] for c in BAD_MESHES])
def test_bad_meshes(error_runs, name, args, expected):
    _check_error(error_runs, "mesh_" + name, expected)


@pytest.mark.parametrize("name, deck, expected", BAD_MOTION, ids=[c[0] for c in BAD_MOTION])
def test_meshes_must_move_with_the_controller(error_runs, name, deck, expected):
    source = "linear/variable" if name == "constant_component" else "fix jack/pile"
    _check_error(error_runs, "motion_" + name, expected, source)
    if name == "not_moved":
        res = error_runs["motion_" + name]
        assert any("move/mesh mesh cone linear/variable v_zero v_zero v_vz" in e
                   for e in res.errors), res.errors


def test_check_motion_no_switches_the_check_off(tmp_path):
    write_pile(tmp_path, TIP_A)
    deck = deck_empty("mode monotonic v 0.5 depth 0.01 check_motion no", 5, move=False)
    res = harness.run_deck(deck, tmp_path, timeout=60, check=True)
    blk = res.thermo[-1]
    # the controller commands the push, but nothing moves the meshes
    assert np.all(blk["f_jack[1]"] == -0.5)
    assert np.all(blk["f_jack[2]"] == 0.0)


# ---------------------------------------------------------------------------
# the depth reference in the file's header (post-processing places the tip
# at z_ref - depth)
# ---------------------------------------------------------------------------

def test_file_header_has_the_depth_reference(tmp_path):
    from crushpost.pile import read_jack

    V = 0.5
    # with `surface`: z_ref is that value, and z_ref - depth is the apex's z
    z_surf = TIP_A - 0.0031
    run_empty(tmp_path / "surface",
              f"mode monotonic v {V} depth 0.001 surface {z_surf!r} file jack.txt every 10", 60)
    text = (tmp_path / "surface" / "jack.txt").read_text()
    assert "z_ref = keyword surface" in text
    j = read_jack(tmp_path / "surface" / "jack.txt")
    assert j["z_ref"] == z_surf
    np.testing.assert_allclose(j["z_ref"] - j["depth"], TIP_A - V * DT_A * j["step"], rtol=0,
                               atol=1e-14)
    # without: the apex at the first run
    run_empty(tmp_path / "apex", f"mode monotonic v {V} depth 0.001 file jack.txt every 10", 20)
    j = read_jack(tmp_path / "apex" / "jack.txt")
    assert j["z_ref"] == TIP_A
    assert "z_ref = the apex z at the first run" in (tmp_path / "apex" / "jack.txt").read_text()
    # after read_restart: the same reference, from the restart file; one
    # header per file, before the first data line
    args = f"mode monotonic v {V} depth 0.01 surface {z_surf!r}"
    pile = lambda out: RESTART_PILE.format(dt=DT_A, args=args, out=out)  # noqa: E731
    wd = tmp_path / "restart"
    write_pile(wd, TIP_A)
    harness.run_deck(RESTART_HEAD + RESTART_BOX + pile("a.txt") + "run 20\nrun 20\n"
                     "write_restart r.restart\n", wd, timeout=60, check=True)
    harness.run_deck(RESTART_HEAD + "read_restart r.restart\n" + pile("b.txt") + "run 20\n",
                     wd, timeout=60, check=True)
    for name, source in (("a.txt", "keyword surface"), ("b.txt", "from the restart file")):
        lines = (wd / name).read_text().splitlines()
        assert [ln for ln in lines if ln.startswith("#")] == lines[:4]
        assert lines[2].startswith("# z_ref ") and lines[2].endswith("z_ref = " + source)
        assert lines[3] == "# step time depth F_cone F_shaft F_head phase cycle v_next"
        assert read_jack(wd / name)["z_ref"] == z_surf
