# SPDX-License-Identifier: GPL-2.0-or-later
"""Deck-level tests of `fix snapshot/hdf5`: HDF5 snapshots of particles and
contacts at the end of every push and every pause of the cyclic jacking of
`fix jack/pile`.

Scene: ~200 NE34-shaped grains (N = 39, grains 10x softer than NE34 for a
larger time step) settled under 100 g in a frictionless cylinder, a steel
cone pile (R = 6 mm) jacked in cyclically: strokes of 4 mm to 12 mm depth,
i.e. push, unload, pause twice and a last push (5 events: 3 push ends, 2
pause ends). The same deck runs at 2 MPI ranks (contacts yes: the fix
creates its computes) and at 1 rank (the deck's own compute pair/gran/local
and wall/gran/local passed with pair_local / wall_local, plus text dumps
written at the snapshot steps of the 2-rank run through
`dump_modify every v_next`).

Checks against independent answers:
a. the files are those of the events in the jack time series: one per push
   end and pause end (`leaving 0 2`), one per phase change (no `leaving`),
   one per pause end (an equal-style variable as trigger); attributes step,
   time, old/new trigger value and counter agree with the series; f_ID
   counts them;
b. particles at a snapshot step equal a `dump custom` (17 digits) written at
   the same step; per-atom values: an atom-style variable (2 z), compute
   ke/atom (1/2 m v^2 from the snapshot's own v and radius), a fix per-atom
   array (store/state of v, whole and one column), compute stress/atom pair
   (its virial tally is needed on the snapshot step) against
   -1/2 sum (x_i - x_j) (x) F over the snapshot's pair contacts;
c. particle-particle contacts equal a `dump local` of the compute at that
   step, and they are exactly the overlapping pairs of the snapshot's
   positions and radii; overlap = r_i + r_j - |x_i - x_j|; the normal force is
   Hertz 4/3 E* sqrt(R* delta) delta along the line of centres (the decks
   have no viscous damping), the tangential force obeys Coulomb, the contact
   point lies on the line of centres at the radii ratio;
d. particle-mesh contacts balance the pile forces of fix jack/pile (cone and
   shaft, from fix mesh/surface/stress);
e. 1-rank and 2-rank snapshots agree (ids, positions, contacts);
f. bad input stops with an error naming the keyword and its allowed values;
   a fix with contacts after the first run is refused with the way out;
g. a snapshot without contacts has empty tables with their row shapes, and
   'unfix' of a fix with its own contact computes lets later runs go on; a
   deck continued with read_restart can still create the contact computes.
"""

import math
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import harness  # noqa: E402
from harness import REPO  # noqa: E402

from crushpost.materials import MU_GRAIN, NU_GRAIN, RHO_GRAIN  # noqa: E402
from crushpost.meshes import write_pile_stl  # noqa: E402
import pile_cell  # noqa: E402
from pile_cell import G_GRAIN, RHO  # noqa: E402
from crushpost.snapshot import list_snapshots, read_snapshot  # noqa: E402

INPUTS = REPO / "inputs"
JACK_COLUMNS = ["step", "time", "depth", "F_cone", "F_shaft", "F_head", "phase", "cycle",
                "v_next"]
PUSH, UNLOAD, PAUSE, DONE = 0, 1, 2, 3

R_CELL = 0.03
H_PACK = 0.035
H_RSA = 0.075
DT = 2e-6
SETTLE_STEPS = 15000
R_PILE = 0.006
N_SEG = 16
SHAFT_LENGTH = 0.06

V, S, VU, T_PAUSE, ZERO_TOL = 0.5, 0.004, 0.5, 2e-4, 0.05
DEPTH = 3 * S
RUN_STEPS = 17000


def header(data_file):
    return pile_cell.header(data_file, R_CELL, DT)


def read_series(path):
    return pile_cell.read_series(path, JACK_COLUMNS)


# the deck's own contact computes (1 rank): LIGGGHTS allows one of each
DECK_COMPUTES = """\
compute         pgl all pair/gran/local pos id force force_normal delta contactPoint
compute         wgl all wall/gran/local pos id force force_normal delta
"""
# columns of pgl in a dump local: pos 1-6, id 7-9, force 10-12, force_normal
# 13-15, delta 16, contactPoint 17-19
PGL_DUMP = " ".join("c_pgl[%d]" % k for k in (7, 8, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19))


def jack_deck(snap_contacts, computes="", dumps=""):
    return header("settled.data") + f"""\
include         ${{inputs}}/unbreakable.in
fix             cone all mesh/surface/stress file cone.stl type 2
fix             shaft all mesh/surface/stress file shaft.stl type 2
fix             pile all wall/gran model hertz tangential history mesh n_meshes 2 meshes cone shaft
{computes}
include         ${{inputs}}/integrate.in
fix             jack all jack/pile cone cone shaft shaft mode cyclic v {V} stroke {S} &
                v_unload {VU} pause {T_PAUSE} depth {DEPTH} zero_tol {ZERO_TOL} file jack.txt every 1
variable        zero equal 0
variable        vz equal f_jack[1]
fix             mv_cone all move/mesh mesh cone linear/variable v_zero v_zero v_vz
fix             mv_shaft all move/mesh mesh shaft linear/variable v_zero v_zero v_vz
variable        phase equal f_jack[6]
variable        zz atom 2*z
compute         ke all ke/atom
compute         sa all stress/atom pair
fix             ss all store/state 1 vx vy vz
fix             snap all snapshot/hdf5 file snap trigger f_jack[6] leaving 0 2 {snap_contacts} &
                values v_zz c_ke c_sa f_ss f_ss[3]
fix             snapall all snapshot/hdf5 file all trigger f_jack[6]
fix             snapv all snapshot/hdf5 file pend trigger v_phase leaving 2
{dumps}
thermo_style    custom step atoms f_jack[2] f_jack[6] f_snap f_snapall f_snapv
thermo_modify   lost error
thermo          500
run             {RUN_STEPS}
print           "FINAL PHASE ${{phase}}"
"""


def dump_lines(steps):
    # next dump step after the current one: sum_k s_k (s_{k-1} <= step < s_k)
    terms = []
    prev = -1
    for s in steps:
        terms.append("%d*(step>=%d)*(step<%d)" % (s, prev, s))
        prev = s
    terms.append("1000000000*(step>=%d)" % prev)
    fmt_c = '"%d %d' + " %.17g" * 7 + '"'
    fmt_l = '"' + " ".join(["%.17g"] * 12) + '"'
    return f"""\
variable        next equal {"+".join(terms)}
dump            dc all custom 1 dump.*.txt id type x y z vx vy vz radius
dump_modify     dc every v_next format {fmt_c}
dump            dl all local 1 local.*.txt {PGL_DUMP}
dump_modify     dl every v_next format {fmt_l}
"""


def read_local_dump(path):
    """(step, rows) of a one-frame text dump local."""
    lines = Path(path).read_text().splitlines()
    step = int(lines[1].split()[0])
    n = int(lines[3].split()[0])
    i = next(k for k, line in enumerate(lines) if line.startswith("ITEM: ENTRIES")) + 1
    rows = np.array([[float(w) for w in line.split()] for line in lines[i:i + n]])
    return step, rows.reshape(n, 12)


@pytest.fixture(scope="module")
def settled(tmp_path_factory):
    wd = tmp_path_factory.mktemp("settle")
    _, atoms = pile_cell.settle(wd, R_CELL, H_PACK, H_RSA, DT, SETTLE_STEPS, seed=20240613,
                                z_box_top=0.16)
    n = len(atoms)
    # apex height at which the descending cone (half-angle 30 degrees) first
    # touches a grain: on its lateral surface (signed distance of the centre
    # from the cone line = r) or, for a grain right under it, at the apex
    r = 0.5 * atoms[:, 2]
    rho = np.hypot(atoms[:, 4], atoms[:, 5])
    zc = atoms[:, 6]
    z_side = zc + 2.0 * r - math.sqrt(3.0) * rho
    on_side = 0.5 * rho + 0.5 * math.sqrt(3.0) * (zc - z_side) >= 0.0
    z_apex = np.where(rho < r, zc + np.sqrt(np.maximum(r * r - rho * rho, 0.0)), -np.inf)
    z_touch = np.where(on_side & (rho < R_PILE + r), z_side, -np.inf)
    ztop = float(max(np.max(z_touch), np.max(z_apex)))
    return wd, n, ztop


def _prepare(settled, wd):
    src, n, ztop = settled
    (wd / "settled.data").write_text((src / "settled.data").read_text())
    write_pile_stl(str(wd), R_PILE, SHAFT_LENGTH, tip_z=ztop + 1e-4, n_seg=N_SEG)


@pytest.fixture(scope="module")
def runs(settled, tmp_path_factory):
    """The 2-rank run (fix-created computes), then the 1-rank run with the
    deck's computes and dumps at the 2-rank snapshot steps."""
    out = {}
    wd2 = tmp_path_factory.mktemp("ranks2")
    _prepare(settled, wd2)
    res2 = harness.run_deck(jack_deck("contacts yes"), wd2, nprocs=2, timeout=300, check=True)
    steps2 = [s for s, _ in list_snapshots(wd2 / "snap")]
    assert steps2, res2.summary()
    out[2] = (wd2, res2)
    wd1 = tmp_path_factory.mktemp("ranks1")
    _prepare(settled, wd1)
    deck1 = jack_deck("contacts yes pair_local pgl wall_local wgl", DECK_COMPUTES,
                      dump_lines(steps2))
    res1 = harness.run_deck(deck1, wd1, nprocs=1, timeout=300, check=True)
    out[1] = (wd1, res1)
    return out


def event_steps(series, leaving=None):
    """Steps of the jack series where the phase changes (from a phase in
    'leaving'), with the old and new phase."""
    step, phase = series["step"].astype(int), series["phase"].astype(int)
    out = []
    # the phase before the first line (step 1) is push: the run starts pushing
    prev = np.concatenate([[PUSH], phase[:-1]])
    for k in np.nonzero(phase != prev)[0]:
        if leaving is None or prev[k] in leaving:
            out.append((int(step[k]), int(prev[k]), int(phase[k])))
    return out


# ---------------------------------------------------------------------------
# a. one file per event
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("nprocs", [1, 2])
def test_snapshots_at_push_and_pause_ends(runs, nprocs):
    wd, res = runs[nprocs]
    assert "FINAL PHASE 3" in res.log, res.summary()
    series = read_series(wd / "jack.txt")
    seq = [p for _, _, p in event_steps(series)]
    assert seq == [UNLOAD, PAUSE, PUSH, UNLOAD, PAUSE, PUSH, DONE], seq
    for prefix, leaving in (("snap", (PUSH, PAUSE)), ("all", None), ("pend", (PAUSE,))):
        events = event_steps(series, leaving)
        files = list_snapshots(wd / prefix)
        assert [s for s, _ in files] == [e[0] for e in events], prefix
        for k, ((step, old, new), (_, path)) in enumerate(zip(events, files)):
            snap = read_snapshot(path)
            assert snap["step"] == step and snap["snapshot"] == k + 1
            assert (snap["trigger_old"], snap["trigger_new"]) == (old, new)
            assert snap["time"] == pytest.approx(step * DT, rel=1e-12)
            assert snap["trigger"] == ("v_phase" if prefix == "pend" else "f_jack[6]")
            assert (snap["contacts"] is not None) == (prefix == "snap")
    # 3 push ends + 2 pause ends; the fix counts them (f_snap)
    assert len(list_snapshots(wd / "snap")) == 5
    last = res.thermo[-1]
    assert last["f_snap"][-1] == 5 and last["f_snapall"][-1] == 7 and last["f_snapv"][-1] == 2


# ---------------------------------------------------------------------------
# b. particles = dump custom at the same step
# ---------------------------------------------------------------------------

def test_particles_equal_dump_custom(runs):
    wd, res = runs[1]
    frames = {f.timestep: f for f in harness.read_dumps(wd, "dump.*.txt")}
    files = list_snapshots(wd / "snap")
    assert sorted(frames) == [s for s, _ in files]
    for step, path in files:
        p = read_snapshot(path)["particles"]
        fr = frames[step]
        assert np.array_equal(p["id"], fr["id"].astype(np.int64))
        assert np.all(np.diff(p["id"]) > 0)
        assert np.array_equal(p["type"], fr["type"].astype(np.int32))
        for k, c in enumerate("xyz"):
            assert np.array_equal(p["x"][:, k], fr[c]), c
            assert np.array_equal(p["v"][:, k], fr["v" + c]), c
        assert np.array_equal(p["radius"], fr["radius"])
        vals = p["values"]
        assert np.array_equal(vals["v_zz"], 2.0 * p["x"][:, 2])
        mass = RHO * 4.0 / 3.0 * math.pi * p["radius"] ** 3
        np.testing.assert_allclose(vals["c_ke"], 0.5 * mass * np.sum(p["v"] ** 2, axis=1),
                                   rtol=1e-12, atol=1e-300)
        # a per-atom array of a fix (whole, and one column): v stored this step
        assert vals["f_ss"].shape == (len(p["id"]), 3)
        assert np.array_equal(vals["f_ss"], p["v"])
        assert np.array_equal(vals["f_ss[3]"], p["v"][:, 2])


# ---------------------------------------------------------------------------
# c. pair contacts = dump local, = geometric overlaps, Hertz, Coulomb
# ---------------------------------------------------------------------------

def _e_star(e1, nu1, e2, nu2):
    return 1.0 / ((1 - nu1 ** 2) / e1 + (1 - nu2 ** 2) / e2)


def test_pair_contacts(runs):
    wd, res = runs[1]
    locs = dict(read_local_dump(p) for p in sorted(wd.glob("local.*.txt")))
    e_grain = 2 * G_GRAIN * (1 + NU_GRAIN)
    e_star = _e_star(e_grain, NU_GRAIN, e_grain, NU_GRAIN)
    total = 0
    for step, path in list_snapshots(wd / "snap"):
        snap = read_snapshot(path)
        p, pp = snap["particles"], snap["contacts"]["pp"]
        ids, x, r = p["id"], p["x"], p["radius"]
        # the dump local of the same compute at the same step
        rows = locs[step]
        a, b = rows[:, 0].astype(np.int64), rows[:, 1].astype(np.int64)
        swap = a > b
        sign = np.where(swap, -1.0, 1.0)[:, None]
        key = np.stack([np.minimum(a, b), np.maximum(a, b)], axis=1)
        order = np.lexsort((key[:, 1], key[:, 0]))
        assert np.array_equal(pp["id"], key[order])
        # columns: id1 id2, force (3), force_normal (3), delta, contactPoint (3)
        np.testing.assert_array_equal(pp["force"], (sign * rows[:, 2:5])[order])
        np.testing.assert_array_equal(pp["force_normal"], (sign * rows[:, 5:8])[order])
        np.testing.assert_array_equal(pp["overlap"], rows[order, 8])
        np.testing.assert_array_equal(pp["contact_point"], rows[order, 9:12])
        # exactly the overlapping pairs of the snapshot's particles
        d = np.linalg.norm(x[:, None, :] - x[None, :, :], axis=2)
        iu, ju = np.nonzero(np.triu(d < r[:, None] + r[None, :], k=1))
        assert np.array_equal(pp["id"], np.stack([ids[iu], ids[ju]], axis=1))
        assert len(iu) > len(ids) // 2                     # a packed bed
        total += len(iu)
        # overlap, contact point, Hertz normal force along the line of centres
        i, j = iu, ju
        dij = x[j] - x[i]
        dist = np.linalg.norm(dij, axis=1)
        n = dij / dist[:, None]
        delta = r[i] + r[j] - dist
        np.testing.assert_allclose(pp["overlap"], delta, rtol=1e-9, atol=1e-15)
        cp = (x[i] * r[j, None] + x[j] * r[i, None]) / (r[i] + r[j])[:, None]
        np.testing.assert_allclose(pp["contact_point"], cp, rtol=0, atol=1e-14)
        r_star = r[i] * r[j] / (r[i] + r[j])
        fn_hertz = 4.0 / 3.0 * e_star * np.sqrt(r_star * delta) * delta
        fn = pp["force_normal"]
        # on i (the lower id), pushed away from j: -n |F_n|
        np.testing.assert_allclose(fn, -fn_hertz[:, None] * n, rtol=1e-6,
                                   atol=1e-9 * fn_hertz.max())
        ft = pp["force"] - fn
        assert np.all(np.abs(np.sum(ft * n, axis=1)) <= 1e-9 * fn_hertz.max())
        assert np.all(np.linalg.norm(ft, axis=1) <= MU_GRAIN * fn_hertz * (1 + 1e-6) + 1e-12)
    assert total > 0


def test_stress_atom_tallied_at_snapshot_steps(runs):
    # compute stress/atom pair needs the per-atom virial of the step: the fix
    # asks for it on every step. Its value is -1/2 sum_c (x_i - x_j) (x) F_i
    # over the pair contacts of i (stress x volume), here from the snapshot's
    # own contact table
    wd, res = runs[1]
    for step, path in list_snapshots(wd / "snap"):
        snap = read_snapshot(path)
        p, pp = snap["particles"], snap["contacts"]["pp"]
        sa = p["values"]["c_sa"]
        assert sa.shape == (len(p["id"]), 6)
        i = np.searchsorted(p["id"], pp["id"][:, 0])
        j = np.searchsorted(p["id"], pp["id"][:, 1])
        dx = p["x"][i] - p["x"][j]
        w = dx[:, :, None] * pp["force"][:, None, :]        # same for i and j
        exp = np.zeros((len(p["id"]), 3, 3))
        np.add.at(exp, i, -0.5 * w)
        np.add.at(exp, j, -0.5 * w)
        voigt = np.stack([exp[:, 0, 0], exp[:, 1, 1], exp[:, 2, 2], exp[:, 0, 1],
                          exp[:, 0, 2], exp[:, 1, 2]], axis=1)
        np.testing.assert_allclose(sa, voigt, rtol=1e-6, atol=1e-9 * np.abs(voigt).max())


# ---------------------------------------------------------------------------
# d. mesh contacts balance the pile forces
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("nprocs", [1, 2])
def test_wall_contacts_balance_pile_forces(runs, nprocs):
    wd, res = runs[nprocs]
    series = read_series(wd / "jack.txt")
    by_step = {int(s): k for k, s in enumerate(series["step"])}
    push_ends = 0
    for step, path in list_snapshots(wd / "snap"):
        snap = read_snapshot(path)
        pw = snap["contacts"]["pw"]
        assert pw["meshes"] == ["cone", "shaft"] and pw["wall_fix"] == "pile"
        k = by_step[step]
        for m, col in ((0, "F_cone"), (1, "F_shaft")):
            sel = pw["mesh"] == m
            # the grains push the mesh up (F > 0): the mesh pushes them down
            fz = -np.sum(pw["force"][sel, 2])
            ref = series[col][k]
            assert fz == pytest.approx(ref, rel=1e-8, abs=1e-9 * max(1.0, abs(ref))), (step, col)
        assert np.all(np.isin(pw["id"], snap["particles"]["id"]))
        assert np.all(pw["overlap"] > 0)
        if snap["trigger_old"] == PUSH:
            push_ends += 1
            assert np.sum(pw["mesh"] == 0) > 0 and series["F_cone"][k] > 0
    assert push_ends == 3


# ---------------------------------------------------------------------------
# e. 1 rank = 2 ranks
# ---------------------------------------------------------------------------

def test_one_and_two_ranks_agree(runs):
    s1 = list_snapshots(runs[1][0] / "snap")
    s2 = list_snapshots(runs[2][0] / "snap")
    assert [s for s, _ in s1] == [s for s, _ in s2]
    for (step, p1), (_, p2) in zip(s1, s2):
        a, b = read_snapshot(p1), read_snapshot(p2)
        assert np.array_equal(a["particles"]["id"], b["particles"]["id"])
        scale = np.max(np.abs(a["particles"]["x"]))
        np.testing.assert_allclose(a["particles"]["x"], b["particles"]["x"], rtol=0,
                                   atol=1e-10 * scale)
        np.testing.assert_array_equal(a["particles"]["radius"], b["particles"]["radius"])
        ca, cb = a["contacts"], b["contacts"]
        assert np.array_equal(ca["pp"]["id"], cb["pp"]["id"])
        fmax = np.max(np.abs(ca["pp"]["force"]))
        np.testing.assert_allclose(ca["pp"]["force"], cb["pp"]["force"], rtol=0,
                                   atol=1e-6 * fmax)
        for k in ("id", "mesh", "triangle"):
            assert np.array_equal(ca["pw"][k], cb["pw"][k]), k


# ---------------------------------------------------------------------------
# f. bad input
# ---------------------------------------------------------------------------

ERROR_DECK = pile_cell.EMPTY_BOX + """\
fix             cone all mesh/surface/stress file cone.stl type 2
fix             shaft all mesh/surface/stress file shaft.stl type 2
fix             pile all wall/gran model hertz tangential history mesh n_meshes 2 meshes cone shaft
{before}
fix             jack all jack/pile cone cone shaft shaft mode monotonic v 0.5 depth 0.01 check_motion no
fix             integ all nve
variable        s equal step>=3
fix             snap all snapshot/hdf5 {args}
{after}
run             5
"""

GOOD = "file s trigger f_jack[6]"

BAD = [
    ("unknown_keyword", GOOD + " colour red", "",
     "unknown keyword 'colour'; expected file, trigger, leaving, contacts"),
    ("missing_file", "trigger f_jack[6]", "", "missing required keyword 'file'"),
    ("missing_trigger", "file s", "", "missing required keyword 'trigger'"),
    ("missing_value", GOOD + " contacts", "", "keyword 'contacts' needs a value"),
    ("bad_contacts", GOOD + " contacts maybe", "",
     "keyword 'contacts' must be 'yes' or 'no', got 'maybe'"),
    ("leaving_word", GOOD + " leaving push", "",
     "value 'push' of keyword 'leaving' is not a number; allowed: a finite number (a value of "
     "the trigger)"),
    ("leaving_empty", GOOD + " leaving contacts no", "",
     "keyword 'leaving' needs at least one value"),
    ("trigger_form", "file s trigger phase", "",
     "keyword 'trigger' got 'phase'; expected c_ID, c_ID[n], f_ID, f_ID[n]"),
    ("trigger_index", "file s trigger f_jack[0]", "",
     "keyword 'trigger': index of 'f_jack[0]' must be an integer >= 1"),
    ("trigger_range", "file s trigger f_jack[9]", "",
     "fix 'jack' has no global vector element 9 (allowed: 1..7)"),
    ("trigger_no_fix", "file s trigger f_nosuch[1]", "", "keyword 'trigger': no fix with ID 'nosuch'"),
    ("trigger_not_equal", "file s trigger v_a", "variable a atom x",
     "keyword 'trigger': variable 'a' is not equal-style"),
    ("trigger_after", "file s trigger f_late[6]", "",
     "keyword 'trigger': fix 'late' is defined after this fix"),
    ("values_no_compute", GOOD + " values c_nosuch", "",
     "keyword 'values': no compute 'nosuch' (for 'c_nosuch')"),
    ("values_not_peratom", GOOD + " values f_jack", "",
     "keyword 'values': fix 'jack' computes no per-atom values"),
    ("values_column", GOOD + " values c_ke[2]", "compute ke all ke/atom",
     "'c_ke[2]': compute 'ke' has a per-atom vector; write it without [n]"),
    ("values_empty", GOOD + " values contacts no", "",
     "keyword 'values' needs at least one per-atom quantity"),
    ("values_twice", GOOD + " values v_s2 v_s2", "", "keyword 'values' names 'v_s2' twice"),
    ("pair_local_without_contacts", GOOD + " pair_local pgl", "",
     "keywords 'pair_local' and 'wall_local' need 'contacts yes'"),
    ("pair_local_columns", GOOD + " contacts yes pair_local pgl",
     "compute pgl all pair/gran/local id force",
     "compute 'pgl' must store pos id force force_normal delta contactPoint"),
    ("pair_local_wrong_style", GOOD + " contacts yes pair_local ke",
     "compute ke all ke/atom", "compute 'ke' (ke/atom) is not a compute pair/gran/local"),
    ("second_pair_local", GOOD + " contacts yes",
     "compute pgl all pair/gran/local pos id force force_normal delta contactPoint",
     "the deck already has compute pair/gran/local 'pgl' and LIGGGHTS allows only one; "
     "pass it with keyword 'pair_local pgl'"),
    ("contacts_after_first_run", GOOD + " contacts yes", "run 1",
     "'contacts yes' creates a compute pair/gran/local, which LIGGGHTS allows only before the "
     "first run"),
    ("no_folder", "file nofolder/s trigger v_s", "",
     "cannot create file 'nofolder/s_3.h5'"),
]


@pytest.fixture(scope="module")
def error_runs(tmp_path_factory):
    cases = {}
    for name, args, before, pattern in BAD:
        after = ""
        if name == "trigger_after":
            after = "fix late all jack/pile cone cone shaft shaft mode monotonic v 0.5 depth 0.01 " \
                    "check_motion no"
        deck = ERROR_DECK.format(inputs=INPUTS, before=before, args=args, after=after)
        cases[name] = (deck, pattern)
    return pile_cell.run_error_cases(
        cases, tmp_path_factory, lambda wd: write_pile_stl(str(wd), 0.004, 0.05, tip_z=0.1, n_seg=8))


@pytest.mark.parametrize("name, args, before, expected", BAD, ids=[c[0] for c in BAD])
def test_bad_input(error_runs, name, args, before, expected):
    res = error_runs[name]
    if isinstance(res, Exception):
        raise res
    assert any(expected in e and "fix snapshot/hdf5" in e for e in res.errors), res.errors


def test_no_contacts_and_unfix(tmp_path):
    # one free grain far from everything (LIGGGHTS needs an atom type in use
    # for a second run): the contact tables are empty, with their row
    # shapes; 'unfix' unregisters the fix's contact computes from the pair
    # style and the wall fix, and later runs go on
    write_pile_stl(str(tmp_path), 0.004, 0.05, tip_z=0.1, n_seg=8)
    one_grain = ("create_atoms 1 single 0.015 0.015 0.19 units box\n"
                 f"set atom 1 diameter 0.001 density {RHO_GRAIN:g}")
    deck = ERROR_DECK.format(inputs=INPUTS, before=one_grain, after="", args=(
        "file s trigger v_s contacts yes")).replace("run             5\n", """\
run             5
unfix           snap
run             5
fix             again all snapshot/hdf5 file t trigger v_s leaving 0
run             5
print           "ALL DONE"
""")
    res = harness.run_deck(deck, tmp_path, timeout=120, check=True)
    assert "ALL DONE" in res.log
    assert [s for s, _ in list_snapshots(tmp_path / "s")] == [3]
    assert list_snapshots(tmp_path / "t") == []        # s stays 1 after step 3
    snap = read_snapshot(tmp_path / "s_3.h5")
    assert snap["particles"]["id"].tolist() == [1]
    np.testing.assert_array_equal(snap["particles"]["x"], [[0.015, 0.015, 0.19]])
    assert snap["particles"]["radius"].tolist() == [0.0005]
    assert snap["contacts"]["pp"]["id"].shape == (0, 2)
    assert snap["contacts"]["pw"]["force"].shape == (0, 3)
    assert snap["contacts"]["pw"]["meshes"] == ["cone", "shaft"]
    assert (snap["trigger_old"], snap["trigger_new"]) == (0.0, 1.0)


RESTART_A = """\
variable        inputs index {inputs}
include         ${{inputs}}/base.in
boundary        f f f
region          box block -0.02 0.02 -0.02 0.02 0.0 0.2 units box
create_box      4 box
create_atoms    1 single 0.015 0.015 0.19 units box
set             atom 1 diameter 0.001 density {rho:g}
include         ${{inputs}}/materials_ne34.in
neighbor        0.002 bin
timestep        1e-5
{walls}
fix             integ all nve
run             5
write_restart   r.restart
"""

RESTART_B = """\
variable        inputs index {inputs}
include         ${{inputs}}/base.in
read_restart    r.restart
include         ${{inputs}}/materials_ne34.in
neighbor        0.002 bin
{walls}
fix             integ all nve
variable        s equal step>=8
fix             snap all snapshot/hdf5 file s trigger v_s contacts yes
run             5
"""

WALLS = """\
fix             cone all mesh/surface/stress file cone.stl type 2
fix             shaft all mesh/surface/stress file shaft.stl type 2
fix             pile all wall/gran model hertz tangential history mesh n_meshes 2 meshes cone shaft
"""


def test_contacts_after_read_restart(tmp_path):
    # a deck continued from a restart file may create the contact computes
    # before its first run (LIGGGHTS' own rule, which the fix follows)
    write_pile_stl(str(tmp_path), 0.004, 0.05, tip_z=0.1, n_seg=8)
    harness.run_deck(RESTART_A.format(inputs=INPUTS, walls=WALLS, rho=RHO_GRAIN), tmp_path, timeout=60,
                     check=True)
    harness.run_deck(RESTART_B.format(inputs=INPUTS, walls=WALLS), tmp_path, timeout=60,
                     check=True)
    assert [s for s, _ in list_snapshots(tmp_path / "s")] == [8]
    snap = read_snapshot(tmp_path / "s_8.h5")
    assert snap["step"] == 8 and snap["particles"]["id"].tolist() == [1]
    assert snap["contacts"]["pw"]["meshes"] == ["cone", "shaft"]
