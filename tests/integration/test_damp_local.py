# SPDX-License-Identifier: GPL-2.0-or-later
"""Deck-level tests of `fix damp/local` (PFC-style local damping, docs/model.md §2.3).

    F_i <- F_i - alpha * |F_i| * sign(v_i),   sign(0) = 0,   0 <= alpha < 1

Exact answers checked (at 1 and 2 MPI ranks; the particles cross the x = 0
mid-plane where `processors * 1 1` splits the box at 2 ranks):

a. constant force F from rest: the discrete velocity-Verlet answer of
   `fix nve` with damping applied on the half-step velocity.  The first
   half kick is undamped (v = 0, sign(0) = 0), every later one uses
   (1 - alpha) F / m.  Relative error < 1e-9; alpha = 0 gives F / m.
b. linear spring: the kinetic energy at successive velocity peaks one full
   cycle apart drops by ((1 - alpha) / (1 + alpha))^2, the peak speed per half
   cycle by sqrt((1 - alpha) / (1 + alpha)).  Within 0.5 %.
c. bad input: clear errors naming 'alpha' or the unknown keyword.

Runs of the same deck at 1 and 2 ranks are also compared with each other
(relative 1e-10).  Each run is made once per session in its own temporary
folder and shared by the tests that need it (see `_run`).
"""

import math
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import harness  # noqa: E402
from crushpost.materials import E_GRAIN, MU_GRAIN, NU_GRAIN, RHO_GRAIN  # noqa: E402

# docs/model.md §3 material (NE34 quartz, crushpost.materials): G = 9 GPa, nu = 0.2 -> E = 2 G (1 + nu) = 21.6 GPa
YOUNG = E_GRAIN
POISSON = NU_GRAIN
FRICTION = MU_GRAIN
DIAMETER = 0.004
DENSITY = RHO_GRAIN
MASS = 4.0 * math.pi / 3.0 * (0.5 * DIAMETER) ** 3 * DENSITY


def header(box="-0.1 0.1 -0.1 0.1 -0.05 0.05"):
    """Common LIGGGHTS granular set-up: one atom type, Hertz pair style (no
    contacts happen in these tests), box split along x at 2 ranks."""
    return f"""\
atom_style      granular
atom_modify     map array
boundary        f f f
newton          off
communicate     single vel yes
units           si
hard_particles  yes
processors      * 1 1
region          box block {box} units box
create_box      1 box
neighbor        0.001 bin
neigh_modify    delay 0
thermo_modify   lost error
fix m1 all property/global youngsModulus peratomtype {YOUNG!r}
fix m2 all property/global poissonsRatio peratomtype {POISSON!r}
fix m3 all property/global coefficientRestitution peratomtypepair 1 0.9
fix m4 all property/global coefficientFriction peratomtypepair 1 {FRICTION!r}
pair_style      gran model hertz tangential history
pair_coeff      * *
"""


# ---------------------------------------------------------------------------
# run cache: one run per (deck, variables, nprocs) per session
# ---------------------------------------------------------------------------

_RUNS = {}


def _run(tmp_path_factory, name, deck, nprocs, variables):
    key = (deck, tuple(sorted(variables.items())), nprocs)
    if key not in _RUNS:
        workdir = tmp_path_factory.mktemp(f"{name}_np{nprocs}")
        _RUNS[key] = harness.run_deck(deck, workdir, nprocs=nprocs,
                                      variables=variables, timeout=120, check=True)
    return _RUNS[key]


def _owner_ranks(res, atom_id, nprocs):
    """Rank owning `atom_id` at each per-processor dump frame (dump.%.txt)."""
    owners = {}
    for rank in range(nprocs):
        for frame in harness.read_dump(res.path(f"dump.{rank}.txt")):
            if len(frame) and atom_id in frame["id"]:
                assert frame.timestep not in owners, "atom owned by two ranks"
                owners[frame.timestep] = rank
    return [owners[s] for s in sorted(owners)]


def _no_order_warning(res):
    assert not [w for w in res.warnings if "damp/local" in w], res.warnings


# ---------------------------------------------------------------------------
# a. constant force from rest
# ---------------------------------------------------------------------------

DT_A = 1.0e-4
NSTEPS_A = 1000
FORCE_A = np.array([1.0e-3, -0.5e-3, 0.0])      # N, on both particles
X0_A = {1: (-0.002, 0.02, 0.0), 2: (-0.002, 0.07, 0.0)}

DECK_A = header() + f"""\
timestep        {DT_A!r}
create_atoms    1 single {X0_A[1][0]} {X0_A[1][1]} {X0_A[1][2]} units box
create_atoms    1 single {X0_A[2][0]} {X0_A[2][1]} {X0_A[2][2]} units box
set             atom * diameter {DIAMETER!r} density {DENSITY!r}
group           damped id 1
fix             integr all nve
fix             push all addforce {FORCE_A[0]!r} {FORCE_A[1]!r} {FORCE_A[2]!r}
fix             damp damped damp/local alpha ${{alpha}}
variable        x1 equal x[1]
variable        y1 equal y[1]
variable        vx1 equal vx[1]
variable        vy1 equal vy[1]
variable        vz1 equal vz[1]
variable        vx2 equal vx[2]
variable        vy2 equal vy[2]
thermo_style    custom step atoms v_x1 v_y1 v_vx1 v_vy1 v_vz1 v_vx2 v_vy2
thermo_modify   format float %.17g norm no lost error
thermo          10
dump            d all custom 100 dump.%.txt id x y z vx vy vz
run             {NSTEPS_A}
"""


def exact_constant_force(alpha, force, mass, dt, nsteps, x0):
    """Velocity Verlet of fix nve with local damping applied in post_force
    on the half-step velocity.  Returns (x, v) at steps 0..nsteps."""
    sign = np.sign  # sign(0) = 0
    x = np.array(x0, dtype=float)
    v = np.zeros(3)
    f = force - alpha * np.abs(force) * sign(v)         # setup(): v = 0, undamped
    xs, vs = [x.copy()], [v.copy()]
    for _ in range(nsteps):
        v = v + 0.5 * dt * f / mass
        x = x + dt * v
        f = force - alpha * np.abs(force) * sign(v)
        v = v + 0.5 * dt * f / mass
        xs.append(x.copy())
        vs.append(v.copy())
    return np.array(xs), np.array(vs)


def test_exact_constant_force_formula():
    """The discrete answer has the closed form v_n = (F dt / m)(n (1 - alpha) + alpha / 2)."""
    alpha = 0.3
    _, v = exact_constant_force(alpha, FORCE_A, MASS, DT_A, 50, (0, 0, 0))
    n = np.arange(51)
    closed = np.outer(np.where(n > 0, n * (1 - alpha) + alpha / 2, 0.0), FORCE_A * DT_A / MASS)
    np.testing.assert_allclose(v, closed, rtol=1e-12, atol=1e-18)


@pytest.mark.parametrize("nprocs", [1, 2])
@pytest.mark.parametrize("alpha", [0.0, 0.05, 0.7])
def test_constant_force_from_rest(tmp_path_factory, alpha, nprocs):
    res = _run(tmp_path_factory, f"const_a{alpha}", DECK_A, nprocs, {"alpha": alpha})
    _no_order_warning(res)
    (blk,) = res.thermo
    steps = blk["Step"].astype(int)
    assert steps[-1] == NSTEPS_A and np.all(blk["Atoms"] == 2)

    x_ex, v_ex = exact_constant_force(alpha, FORCE_A, MASS, DT_A, NSTEPS_A, X0_A[1])
    x_ex, v_ex = x_ex[steps], v_ex[steps]
    # damped particle 1: velocity and displacement
    for col, k in (("v_vx1", 0), ("v_vy1", 1)):
        np.testing.assert_allclose(blk[col][1:], v_ex[1:, k], rtol=1e-9, atol=0)
    np.testing.assert_array_equal(blk["v_vz1"], 0.0)          # no force, no motion
    for col, k in (("v_x1", 0), ("v_y1", 1)):
        disp = blk[col] - X0_A[1][k]
        np.testing.assert_allclose(disp[1:], x_ex[1:, k] - X0_A[1][k], rtol=1e-9, atol=0)

    # after the first step the acceleration is exactly (1 - alpha) F / m
    i = np.searchsorted(steps, [100, NSTEPS_A])
    acc = (blk["v_vx1"][i[1]] - blk["v_vx1"][i[0]]) / ((steps[i[1]] - steps[i[0]]) * DT_A)
    assert acc == pytest.approx((1 - alpha) * FORCE_A[0] / MASS, rel=1e-9)

    # particle 2 is outside the fix group: undamped, a = F / m
    _, v_free = exact_constant_force(0.0, FORCE_A, MASS, DT_A, NSTEPS_A, X0_A[2])
    np.testing.assert_allclose(blk["v_vx2"][1:], v_free[steps][1:, 0], rtol=1e-9, atol=0)
    np.testing.assert_allclose(blk["v_vy2"][1:], v_free[steps][1:, 1], rtol=1e-9, atol=0)

    # the damped particle crosses x = 0; at 2 ranks it moves from rank 0 to rank 1
    owners = _owner_ranks(res, 1, nprocs)
    if nprocs == 2:
        assert owners[0] == 0 and owners[-1] == 1, owners
    assert blk["v_x1"][0] < 0 < blk["v_x1"][-1]


@pytest.mark.parametrize("alpha", [0.0, 0.05, 0.7])
def test_constant_force_ranks_agree(tmp_path_factory, alpha):
    r1 = _run(tmp_path_factory, f"const_a{alpha}", DECK_A, 1, {"alpha": alpha})
    r2 = _run(tmp_path_factory, f"const_a{alpha}", DECK_A, 2, {"alpha": alpha})
    b1, b2 = r1.thermo[0], r2.thermo[0]
    assert b1.columns == b2.columns and len(b1) == len(b2)
    np.testing.assert_allclose(b2.data, b1.data, rtol=1e-10, atol=1e-14)


# ---------------------------------------------------------------------------
# b. damped linear oscillator
# ---------------------------------------------------------------------------

K_B = 1.0              # N/m, omega = sqrt(K/m) ~ 109 rad/s, period ~ 0.058 s
X0_B = -0.005          # released from rest, oscillates about x = 0
DT_B = 2.0e-5          # ~2900 steps per period
NSTEPS_B = 10000       # ~3.4 periods

DECK_B = header() + f"""\
timestep        {DT_B!r}
create_atoms    1 single {X0_B!r} 0.0 0.0 units box
set             atom 1 diameter {DIAMETER!r} density {DENSITY!r}
fix             integr all nve
variable        fx atom -{K_B!r}*x
fix             spring all addforce v_fx 0.0 0.0
fix             damp all damp/local alpha ${{alpha}}
variable        x1 equal x[1]
variable        vx1 equal vx[1]
thermo_style    custom step v_x1 v_vx1
thermo_modify   format float %.17g norm no lost error
thermo          1
dump            d all custom 250 dump.%.txt id x vx
run             {NSTEPS_B}
"""


def exact_oscillator(alpha, k, mass, dt, nsteps, x0):
    """Discrete answer of fix nve + addforce -k x + local damping (1-D)."""
    x, v = x0, 0.0
    f = -k * x
    vs = np.empty(nsteps + 1)
    vs[0] = 0.0
    for n in range(1, nsteps + 1):
        v += 0.5 * dt * f / mass
        x += dt * v
        f = -k * x
        f -= alpha * abs(f) * np.sign(v)
        v += 0.5 * dt * f / mass
        vs[n] = v
    return vs


def peak_speeds(v):
    """Largest |v| of each complete half swing (between sign changes of v)."""
    s = np.sign(v)
    nz = np.nonzero(s)[0]
    s_nz = s[nz]
    cuts = nz[np.nonzero(s_nz[1:] != s_nz[:-1])[0] + 1]     # first index of each new swing
    return np.array([np.max(np.abs(v[a:b])) for a, b in zip(cuts[:-1], cuts[1:])])


@pytest.mark.parametrize("nprocs", [1, 2])
@pytest.mark.parametrize("alpha", [0.05, 0.2])
def test_damped_oscillator_energy_ratio(tmp_path_factory, alpha, nprocs):
    res = _run(tmp_path_factory, f"osc_a{alpha}", DECK_B, nprocs, {"alpha": alpha})
    _no_order_warning(res)
    (blk,) = res.thermo
    assert np.array_equal(blk["Step"], np.arange(NSTEPS_B + 1))
    v = blk["v_vx1"]

    omega = math.sqrt(K_B / MASS)
    period = math.pi / omega * (1 / math.sqrt(1 - alpha) + 1 / math.sqrt(1 + alpha))
    assert period / DT_B >= 2000

    # first half swing (release to first turning point): peak KE = k (1 - alpha) x0^2 / 2
    peaks = peak_speeds(v)
    assert len(peaks) >= 5, peaks
    first_peak_ke = 0.5 * MASS * np.max(np.abs(v[: int(period / DT_B / 2)])) ** 2
    assert first_peak_ke == pytest.approx(0.5 * K_B * (1 - alpha) * X0_B ** 2, rel=1e-3)

    ke = 0.5 * MASS * peaks ** 2
    r = (1 - alpha) / (1 + alpha)
    per_cycle = ke[2:] / ke[:-2]
    per_half_speed = peaks[1:] / peaks[:-1]
    np.testing.assert_allclose(per_cycle, r ** 2, rtol=5e-3)
    np.testing.assert_allclose(per_half_speed, math.sqrt(r), rtol=5e-3)

    # and the whole trace is the discrete answer of the same integrator
    v_ex = exact_oscillator(alpha, K_B, MASS, DT_B, NSTEPS_B, X0_B)
    np.testing.assert_allclose(v, v_ex, rtol=0, atol=1e-7 * np.max(np.abs(v_ex)))

    # the particle swings across the x = 0 mid-plane: both ranks own it in turn
    owners = _owner_ranks(res, 1, nprocs)
    assert set(owners) == set(range(nprocs)), owners


@pytest.mark.parametrize("alpha", [0.05, 0.2])
def test_damped_oscillator_ranks_agree(tmp_path_factory, alpha):
    r1 = _run(tmp_path_factory, f"osc_a{alpha}", DECK_B, 1, {"alpha": alpha})
    r2 = _run(tmp_path_factory, f"osc_a{alpha}", DECK_B, 2, {"alpha": alpha})
    b1, b2 = r1.thermo[0], r2.thermo[0]
    vmax = np.max(np.abs(b1["v_vx1"]))
    np.testing.assert_array_equal(b1["Step"], b2["Step"])
    np.testing.assert_allclose(b2["v_vx1"], b1["v_vx1"], rtol=1e-10, atol=1e-10 * vmax)
    np.testing.assert_allclose(b2["v_x1"], b1["v_x1"], rtol=1e-10, atol=1e-10 * abs(X0_B))


# ---------------------------------------------------------------------------
# c. input errors and the ordering warning
# ---------------------------------------------------------------------------

DECK_C = header() + """\
timestep        1e-5
create_atoms    1 single 0.0 0.0 0.0 units box
set             atom 1 diameter 0.004 density {rho:g}
fix             integr all nve
fix             damp all damp/local {args}
run             1
"""


@pytest.mark.parametrize("args, expected", [
    ("", "missing required keyword 'alpha'"),
    ("alpha -0.1", "'alpha' must be in [0, 1)"),
    ("alpha 1", "'alpha' must be in [0, 1)"),
    ("alpha 1.0", "'alpha' must be in [0, 1)"),
    ("alpha 1.5", "'alpha' must be in [0, 1)"),
    ("alpha nan", "'alpha' must be in [0, 1)"),
    ("alpha abc", "value 'abc' of keyword 'alpha' is not a number; allowed: in [0, 1)"),
    ("alpha 0.05x", "value '0.05x' of keyword 'alpha' is not a number"),
    ("beta 0.1", "unknown keyword 'beta'"),
    ("alpha 0.05 gamma", "unknown keyword 'gamma'"),
    ("alpha", "keyword 'alpha' needs a value"),
], ids=["missing", "negative", "one", "one_float", "above_one", "nan", "non_numeric",
        "trailing_garbage", "unknown_keyword", "unknown_after_alpha", "missing_value"])
def test_bad_input(tmp_path, args, expected):
    res = harness.expect_error(DECK_C.format(args=args, rho=RHO_GRAIN), tmp_path, expected, timeout=60)
    (err,) = [e for e in res.errors if "damp/local" in e]
    assert "fix damp/local" in err


def test_warning_when_force_fix_defined_after(tmp_path):
    deck = DECK_C.format(args="alpha 0.05", rho=RHO_GRAIN) + "fix late all addforce 1e-3 0.0 0.0\nrun 1\n"
    res = harness.run_deck(deck, tmp_path, timeout=60, check=True)
    assert any("fix 'late' (addforce) is defined after it" in w for w in res.warnings), \
        res.warnings
