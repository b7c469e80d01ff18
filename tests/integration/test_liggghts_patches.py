# SPDX-License-Identifier: GPL-2.0-or-later
"""Deck tests of the changes this package makes to the LIGGGHTS 3.8 sources in
the build tree (cmake/PrepareLiggghtsSource.cmake, docs/liggghts-patches.md):
a stock deck must run exactly as with stock LIGGGHTS. The decks here use
stock styles only, so each is also run with Debian's stock binary
(/usr/bin/liggghts, installed by scripts/setup; LIGGGHTS_STOCK_BIN for
another) and must print the same thermo output to the last printed digit.

a. mesh/surface/stress at the set-up of a run. Stock LIGGGHTS adds the
   set-up wall forces on top of the previous step's summed total, so the
   set-up row of every later run reads the previous total plus the set-up
   contacts (twice the force at one rank). An earlier version of this
   package changed that in mesh_module_stress.h; the change altered what
   stock decks print and was dropped: this build must print what stock
   prints. Scene: one grain squeezed between a primitive bottom wall and a
   fixed mesh plate with the same overlap delta at both, so it stays at rest
   and the plate force is the Hertz force F = 4/3 E* sqrt(r delta) delta
   (independent answer) during the runs, and 2 F at the set-up of a later
   run at one rank (the reading of mesh_module_stress.cpp above).
b. FixContactHistoryMesh::markAllContacts (the speed change, below).
c. lammps.cpp, `-screen none`: stock crashes on a deck with a mesh (the STL
   reader prints to the screen unchecked); this build runs it, with the same
   output as with the screen sent to /dev/null.
"""

import math
import os
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import crush_multi as cm  # noqa: E402
import harness  # noqa: E402

D = 1.0e-3
DELTA = 2.0e-6
STOCK_BIN = Path(os.environ.get("LIGGGHTS_STOCK_BIN", "/usr/bin/liggghts"))


def run_stock(monkeypatch, *args, **kwargs):
    """harness.run_deck with Debian's stock binary."""
    if not (STOCK_BIN.is_file() and os.access(str(STOCK_BIN), os.X_OK)):
        pytest.fail("stock LIGGGHTS not found at %s: run scripts/setup (installs Debian's "
                    "package liggghts), or set LIGGGHTS_STOCK_BIN" % STOCK_BIN)
    with monkeypatch.context() as m:
        m.setenv("LIGGGHTS_BIN", str(STOCK_BIN))
        return harness.run_deck(*args, **kwargs)


def assert_same_thermo(stock, build):
    """Every thermo block of the two runs is the same, to the printed digit."""
    a, b = stock.thermo, build.thermo
    assert len(a) == len(b), (len(a), len(b))
    for x, y in zip(a, b):
        assert x.columns == y.columns
        np.testing.assert_array_equal(x.data, y.data)


def deck():
    z_plate = D - 2 * DELTA
    return cm.header(processors="* * *") + f"""\
timestep        1e-8
fix             bottom all wall/gran model hertz tangential history primitive type 2 zplane 0.0
fix             top all mesh/surface/stress file plate.stl type 2 move 0 0 {z_plate!r}
fix             walls all wall/gran model hertz tangential history mesh n_meshes 1 meshes top
fix             integ all nve
thermo_style    custom step f_top[3]
thermo_modify   format float %.15g lost error
thermo          10
run             50
run             50
run             0
"""


def _plate_scene(path):
    r = D / 2
    box = ((-2e-3, 2e-3), (-2e-3, 2e-3), (-1e-3, 3e-3))
    cm.write_data(path / "grains.data", [(0.0, 0.0, r - DELTA, D)], box)
    cm.write_plate_stl(path / "plate.stl", -2e-3, 2e-3, -2e-3, 2e-3)


@pytest.mark.parametrize("nprocs", [1, 2])
def test_mesh_force_at_setup_as_in_stock(tmp_path, monkeypatch, nprocs):
    for which in ("build", "stock"):
        (tmp_path / which).mkdir()
        _plate_scene(tmp_path / which)
    res = harness.run_deck(deck(), tmp_path / "build", nprocs=nprocs, extra_args=cm.MESH_ARGS,
                           check=True)
    stock = run_stock(monkeypatch, deck(), tmp_path / "stock", nprocs=nprocs,
                      extra_args=cm.MESH_ARGS, check=True)
    assert_same_thermo(stock, res)
    runs = [np.asarray(b["top[3]"]) for b in res.thermo]
    assert len(runs) == 3, res.summary()

    r = D / 2
    e_star = 1.0 / ((1 - cm.NU_GRAIN ** 2) / cm.E_GRAIN + (1 - cm.NU_WALL ** 2) / cm.E_WALL)
    f_hertz = 4.0 / 3.0 * e_star * math.sqrt(r * DELTA) * DELTA
    # during the runs the plate is pushed up by the Hertz force (grain at rest)
    for fz in (runs[0][1:], runs[1][1:]):
        np.testing.assert_allclose(fz, f_hertz, rtol=1e-6)
    # at the set-up of a later run, stock LIGGGHTS adds the set-up contacts
    # of the rank that prints to the last summed total: twice the force at
    # one rank (at two, it depends on which rank owns the grain)
    if nprocs == 1:
        np.testing.assert_allclose(runs[1][0], 2 * runs[0][-1], rtol=1e-12)
        np.testing.assert_allclose(runs[2][0], 2 * runs[1][-1], rtol=1e-12)


# ---------------------------------------------------------------------------
# FixContactHistoryMesh::markAllContacts (the build's speed patch: only the
# slots of grains with mesh neighbours are cleared and handed out). The
# tangential history of a grain-mesh contact must grow by k_t v dt per step
# while the contact lasts (also across the set-up of a following run) and be
# deleted when the grain leaves the plate, even when no neighbour-list build
# comes in between (that is what the cleared keep flags do). Scene: one grain
# held at a fixed overlap (not integrated) on a plate that slides at speed v,
# lifted by less than half the skin and put back by fix move; grains far from
# the plate (no mesh neighbour) and one near it without contact around it.
# Mindlin: k_t = 8 G* sqrt(R delta), G* = 1 / (2 (2 - nu1)(1 + nu1)/E1 +
# 2 (2 - nu2)(1 + nu2)/E2) (LIGGGHTS' Geff); the viscous part gamma_t v is
# constant at constant v.
# ---------------------------------------------------------------------------

V_SLIDE = 0.01
DT_SLIDE = 1e-8
V_LIFT, LIFT_STEPS = 10.0, 300     # lifted by 3e-5 m < skin / 2: no list build


def slide_deck():
    return cm.header(processors="* * *") + f"""\
timestep        {DT_SLIDE!r}
group           held id 1
group           free id > 1
fix             top all mesh/surface/stress file plate.stl type 2
fix             walls all wall/gran model hertz tangential history mesh n_meshes 1 meshes top
fix             slide all move/mesh mesh top linear {V_SLIDE!r} 0 0
fix             integ free nve
thermo_style    custom step f_top[1] f_top[3]
thermo_modify   format float %.15g lost error
thermo          10
run             100
run             100
fix             lift held move linear 0 0 {V_LIFT!r}
run             {LIFT_STEPS}
unfix           lift
fix             lower held move linear 0 0 {-V_LIFT!r}
run             {LIFT_STEPS}
unfix           lower
velocity        held set 0 0 0
run             100
"""


@pytest.mark.parametrize("nprocs", [1, 2])
def test_mesh_contact_history_lives_and_dies_with_the_contact(tmp_path, monkeypatch, nprocs):
    r = D / 2
    box = ((-2e-3, 2e-3), (-2e-3, 2e-3), (-1e-3, 3e-3))
    grains = [(0.8e-3, -0.5e-3, r - DELTA, D),               # on the plate
              (-1.0e-3, 1.0e-3, r + 0.5e-4, D)]              # within the skin, no contact
    grains += [(x, y, 2.0e-3, D) for x in (-1.5e-3, 0.0, 1.5e-3) for y in (-1.5e-3, 1.5e-3)]  # far
    cm.write_data(tmp_path / "grains.data", grains, box)
    cm.write_plate_stl(tmp_path / "plate.stl", -2e-3, 2e-3, -2e-3, 2e-3)
    (tmp_path / "stock").mkdir()
    for name in ("grains.data", "plate.stl"):
        (tmp_path / "stock" / name).write_bytes((tmp_path / name).read_bytes())
    res = harness.run_deck(slide_deck(), tmp_path, nprocs=nprocs, extra_args=cm.MESH_ARGS, check=True)
    # the speed change gives what stock LIGGGHTS gives, to the printed digit
    stock = run_stock(monkeypatch, slide_deck(), tmp_path / "stock", nprocs=nprocs,
                      extra_args=cm.MESH_ARGS, check=True)
    assert_same_thermo(stock, res)
    # no neighbour-list build while the grain goes up and down (runs 3, 4)
    builds = [int(line.split("=")[1]) for line in res.log.splitlines()
              if line.startswith("Neighbor list builds")]
    assert len(builds) == 5 and builds[2] == 0 and builds[3] == 0, builds
    runs = [b for b in res.thermo]
    assert len(runs) == 5, res.summary()
    fx = [np.abs(np.asarray(b["top[1]"])) for b in runs]

    g_star = 1.0 / (2 * (2 - cm.NU_GRAIN) * (1 + cm.NU_GRAIN) / cm.E_GRAIN
                    + 2 * (2 - cm.NU_WALL) * (1 + cm.NU_WALL) / cm.E_WALL)
    k_t = 8.0 * g_star * math.sqrt(r * DELTA)
    per_step = k_t * V_SLIDE * DT_SLIDE
    # first run: the history grows by k_t v dt per step (the set-up row of a
    # run's first contact has neither the elastic nor the viscous part yet)
    np.testing.assert_allclose(np.diff(fx[0][1:]), 10 * per_step, rtol=1e-6)
    # across the set-up of the next run it is kept (no update at set-up): the
    # next run goes on from where the first ended (its set-up row itself
    # reads the previous total plus the set-up contacts, as in stock: a)
    np.testing.assert_allclose(fx[1][1] - fx[0][-1], 10 * per_step, rtol=1e-6)
    np.testing.assert_allclose(np.diff(fx[1][1:]), 10 * per_step, rtol=1e-6)
    # lifted off (after the first rows): no contact, no force
    assert np.all(fx[2][2:] == 0.0), fx[2]
    # back on the plate: a new contact whose history started from nothing
    # when it formed on the way down (at most a few dozen steps before the
    # end of the lowering); a history kept from before would carry the
    # 200 steps of the first two runs
    n_back = fx[4][-1] / per_step
    n_first = fx[0][-1] / per_step
    assert n_first < n_back < n_first + 40, (n_first, n_back)


# ---------------------------------------------------------------------------
# lammps.cpp: `-screen none`
# ---------------------------------------------------------------------------

def test_screen_none_runs_a_mesh_deck_as_with_a_screen(tmp_path, monkeypatch):
    for which in ("none", "devnull", "stock"):
        (tmp_path / which).mkdir()
        _plate_scene(tmp_path / which)
    # harness.run_deck passes -screen none; MESH_ARGS adds -screen /dev/null after it
    none = harness.run_deck(deck(), tmp_path / "none", check=True)
    devnull = harness.run_deck(deck(), tmp_path / "devnull", extra_args=cm.MESH_ARGS, check=True)
    assert len(none.thermo) == 3
    assert_same_thermo(devnull, none)
    # the reason for the change: stock LIGGGHTS crashes there (the STL reader
    # prints to the screen, which -screen none leaves unset)
    stock = run_stock(monkeypatch, deck(), tmp_path / "stock")
    assert stock.returncode != 0 and not stock.thermo, stock.summary()
