# SPDX-License-Identifier: GPL-2.0-or-later
"""Deck-level tests of `fix crush/particle` on one or two grains (docs/model.md §2).

Every expected number is computed here in Python from the formulas of docs/model.md §2
(see crush_decks.py), never taken from a previous run.

Scene ("stack"): grains stacked on the z axis at x = y = 0, the lowest one
resting on a primitive `wall/gran ... zplane 0` (bottom), the highest one
pressed by a descending `fix mesh/surface/stress` platen (two-triangle STL)
at constant speed.  Atom types: 1 grain (G = 9 GPa, nu = 0.2), 2 steel
(E = 200 GPa, nu = 0.2), 3 a third wall material (E = 50 GPa, nu = 0.3) so
that the two walls have different E* and the critical contact (the one with
the smaller F_lim) is known in advance.  No contact damping (restitution 1)
unless stated, so the contact forces are the elastic Hertz forces.

Timing convention found (and asserted): the fix tests contacts at the end
of step n and breaks in pre_exchange of step n+1; the event file reports
step n+1 (the step at which the fragments exist, e.g. in a dump), the
position of the parent at that moment (after the position update of step
n+1), and F_n / F_lim of the contact at the end of step n.

a. one grain, var 0, N = 1 (d = 1 mm) and N = 39 (d = 8.19 mm = 39 d50),
   d_comm = 0.55 d (the ratio of docs/model.md §3: the fragments cannot break again),
   mesh platen critical and primitive wall critical: one break; F_lim of the
   event = Python F_lim (1e-6); F_n = Hertz force of the dumped geometry at
   step n (1e-6), within 1 % above F_lim, and the previous step was below
   the limit; platen force f_top[3] at step n within 1 % of F_lim;
   fragments (radii, positions, three orthogonal axes, cube diagonals, tags,
   generation, strength, mass, velocity) and exact mass balance.
   At 1 and 2 MPI ranks (`processors 2 1 1`, grain centred on the x = 0
   subdomain boundary); the two rank counts agree.
b. two grains (1.2 mm under 1.0 mm): the critical contact is the grain-grain
   one, and the larger (weaker) grain breaks there (partner 'particle').
f. comminution limit: with d_comm between the parent and fragment sizes the
   fragments are pressed far beyond their own F_lim and never break; the
   same deck with a smaller d_comm breaks them (control).
g. restart: write_restart mid-run, continue in the same deck and from
   read_restart in a new one (also at 2 ranks); strengths, generations and
   counters carry over, later events and strengths match.  Also: the event
   `time` column after read_restart is step * dt, and a break detected at the
   end of the last step of a run (or of the run that wrote the restart file)
   is executed at the first step of the next run as in a continuous run.
"""

import math
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import crush_decks as cd  # noqa: E402
import harness  # noqa: E402

GRAIN = (cd.E_GRAIN, cd.NU_GRAIN, "grain")
STEEL = (cd.E_STEEL, cd.NU_STEEL, "wall")
OTHER = (50.0e9, 0.3, "wall")
MATERIALS = [GRAIN, STEEL, OTHER]          # atom types 1, 2, 3
T_STEEL, T_OTHER = 2, 3


def e_star(wall_type=None):
    """E* of a grain contact with a grain (None) or with a wall type."""
    other = GRAIN if wall_type is None else MATERIALS[wall_type - 1]
    return cd.effective_modulus(GRAIN[0], GRAIN[1], other[0], other[1])


# ---------------------------------------------------------------------------
# the stack scene
# ---------------------------------------------------------------------------

class Stack:
    """Grains of diameters `d` (bottom to top) between a primitive bottom wall
    of type `bottom` and a mesh platen of type `top`, var 0, scale N."""

    def __init__(self, name, d, N=1, top=T_STEEL, bottom=T_OTHER, speed=0.08,
                 dt_frac=0.15, dt_radius=None, gap=None, restitution=1.0,
                 d_comm=None, crush_extra="", pre_margin=400, post=50,
                 until_top=None, dump_every=1, thermo_every=1, half=0.01):
        self.name = name
        self.d = np.array(d, dtype=float)
        self.r = 0.5 * self.d
        self.N = N
        self.top, self.bottom = top, bottom
        self.speed = speed
        self.dt = dt_frac * cd.rayleigh_time(dt_radius if dt_radius else self.r.min())
        self.gap = gap if gap is not None else 0.01 * self.d.max()
        self.restitution = restitution
        # docs/model.md §3: d_comm = 0.55 d50; with the grain as d50 the fragments
        # (0.41 d and 0.23 d) are below it and the single break cannot cascade
        self.d_comm = d_comm if d_comm is not None else 0.55 * self.d.min()
        self.crush_extra = crush_extra
        self.half = half
        # centres: touching each other and the bottom wall
        self.z = np.cumsum(self.d) - self.r
        self.z_top0 = self.d.sum() + self.gap
        self.sigma = cd.strength(self.d, N)
        self.mass0 = float(np.sum(cd.sphere_mass(self.r)))
        self._predict()
        self.n_pre = max(self.step_pred - pre_margin, 1)
        if until_top is None:
            self.n_post = pre_margin + post
        else:   # keep pressing until the platen is at z = until_top
            self.n_post = int(math.ceil((self.z_top0 - until_top) / (speed * self.dt))) - self.n_pre
        self.dump_every = dump_every
        self.thermo_every = thermo_every

    # contacts: ('bottom', k) grain k on the bottom wall, ('top', k) on the
    # platen, ('pair', k) between grains k and k+1
    def contacts(self):
        n = len(self.d)
        out = [("bottom", 0, cd.effective_radius(self.r[0]), e_star(self.bottom))]
        for k in range(n - 1):
            out.append(("pair", k, cd.effective_radius(self.r[k], self.r[k + 1]), e_star()))
        out.append(("top", n - 1, cd.effective_radius(self.r[-1]), e_star(self.top)))
        return out

    def limits(self):
        """(F_lim, grain index, contact kind) for every grain on every contact,
        sorted: the first one is reached first (the same force runs through the
        stack in a quasi-static press)."""
        lims = []
        for kind, k, Rs, Es in self.contacts():
            grains = [k, k + 1] if kind == "pair" else [k]
            for g in grains:
                if self.d[g] >= self.d_comm:
                    lims.append((cd.limit_force(self.sigma[g], Rs, Es), g, kind))
        return sorted(lims)

    def _predict(self):
        F, _, _ = self.limits()[0]
        travel = self.gap + sum(cd.hertz_overlap(F, Rs, Es) for _, _, Rs, Es in self.contacts())
        self.F_crit = F
        self.step_pred = int(round(travel / (self.speed * self.dt)))

    def z_top(self, step):
        return self.z_top0 - self.speed * step * self.dt

    def deck(self, processors=None):
        box = (f"-{self.half!r} {self.half!r} -{self.half!r} {self.half!r} "
               f"-0.001 {self.z_top0 + 0.001!r}")
        text = cd.header(box, MATERIALS, restitution=self.restitution, processors=processors)
        text += f"timestep {self.dt!r}\n"
        for k, (rk, zk) in enumerate(zip(self.r, self.z)):
            text += f"create_atoms 1 single 0 0 {zk!r} units box\n"
            text += f"set atom {k + 1} diameter {self.d[k]!r} density {cd.DENSITY!r}\n"
        text += f"""\
fix top all mesh/surface/stress file plate.stl type {self.top} move 0 0 {self.z_top0!r}
fix walls all wall/gran model hertz tangential history mesh n_meshes 1 meshes top
fix bottom all wall/gran model hertz tangential history primitive type {self.bottom} zplane 0.0
fix mv all move/mesh mesh top linear 0. 0. {-self.speed!r}
fix integ all nve
"""
        text += cd.crush_fix(scale=self.N, var=0.0, d_comm=self.d_comm, extra=self.crush_extra)
        text += f"""\
thermo_style custom step atoms f_top[3] f_crush[1] f_crush[2] f_crush[3] f_crush[4] f_crush[5] f_crush[6]
thermo_modify format float %.17g lost error
thermo 1000
dump d0 all custom 1 dump0.txt id radius f_crush[1] f_crush[2]
dump_modify d0 format "%d %.17g %.17g %.17g" sort id
run 0
undump d0
run {self.n_pre}
thermo {self.thermo_every}
{cd.dump_lines(self.dump_every)}dump p all custom {self.dump_every} pdump.%.txt id
run {self.n_post}
"""
        return text

    def write_stl(self, path):
        cd.write_plate_stl(path, half=0.9 * self.half)


CASES = {
    # N = 1: the mesh platen is steel, the bottom wall softer -> mesh critical
    "n1_mesh": Stack("n1_mesh", [1.0e-3], N=1, top=T_STEEL, bottom=T_OTHER),
    # the other way round -> primitive wall critical
    "n1_prim": Stack("n1_prim", [1.0e-3], N=1, top=T_OTHER, bottom=T_STEEL),
    # N = 39: d = 39 d50 = 8.19 mm, d0 scaled by N inside the fix
    "n39_mesh": Stack("n39_mesh", [39 * cd.D50], N=39, top=T_STEEL, bottom=T_OTHER,
                      speed=0.1, half=0.02),
    # two grains, the larger (weaker) one below
    "pair": Stack("pair", [1.2e-3, 1.0e-3], N=1, top=T_STEEL, bottom=T_STEEL),
}
SINGLE = ["n1_mesh", "n1_prim", "n39_mesh"]

# f. comminution limit: keep pressing a 1 mm grain after it broke until the
# platen is at 0.3 mm, below the 0.414 mm of the large fragments.  Contact
# damping so the fragments settle.  d_frag_min 0.1 mm: in the control,
# fragments of fragments finer than that go to fines; the time step is
# 0.18 T_R of the smallest particle that can then occur (r = d_frag_min / 2).
def _dcomm_case(name, d_comm):
    return Stack(name, [1.0e-3], N=1, top=T_STEEL, bottom=T_STEEL, speed=0.5,
                 dt_frac=0.18, dt_radius=0.5e-4, restitution=0.5,
                 d_comm=d_comm, crush_extra="d_frag_min 1e-4", until_top=0.3e-3,
                 dump_every=250, thermo_every=250)


CASES["dcomm"] = _dcomm_case("dcomm", 0.5e-3)          # fragments may not break
CASES["dcomm_control"] = _dcomm_case("dcomm_control", 0.3e-3)   # large fragments may break

_RUNS = {}


def _run(tmp_path_factory, case, nprocs):
    key = (case.name, nprocs, id(case))
    if key not in _RUNS:
        wd = tmp_path_factory.mktemp(f"{case.name}_np{nprocs}")
        res = cd.run(case.deck("2 1 1" if nprocs == 2 else None), wd, nprocs=nprocs,
                     files={"plate.stl": case.write_stl})
        frames = {f.timestep: f for f in harness.read_dump(res.path("dump.txt"))}
        _RUNS[key] = (res, cd.read_events(res.path("events.txt")), frames)
    return _RUNS[key]


def _window(res):
    """The thermo block written every step (the last one)."""
    blk = res.thermo[-1]
    return blk, {int(s): i for i, s in enumerate(blk["Step"])}


def _vec(frame, names, rows=slice(None)):
    return np.column_stack([frame[n][rows] for n in names])


def _pre_exchange_state(frame, dt):
    """Velocity and position of every atom at pre_exchange of the step after
    `frame` (velocity Verlet of fix nve: half kick with the dumped force,
    then drift)."""
    v = _vec(frame, ("vx", "vy", "vz")) + 0.5 * dt * _vec(frame, ("fx", "fy", "fz")) / frame["mass"][:, None]
    x = _vec(frame, ("x", "y", "z")) + dt * v
    return x, v


def _contact_ratios(case, frame, step):
    """F_n / F_lim and F_n on every contact of the stack at a dumped step
    (grains still whole), keyed like Stack.limits."""
    z = frame["z"]
    out = {}
    for kind, k, Rs, Es in case.contacts():
        if kind == "bottom":
            delta = case.r[0] - z[0]
        elif kind == "top":
            delta = z[k] + case.r[k] - case.z_top(step)
        else:
            delta = case.r[k] + case.r[k + 1] - (z[k + 1] - z[k])
        F = float(cd.hertz_force(delta, Rs, Es))
        for g in ([k, k + 1] if kind == "pair" else [k]):
            out[(g, kind)] = (F / cd.limit_force(case.sigma[g], Rs, Es), F)
    return out


# ---------------------------------------------------------------------------
# checks of the independent answers themselves
# ---------------------------------------------------------------------------

def test_python_reference_values():
    """The Python answers agree with the numbers given in docs/model.md."""
    assert cd.E_GRAIN == pytest.approx(21.6e9, rel=1e-15)  # lint: calibrated-ok docs/model.md's E, checked
    assert cd.R1_RATIO == pytest.approx(0.414214, abs=1e-6)
    assert cd.R2_RATIO == pytest.approx(0.230093, abs=1e-6)
    assert cd.KEPT_VOLUME_FRACTION == pytest.approx(0.5239, abs=1e-4)
    # F_lim is the force at which the mean Hertz pressure F / (pi a^2) is sigma
    sigma, Rs, Es = 2.3e9, 4e-4, 2e10
    F = cd.limit_force(sigma, Rs, Es)
    a = (3 * F * Rs / (4 * Es)) ** (1 / 3)
    assert F / (math.pi * a * a) == pytest.approx(sigma, rel=1e-12)
    # the design of the scenes: critical contacts are well separated
    for name in SINGLE:
        lims = CASES[name].limits()
        assert lims[1][0] > 1.2 * lims[0][0], (name, lims)
    assert CASES["n1_mesh"].limits()[0][2] == "top"
    assert CASES["n1_prim"].limits()[0][2] == "bottom"
    assert CASES["n39_mesh"].limits()[0][2] == "top"
    lims = CASES["pair"].limits()
    assert lims[0][1:] == (0, "pair"), lims          # the larger grain, at the grain contact
    assert lims[1][0] > 1.1 * lims[0][0], lims


# ---------------------------------------------------------------------------
# a. one grain between two platens
# ---------------------------------------------------------------------------

def _check_break(case, res, events, frames, expect_grain, expect_kind):
    assert len(events) == 1, events
    ev = events[0]
    n = ev.step - 1                       # contacts tested at the end of step n
    F_lim, g, kind = case.limits()[0]
    assert (g, kind) == (expect_grain, expect_kind)
    assert ev.tag == g + 1
    assert ev.diameter == pytest.approx(case.d[g], rel=1e-9)
    assert ev.generation == 0
    assert ev.partner == ("particle" if kind == "pair" else "wall")
    assert ev.F_lim == pytest.approx(F_lim, rel=1e-6)

    # F_n: the Hertz force of the geometry at step n, over the limit there and
    # below it one step earlier; within 1 % of F_lim (quasi-static press)
    ratios_n = _contact_ratios(case, frames[n], n)
    ratios_prev = _contact_ratios(case, frames[n - 1], n - 1)
    ratio, F = ratios_n[(g, kind)]
    assert ev.F_n == pytest.approx(F, rel=1e-6)
    assert 1.0 <= ev.F_n / F_lim < 1.01, (ev.F_n, F_lim)
    assert ratio >= 1.0
    assert max(r for r, _ in ratios_prev.values()) < 1.0, ratios_prev
    # every other contact stayed below its own limit (not the critical one)
    others = [r for key, (r, _) in ratios_n.items() if key != (g, kind)]
    assert max(others) < 1.0, ratios_n

    # the platen force at step n: the same force runs through the stack
    blk, row = _window(res)
    F_top = blk["f_top[3]"][row[n]]
    assert abs(F_top) == pytest.approx(F_lim, rel=0.01)
    top_ratio, F_top_hertz = ratios_n[(len(case.d) - 1, "top")]
    assert abs(F_top) == pytest.approx(F_top_hertz, rel=1e-6)
    # the parent is whole at step n, the fragments exist at the event step
    assert len(frames[n]) == len(case.d) and len(frames[ev.step]) == len(case.d) + 13
    return ev


def _check_fragments(case, ev, frames, nprocs, res):
    g = ev.tag - 1
    r = case.r[g]
    before, after = frames[ev.step - 1], frames[ev.step]
    ids_before = set(before["id"].astype(int))
    assert ids_before == set(range(1, len(case.d) + 1))
    ids = after["id"].astype(int)
    new = np.array([i for i in ids if i not in ids_before])
    assert ev.tag not in ids
    assert len(new) == 14 and len(set(new)) == 14
    assert new.min() > max(ids_before)            # new, unique tags
    sel = np.isin(ids, new)
    frag = {c: after[c][sel] for c in after.columns}

    # parent state at pre_exchange of the event step, from the dump at step n
    pidx = list(before["id"].astype(int)).index(ev.tag)
    xp_all, vp_all = _pre_exchange_state(before, case.dt)
    xp, vp = xp_all[pidx], vp_all[pidx]
    np.testing.assert_allclose(ev.x, xp, rtol=0, atol=1e-9 * r)      # logged centre

    # radii: 6 x r1, 8 x r2
    rad = np.sort(frag["radius"])
    np.testing.assert_allclose(rad[:8], cd.R2_RATIO * r, rtol=1e-9)
    np.testing.assert_allclose(rad[8:], cd.R1_RATIO * r, rtol=1e-9)
    large = frag["radius"] > 0.3 * r
    # all at distance r - r_k from the parent centre (tangent to its surface)
    X = np.column_stack([frag["x"], frag["y"], frag["z"]]) - xp
    dist = np.linalg.norm(X, axis=1)
    np.testing.assert_allclose(dist, r - frag["radius"], rtol=0, atol=1e-9 * r)
    U = X / dist[:, None]
    # the 6 large ones on three orthogonal axes: Gram matrix rows are a
    # permutation of (1, -1, 0, 0, 0, 0)
    UL = U[large]
    gram = UL @ UL.T
    for row in gram:
        np.testing.assert_allclose(np.sort(row), [-1, 0, 0, 0, 0, 1], rtol=0, atol=1e-9)
    axes = []
    for u in UL:
        if not any(abs(abs(u @ a) - 1) < 1e-6 for a in axes):
            axes.append(u)
    assert len(axes) == 3
    A = np.array(axes)
    # the 8 small ones on the cube diagonals of that frame, all 8 octants
    S = U[~large] @ A.T
    np.testing.assert_allclose(np.abs(S), 1 / math.sqrt(3), rtol=0, atol=1e-9)
    assert len({tuple(np.sign(s).astype(int)) for s in S}) == 8
    # each small fragment touches three large ones, large neighbours touch
    XL, XS = X[large], X[~large]
    r1, r2 = cd.R1_RATIO * r, cd.R2_RATIO * r
    dLS = np.linalg.norm(XS[:, None, :] - XL[None, :, :], axis=2)
    assert np.all(np.sum(np.abs(dLS - (r1 + r2)) < 1e-9 * r, axis=1) == 3)
    dLL = np.linalg.norm(XL[:, None, :] - XL[None, :, :], axis=2)
    assert np.all(np.sum(np.abs(dLL - 2 * r1) < 1e-9 * r, axis=1) == 4)
    # the frame is rotated (docs/model.md §2.6: random rotation per event), not the box axes
    assert np.max(np.abs(UL)) < 1 - 1e-6

    # same velocity as the parent (undo the half kick of final_integrate)
    vf = np.column_stack([frag["vx"], frag["vy"], frag["vz"]]) \
        - 0.5 * case.dt * np.column_stack([frag["fx"], frag["fy"], frag["fz"]]) / frag["mass"][:, None]
    scale = max(np.linalg.norm(vp), 1e-6)
    np.testing.assert_allclose(vf, np.tile(vp, (14, 1)), rtol=0, atol=1e-9 * scale)

    # type, density (mass), generation, strength of the fragments
    assert np.all(frag["type"] == 1)
    np.testing.assert_allclose(frag["mass"], cd.sphere_mass(frag["radius"]), rtol=1e-12)
    np.testing.assert_array_equal(frag["f_crush[2]"], 1.0)
    np.testing.assert_allclose(frag["f_crush[1]"], cd.strength(2 * frag["radius"], case.N), rtol=1e-12)
    # the other grain (pair case) is untouched: generation 0, own strength
    for k in range(len(case.d)):
        if k != g:
            i = list(ids).index(k + 1)
            assert after["f_crush[2]"][i] == 0.0
            assert after["f_crush[1]"][i] == pytest.approx(case.sigma[k], rel=1e-12)

    # at 2 ranks the fragments lie on both sides of the x = 0 boundary and
    # end up owned by both ranks right away
    if nprocs == 2:
        owners = set()
        for rank in range(2):
            for fr in harness.read_dump(res.path(f"pdump.{rank}.txt")):
                if fr.timestep == ev.step and len(fr) and np.isin(fr["id"], new).any():
                    owners.add(rank)
        assert owners == {0, 1}


def _check_mass(case, res, ev):
    blk, row = _window(res)
    m_parent = float(cd.sphere_mass(case.r[ev.tag - 1]))
    steps = blk["Step"].astype(int)
    after = steps >= ev.step
    assert np.all(blk["f_crush[1]"][~after] == 0) and np.all(blk["f_crush[1]"][after] == 1)
    assert np.all(blk["f_crush[2]"][after] == 14)
    assert np.all(blk["Atoms"][after] == len(case.d) + 13)
    np.testing.assert_allclose(blk["f_crush[3]"][after], m_parent * (1 - cd.KEPT_VOLUME_FRACTION),
                               rtol=1e-12)
    np.testing.assert_allclose(blk["f_crush[4]"] + blk["f_crush[3]"], case.mass0, rtol=1e-12)
    np.testing.assert_allclose(blk["f_crush[6]"][~after], case.r.min(), rtol=1e-12)
    np.testing.assert_allclose(blk["f_crush[6]"][after],
                               min(case.r.min(), cd.R2_RATIO * case.r[ev.tag - 1]), rtol=1e-12)


@pytest.mark.parametrize("nprocs", [1, 2])
@pytest.mark.parametrize("name", SINGLE)
def test_single_grain_breaks_at_limit(tmp_path_factory, name, nprocs):
    case = CASES[name]
    res, events, frames = _run(tmp_path_factory, case, nprocs)
    expect = "top" if case.top == T_STEEL else "bottom"
    _check_break(case, res, events, frames, 0, expect)
    # initial strength of the grain (dump at step 0)
    (f0,) = harness.read_dump(res.path("dump0.txt"))
    assert f0["f_crush[1]"][0] == pytest.approx(case.sigma[0], rel=1e-12)
    assert f0["f_crush[2]"][0] == 0.0


@pytest.mark.parametrize("nprocs", [1, 2])
@pytest.mark.parametrize("name", SINGLE + ["pair"])
def test_fragments(tmp_path_factory, name, nprocs):
    case = CASES[name]
    res, events, frames = _run(tmp_path_factory, case, nprocs)
    assert len(events) == 1, events
    _check_fragments(case, events[0], frames, nprocs, res)


@pytest.mark.parametrize("nprocs", [1, 2])
@pytest.mark.parametrize("name", SINGLE + ["pair"])
def test_mass_balance(tmp_path_factory, name, nprocs):
    case = CASES[name]
    res, events, frames = _run(tmp_path_factory, case, nprocs)
    assert len(events) == 1, events
    _check_mass(case, res, events[0])


@pytest.mark.parametrize("name", SINGLE + ["pair"])
def test_ranks_agree(tmp_path_factory, name):
    case = CASES[name]
    r1, e1, f1 = _run(tmp_path_factory, case, 1)
    r2, e2, f2 = _run(tmp_path_factory, case, 2)
    assert [e.step for e in e1] == [e.step for e in e2]
    assert [e.tag for e in e1] == [e.tag for e in e2]
    for a, b in zip(e1, e2):
        assert b.F_n == pytest.approx(a.F_n, rel=1e-6)
        assert b.F_lim == pytest.approx(a.F_lim, rel=1e-9)
    s = e1[0].step
    a, b = f1[s], f2[s]
    np.testing.assert_array_equal(a["id"], b["id"])
    for c in ("radius", "f_crush[1]", "f_crush[2]"):
        np.testing.assert_allclose(b[c], a[c], rtol=1e-12)
    np.testing.assert_allclose(_vec(b, "xyz"), _vec(a, "xyz"), rtol=0, atol=1e-9 * case.r.max())


# ---------------------------------------------------------------------------
# b. two grains: the grain-grain contact is the critical one
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("nprocs", [1, 2])
def test_pair_breaks_at_particle_contact(tmp_path_factory, nprocs):
    case = CASES["pair"]
    res, events, frames = _run(tmp_path_factory, case, nprocs)
    ev = _check_break(case, res, events, frames, 0, "pair")
    assert ev.partner == "particle"
    # the stronger (smaller) grain survives with its strength and generation 0
    after = frames[ev.step]
    assert 2 in after["id"]


# ---------------------------------------------------------------------------
# f. comminution limit
# ---------------------------------------------------------------------------

def _load_ratios(case, frame, step):
    """Largest F_n / F_lim over the contacts of every atom of a dump frame:
    Hertz force of the overlap with the bottom wall, the platen and every
    other atom, F_lim with the atom's own strength (dump column f_crush[1])."""
    X = _vec(frame, "xyz")
    r = frame["radius"]
    sig = frame["f_crush[1]"]
    n = len(r)
    best = np.zeros(n)
    Eb, Et, Eg = e_star(case.bottom), e_star(case.top), e_star()
    for i in range(n):
        walls = ((r[i] - X[i, 2], Eb), (X[i, 2] + r[i] - case.z_top(step), Et))
        for delta, Es in walls:
            if delta > 0:
                F = float(cd.hertz_force(delta, r[i], Es))
                best[i] = max(best[i], F / cd.limit_force(sig[i], r[i], Es))
        dist = np.linalg.norm(X - X[i], axis=1)
        for j in np.nonzero((dist < r + r[i]) & (np.arange(n) != i))[0]:
            Rs = cd.effective_radius(r[i], r[j])
            F = float(cd.hertz_force(r[i] + r[j] - dist[j], Rs, Eg))
            best[i] = max(best[i], F / cd.limit_force(sig[i], Rs, Eg))
    return best


def _dcomm_run(tmp_path_factory, name):
    case = CASES[name]
    res, events, frames = _run(tmp_path_factory, case, 1)
    assert not [w for w in res.warnings if "time step" in w], res.warnings
    return case, res, events, frames


def test_no_break_below_d_comm(tmp_path_factory):
    case, res, events, frames = _dcomm_run(tmp_path_factory, "dcomm")
    assert len(events) >= 1
    assert all(e.diameter >= case.d_comm for e in events), events
    assert len(events) == 1 and events[0].diameter == pytest.approx(1e-3, rel=1e-9)
    # the fragments, all finer than d_comm, were pressed far beyond their own
    # limit force after the break, and stayed whole
    last = max(frames)
    fr = frames[last]
    assert len(fr) == 14 and np.all(2 * fr["radius"] < case.d_comm)
    assert case.z_top(last) < 2 * cd.R1_RATIO * case.r[0]      # platen below the large ones
    peak = max(np.max(_load_ratios(case, f, s)) for s, f in frames.items() if s > events[0].step)
    assert peak > 2.0, peak
    assert np.max(_load_ratios(case, fr, last)) > 2.0
    blk = res.thermo[-1]
    assert blk["f_crush[1]"][-1] == 1 and blk["f_crush[2]"][-1] == 14
    np.testing.assert_allclose(blk["f_crush[4]"] + blk["f_crush[3]"], case.mass0, rtol=1e-12)


def test_control_breaks_above_d_comm(tmp_path_factory):
    """The same press with d_comm below the large fragments: they break."""
    case, res, events, frames = _dcomm_run(tmp_path_factory, "dcomm_control")
    assert all(e.diameter >= case.d_comm for e in events), events
    second = [e for e in events if e.generation == 1]
    assert second, events
    d1 = 2 * cd.R1_RATIO * case.r[0]
    for e in second:
        assert e.diameter == pytest.approx(d1, rel=1e-9)
        if e.partner == "wall":        # both walls are steel here
            F_lim = cd.limit_force(cd.strength(d1), 0.5 * d1, e_star(T_STEEL))
            assert e.F_lim == pytest.approx(F_lim, rel=1e-6)
            assert e.F_n >= e.F_lim
    # d_frag_min 0.1 mm: a 0.414 mm parent keeps its 6 large fragments only
    blk = res.thermo[-1]
    n_ev = len(events)
    assert blk["f_crush[1]"][-1] == n_ev
    assert blk["f_crush[2]"][-1] == 14 + 6 * (n_ev - 1)
    np.testing.assert_allclose(blk["f_crush[4]"] + blk["f_crush[3]"], case.mass0, rtol=1e-12)


# ---------------------------------------------------------------------------
# g. restart
# ---------------------------------------------------------------------------
#
# 27 grains (0.9-1.0 mm, var 0.36) in three touching columns per direction,
# between primitive side walls and a primitive bottom, pressed by the mesh
# platen at 1 m/s; d_comm 0.8 mm (fragments do not break again), contact
# damping.  A few grains break before and after the restart point.
#
# LIGGGHTS read_restart requirements met by the restart deck: `newton off`,
# `atom_modify map array`, `communicate single vel yes`, `hard_particles yes`
# before read_restart; material fixes, pair_style/pair_coeff and time step
# again; every fix re-defined with the same ID and style (mesh data, wall
# contact histories, move/mesh state and the crush/particle state are then
# taken from the file; the STL must still exist).  The restart deck writes its
# events to another file.

class Packing:
    def __init__(self):
        rng = np.random.default_rng(20240611)          # test-side layout only
        n, s = 3, 1.05e-3
        self.wall = 1.6e-3
        d = rng.uniform(0.9e-3, 1.0e-3, (n, n, n))
        atoms = []
        for i in range(n):
            for j in range(n):
                z = 0.0
                for k in range(n):
                    x = (i - 1) * s + rng.uniform(-2e-5, 2e-5)
                    y = (j - 1) * s + rng.uniform(-2e-5, 2e-5)
                    atoms.append((x, y, z + 0.5 * d[i, j, k], d[i, j, k]))
                    z += d[i, j, k]
        self.atoms = atoms
        self.d = np.array([a[3] for a in atoms])
        self.mass0 = float(np.sum(cd.sphere_mass(0.5 * self.d)))
        self.z_top0 = max(a[2] + 0.5 * a[3] for a in atoms) + 1e-5
        self.d_comm = 0.8e-3
        self.var = 0.36
        # 0.18 T_R of the smallest fragment of a grain at d_comm
        self.dt = 0.18 * cd.rayleigh_time(cd.R2_RATIO * 0.5 * self.d_comm)
        self.nsteps = 12000

    def _prefix(self, restart, processors):
        if not restart:
            box = f"-2e-3 2e-3 -2e-3 2e-3 -0.5e-3 {self.z_top0 + 0.5e-3!r}"
            text = cd.header(box, [GRAIN, STEEL], restitution=0.5, processors=processors)
            text += f"timestep {self.dt!r}\n"
            for k, (x, y, z, d) in enumerate(self.atoms):
                text += (f"create_atoms 1 single {x!r} {y!r} {z!r} units box\n"
                         f"set atom {k + 1} diameter {d!r} density {cd.DENSITY!r}\n")
            return text
        # same header without box creation: read_restart instead
        keep = []
        for line in cd.header("0 1 0 1 0 1", [GRAIN, STEEL], restitution=0.5,
                              processors=processors).splitlines():
            w = line.split()[:1]
            if w and w[0] in ("units", "atom_style", "boundary", "region"):
                continue
            keep.append("read_restart restart.bin" if w == ["create_box"] else line)
        return "\n".join(keep) + f"\ntimestep {self.dt!r}\n"

    def deck(self, runs, restart=False, processors=None, events="events.txt"):
        W = self.wall
        text = self._prefix(restart, processors)
        text += f"""\
fix top all mesh/surface/stress file plate.stl type 2 move 0 0 {self.z_top0!r}
fix walls all wall/gran model hertz tangential history mesh n_meshes 1 meshes top
fix bottom all wall/gran model hertz tangential history primitive type 2 zplane 0.0
fix xlo all wall/gran model hertz tangential history primitive type 2 xplane {-W!r}
fix xhi all wall/gran model hertz tangential history primitive type 2 xplane {W!r}
fix ylo all wall/gran model hertz tangential history primitive type 2 yplane {-W!r}
fix yhi all wall/gran model hertz tangential history primitive type 2 yplane {W!r}
fix mv all move/mesh mesh top linear 0. 0. -1.0
fix integ all nve
"""
        text += cd.crush_fix(var=self.var, d_comm=self.d_comm, events=events)
        text += f"""\
thermo_style custom step atoms f_top[3] f_crush[1] f_crush[2] f_crush[3] f_crush[4] f_crush[5] f_crush[6]
thermo_modify format float %.17g lost error
thermo 100
{cd.dump_lines(500)}"""
        text += "".join(runs)
        return text

    def write_stl(self, path):
        cd.write_plate_stl(path, half=1.9e-3)


PACK = Packing()
RESTART_STEP = 6000
_PRUNS = {}


def _prun(tmp_path_factory, key, deck, nprocs=1, restart_from=None, events="events.txt"):
    if key not in _PRUNS:
        wd = tmp_path_factory.mktemp(key)
        files = {"plate.stl": PACK.write_stl}
        if restart_from is not None:
            src = restart_from.path("restart.bin")
            files["restart.bin"] = lambda p: p.write_bytes(src.read_bytes())
        res = cd.run(deck, wd, nprocs=nprocs, files=files)
        frames = {f.timestep: f for f in harness.read_dump(res.path("dump.txt"))}
        _PRUNS[key] = (res, cd.read_events(res.path(events)), frames)
    return _PRUNS[key]


def _continuous(tmp_path_factory):
    return _prun(tmp_path_factory, "pack_cont", PACK.deck([f"run {PACK.nsteps}\n"]))


def _original(tmp_path_factory, R=RESTART_STEP):
    runs = [f"run {R}\n", "write_restart restart.bin\n", f"run {PACK.nsteps - R}\n"]
    return _prun(tmp_path_factory, f"pack_orig_{R}", PACK.deck(runs))


def _restarted(tmp_path_factory, nprocs, R=RESTART_STEP):
    orig = _original(tmp_path_factory, R)[0]
    deck = PACK.deck([f"run {PACK.nsteps - R}\n"], restart=True,
                     processors="2 1 1" if nprocs == 2 else None, events="events_restart.txt")
    return _prun(tmp_path_factory, f"pack_restart_{R}_np{nprocs}", deck, nprocs=nprocs,
                 restart_from=orig, events="events_restart.txt")


def _thermo_at(res, step):
    for blk in res.thermo:
        steps = list(blk["Step"].astype(int))
        if step in steps:
            i = steps.index(step)
            return {c: blk["f_" + c][i] if c.startswith("crush") else blk[c][i]
                    for c in ("Step", "Atoms", "top[3]") + tuple("crush[%d]" % k for k in range(1, 7))}
    raise KeyError(step)


@pytest.mark.parametrize("nprocs", [1, 2])
def test_restart_continues_state(tmp_path_factory, nprocs):
    R = RESTART_STEP
    o_res, o_ev, o_fr = _original(tmp_path_factory)
    r_res, r_ev, r_fr = _restarted(tmp_path_factory, nprocs)
    before = [e for e in o_ev if e.step <= R]
    after = [e for e in o_ev if e.step > R]
    # scene design: events on both sides, none pending across the restart
    assert len(before) >= 2 and len(after) >= 2, o_ev
    assert not [e for e in o_ev if e.step == R + 1]

    # per-atom state right after the restart == original at the same step
    a, b = o_fr[R], r_fr[R]
    np.testing.assert_array_equal(b["id"], a["id"])
    for c in ("radius", "mass", "f_crush[1]", "f_crush[2]"):
        np.testing.assert_array_equal(b[c], a[c])
    assert np.all(a["f_crush[1]"] > 0) and set(a["f_crush[2]"]) == {0.0, 1.0}

    # global counters continue (not reset), Br from the restored F0
    ta, tb = _thermo_at(o_res, R), _thermo_at(r_res, R)
    assert ta["crush[1]"] == len(before) and tb["crush[1]"] == len(before)
    for c in ("crush[1]", "crush[2]", "crush[3]"):
        assert tb[c] == ta[c], c
    assert tb["crush[4]"] == pytest.approx(ta["crush[4]"], rel=1e-14)   # summation order
    assert tb["crush[5]"] == pytest.approx(ta["crush[5]"], rel=1e-12)
    assert tb["crush[3]"] > 0
    for res in (o_res, r_res):
        for blk in res.thermo:
            np.testing.assert_allclose(blk["f_crush[4]"] + blk["f_crush[3]"], PACK.mass0, rtol=1e-12)
    fin_a, fin_b = _thermo_at(o_res, PACK.nsteps), _thermo_at(r_res, PACK.nsteps)
    assert fin_b["crush[1]"] == fin_a["crush[1]"] == len(o_ev)

    # later events: same parents at the same steps, same forces
    assert len(r_ev) == len(after)
    for e, f in zip(after[:3], r_ev[:3]):
        assert (f.step, f.tag, f.partner, f.generation) == (e.step, e.tag, e.partner, e.generation)
        # trajectories are not bitwise equal across a restart (sum order)
        assert f.F_n == pytest.approx(e.F_n, rel=1e-4) and f.F_n >= f.F_lim
        assert f.F_lim == pytest.approx(e.F_lim, rel=1e-9)

    # fragments made after the restart: new tags above every tag used before,
    # the same tags and identical strengths and generations as the original
    a, b = o_fr[PACK.nsteps], r_fr[PACK.nsteps]
    np.testing.assert_array_equal(b["id"], a["id"])
    for c in ("radius", "f_crush[1]", "f_crush[2]"):
        np.testing.assert_array_equal(b[c], a[c])
    used_before = len(PACK.atoms) + 14 * len(before)      # every tag handed out before R
    assert o_fr[R]["id"].max() == used_before
    new = set(a["id"].astype(int)) - set(o_fr[R]["id"].astype(int))
    assert len(new) == 14 * len(after) and min(new) > used_before


def test_restart_matches_continuous_run(tmp_path_factory):
    """The run split for write_restart against one continuous run: the
    events before the split are identical, the first ones after it too (the
    new setup reorders sums, so trajectories may drift apart later); every
    particle present in both at the end has the same strength and generation."""
    R = RESTART_STEP
    c_res, c_ev, c_fr = _continuous(tmp_path_factory)
    o_res, o_ev, o_fr = _original(tmp_path_factory)
    key = lambda e: (e.step, e.tag, e.generation)      # noqa: E731
    assert [key(e) for e in o_ev if e.step <= R] == [key(e) for e in c_ev if e.step <= R]
    o_after = [key(e) for e in o_ev if e.step > R][:2]
    c_after = [key(e) for e in c_ev if e.step > R][:2]
    assert len(o_after) == 2 and o_after == c_after
    a, b = o_fr[PACK.nsteps], c_fr[PACK.nsteps]
    common, ia, ib = np.intersect1d(a["id"], b["id"], return_indices=True)
    assert len(common) >= 0.9 * max(len(a), len(b))
    for c in ("radius", "f_crush[1]", "f_crush[2]"):
        np.testing.assert_array_equal(a[c][ia], b[c][ib])


def test_strengths_of_packing(tmp_path_factory):
    """sigma_lim = sigma_lim0 f (d/(N d0))^(-3/m): the factor f of every
    particle (initial grains and fragments) is positive, fragments' f are
    drawn anew, and the spread is about var."""
    c_res, c_ev, c_fr = _continuous(tmp_path_factory)
    fr = c_fr[PACK.nsteps]
    f = fr["f_crush[1]"] / cd.strength(2 * fr["radius"])
    assert np.all(f > 0)
    assert len(f) > 60
    assert abs(np.mean(f) - 1) < 4 * PACK.var / math.sqrt(len(f))
    assert 0.6 * PACK.var < np.std(f) < 1.4 * PACK.var
    f0 = _original(tmp_path_factory)[2][0]
    f_init = f0["f_crush[1]"] / cd.strength(f0["radius"] * 2)
    assert len(np.unique(np.round(f_init, 12))) == 27           # one draw per grain


def test_event_time_after_restart(tmp_path_factory):
    """The `time` column of the event file is the simulation time, step * dt
    (constant dt), also after read_restart."""
    o_res, o_ev, _ = _original(tmp_path_factory)
    r_res, r_ev, _ = _restarted(tmp_path_factory, 1)
    for e in o_ev:
        assert e.time == pytest.approx(e.step * PACK.dt, rel=1e-9), e
    for e in r_ev:
        assert e.time == pytest.approx(e.step * PACK.dt, rel=1e-9), (e, e.time)


@pytest.mark.parametrize("how", ["split", "restart"])
def test_pending_break_across_run_boundary(tmp_path_factory, how):
    """A break detected at the end of the last step of a run (or of the run
    that wrote the restart file) is executed at the first step of the next
    run, as in a continuous run: same step, same F_n."""
    c_res, c_ev, _ = _continuous(tmp_path_factory)
    target = c_ev[len(c_ev) // 2]
    R = target.step - 1                      # detection at the end of step R
    o_res, o_ev, _ = _original(tmp_path_factory, R)
    if how == "split":
        got = [e for e in o_ev if e.tag == target.tag]
    else:
        got = [e for e in _restarted(tmp_path_factory, 1, R)[1] if e.tag == target.tag]
    assert len(got) == 1
    assert (got[0].step, got[0].F_n) == (target.step, pytest.approx(target.F_n, rel=1e-9)), \
        (target, got[0])
