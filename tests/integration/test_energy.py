# SPDX-License-Identifier: GPL-2.0-or-later
"""Energy accounting of breaks (`fix crush/particle ... energy yes`,
docs/fix_crush_particle.md "Energy accounting", docs/stability.md).

Every expected number is computed here in Python from the dumped state and
the Hertz formula U_n = 8/15 E* sqrt(R*) delta^(5/2), never taken from a
previous run.

a. one grain, N = 39 (d = 8.19 mm) pressed between a steel mesh platen and a
   primitive wall (the issue's scene; scene of test_crush_single_grain.py):
   per event, E_el_before = Hertz energy of the parent's two wall contacts at
   pre_exchange of the event step (the platen touches the grain on the
   shared edge of its two triangles: counted once), E_el_after = the
   fragments' wall contacts and their mutual round-off overlaps from the
   dump of the event step (fragments do not move between their creation and
   that dump), KE_before / KE_frag0 from the parent's velocity, KE_gain and
   v_max from the fragments' dumped velocities over the window. The
   cumulative outputs f_crush[9..13] are the sums.
b. 27 grains of a simple cubic stack, frictionless, var 0, pressed by a
   platen: many grains break in the same step next to each other. Per step,
   the sum over events of E_el_before = the Hertz energy of every contact
   that touches a parent (contacts between two parents once), E_el_after =
   every contact of a new fragment (fragments of neighbouring parents
   included); every event has E_el_after + KE_frag0 <= E_el_before +
   KE_before (a break never raises the energy).
c. a closed elastic box: frictionless grains with random velocities between
   six frictionless primitive walls, no damping, no breaks, 10,000 steps:
   kinetic + f_crush[14] (elastic energy of all contacts) stays within 1 %.
"""

import math
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import crush_decks as cd  # noqa: E402
import harness  # noqa: E402
import test_crush_single_grain as sg  # noqa: E402

ENERGY_COLUMNS = ("E_el_before", "E_el_after", "KE_before", "KE_frag0", "KE_gain", "v_max", "n_steps")


def read_energy_events(path):
    """Event lines with the 7 energy columns: list of dicts."""
    out = []
    for line in Path(path).read_text().splitlines():
        s = line.strip()
        if not s or s.startswith("#"):
            continue
        w = s.split()
        assert len(w) == 18, "bad event line: %r" % line
        e = {"step": int(w[0]), "tag": int(w[2]), "diameter": float(w[3]),
             "x": np.array([float(w[4]), float(w[5]), float(w[6])])}
        for k, name in enumerate(ENERGY_COLUMNS):
            e[name] = float(w[11 + k])
        out.append(e)
    return out


def hertz_energy(delta, R, E):
    delta = np.asarray(delta, dtype=float)
    return np.where(delta > 0, 8.0 / 15.0 * E * np.sqrt(R * np.clip(delta, 0, None)) * np.clip(delta, 0, None) ** 2, 0.0)


def pair_energy(x, r, E_star, mask_pairs=None):
    """Hertz energy of every overlapping pair (i < j) of spheres x, r: list of
    (i, j, U)."""
    out = []
    n = len(r)
    for i in range(n):
        d = np.linalg.norm(x[i + 1:] - x[i], axis=1)
        delta = r[i] + r[i + 1:] - d
        for k in np.nonzero(delta > 0)[0]:
            j = i + 1 + k
            R = r[i] * r[j] / (r[i] + r[j])
            out.append((i, j, float(hertz_energy(delta[k], R, E_star))))
    return out


# ---------------------------------------------------------------------------
# a. one grain between a mesh platen and a primitive wall
# ---------------------------------------------------------------------------

WINDOW = 20


def _single_case():
    case = sg.Stack("energy_n39", [39 * cd.D50], N=39, top=sg.T_STEEL, bottom=sg.T_OTHER,
                    speed=0.1, half=0.02, crush_extra=f"energy yes energy_window {WINDOW}",
                    pre_margin=400, post=40)
    return case


def _single_deck(case, processors=None):
    deck = case.deck(processors)
    deck = deck.replace("f_crush[5] f_crush[6]\n",
                        "f_crush[5] f_crush[6] f_crush[9] f_crush[10] f_crush[11] f_crush[12] "
                        "f_crush[13] f_crush[14]\n")
    assert "f_crush[14]" in deck
    return deck


@pytest.mark.parametrize("nprocs", [1, 2])
def test_single_grain_break_energy(tmp_path, nprocs):
    case = _single_case()
    res = cd.run(_single_deck(case, "2 1 1" if nprocs == 2 else None), tmp_path, nprocs=nprocs,
                 files={"plate.stl": case.write_stl})
    frames = {f.timestep: f for f in harness.read_dump(res.path("dump.txt"))}
    events = read_energy_events(res.path("events.txt"))
    assert len(events) == 1, events
    ev = events[0]
    s = ev["step"]
    r = case.r[0]
    E_bot, E_top = sg.e_star(case.bottom), sg.e_star(case.top)

    # before: the parent at pre_exchange of step s
    x, v = sg._pre_exchange_state(frames[s - 1], case.dt)
    z = x[0, 2]
    U_before = float(hertz_energy(r - z, r, E_bot) + hertz_energy(z + r - case.z_top(s), r, E_top))
    assert U_before > 0
    assert ev["E_el_before"] == pytest.approx(U_before, rel=1e-6)
    m_p = cd.sphere_mass(r)
    assert ev["KE_before"] == pytest.approx(0.5 * m_p * float(v[0] @ v[0]), rel=1e-6, abs=1e-30)

    # after: the fragments as created (the dump of step s)
    f = frames[s]
    new = f["id"].astype(int) > 1
    assert new.sum() == 14
    xf = np.column_stack([f["x"], f["y"], f["z"]])[new]
    rf = f["radius"][new]
    mf = f["mass"][new]
    U_after = float(np.sum(hertz_energy(rf - xf[:, 2], rf, E_bot)) +
                    np.sum(hertz_energy(xf[:, 2] + rf - case.z_top(s), rf, E_top)))
    U_after += sum(u for _, _, u in pair_energy(xf, rf, sg.e_star()))
    assert ev["E_el_after"] == pytest.approx(U_after, rel=1e-6, abs=1e-12 * U_before)
    assert ev["KE_frag0"] == pytest.approx(0.5 * float(np.sum(mf)) * float(v[0] @ v[0]), rel=1e-6, abs=1e-30)
    # the break lowers the energy: fragments inside the parent overlap less
    assert ev["E_el_after"] + ev["KE_frag0"] <= ev["E_el_before"] + ev["KE_before"]

    # over the window: the fragments' kinetic energy and speed, every step
    ke, vmax = [], []
    for step in range(s, s + WINDOW):
        g = frames[step]
        sel = g["id"].astype(int) > 1
        vv = np.column_stack([g["vx"], g["vy"], g["vz"]])[sel]
        ke.append(0.5 * float(np.sum(g["mass"][sel] * np.sum(vv * vv, axis=1))))
        vmax.append(float(np.max(np.linalg.norm(vv, axis=1))))
    assert ev["n_steps"] == WINDOW
    assert ev["KE_gain"] == pytest.approx(max(ke) - ev["KE_frag0"], rel=1e-6)
    assert ev["v_max"] == pytest.approx(max(vmax), rel=1e-9)
    # the release is violent (issue 12): a large share of the stored energy
    # becomes kinetic within the window, at speeds of tens of m/s or more
    assert ev["KE_gain"] > 0.1 * (ev["E_el_before"] - ev["E_el_after"])

    # cumulative outputs, after the window closed
    blk = res.thermo[-1]
    # LIGGGHTS cuts thermo headers to 8 characters: columns by position
    assert blk.columns[9] == "crush[9]"
    last = {"f_crush[%d]" % q: float(blk.data[-1, q]) for q in range(9, 15)}
    assert last["f_crush[9]"] == pytest.approx(ev["E_el_before"], rel=1e-9)
    assert last["f_crush[10]"] == pytest.approx(ev["E_el_after"], rel=1e-9, abs=1e-20)
    released = ev["E_el_before"] + ev["KE_before"] - ev["E_el_after"] - ev["KE_frag0"]
    assert last["f_crush[11]"] == pytest.approx(released, rel=1e-9)
    assert last["f_crush[12]"] == pytest.approx(ev["KE_gain"], rel=1e-9)
    assert last["f_crush[13]"] == pytest.approx(ev["v_max"], rel=1e-9)
    # the elastic energy of all contacts at the last step, from the dump
    last_step = max(frames)
    g = frames[last_step]
    xg = np.column_stack([g["x"], g["y"], g["z"]])
    rg = g["radius"]
    U = float(np.sum(hertz_energy(rg - xg[:, 2], rg, E_bot)) +
              np.sum(hertz_energy(xg[:, 2] + rg - case.z_top(last_step), rg, E_top)))
    pairs = pair_energy(xg, rg, sg.e_star())
    U_pairs = sum(u for _, _, u in pairs)
    # with friction, pair contacts also store the history spring, capped:
    # |F_t|^2 / (2 k_t) <= mu^2 F_n^2 / (2 k_t) = mu^2 E*/(4.8 G*) U_n, and
    # E*/G* = 2 (2 - nu)/(1 - nu) for two grains
    U_total = last["f_crush[14]"]
    assert U + U_pairs <= U_total * (1 + 1e-9) + 1e-30
    cap = cd.FRICTION_GG ** 2 * 2 * (2 - cd.NU_GRAIN) / (1 - cd.NU_GRAIN) / 4.8
    assert U_total <= (U + U_pairs * (1 + cap)) * (1 + 1e-9)
    print("single grain N=39: E_before %.4g J, E_after %.4g J, KE_gain %.4g J, v_max %.4g m/s"
          % (ev["E_el_before"], ev["E_el_after"], ev["KE_gain"], ev["v_max"]))



# ---------------------------------------------------------------------------
# b. many grains break in the same step next to each other
# ---------------------------------------------------------------------------

class Lattice:
    """n x n x n equal grains on a simple cubic lattice (lateral spacing
    1.001 d, stacked columns) on a primitive floor, pressed by a steel mesh
    platen; frictionless, var 0: the columns carry the same force, so many
    grains reach their limit in the same step."""

    def __init__(self, n=3, d=1.0e-3, speed=0.2):
        self.n, self.d, self.r = n, d, 0.5 * d
        self.speed = speed
        self.dt = 0.15 * cd.rayleigh_time(0.5 * d * cd.R2_RATIO)
        self.gap = 0.002 * d
        self.z_top0 = n * d + self.gap
        self.half = 0.6 * n * d + 4 * d
        a = 1.001 * d
        c = (np.arange(n) - (n - 1) / 2.0) * a
        self.pos = np.array([(x, y, (k + 0.5) * d) for k in range(n) for x in c for y in c])
        # travel to the first limit of a column: the grain-grain contacts
        # (R* = r/2) reach theirs before the platen and floor (R* = r)
        sigma = cd.strength(d, 1)
        E_w, E_g = sg.e_star(sg.T_STEEL), sg.e_star()
        F = min(cd.limit_force(sigma, self.r, E_w), cd.limit_force(sigma, self.r / 2, E_g))
        travel = self.gap + 2 * cd.hertz_overlap(F, self.r, E_w) + (n - 1) * cd.hertz_overlap(F, self.r / 2, E_g)
        self.step_pred = int(travel / (speed * self.dt))
        # fragments fly off at hundreds of m/s: few steps after the breaks,
        # or they leave the box
        self.n_pre = max(self.step_pred - 100, 1)
        self.n_post = 150

    def z_top(self, step):
        return self.z_top0 - self.speed * step * self.dt

    def deck(self, processors=None):
        h = self.half
        box = f"-{h!r} {h!r} -{h!r} {h!r} -0.004 {self.z_top0 + 0.004!r}"
        text = cd.header(box, sg.MATERIALS, restitution=1.0, processors=processors)
        # frictionless: the test computes every contact energy from positions
        text = text.replace("coefficientFriction peratomtypepair 3 " + " ".join(
            repr(v) for v in [cd.FRICTION_GG] + [cd.FRICTION_GW] * 3 + [cd.FRICTION_GW] * 5),
            "coefficientFriction peratomtypepair 3 " + " ".join(["0.0"] * 9))
        assert "peratomtypepair 3 0.0 0.0" in text, text
        text += f"timestep {self.dt!r}\n"
        for k, p in enumerate(self.pos):
            text += f"create_atoms 1 single {p[0]!r} {p[1]!r} {p[2]!r} units box\n"
            text += f"set atom {k + 1} diameter {self.d!r} density {cd.DENSITY!r}\n"
        text += f"""\
fix top all mesh/surface/stress file plate.stl type {sg.T_STEEL} move 0 0 {self.z_top0!r}
fix walls all wall/gran model hertz tangential history mesh n_meshes 1 meshes top
fix bottom all wall/gran model hertz tangential history primitive type {sg.T_STEEL} zplane 0.0
fix mv all move/mesh mesh top linear 0. 0. {-self.speed!r}
fix integ all nve
"""
        text += cd.crush_fix(scale=1, var=0.0, d_comm=0.55 * self.d, extra="energy yes energy_window 10")
        text += f"""\
thermo_style custom step atoms f_crush[1] f_crush[9] f_crush[10] f_crush[11] f_crush[14]
thermo_modify format float %.17g lost error
thermo 1000
run {self.n_pre}
{cd.dump_lines(1)}run {self.n_post}
"""
        return text

    def write_stl(self, path):
        cd.write_plate_stl(path, half=self.half * 0.95)


def _all_contacts_energy(lat, x, r, step, keep):
    """Hertz energy of every contact with at least one sphere in `keep`
    (bool array): pairs, the floor (z = 0) and the platen."""
    E_gg, E_st = sg.e_star(), sg.e_star(sg.T_STEEL)
    U = 0.0
    for i, j, u in pair_energy(x, r, E_gg):
        if keep[i] or keep[j]:
            U += u
    k = keep
    U += float(np.sum(hertz_energy(r[k] - x[k, 2], r[k], E_st)))
    U += float(np.sum(hertz_energy(x[k, 2] + r[k] - lat.z_top(step), r[k], E_st)))
    return U


_LATTICE_EVENTS = {}


@pytest.mark.parametrize("nprocs", [1, 2])
def test_many_breaks_same_step(tmp_path, nprocs):
    """At 2 ranks the cut x = 0 runs through the middle column: parents have
    parents of the other rank as contact partners (ghosts), whose fragments
    the fix rebuilds from the ghost's position, radius and tag."""
    lat = Lattice()
    res = cd.run(lat.deck("2 1 1" if nprocs == 2 else None), tmp_path, nprocs=nprocs,
                 files={"plate.stl": lat.write_stl})
    frames = {f.timestep: f for f in harness.read_dump(res.path("dump.txt"))}
    events = read_energy_events(res.path("events.txt"))
    assert len(events) >= 9, len(events)
    steps = sorted(set(e["step"] for e in events))
    per_step = {s: [e for e in events if e["step"] == s] for s in steps}
    biggest = max(steps, key=lambda s: len(per_step[s]))
    assert len(per_step[biggest]) >= 9, {s: len(per_step[s]) for s in steps}

    for e in events:
        assert e["E_el_after"] + e["KE_frag0"] <= e["E_el_before"] + e["KE_before"], e

    for s in steps:
        evs = per_step[s]
        if s - 1 not in frames or s not in frames:
            continue
        parents = set(e["tag"] for e in evs)
        f0 = frames[s - 1]
        x, _ = sg._pre_exchange_state(f0, lat.dt)
        ids0 = f0["id"].astype(int)
        U_b = _all_contacts_energy(lat, x, f0["radius"], s, np.isin(ids0, list(parents)))
        assert sum(e["E_el_before"] for e in evs) == pytest.approx(U_b, rel=1e-6), s
        f1 = frames[s]
        ids1 = f1["id"].astype(int)
        x1 = np.column_stack([f1["x"], f1["y"], f1["z"]])
        fresh = ~np.isin(ids1, ids0)
        assert fresh.sum() == 14 * len(evs)
        U_a = _all_contacts_energy(lat, x1, f1["radius"], s, fresh)
        assert sum(e["E_el_after"] for e in evs) == pytest.approx(U_a, rel=1e-6, abs=1e-9 * U_b), s
    _LATTICE_EVENTS[nprocs] = [(e["step"], e["tag"], e["E_el_before"], e["E_el_after"]) for e in events]
    if 1 in _LATTICE_EVENTS and 2 in _LATTICE_EVENTS:
        a, b = _LATTICE_EVENTS[1], _LATTICE_EVENTS[2]
        assert [x[:2] for x in a] == [x[:2] for x in b]
        for x, y in zip(a, b):
            assert y[2] == pytest.approx(x[2], rel=1e-9) and y[3] == pytest.approx(x[3], rel=1e-9, abs=1e-20)
    print("lattice: %d events, %d in step %d; E_before %.4g J, E_after %.4g J, v_max %.4g m/s"
          % (len(events), len(per_step[biggest]), biggest, sum(e["E_el_before"] for e in events),
             sum(e["E_el_after"] for e in events), max(e["v_max"] for e in events)))


def test_energy_accounting_does_not_change_the_run(tmp_path):
    """The same lattice at 2 ranks without `energy yes`: the same events
    (step, parent, F_n to the 10 digits of the events file): the accounting
    (and its update of the ghosts in pre_exchange) only reads."""
    lat = Lattice()
    runs = {}
    for flag in ("on", "off"):
        deck = lat.deck("2 1 1")
        if flag == "off":
            deck = deck.replace(" energy yes energy_window 10", "").replace(
                " f_crush[9] f_crush[10] f_crush[11] f_crush[14]", "")
            assert "energy" not in deck
        res = cd.run(deck, tmp_path / flag, nprocs=2, files={"plate.stl": lat.write_stl})
        runs[flag] = [(e.step, e.tag, e.F_n) for e in cd.read_events(res.path("events.txt"))] \
            if flag == "off" else [(e["step"], e["tag"], None) for e in read_energy_events(res.path("events.txt"))]
        if flag == "on":
            runs["on_Fn"] = [float(l.split()[7]) for l in Path(res.path("events.txt")).read_text().splitlines()
                             if l.strip() and not l.startswith("#")]
    assert [x[:2] for x in runs["on"]] == [x[:2] for x in runs["off"]]
    assert runs["on_Fn"] == [x[2] for x in runs["off"]]


# ---------------------------------------------------------------------------
# c. closed elastic box
# ---------------------------------------------------------------------------

def closed_box_deck(n_side=4, d=1.0e-3, v_rms=5.0, steps=10000, restitution=1.0, seed=12345):
    rng = np.random.default_rng(seed)
    a = 1.3 * d
    L = n_side * a
    box = f"0 {L!r} 0 {L!r} 0 {L!r}"
    text = cd.header(box, sg.MATERIALS[:1] + [(cd.E_GRAIN, cd.NU_GRAIN, "wall")], restitution=restitution)
    text = text.replace(f"coefficientFriction peratomtypepair 2 {cd.FRICTION_GG!r} {cd.FRICTION_GW!r} "
                        f"{cd.FRICTION_GW!r} {cd.FRICTION_GW!r}",
                        "coefficientFriction peratomtypepair 2 0.0 0.0 0.0 0.0")
    assert "peratomtypepair 2 0.0 0.0 0.0 0.0" in text
    dt = 0.1 * cd.rayleigh_time(0.5 * d * 0.9)
    text += f"timestep {dt!r}\n"
    k = 0
    for i in range(n_side):
        for j in range(n_side):
            for l in range(n_side):
                k += 1
                p = (np.array([i, j, l]) + 0.5) * a
                dd = d * (0.9 + 0.2 * rng.random())
                vel = rng.normal(0.0, v_rms, 3)
                text += f"create_atoms 1 single {p[0]!r} {p[1]!r} {p[2]!r} units box\n"
                text += f"set atom {k} diameter {dd!r} density {cd.DENSITY!r}\n"
                text += (f"group gv id {k}\nvelocity gv set {vel[0]!r} {vel[1]!r} {vel[2]!r} units box\n"
                         "group gv delete\n")
    for w in ("xplane 0.0", f"xplane {L!r}", "yplane 0.0", f"yplane {L!r}", "zplane 0.0", f"zplane {L!r}"):
        name = "w" + w.replace(" ", "_").replace(".", "p").replace("-", "m")
        text += f"fix {name} all wall/gran model hertz tangential history primitive type 2 {w}\n"
    text += "fix integ all nve\n"
    # no breaks: a strength far above any contact pressure
    text += cd.crush_fix(sigma0=1e15, d_comm=1e-4, extra="energy yes", events=None)
    text += f"""\
compute ke_t all ke
variable U_el equal f_crush[14]
variable E_tot equal c_ke_t+f_crush[14]
thermo_style custom step atoms c_ke_t v_U_el v_E_tot
thermo_modify format float %.17g lost error
thermo 100
run {steps}
"""
    return text


def _closed_box_drift(tmp_path, **kw):
    res = cd.run(closed_box_deck(**kw), tmp_path)
    blk = res.thermo[-1]
    E = np.asarray(blk["v_E_tot"], dtype=float)
    K = np.asarray(blk["c_ke_t"], dtype=float)
    U = np.asarray(blk["v_U_el"], dtype=float)
    assert len(E) == 101
    return (float(np.max(np.abs(E - E[0])) / E[0]), float(np.max(np.abs(K - K[0])) / E[0]),
            float(np.mean(U > 0)))


def test_closed_elastic_box_conserves_energy(tmp_path):
    drift, drift_ke, busy = _closed_box_drift(tmp_path)
    print("closed box: largest |E - E0| / E0 = %.3g over 10,000 steps (kinetic alone: %.3g); "
          "contacts stored energy at %.0f %% of the outputs" % (drift, drift_ke, 100 * busy))
    # contacts happen: the kinetic energy alone is not conserved ...
    assert drift_ke > 0.01 and busy > 0.5
    # ... kinetic + elastic energy is
    assert drift < 0.01


# ---------------------------------------------------------------------------
# d. energy budget of a compression with hundreds of breaks
# ---------------------------------------------------------------------------

def _bench():
    """bench/extreme_loading/run.py, loaded under its own name."""
    import importlib.util
    path = Path(__file__).resolve().parents[2] / "bench" / "extreme_loading" / "run.py"
    spec = importlib.util.spec_from_file_location("extreme_loading_bench", str(path))
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


BUDGET_TOL = 0.01   # measured: 0.2 % at the end, 0.3 % at most over the run


def budget_terms(tmp_path, drop=()):
    """Small oedometer of bench/extreme_loading (64 grains, to 100 MPa,
    fragments of fragments break): the budget analysis, with the terms named
    in `drop` left out of the sum (to show that the test sees them)."""
    bench = _bench()
    text, files, info = bench.oedometer(n=(4, 4, 4), chunk=1000)
    log, _ = bench.run_deck(text, files, str(tmp_path), str(harness.liggghts_bin()), 1)
    rows = bench.thermo_rows(log)
    for name, col in (("damping", 5), ("friction", 6), ("breaks", 7)):
        if name in drop:
            rows[:, col] = 0.0
    res = bench.analyse_oedometer(rows, info)
    res.update(bench.event_summary(bench.read_events(str(tmp_path / "events.txt"))))
    return res


def test_energy_budget_closes_in_compression(tmp_path):
    res = budget_terms(tmp_path)
    print("budget:", {k: res[k] for k in ("breaks", "W_platen_J", "elastic_J", "kinetic_J", "damping_J",
                                          "friction_J", "released_by_breaks_J", "budget_residual_rel",
                                          "budget_residual_rel_max_over_run", "sigma_v_end_MPa")})
    # the scene: hundreds of breaks, to 100 MPa, no atom lost (the deck
    # stops at the first), mass balance to round-off
    assert res["breaks"] >= 200
    assert res["sigma_v_end_MPa"] >= 100.0
    assert res["mass_balance_rel_max"] < 1e-12
    assert res["breaks_that_raised_energy"] == 0
    # every term of the budget is exercised
    W = res["W_platen_J"]
    for k in ("friction_J", "released_by_breaks_J", "damping_J", "elastic_J"):
        assert res[k] > 0.02 * W, (k, res[k], W)
    # W_platen = dE_el + dE_kin + D_damping + D_friction + R_breaks
    assert abs(res["budget_residual_rel"]) < BUDGET_TOL
    assert res["budget_residual_rel_max_over_run"] < BUDGET_TOL


# ---------------------------------------------------------------------------
# e. keywords
# ---------------------------------------------------------------------------

import test_crush_errors as ce  # noqa: E402


@pytest.mark.parametrize("key", ["energy", "energy_budget"])
def test_energy_yes_no_bad_value(tmp_path, key):
    res = ce.check_error(tmp_path, ce.deck(ce.args(extra=f"energy yes {key} maybe".replace(
        "energy yes energy maybe", "energy maybe"))), f"keyword '{key}'")
    assert any("'yes' or 'no'" in e and "maybe" in e for e in res.errors), res.errors


@pytest.mark.parametrize("value", ["0", "-5", "2.5", "many"])
def test_energy_window_range(tmp_path, value):
    res = ce.check_error(tmp_path, ce.deck(ce.args(extra=f"energy yes energy_window {value}")),
                         "keyword 'energy_window'")
    assert any("integer >= 1 (steps)" in e for e in res.errors), res.errors


def test_energy_budget_needs_energy(tmp_path):
    ce.check_error(tmp_path, ce.deck(ce.args(extra="energy_budget yes")),
                   "keyword 'energy_budget yes' needs 'energy yes'")


def test_damp_local_energy_bad_value(tmp_path):
    text = ce.deck(ce.args()).replace("fix crush all", "fix damp all damp/local alpha 0.05 energy maybe\nfix crush all")
    res = ce.check_error(tmp_path, text, "keyword 'energy'")
    assert any("'yes' or 'no'" in e for e in res.errors), res.errors
