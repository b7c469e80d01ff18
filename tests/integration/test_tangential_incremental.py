# SPDX-License-Identifier: GPL-2.0-or-later
"""`tangential incremental` (docs/tangential_incremental.md) against the
analytic answer, and against `tangential history` on the same path.

One grain on a plane of the same material (wall/gran primitive), moved by
`fix move` (not integrated), so the contact follows a prescribed path:
  1. slide along x by U at the overlap delta_1 (constant normal force);
  2. lift the grain to delta_2 = delta_1/2 with no tangential motion: the
     Coulomb limit mu F_n(delta_2) stays above the tangential force;
  3. lift it to delta_3 = delta_1/4, where the limit falls below it.
Hertz for a sphere (radius r) on a plane of the same material:
  F_n = 4/3 E* sqrt(r) delta^1.5,  E* = E / (2 (1 - nu^2)),
  k_t = 8 G* sqrt(r delta),        G* = G / (2 (2 - nu)), G = E / (2 (1 + nu)).
Answers: after 1, F_t = -k_t(delta_1) U for both models; after 2,
incremental keeps F_t while history gives F_t k_t(delta_2)/k_t(delta_1)
= F_t / sqrt(2); after 3 both slide at |F_t| = mu F_n(delta_3)."""

import math

import pytest

import crush_multi as cm
from crushpost.materials import E_GRAIN, NU_GRAIN, RHO_GRAIN
from harness import expect_error, run_deck

E = E_GRAIN
NU = NU_GRAIN
MU = 0.5
R = 1e-3
DELTA1 = 2e-6
DT = 1e-7
N = 1000          # steps per phase

E_STAR = E / (2.0 * (1.0 - NU * NU))
G_STAR = E / (2.0 * (1.0 + NU)) / (2.0 * (2.0 - NU))


def f_normal(delta):
    return 4.0 / 3.0 * E_STAR * math.sqrt(R) * delta ** 1.5


def k_t(delta):
    return 8.0 * G_STAR * math.sqrt(R * delta)


# U chosen so that F_t after phase 1 is 30 % of the limit mu F_n(delta_1).
F_T1 = 0.3 * MU * f_normal(DELTA1)
U = F_T1 / k_t(DELTA1)
DELTA2 = DELTA1 / 2.0
DELTA3 = DELTA1 / 4.0

# one grain type, hertz with the chosen tangential model (both decks below)
_HEADER = "\n" + cm.preamble() + """region box block -0.01 0.01 -0.01 0.01 {{zlo}} 0.01
create_box 1 box
neighbor 0.0002 bin
neigh_modify delay 0
fix m1 all property/global youngsModulus peratomtype {E!r}
fix m2 all property/global poissonsRatio peratomtype {nu!r}
fix m3 all property/global coefficientRestitution peratomtypepair 1 1.0
fix m4 all property/global coefficientFriction peratomtypepair 1 {mu!r}
pair_style gran model hertz tangential {tm}
pair_coeff * *
timestep {dt!r}
"""

DECK = _HEADER.replace("{{zlo}}", "-0.001") + """create_atoms 1 single {x0!r} 0 {z0!r} units box
set atom 1 diameter {d!r} density """ + "%g" % RHO_GRAIN + """
fix plane all wall/gran model hertz tangential {tm} primitive type 1 zplane 0.0
variable fx equal fx[1]
variable fz equal fz[1]
thermo_style custom step v_fx v_fz
thermo_modify lost error format float %.15g
thermo {n}
# 1: slide by U at constant overlap
fix mv all move linear {vx!r} 0 0
run {n}
unfix mv
velocity all set 0 0 0
# 2: lift to delta_2, no tangential motion
fix mv all move linear 0 0 {vz2!r}
run {n}
unfix mv
velocity all set 0 0 0
# 3: lift to delta_3
fix mv all move linear 0 0 {vz3!r}
run {n}
"""


def run(tmp_path, tm, nprocs=1):
    deck = DECK.format(E=E, nu=NU, mu=MU, tm=tm, dt=DT, x0=0.004 if nprocs > 1 else 0.0,
                       z0=R - DELTA1, d=2 * R, n=N, vx=U / (N * DT),
                       vz2=(DELTA1 - DELTA2) / (N * DT), vz3=(DELTA2 - DELTA3) / (N * DT))
    res = run_deck(deck, tmp_path, nprocs=nprocs, check=True)
    return [(b["fx"][-1], b["fz"][-1]) for b in res.thermo[-3:]]


@pytest.mark.parametrize("nprocs", [1, 2])
def test_incremental_keeps_the_force_when_the_normal_force_falls(tmp_path, nprocs):
    (fx1, fz1), (fx2, fz2), (fx3, fz3) = run(tmp_path, "incremental", nprocs)
    # the normal force follows Hertz (checks the path: delta_1, delta_2, delta_3)
    assert fz1 == pytest.approx(f_normal(DELTA1), rel=1e-9)
    assert fz2 == pytest.approx(f_normal(DELTA2), rel=1e-9)
    assert fz3 == pytest.approx(f_normal(DELTA3), rel=1e-9)
    # 1: F_t = -k_t U (opposes the motion along +x)
    assert fx1 == pytest.approx(-F_T1, rel=1e-9)
    # 2: below the limit, the force is kept although k_t fell by sqrt(2)
    assert MU * fz2 > F_T1
    assert fx2 == pytest.approx(-F_T1, rel=1e-9)
    # 3: the limit fell below it: sliding at mu F_n
    assert MU * fz3 < F_T1
    assert fx3 == pytest.approx(-MU * f_normal(DELTA3), rel=1e-9)


def test_history_scales_the_force_with_the_stiffness(tmp_path):
    # Same path with `tangential history`: same stiffness (phase 1), but the
    # force follows k_t down (phase 2): the difference the option is for.
    (fx1, _), (fx2, _), (fx3, fz3) = run(tmp_path, "history")
    assert fx1 == pytest.approx(-F_T1, rel=1e-9)
    assert fx2 == pytest.approx(-F_T1 * k_t(DELTA2) / k_t(DELTA1), rel=1e-9)
    assert fx2 == pytest.approx(-F_T1 / math.sqrt(2.0), rel=1e-9)
    assert fx3 == pytest.approx(-MU * f_normal(DELTA3), rel=1e-9)


def test_energy_options_are_refused(tmp_path):
    deck = DECK.format(E=E, nu=NU, mu=MU, tm="incremental computeDissipatedEnergy on",
                       dt=DT, x0=0.0, z0=R - DELTA1, d=2 * R, n=N, vx=0.0, vz2=0.0, vz3=0.0)
    expect_error(deck, tmp_path, "tangential incremental: computeElasticPotential and "
                 "computeDissipatedEnergy are not available")


def test_rolling_sphere_gets_the_torque(tmp_path):
    # The torque of the tangential force: a sphere free to rotate (nve/sphere)
    # rolls without slip down an incline at a = 5/7 g sin(theta), as with
    # history (test_rotation_inhibited.py, same deck and fit).
    import numpy as np
    import test_rotation_inhibited as tri
    th = math.radians(10.0)
    deck = tri.DECK.replace("tangential history", "tangential incremental").format(
        mu=tri.MU, r=tri.R, d=2 * tri.R, x0=0.0, g=tri.G, sx=math.sin(th), sz=-math.cos(th),
        integrator="nve/sphere")
    assert deck.count("tangential incremental") == 2
    b = run_deck(deck, tmp_path, check=True).thermo[-1]
    a = tri.fitted_acceleration(b["Time"], b["x"])
    expected = 5.0 / 7.0 * tri.G * math.sin(th)
    assert abs(a - expected) / expected < 0.02, (a, expected)
    assert np.max(np.abs(b["wy"])) > 0.0


PAIR_DECK = _HEADER.replace("{{zlo}}", "-0.01") + """# the contact straddles the middle of the box (x = 0): at 2 ranks the two
# grains are on different ranks
create_atoms 1 single {xa!r} 0 0 units box
create_atoms 1 single {xb!r} 0 0 units box
set atom * diameter {d!r} density """ + "%g" % RHO_GRAIN + """
group mover id 2
variable fx equal fx[2]
variable fy equal fy[2]
variable fz equal fz[2]
variable x2 equal x[2]
variable y2 equal y[2]
variable z2 equal z[2]
variable x1 equal x[1]
thermo_style custom step v_fx v_fy v_fz v_x1 v_x2 v_y2 v_z2
thermo_modify lost error format float %.15g
thermo {n}
# 1: grain 2 slides by U along z (normal along x)
fix mv mover move linear 0 0 {vt!r}
run {n}
unfix mv
velocity all set 0 0 0
# 2: pulled apart along the branch vector (no tangential motion) to delta_1/2
fix mv mover move linear {vnx!r} 0 {vnz!r}
run {n}
"""


@pytest.mark.parametrize("nprocs", [1, 2])
def test_pair_contact_across_ranks(tmp_path, nprocs):
    # Two equal grains: R* = r/2, E* and G* as for the plane above. Grain 2
    # is moved, grain 1 is not integrated. The tangential force is the part
    # of grain 2's force normal to the branch vector (which turns by U/d).
    r = R
    r_star = r / 2.0
    fn = lambda dl: 4.0 / 3.0 * E_STAR * math.sqrt(r_star) * dl ** 1.5
    kt = lambda dl: 8.0 * G_STAR * math.sqrt(r_star * dl)
    f_t1 = 0.3 * MU * fn(DELTA1)
    u = f_t1 / kt(DELTA1)
    # after the slide the branch vector is tilted by `tilt` from x
    tilt = math.atan2(u, 2 * r - DELTA1)
    vn = (DELTA1 - DELTA2) / (N * DT)
    deck = PAIR_DECK.format(E=E, nu=NU, mu=MU, tm="incremental", dt=DT, d=2 * r, n=N,
                            xa=-(r - DELTA1 / 2), xb=r - DELTA1 / 2, vt=u / (N * DT),
                            vnx=vn * math.cos(tilt), vnz=vn * math.sin(tilt))
    res = run_deck(deck, tmp_path, nprocs=nprocs, check=True)
    got = []
    for b in res.thermo[-2:]:
        f = [b[k][-1] for k in ("fx", "fy", "fz")]
        br = [b["x2"][-1] - b["x1"][-1], b["y2"][-1], b["z2"][-1]]
        L = math.sqrt(sum(c * c for c in br))
        n = [c / L for c in br]
        f_n = sum(a * c for a, c in zip(f, n))
        f_t = math.sqrt(max(sum(c * c for c in f) - f_n * f_n, 0.0))
        got.append((f_n, f_t, 2 * r - L))
    (fn1, ft1, d1), (fn2, ft2, d2) = got
    assert fn1 == pytest.approx(fn(d1), rel=1e-9)
    assert d1 == pytest.approx(DELTA1, rel=1e-4)   # the slide opens it by U^2/(2d)
    # k_t U, up to the slide's own change of overlap and direction (~1e-6)
    assert ft1 == pytest.approx(f_t1, rel=1e-5)
    assert fn2 == pytest.approx(fn(d2), rel=1e-9)
    assert d2 == pytest.approx(DELTA2, rel=1e-4)
    # kept, where history would give f_t1 k_t(delta_2)/k_t(delta_1) = f_t1/sqrt(2)
    assert MU * fn2 > f_t1
    assert ft2 == pytest.approx(ft1, rel=1e-9)
