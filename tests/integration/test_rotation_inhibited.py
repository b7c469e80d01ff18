# SPDX-License-Identifier: GPL-2.0-or-later
"""Rotation inhibition (docs/model.md §2.2): with `fix nve` a grain translates but
never rotates. On a rigid plane inclined at theta (gravity tilted instead of the
plane) it slides with a = g (sin theta - mu cos theta) when tan theta > mu and
stays put when tan theta < mu. With `fix nve/sphere` the same grain rolls, with
a = 5/7 g sin theta: the contrast shows the inhibition is what the test sees."""

import math

import numpy as np
import pytest

import crush_multi as cm
from crushpost.materials import E_GRAIN, MU_GRAIN, RHO_GRAIN
from harness import run_deck

G = 9.81
MU = MU_GRAIN
R = 0.5e-3

DECK = "\n" + cm.preamble() + """region box block -0.05 0.05 -0.01 0.01 -0.001 0.01
create_box 2 box
neighbor 0.0002 bin
neigh_modify delay 0
thermo_modify lost error
fix m1 all property/global youngsModulus peratomtype """ + f"{E_GRAIN!r} {E_GRAIN!r}" + """
fix m2 all property/global poissonsRatio peratomtype 0.2 0.2
fix m3 all property/global coefficientRestitution peratomtypepair 2 0.1 0.1 0.1 0.1
fix m4 all property/global coefficientFriction peratomtypepair 2 {mu} {mu} {mu} {mu}
pair_style gran model hertz tangential history
pair_coeff * *
timestep 2e-7
create_atoms 1 single {x0} 0 {r} units box
set atom 1 diameter {d} density """ + "%g" % RHO_GRAIN + """
fix plane all wall/gran model hertz tangential history primitive type 2 zplane 0.0
fix integ all {integrator}
# settle on the plane under normal gravity, then tilt gravity by theta
fix grav all gravity {g} vector 0 0 -1
run 20000
unfix grav
fix grav all gravity {g} vector {sx} 0 {sz}
variable x equal x[1]
variable vx equal vx[1]
variable wy equal omegay[1]
thermo_style custom step time v_x v_vx v_wy
thermo_modify lost error
thermo 200
run 10000
"""


def run(tmp_path, theta_deg, integrator="nve", nprocs=1):
    th = math.radians(theta_deg)
    deck = DECK.format(mu=MU, r=R, d=2 * R, x0=-0.02 if nprocs > 1 else 0.0, g=G,
                       sx=math.sin(th), sz=-math.cos(th), integrator=integrator)
    res = run_deck(deck, tmp_path, nprocs=nprocs, check=True)
    b = res.thermo[-1]
    return b["Time"], b["x"], b["vx"], b["wy"]


def fitted_acceleration(t, x):
    # x = x0 + v0 t + a t^2 / 2 over the second half (contact fully settled)
    k = len(t) // 2
    c = np.polyfit(t[k:] - t[k], x[k:], 2)
    return 2.0 * c[0]


@pytest.mark.parametrize("nprocs", [1, 2])
def test_slides_without_rolling_when_tan_theta_exceeds_mu(tmp_path, nprocs):
    theta = 30.0
    t, x, vx, wy = run(tmp_path, theta, nprocs=nprocs)
    th = math.radians(theta)
    expected = G * (math.sin(th) - MU * math.cos(th))
    a = fitted_acceleration(t, x)
    assert abs(a - expected) / expected < 0.01, (a, expected)
    assert np.all(wy == 0.0), "grain rotated under fix nve"


def test_stays_put_when_tan_theta_below_mu(tmp_path):
    t, x, vx, wy = run(tmp_path, 10.0)
    # only the elastic tangential spring displacement, far below the radius
    assert np.max(np.abs(x - x[0])) < 1e-4 * R
    assert np.max(np.abs(vx)) < 1e-4
    assert np.all(wy == 0.0)


def test_rolls_with_rotation_enabled(tmp_path):
    # contrast: nve/sphere integrates rotation; a sticking sphere rolls at 5/7 g sin theta
    theta = 10.0
    t, x, vx, wy = run(tmp_path, theta, integrator="nve/sphere")
    expected = 5.0 / 7.0 * G * math.sin(math.radians(theta))
    a = fitted_acceleration(t, x)
    assert abs(a - expected) / expected < 0.02, (a, expected)
    assert np.max(np.abs(wy)) > 0.0
