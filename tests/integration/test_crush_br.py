# SPDX-License-Identifier: GPL-2.0-or-later
"""Deck-level tests of the breakage index of `fix crush/particle` and of its
atom-count check (docs/model.md §2.7-§2.8; docs/fix_crush_particle.md).

a. Br from the outside: a multi-grain compression (crush_multi scene, about
   60 grains of 0.6-1.2 mm with the Br range d_min 0.05 mm, d_max 1.3 mm, a
   few tens of breaks) at 1 and 2 ranks. At the last step f_crush[5] (Br,
   bounded) and f_crush[8] (Einav's unclipped ratio) equal what
   crushpost.breakage computes from the final dump, the initial dump and the
   event log alone (fines per event from the parent diameter), to 1e-10;
   f_crush[3] equals the fines of the event log. Default `fines_grading
   fractal`, and `fines_grading d_min` with `d_frag_min` (fragments finer
   than it are not created and count at their own size in 'fractal', below
   d_min in 'd_min'). With `d_min` the unclipped ratio is the former formula
   (all fines finer than d_min), computed here from the dump and f_crush[3].
   Br never decreases, and never exceeds the unclipped ratio (the bound
   clips a bin's integral to its limit grading's; breakage only moves mass
   finer, so no bin falls below its initial integral).
a2. The bound at work: the same compression pushed further (60,000 steps,
   about 80 breaks, fines below d_min) takes Einav's unclipped ratio past 1
   (about 1.3: finer than the limit grading at the coarse end). f_crush[8]
   equals crushpost's unclipped ratio and f_crush[5] crushpost's bounded Br
   (numpy, from the dumps and the event log), which is below 1 and below the
   unclipped ratio at every output.
b. Lost grains: a grain flies out through a boundary without a wall while
   another grain is crushed by a platen, with thermo output only at the
   start and the end; `thermo_modify lost ignore` would let the run go on
   (and stock LIGGGHTS 3.8's `lost error`, which compares counts between
   thermo outputs, would let the break's 13 new atoms hide the loss), but
   the fix stops at the first neighbour-list build after the grain left,
   before the break, with the number of atoms lost.
"""

import math
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import crush_decks as cd  # noqa: E402
import crush_multi as cm  # noqa: E402
import harness  # noqa: E402

from crushpost.breakage import break_fines, breakage, grading_integral  # noqa: E402
from crushpost.dump import read_crush_log, read_dump  # noqa: E402

BR_DMIN, BR_DMAX = 0.05e-3, 1.3e-3
NSTEPS = 21000
SCENES = {
    "fractal": "",
    "dmin_fragmin": " fines_grading d_min d_frag_min 2.5e-4",
    "fractal_fragmin": " fines_grading fractal d_frag_min 2.5e-4",
}

_RUNS = {}


def _run(tmp_path_factory, name, nprocs):
    key = (name, nprocs)
    if key not in _RUNS:
        workdir = tmp_path_factory.mktemp(f"br_{name}_np{nprocs}")
        extra = f" d_min {BR_DMIN!r} d_max {BR_DMAX!r}" + SCENES[name]
        # d_frag_min 0.25 mm > 0.414 d_comm (0.4 mm): a grain that goes entirely
        # to fines lowers the atom count on purpose, which stock `lost error`
        # takes for lost atoms; the fix's own count still stops a real loss
        lost = "ignore" if "d_frag_min" in SCENES[name] else "error"
        scene = cm.compression_scene(workdir, nx=4, ny=2, height=0.006, dmin=6e-4, dmax=1.2e-3,
                                     nsteps=NSTEPS, thermo=500, dump_every=NSTEPS, extra=extra,
                                     lost=lost)
        deck = scene.deck.replace("f_crush[6] f_crush[7]\n", "f_crush[6] f_crush[7] f_crush[8]\n")
        assert deck != scene.deck
        res = harness.run_deck(deck, workdir, nprocs=nprocs, timeout=300,
                               extra_args=cm.MESH_ARGS, check=True, lost_ok=(lost == "ignore"))
        (res.blk,) = res.thermo
        assert res.blk["Step"][-1] == NSTEPS, res.summary()
        _RUNS[key] = res
    return _RUNS[key]


def _grading(res, step):
    (snap,) = read_dump(res.path(f"dump.{step}.txt"))
    assert snap["timestep"] == step
    a = snap["atoms"]
    return 2.0 * a["radius"], a["mass"]


@pytest.mark.parametrize("nprocs", [1, 2])
@pytest.mark.parametrize("name", list(SCENES))
def test_br_equals_crushpost_from_dump_and_event_log(tmp_path_factory, name, nprocs):
    res = _run(tmp_path_factory, name, nprocs)
    blk = res.blk
    d, m = _grading(res, NSTEPS)
    d0, m0 = _grading(res, 0)
    ev = read_crush_log(res.path("events.txt"))
    n_ev = len(ev["step"])
    assert n_ev >= 5 and blk["crush[1]"][-1] == n_ev, res.summary()
    d_frag_min = 2.5e-4 if "fragmin" in name else 0.0
    grading = "d_min" if name.startswith("dmin") else "fractal"
    fines = break_fines(ev["parent_diameter"], density=cm.DENSITY, d_frag_min=d_frag_min)
    if d_frag_min:
        assert fines.dropped_m.size > 0        # some fragments were not created
    assert blk["crush[3]"][-1] == pytest.approx(fines.total, rel=1e-12)
    py = breakage(d, m, d0, m0, BR_DMIN, BR_DMAX, fines=fines, fines_grading=grading)
    assert blk["crush[5]"][-1] == pytest.approx(py.Br, rel=1e-10, abs=1e-12)
    assert blk["crush[8]"][-1] == pytest.approx(py.Br_einav, rel=1e-10, abs=1e-12)
    br = blk["crush[5]"]
    assert br[-1] > 0
    # the bound only lowers Br (the fix's bounded value is not checked
    # against [0, 1] here: it is clipped by construction; a2 below)
    assert np.all(br <= blk["crush[8]"] + 1e-12), (br, blk["crush[8]"])
    assert np.all(np.diff(br) >= -1e-12), "Br decreased"
    if grading == "d_min":
        # the former formula: every fines mass finer than d_min
        i = grading_integral(d, m, blk["crush[3]"][-1], BR_DMIN, BR_DMAX)
        i0 = grading_integral(d0, m0, 0.0, BR_DMIN, BR_DMAX)
        assert blk["crush[8]"][-1] == pytest.approx((i - i0) / (py.B_p), rel=1e-10)


def test_fractal_fines_count_less_than_fines_below_d_min(tmp_path_factory):
    # same scene, d_frag_min 2.5e-4 in both: the fix's Br with the fines at
    # d_min is the larger, and crushpost agrees on both from one run's files
    res = _run(tmp_path_factory, "fractal_fragmin", 1)
    d, m = _grading(res, NSTEPS)
    d0, m0 = _grading(res, 0)
    ev = read_crush_log(res.path("events.txt"))
    fines = break_fines(ev["parent_diameter"], density=cm.DENSITY, d_frag_min=2.5e-4)
    fr = breakage(d, m, d0, m0, BR_DMIN, BR_DMAX, fines=fines)
    dm = breakage(d, m, d0, m0, BR_DMIN, BR_DMAX, fines=fines, fines_grading="d_min")
    assert res.blk["crush[5]"][-1] == pytest.approx(fr.Br, rel=1e-10)
    assert 0 < fr.Br < dm.Br


# ---------------------------------------------------------------------------
# a2. the bound acting on an unclipped ratio above 1
# ---------------------------------------------------------------------------

FAR_STEPS = 60000


def test_bound_acts_when_einav_ratio_passes_one(tmp_path):
    extra = f" d_min {BR_DMIN!r} d_max {BR_DMAX!r} fines_grading d_min"
    scene = cm.compression_scene(tmp_path, nx=4, ny=2, height=0.006, dmin=6e-4, dmax=1.2e-3,
                                 nsteps=FAR_STEPS, thermo=500, dump_every=FAR_STEPS, extra=extra)
    deck = scene.deck.replace("f_crush[6] f_crush[7]\n", "f_crush[6] f_crush[7] f_crush[8]\n")
    assert deck != scene.deck
    res = harness.run_deck(deck, tmp_path, nprocs=1, timeout=300, extra_args=cm.MESH_ARGS,
                           check=True)
    (blk,) = res.thermo
    assert blk["Step"][-1] == FAR_STEPS, res.summary()
    d, m = _grading(res, FAR_STEPS)
    d0, m0 = _grading(res, 0)
    ev = read_crush_log(res.path("events.txt"))
    assert len(ev["step"]) == blk["crush[1]"][-1] >= 50
    fines = break_fines(ev["parent_diameter"], density=cm.DENSITY)
    py = breakage(d, m, d0, m0, BR_DMIN, BR_DMAX, fines=fines, fines_grading="d_min")
    # the case the bound is for: the unclipped ratio is outside [0, 1]
    assert py.Br_einav > 1.1, py
    assert blk["crush[8]"][-1] == pytest.approx(py.Br_einav, rel=1e-10)
    assert blk["crush[5]"][-1] == pytest.approx(py.Br, rel=1e-10)
    assert 0.5 < py.Br < 1.0
    br, einav = blk["crush[5]"], blk["crush[8]"]
    assert np.all(br <= einav + 1e-12) and np.all(br < 1.0)
    assert np.any(einav > 1.0) and np.all(np.diff(br) >= -1e-12)


# ---------------------------------------------------------------------------
# b. a grain lost in the same thermo interval as a break
# ---------------------------------------------------------------------------

def _lost_grain_deck(lost, crush_extra="", runs=None):
    """A 1 mm grain on a steel bottom wall pressed by a steel platen at
    0.5 m/s, and a free 0.2 mm grain (finer than d_comm) flying out through
    the x boundary at 10 m/s, no wall there. Thermo only at the start and the
    end. Returns (deck, step of the break predicted from Hertz, time step)."""
    d, gap, speed, half = 1.0e-3, 1.0e-5, 0.5, 1.0e-3
    r = 0.5 * d
    d_comm = 0.6e-3
    dt = 0.18 * cd.rayleigh_time(cd.R2_RATIO * r)
    Es = cd.effective_modulus(cd.E_GRAIN, cd.NU_GRAIN, cd.E_STEEL, cd.NU_STEEL)
    F_lim = cd.limit_force(cd.strength(d), r, Es)
    travel = gap + 2.0 * cd.hertz_overlap(F_lim, r, Es)
    step_break = int(math.ceil(travel / (speed * dt)))
    z_top0 = d + gap
    box = f"-{half!r} {half!r} -{half!r} {half!r} -0.001 {z_top0 + 0.001!r}"
    deck = cd.header(box, [(cd.E_GRAIN, cd.NU_GRAIN, "grain"), (cd.E_STEEL, cd.NU_STEEL, "wall")])
    deck += f"""\
timestep {dt!r}
create_atoms 1 single 0 0 {r!r} units box
set atom 1 diameter {d!r} density {cd.DENSITY!r}
create_atoms 1 single 0.8e-3 0 0.5e-3 units box
set atom 2 diameter 0.2e-3 density {cd.DENSITY!r}
group flyer id 2
velocity flyer set 10.0 0 0 units box
fix top all mesh/surface/stress file plate.stl type 2 move 0 0 {z_top0!r}
fix walls all wall/gran model hertz tangential history mesh n_meshes 1 meshes top
fix bottom all wall/gran model hertz tangential history primitive type 2 zplane 0.0
fix mv all move/mesh mesh top linear 0. 0. {-speed!r}
fix integ all nve
"""
    deck += cd.crush_fix(d_comm=d_comm, extra=crush_extra)
    deck += f"""\
thermo_style custom step atoms f_crush[1] f_crush[2] f_crush[5]
thermo_modify format float %.17g lost {lost}
thermo {10 * step_break}
"""
    deck += runs if runs is not None else f"run {step_break + 300}\n"
    return deck, step_break, dt


@pytest.mark.parametrize("lost", ["ignore", "error"])
def test_lost_grain_stops_the_run_before_the_break(tmp_path, lost):
    deck, step_break, dt = _lost_grain_deck(lost)
    res = cd.expect_error(deck, tmp_path, "1 atoms lost by step",
                          files={"plate.stl": lambda p: cd.write_plate_stl(p, half=0.9e-3)},
                          lost_ok=(lost == "ignore"))
    assert "(expected 2, found 1)" in res.all_text, res.summary()
    assert "must not lose grains" in res.all_text
    # it stops at the first neighbour-list build after the flyer's centre
    # left the box (0.2 mm at 10 m/s); builds come when a grain moved more
    # than half the skin (0.25 mm), long before the break
    step = int(res.all_text.split("atoms lost by step ")[1].split()[0])
    step_out, step_build = 0.2e-3 / (10.0 * dt), 0.25e-3 / (10.0 * dt)
    assert step_out <= step <= step_build + 2 < step_break, (step, step_out, step_break)


def test_no_false_alarm_without_a_lost_grain(tmp_path):
    # the same deck with the flyer at rest: the grain breaks, the run ends
    deck, step_break, _ = _lost_grain_deck("error")
    deck = deck.replace("velocity flyer set 10.0 0 0 units box\n", "")
    res = cd.run(deck, tmp_path, files={"plate.stl": lambda p: cd.write_plate_stl(p, half=0.9e-3)})
    (blk,) = res.thermo
    assert blk["crush[1]"][-1] == 1 and blk["Atoms"][-1] == 15


# ---------------------------------------------------------------------------
# c. keyword errors and restart files
# ---------------------------------------------------------------------------

STL = {"plate.stl": lambda p: cd.write_plate_stl(p, half=0.9e-3)}


def test_fines_grading_bad_value(tmp_path):
    deck, _, _ = _lost_grain_deck("error", crush_extra="fines_grading sieve", runs="run 1\n")
    cd.expect_error(deck, tmp_path, "keyword 'fines_grading' must be 'fractal' or 'd_min', "
                    "got 'sieve'", files=STL)


def test_fines_grading_needs_a_value(tmp_path):
    deck, _, _ = _lost_grain_deck("error", crush_extra="fines_grading", runs="run 1\n")
    cd.expect_error(deck, tmp_path, "keyword 'fines_grading' needs a value", files=STL)


def _restart_deck(crush_extra):
    """The deck of _lost_grain_deck (flyer at rest) read back from restart.bin."""
    deck, step_break, _ = _lost_grain_deck("error", crush_extra=crush_extra, runs="run 100\n")
    keep = []
    for line in deck.splitlines():
        w = line.split()[:1]
        if w and w[0] in ("units", "atom_style", "boundary", "region", "create_atoms", "set",
                          "velocity"):
            continue
        keep.append("read_restart restart.bin" if w == ["create_box"] else line)
    return "\n".join(keep) + "\n"


def _written_restart(tmp_path):
    """Run past the break of the 1 mm grain and write restart.bin; returns
    (the run, Br after the break)."""
    deck, step_break, _ = _lost_grain_deck("error", runs="")
    deck = deck.replace("velocity flyer set 10.0 0 0 units box\n", "")
    deck += f"run {step_break + 100}\nwrite_restart restart.bin\n"
    res = cd.run(deck, tmp_path / "write", files=STL)
    (blk,) = res.thermo
    assert blk["crush[1]"][-1] == 1 and blk["crush[5]"][-1] > 0
    return res, blk["crush[5]"][-1]


def test_restart_keeps_br_and_refuses_other_br_settings(tmp_path):
    res, br = _written_restart(tmp_path)
    copy = {"restart.bin": lambda p: p.write_bytes(res.path("restart.bin").read_bytes()), **STL}
    # same settings: Br continues from the restored initial grading and fines
    again = cd.run(_restart_deck(""), tmp_path / "same", files=copy)
    assert again.thermo[0]["crush[5]"][0] == pytest.approx(br, rel=1e-13)
    for extra, what in (("fines_grading d_min", "fines_grading fractal"),
                        ("omega 2.5", "omega 2.6"), ("d_min 2e-05", "d_min 1e-05")):
        bad = cd.expect_error(_restart_deck(extra), tmp_path / extra.split()[0], "the Br settings "
                              "differ from those in the restart file", files=copy)
        assert what in bad.all_text, bad.errors
