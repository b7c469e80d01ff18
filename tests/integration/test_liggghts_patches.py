"""Deck tests of the fixes this package applies to the LIGGGHTS 3.8 sources
in the build tree (cmake/PrepareLiggghtsSource.cmake).

mesh/surface/stress at the set-up of a run: stock LIGGGHTS adds the set-up
wall forces on top of the previous step's summed total, so the first thermo
row of every run read about twice the force on a mesh. Scene: one grain
squeezed between a primitive bottom wall and a fixed mesh plate with the same
overlap delta at both, so it stays at rest and the plate force is the Hertz
force F = 4/3 E* sqrt(r delta) delta (independent answer).
"""

import math
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import crush_multi as cm  # noqa: E402
import harness  # noqa: E402

D = 1.0e-3
DELTA = 2.0e-6


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


@pytest.mark.parametrize("nprocs", [1, 2])
def test_mesh_force_at_setup_is_not_double_counted(tmp_path, nprocs):
    r = D / 2
    box = ((-2e-3, 2e-3), (-2e-3, 2e-3), (-1e-3, 3e-3))
    cm.write_data(tmp_path / "grains.data", [(0.0, 0.0, r - DELTA, D)], box)
    cm.write_plate_stl(tmp_path / "plate.stl", -2e-3, 2e-3, -2e-3, 2e-3)
    res = harness.run_deck(deck(), tmp_path, nprocs=nprocs, extra_args=cm.MESH_ARGS, check=True)
    runs = [np.asarray(b["top[3]"]) for b in res.thermo]
    assert len(runs) == 3, res.summary()

    e_star = 1.0 / ((1 - cm.NU_GRAIN ** 2) / cm.E_GRAIN + (1 - cm.NU_WALL ** 2) / cm.E_WALL)
    f_hertz = 4.0 / 3.0 * e_star * math.sqrt(r * DELTA) * DELTA
    # during the runs the plate is pushed up by the Hertz force (grain at rest)
    for fz in (runs[0][1:], runs[1][1:]):
        np.testing.assert_allclose(fz, f_hertz, rtol=1e-6)
    # at the set-up of a following run: the last summed total, not twice it
    assert runs[1][0] == runs[0][-1], (runs[1][0], runs[0][-1])
    assert runs[2][0] == runs[1][-1], (runs[2][0], runs[1][-1])
