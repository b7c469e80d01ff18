# SPDX-License-Identifier: GPL-2.0-or-later
"""Time step over the stiffest contact (fix crush/particle, keyword dt_omega)
and blow-up detection (fix check/stability); docs/stability.md, "Time step
and blow-up detection".

Independent answers computed here: the stiffest contact of a particle of
radius r and mass m whose contacts carry a mean pressure of at most p has
omega_max = sqrt(3/2 pi p r / m) (Hertz tangent stiffness 2 E* sqrt(R* delta)
at the overlap where F / (pi a^2) = p, a wall R* = r or an equal particle
R* = r/2, m* = m/2); p is the particle's sigma_lim for breakable particles,
the strength of a d_comm particle with a factor 1 + 3 var for particles that
cannot break (fragments).
"""

import math
import re
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import crush_decks as cd  # noqa: E402
import crush_multi as cm  # noqa: E402
import harness  # noqa: E402

D_GRAIN = 1.0e-3
D_COMM = 5e-4
STEEL, RIGID, PLATEN = 2, 3, 4   # atom types of the walls in `init_deck`
E_PLATEN = 3.0e11                # a mesh wall's material, stiffer than steel


def p_unbreakable(sigma0, var=0.0, d_comm=D_COMM):
    return cd.strength(d_comm, f=1.0 + 3.0 * var, sigma0=sigma0)


def omega_max(p, r, m):
    return math.sqrt(1.5 * math.pi * p * r / m)


def r_frag(d_comm=D_COMM):
    return cd.R2_RATIO * 0.5 * d_comm


def scale_factor(d, d_ref):
    return (d_ref / d) ** 2 if d_ref > 0 and d < d_ref else 1.0


def init_deck(sigma0, dt, extra=""):
    """One 1 mm grain on a steel wall (type 2) next to a rigid plane (type 3,
    E = 1e21 Pa like the symmetry planes of inputs/materials_ne34.in) under a
    mesh platen (type 4, plate.stl, written by the caller); the fix with
    var 0 (the grain's own strength is then sigma(1 mm))."""
    setup = cd.header("-0.01 0.01 -0.01 0.01 -0.001 0.01",
                      [(cd.E_GRAIN, cd.NU_GRAIN, "grain"), (cd.E_STEEL, cd.NU_STEEL, "wall"),
                       (1e21, cd.NU_GRAIN, "wall"), (E_PLATEN, cd.NU_STEEL, "wall")])
    return setup + f"""\
timestep {dt!r}
fix plate all mesh/surface file plate.stl type {PLATEN}
fix platen all wall/gran model hertz tangential history mesh n_meshes 1 meshes plate
create_atoms 1 single -0.002 0 0.0005 units box
set atom 1 diameter {D_GRAIN!r} density {cd.DENSITY!r}
fix bottom all wall/gran model hertz tangential history primitive type {STEEL} zplane 0.0
fix side all wall/gran model hertz tangential history primitive type {RIGID} xplane -0.0025
fix integ all nve
fix crush all crush/particle sigma_lim0 {sigma0!r} m 10 d0 0.002 scale 1 var 0.0 d_comm {D_COMM!r} seed {cd.SEED} {extra}
thermo_style custom step atoms
thermo_modify lost error
run 0
"""


CONTACT_RE = re.compile(
    r"stiffest contact (grain|fragment) \(type (\d+), r (\S+), mass (\S+)\) - (particle|wall) type (\d+): "
    r"p_max (\S+), E\* (\S+), overlap/r (\S+), k_max (\S+), omega_max dt = (\S+) \(limit dt_omega = (\S+)\)")


PLATE = {"plate.stl": lambda path: cd.write_plate_stl(path, half=0.009, z=0.009)}


def contact_lines(res):
    out = {}
    for m in CONTACT_RE.finditer(res.log):
        out[(m.group(1), m.group(5), int(m.group(6)))] = dict(
            r=float(m.group(3)), mass=float(m.group(4)), p=float(m.group(7)), E_star=float(m.group(8)),
            overlap=float(m.group(9)), k=float(m.group(10)), wdt=float(m.group(11)))
    return out


def contact_warnings(res):
    return [w for w in res.warnings if "stiffest" in w and "dt_omega" in w]


def rayleigh_warnings(res):
    return [w for w in res.warnings if "dt_frac * T_R" in w]


# 0.18 of the Rayleigh time of the smallest fragment passes the Rayleigh
# check (dt_frac 0.2) for every case below
DT = 0.18 * cd.rayleigh_time(r_frag())


@pytest.mark.parametrize("sigma0,flagged", [(cd.SIGMA0, False), (2e10, True)], ids=["ne34", "strong"])
def test_init_check_fragment_steel(tmp_path, sigma0, flagged):
    """sigma_lim0 20 GPa: the Rayleigh check and the grain's own contacts pass,
    the smallest fragment against steel does not (omega dt 1.21 > 1): one
    warning. sigma_lim0 1.9 GPa (NE34): no warning. var 0, so p_max is
    sigma_lim of a d_comm particle."""
    res = cd.run(init_deck(sigma0, DT), tmp_path, files=PLATE)
    lines = contact_lines(res)
    # every pair of types: grain and fragment against the grain type and both walls
    assert set(lines) == {(c, k, t) for c in ("grain", "fragment")
                          for k, t in (("particle", 1), ("wall", STEEL), ("wall", RIGID),
                                       ("wall", PLATEN))}, lines.keys()
    rf, rg = r_frag(), 0.5 * D_GRAIN
    p_f, p_g = p_unbreakable(sigma0), cd.strength(D_GRAIN, sigma0=sigma0)
    w_f = omega_max(p_f, rf, cd.sphere_mass(rf)) * DT
    w_g = omega_max(p_g, rg, cd.sphere_mass(rg)) * DT
    for (cls, kind, t), v in lines.items():
        w, p, r = (w_f, p_f, rf) if cls == "fragment" else (w_g, p_g, rg)
        assert v["wdt"] == pytest.approx(w, rel=1e-5), (cls, kind, t)
        assert v["p"] == pytest.approx(p, rel=1e-5)
        # overlap at p: R* (3 pi p / (4 E*))^2 with the pair's E*
        E_q = {1: cd.E_GRAIN, STEEL: cd.E_STEEL, RIGID: 1e21, PLATEN: E_PLATEN}[t]
        nu_q = cd.NU_STEEL if t in (STEEL, PLATEN) else cd.NU_GRAIN
        E_star = cd.effective_modulus(cd.E_GRAIN, cd.NU_GRAIN, E_q, nu_q)
        R_star = 0.5 * r if kind == "particle" else r
        assert v["E_star"] == pytest.approx(E_star, rel=1e-5)
        assert v["overlap"] * r == pytest.approx(R_star * (3 * math.pi * p / (4 * E_star)) ** 2, rel=1e-5)
    # the rigid plane (E 1e21) and the mesh platen bound nothing less than
    # steel: the same omega
    for t in (RIGID, PLATEN):
        assert lines[("fragment", "wall", t)]["wdt"] == lines[("fragment", "wall", STEEL)]["wdt"]
    assert w_g < 1.0
    assert not rayleigh_warnings(res)
    assert (w_f > 1.0) == flagged
    assert len(contact_warnings(res)) == (1 if flagged else 0), res.warnings


@pytest.mark.parametrize("nprocs", [1, 2])
def test_init_check_dt_check_error(tmp_path, nprocs):
    """dt_check error turns the contact warning into an error, at 1 and 2 ranks."""
    res = cd.expect_error(init_deck(2e10, DT, "dt_check error"), tmp_path,
                          "exceeds dt_omega / omega_max", nprocs=nprocs, files=PLATE)
    err = [e for e in res.errors if "dt_omega" in e][0]
    assert "fragment" in err and "reduce the time step" in err


def test_init_check_density_scaling(tmp_path):
    """density_scale raises the fragment's mass by (d_ref/d)^2: omega falls by
    d_ref/d and the strong deck is no longer flagged."""
    d_ref = 4.0 * 2.0 * r_frag()
    res = cd.run(init_deck(2e10, DT, f"density_scale {d_ref!r}"), tmp_path, files=PLATE)
    rf = r_frag()
    m = cd.sphere_mass(rf) * scale_factor(2 * rf, d_ref)
    w = omega_max(p_unbreakable(2e10), rf, m) * DT
    assert w == pytest.approx(omega_max(p_unbreakable(2e10), rf, cd.sphere_mass(rf)) * DT / 4.0, rel=1e-12)
    assert contact_lines(res)[("fragment", "wall", STEEL)]["wdt"] == pytest.approx(w, rel=1e-5)
    assert contact_lines(res)[("fragment", "wall", STEEL)]["mass"] == pytest.approx(m, rel=1e-5)
    assert not contact_warnings(res) and not rayleigh_warnings(res)


def test_init_check_dt_omega_keyword(tmp_path):
    """dt_omega sets the limit: 1.3 lets the strong deck (omega dt 1.21) pass; out of range is an error."""
    res = cd.run(init_deck(2e10, DT, "dt_omega 1.3"), tmp_path / "ok", files=PLATE)
    assert not contact_warnings(res)
    assert "omega_max dt = 1.21" in res.log and "(limit dt_omega = 1.3)" in res.log
    cd.expect_error(init_deck(2e10, DT, "dt_omega 2.5"), tmp_path / "bad",
                    "keyword 'dt_omega' must be in (0, 2)", files=PLATE)


# ---------------------------------------------------------------------------
# fix check/stability
# ---------------------------------------------------------------------------

UNSTABLE_RE = re.compile(
    r"fix check/stability: unstable at step (\d+), signal '(\w+)': particle (\d+) \(type (\d+), "
    r"radius (\S+), mass (\S+)\) at \((\S+), (\S+), (\S+)\), speed (\S+): (.*); likely cause: (.*)")


def unstable(res):
    m = UNSTABLE_RE.search(res.all_text)
    assert m, res.summary()
    return dict(step=int(m.group(1)), signal=m.group(2), tag=int(m.group(3)), type=int(m.group(4)),
                radius=float(m.group(5)), x=[float(m.group(k)) for k in (7, 8, 9)],
                speed=float(m.group(10)), what=m.group(11), cause=m.group(12))


def pair_deck(dist_over_r, processors="* 1 1", check="fix stab all check/stability", nsteps=20,
              dt_frac=0.1):
    """Two 1 mm grains whose centres are dist_over_r * r apart, across x = 0
    (the processor cut at 2 ranks)."""
    r = 0.5 * D_GRAIN
    h = 0.5 * dist_over_r * r
    setup = cd.header("-0.01 0.01 -0.01 0.01 -0.01 0.01",
                      [(cd.E_GRAIN, cd.NU_GRAIN, "grain"), (cd.E_STEEL, cd.NU_STEEL, "wall")],
                      processors=processors)
    return setup + f"""\
timestep {dt_frac * cd.rayleigh_time(r)!r}
create_atoms 1 single {-h!r} 0 0 units box
create_atoms 1 single {h!r} 0 0 units box
set group all diameter {D_GRAIN!r} density {cd.DENSITY!r}
fix integ all nve
{check}
thermo_style custom step atoms
thermo_modify lost error
thermo 1
run {nsteps}
"""


@pytest.mark.parametrize("nprocs", [1, 2])
def test_grain_inserted_deep_stops_at_setup(tmp_path, nprocs):
    """Centres 0.3 r apart (overlap 1.7 r > 1.5 r): the run stops at step 0,
    naming the smaller particle of the pair and its partner. Without the fix
    the pair flies apart and both grains leave the 2 cm box (lost atoms)."""
    res = cd.expect_error(pair_deck(0.3, processors="2 1 1" if nprocs == 2 else "* 1 1"),
                          tmp_path, "fix check/stability: unstable at step 0", nprocs=nprocs)
    u = unstable(res)
    assert u["signal"] == "overlap" and u["tag"] in (1, 2) and u["type"] == 1
    assert u["radius"] == pytest.approx(0.5 * D_GRAIN)
    assert abs(u["x"][0]) == pytest.approx(0.075 * D_GRAIN) and u["speed"] == 0.0
    assert re.search(r"overlaps particle [12] \(radius 0.0005\) by 1.7 of its radius \(limit overlap 1.5\)",
                     u["what"]), u["what"]
    assert "inserted or created overlapping" in u["cause"]


def test_grain_inserted_deep_is_lost_without_the_fix(tmp_path):
    """The same pair without fix check/stability: atoms are lost (what the
    check prevents)."""
    res = cd.expect_error(pair_deck(0.3, check="", nsteps=1000), tmp_path, "Lost atoms")
    assert res.errors


@pytest.mark.parametrize("nprocs", [1, 2])
def test_moderate_overlap_moves_too_far(tmp_path, nprocs):
    """Centres 1.0 r apart (overlap 1.0 r, below the overlap limit), dt 0.2
    T_R: the repulsion sends the grains off at a speed that moves them more
    than 0.1 r in one step; the run stops within the first steps, signal
    'move', before the atoms leave the box (which takes hundreds of steps).
    At 2 ranks each grain is on its own rank."""
    res = cd.expect_error(pair_deck(1.0, processors="2 1 1" if nprocs == 2 else "* 1 1",
                                    dt_frac=0.2, nsteps=1000), tmp_path,
                          "fix check/stability: unstable at step", nprocs=nprocs)
    u = unstable(res)
    assert u["signal"] == "move" and 1 <= u["step"] <= 5, u
    dt = 0.2 * cd.rayleigh_time(0.5 * D_GRAIN)
    assert u["speed"] * dt > 0.1 * u["radius"]
    assert "moves" in u["what"] and "(limit move 0.1)" in u["what"]
    assert "Lost" not in res.all_text


# the compression scene of test_parallel_edges.py / test_crush_parallel.py
SCENE = dict(nx=2, ny=2, height=6e-3, dmin=6e-4, dmax=1.2e-3, speed=2.0)


def scene_with_check(workdir, nsteps, dt_frac, check="fix stab all check/stability", thermo=1000):
    sc = cm.compression_scene(workdir, SCENE["nx"], SCENE["ny"], SCENE["height"], SCENE["dmin"],
                              SCENE["dmax"], nsteps, speed=SCENE["speed"], dt_frac=dt_frac,
                              thermo=thermo, processors="* 1 1")
    deck = sc.deck.replace("thermo_style", check + "\nthermo_style", 1)
    if check:
        deck = deck.replace("f_crush[7]\n", "f_crush[7] f_stab[1] f_stab[2]\n", 1)
    (Path(workdir) / "in.deck").write_text(deck)
    return sc, deck


def run_scene(deck, workdir, nprocs=1, check=True):
    return harness.run_deck(deck, workdir, nprocs=nprocs, check=check, extra_args=cm.MESH_ARGS,
                            timeout=600)


@pytest.mark.parametrize("nprocs", [1, 2])
def test_no_false_alarm_in_crushing_scene(tmp_path, nprocs):
    """Crushing at dt = 0.18 T_R of the smallest fragment: the run ends, with
    breaks, and the largest move and overlap fractions stay below the limits
    (printed with -s: the margin)."""
    sc, deck = scene_with_check(tmp_path, 60000, 0.18)
    res = run_scene(deck, tmp_path, nprocs)
    th = harness.parse_thermo(res.log)[-1]
    assert th["f_crush[1]"][-1] > 0, "no break: the scene does not test crushing"
    move, ovl = th["f_stab[1]"].max(), th["f_stab[2]"].max()
    print(f"\n{nprocs} ranks: {th['f_crush[1]'][-1]:.0f} breaks, largest |v| dt / r {move:.3g}, "
          f"largest overlap / r {ovl:.3g}")
    assert 0 < move < 0.1 and 0 < ovl < 1.5


def _lost(text):
    return "Lost atoms" in text or re.search(r"fix crush/particle \(fix \w+\): \d+ atoms lost", text)


def test_time_step_too_large_stops_before_atoms_are_lost(tmp_path):
    """dt = 3 T_R of the smallest fragment: without the check the run loses
    atoms (run 'ref'); with it, it stops at an earlier step with signal
    'move', naming a particle of the run, and the time step as the cause."""
    ref_deck = scene_with_check(tmp_path / "ref", 4000, 3.0, check="", thermo=1)[1]
    ref = run_scene(ref_deck, tmp_path / "ref", check=False)
    # a lost grain stops the run: LIGGGHTS' own check, or (in a crushing run)
    # fix crush/particle's count at the next neighbour-list build
    assert _lost(ref.all_text), ref.summary()
    # thermo every step: the loss is found at the step after the last row
    lost_step = int(harness.parse_thermo(ref.log)[-1]["Step"][-1]) + 1
    sc, deck = scene_with_check(tmp_path / "check", 4000, 3.0, thermo=1)
    res = run_scene(deck, tmp_path / "check", check=False)
    u = unstable(res)
    print(f"\nstopped at step {u['step']} ({u['signal']}), atoms lost without the check at {lost_step}")
    assert u["step"] < lost_step
    assert not _lost(res.all_text)
    assert u["signal"] == "move"
    assert "time step is too large" in u["cause"]


@pytest.mark.parametrize("args,expected", [
    ("move -0.1", "keyword 'move' must be >= 0 (fraction of the radius; 0 = off), got -0.1"),
    ("overlap nan", "keyword 'overlap' must be"),
    ("every 0", "keyword 'every'"),
    ("every 3 overlap_every 100", "keyword 'overlap_every' must be a multiple of 'every' (steps), got 100 and 3"),
    ("colour red", "unknown keyword 'colour'"),
], ids=["move_negative", "overlap_nan", "every_0", "overlap_every_not_multiple", "unknown"])
def test_bad_input(tmp_path, args, expected):
    res = cd.expect_error(pair_deck(3.0, check=f"fix stab all check/stability {args}"), tmp_path,
                          expected)
    assert any("fix check/stability" in e for e in res.errors), res.errors
