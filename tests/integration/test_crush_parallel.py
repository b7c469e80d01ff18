# SPDX-License-Identifier: GPL-2.0-or-later
"""Deck-level tests of `fix crush/particle` in multi-grain compressions, at 1
and 2 MPI ranks (docs/model.md §2.7: exact mass accounting at every step, on any
rank count; draws that do not depend on the number of ranks).

Scenes (crush_multi.compression_scene): columns of grains with a log-uniform
grading 0.6-1.2 mm, var 0.36 unless said, compressed by a flat mesh platen
descending at 2 m/s onto a primitive bottom wall, local damping 0.05,
translation only (`fix nve`), dt = 0.18 T_R of the smallest fragment that can
occur.  At 2 ranks `processors * 1 1` splits the box at the x = 0 plane.

d. mass balance ("big": 8 x 8 columns, 694 grains, > 200 breaks): at every
   thermo output, particle mass + fines mass == initial particle mass
   (relative 1e-12), atoms == initial + created - events, created == 14 events
   (d_frag_min 0), smallest radius >= the analytic bound
   min(r2 d_comm / 2, smallest initial radius).  The final dump is checked
   against the events file exactly: the missing tags are the parents' tags,
   every fragment tag maps to its event (tags are given 14 per event in event
   order), and its radius and generation follow from the parent.  At 2 ranks
   the breaks must happen on both sides of the processor boundary.
   Same with d_frag_min > 0 (fragments finer than it go to fines): created
   == sum over events of the kept fragments.  That run uses `thermo_modify
   lost ignore`: LIGGGHTS 3.8 reports 'Lost atoms' whenever the total count
   drops between two thermo outputs, which a grain going entirely to fines
   does on purpose (d_frag_min 0.25 mm > 0.414 d_comm); the fix's own count
   (it stops on a real loss) and the exact bookkeeping checks here stand in
   for it.
e. rank independence ("small": 4 x 2 columns, the x < 0 half the mirror image
   of the x > 0 half, var 0, so the first two grains break in the same step,
   one on each rank): the first 10 events (steps, parent tags, F_n, positions)
   and the dumps up to just after the 10th event (ids, radii, strengths,
   generations exactly; positions to round-off) are the same at 1 and 2
   ranks.  The fragments of the first simultaneous pair get tags in the order
   of their parents' tags.
p. periodic x and y ("p p f"): the first row and column of grains straddle the
   periodic boundaries; grains that straddle them break, mass balance is
   exact, no atom is lost, fragments of a straddling parent sit around the
   parent centre in the minimum image.

Each scene runs once per session (module cache).  LIGGGHTS' STL reader
writes to `screen` unchecked, so mesh decks run with `-screen /dev/null`
(crush_multi.MESH_ARGS).
"""

import math
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import crush_multi as cm  # noqa: E402
import harness  # noqa: E402

MASS_RTOL = 1e-12

SCENES = {
    # d: hundreds of breaks (~270 at 30000 steps)
    "big": dict(nx=8, ny=8, height=0.010, dmin=6e-4, dmax=1.2e-3, nsteps=30000,
                thermo=500),
    # d with every contact list examined every step (margin_skip no)
    "big_noskip": dict(nx=8, ny=8, height=0.010, dmin=6e-4, dmax=1.2e-3, nsteps=30000,
                       thermo=500, extra=" margin_skip no"),
    # d with d_frag_min: fragments finer than 0.25 mm go to fines
    "fragmin": dict(nx=4, ny=4, height=0.008, dmin=6e-4, dmax=1.2e-3, nsteps=24000,
                    thermo=500, extra=" d_frag_min 2.5e-4", lost="ignore"),
    # e: mirror-symmetric, var 0
    "small": dict(nx=4, ny=2, height=0.006, dmin=6e-4, dmax=1.2e-3, nsteps=21000,
                  var=0.0, mirror=True, thermo=250, dump_every=250),
    # p: periodic in x and y
    "periodic": dict(nx=4, ny=4, height=0.006, dmin=6e-4, dmax=1.2e-3, nsteps=24000,
                     periodic=True, thermo=250, dump_every=250),
}

_RUNS = {}


def _run(tmp_path_factory, name, nprocs):
    key = (name, nprocs)
    if key not in _RUNS:
        kw = dict(SCENES[name])
        if name in ("big", "big_noskip"):
            kw["dump_every"] = kw["nsteps"]          # first and last frame only
        if name == "fragmin":
            kw["dump_every"] = kw["nsteps"]
        workdir = tmp_path_factory.mktemp(f"{name}_np{nprocs}")
        scene = cm.compression_scene(workdir, **kw)
        res = harness.run_deck(scene.deck, workdir, nprocs=nprocs, timeout=300,
                               extra_args=cm.MESH_ARGS, check=True,
                               lost_ok=kw.get("lost", "error") != "error")
        res.scene = scene
        res.events = cm.read_events(workdir / "events.txt")
        (res.blk,) = res.thermo
        assert res.blk["Step"][-1] == kw["nsteps"], res.summary()
        _RUNS[key] = res
    return _RUNS[key]


def _frame(res, step):
    (frame,) = harness.read_dump(res.path(f"dump.{step}.txt"))
    assert frame.timestep == step
    return frame


def _check_decomposed(res, nprocs):
    if nprocs == 2:
        assert "2 by 1 by 1 MPI processor grid" in res.log, res.summary()


def _check_counters(res, d_frag_min=0.0):
    """Mass balance, atom count and created/events at every thermo output."""
    sc, blk = res.scene, res.blk
    n0 = len(sc.grains)
    events, created = blk["crush[1]"], blk["crush[2]"]
    fines, mass = blk["crush[3]"], blk["crush[4]"]

    assert mass[0] == pytest.approx(sc.mass0, rel=MASS_RTOL)
    assert fines[0] == 0.0 and events[0] == 0.0
    err = np.abs(mass + fines - sc.mass0) / sc.mass0
    assert err.max() <= MASS_RTOL, (err.max(), blk["Step"][np.argmax(err)])
    np.testing.assert_array_equal(blk["Atoms"], n0 + created - events)
    assert np.all(np.diff(events) >= 0) and np.all(np.diff(fines) >= 0)
    if d_frag_min == 0.0:
        np.testing.assert_array_equal(created, 14 * events)

    # smallest radius: never below the analytic bound
    r_bound = min(cm.smallest_fragment_radius(sc.d_comm), 0.5 * sc.grains[:, 3].min())
    if d_frag_min > 0:
        r_bound = max(r_bound, 0.5 * d_frag_min)
    assert np.all(blk["crush[6]"] >= r_bound * (1 - 1e-12)), (blk["crush[6]"].min(), r_bound)
    assert blk["crush[6]"][0] == pytest.approx(0.5 * sc.grains[:, 3].min(), rel=1e-12)

    # the events file holds one line per event, in step order
    ev = res.events
    assert len(ev["step"]) == events[-1]
    assert np.all(np.diff(ev["step"]) >= 0)
    assert np.all(ev["d"] >= sc.d_comm * (1 - 1e-9))               # comminution limit
    assert np.all(ev["F_n"] >= ev["F_lim"] * (1 - 1e-8))          # criterion met
    # events per thermo interval agree with the counter
    steps = blk["Step"]
    n_by_step = np.searchsorted(ev["step"], steps, side="right")
    np.testing.assert_array_equal(n_by_step, events)


def _kept_fragments(d_parent, d_frag_min):
    n = np.zeros(len(d_parent), dtype=np.int64)
    n += np.where(cm.R1_RATIO * d_parent >= d_frag_min, 6, 0)
    n += np.where(cm.R2_RATIO * d_parent >= d_frag_min, 8, 0)
    return n


def _check_final_dump(res, d_frag_min=0.0):
    """The last frame against the events file, exactly."""
    sc, blk, ev = res.scene, res.blk, res.events
    n0 = len(sc.grains)
    frame = _frame(res, int(blk["Step"][-1]))
    ids = frame["id"].astype(np.int64)
    assert len(ids) == blk["Atoms"][-1] == frame.natoms
    assert len(np.unique(ids)) == len(ids)

    kept = _kept_fragments(ev["d"], d_frag_min)
    assert kept.sum() == blk["crush[2]"][-1]
    max_tag = n0 + int(kept.sum())
    assert ids.min() >= 1 and ids.max() <= max_tag
    # the tags missing from 1..max_tag are exactly those of the broken parents
    missing = np.setdiff1d(np.arange(1, max_tag + 1), ids)
    np.testing.assert_array_equal(missing, np.sort(ev["tag"]))
    assert len(np.unique(ev["tag"])) == len(ev["tag"])           # each breaks once

    # fragment tags: consecutive blocks in event order (file order)
    first = n0 + 1 + np.concatenate([[0], np.cumsum(kept)[:-1]])
    frag = ids > n0
    k = np.searchsorted(first, ids[frag], side="right") - 1
    gen = frame["f_crush[2]"]
    np.testing.assert_array_equal(gen[frag], ev["generation"][k] + 1)
    np.testing.assert_array_equal(gen[~frag], 0)
    ratio = frame["radius"][frag] / (0.5 * ev["d"][k])
    near = np.minimum(np.abs(ratio / cm.R1_RATIO - 1), np.abs(ratio / cm.R2_RATIO - 1))
    assert near.max() < 2e-6, near.max()
    # an initial grain keeps its radius
    np.testing.assert_allclose(frame["radius"][~frag], 0.5 * sc.grains[ids[~frag] - 1, 3],
                               rtol=1e-15)

    # totals of the frame match the thermo counters
    assert frame["mass"].sum() == pytest.approx(blk["crush[4]"][-1], rel=1e-12)
    assert frame["radius"].min() == pytest.approx(blk["crush[6]"][-1], rel=1e-15)
    np.testing.assert_allclose(frame["mass"], 4 / 3 * math.pi * frame["radius"] ** 3
                               * cm.DENSITY, rtol=1e-12)
    return frame


# ---------------------------------------------------------------------------
# d. mass balance with hundreds of breaks
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("nprocs", [1, 2])
def test_mass_balance_compression(tmp_path_factory, nprocs):
    res = _run(tmp_path_factory, "big", nprocs)
    _check_decomposed(res, nprocs)
    blk, ev = res.blk, res.events
    assert blk["crush[1]"][-1] >= 200, blk["crush[1]"][-1]
    _check_counters(res)
    _check_final_dump(res)

    # breakage cascades: fragments break again, and both contact kinds occur
    assert ev["generation"].max() >= 1
    assert set(ev["partner"]) == {"wall", "particle"}
    assert blk["crush[5]"][-1] > 0                                  # Br grew

    # breaks on both sides of the processor boundary (x = 0)
    left, right = np.sum(ev["x"] < 0), np.sum(ev["x"] > 0)
    assert min(left, right) >= 0.2 * len(ev["x"]), (left, right)


@pytest.mark.parametrize("nprocs", [1, 2])
def test_mass_balance_with_d_frag_min(tmp_path_factory, nprocs):
    res = _run(tmp_path_factory, "fragmin", nprocs)
    _check_decomposed(res, nprocs)
    blk, ev = res.blk, res.events
    d_frag_min = 2.5e-4
    assert blk["crush[1]"][-1] >= 20, blk["crush[1]"][-1]
    _check_counters(res, d_frag_min=d_frag_min)
    kept = _kept_fragments(ev["d"], d_frag_min)
    # both cases occur: parents that keep only their 6 large fragments, and all 14
    assert set(kept) >= {6, 14}, set(kept)
    # counter after each thermo interval == sum of kept fragments of its events
    n_by_step = np.searchsorted(ev["step"], blk["Step"], side="right")
    csum = np.concatenate([[0], np.cumsum(kept)])
    np.testing.assert_array_equal(blk["crush[2]"], csum[n_by_step])
    _check_final_dump(res, d_frag_min=d_frag_min)


def test_margin_skip_finds_the_same_events(tmp_path_factory):
    """Skipping contact lists far from their limits (the default) must not
    change a single event: same steps, tags and forces as examining every
    contact of every step, over hundreds of breaks, dozens of them at the
    descending platen (the wall contacts' skip bounds the mesh's motion)."""
    a = _run(tmp_path_factory, "big", 1)
    b = _run(tmp_path_factory, "big_noskip", 1)
    ea, eb = a.events, b.events
    assert len(ea["step"]) >= 200
    assert np.sum(np.asarray(ea["partner"]) == "wall") >= 30
    assert len(ea["step"]) == len(eb["step"])
    for col in ("step", "tag", "generation", "partner", "d", "F_n", "F_lim", "x", "y", "z"):
        np.testing.assert_array_equal(ea[col], eb[col], err_msg=col)
    np.testing.assert_array_equal(a.blk["crush[1]"], b.blk["crush[1]"])
    # f_crush[7]: share of contact lists examined; the skip must have skipped
    assert b.blk["crush[7]"][-1] == 1.0
    assert a.blk["crush[7]"][-1] < 0.5, a.blk["crush[7]"][-1]
    print("share of contact lists examined with margin_skip:", a.blk["crush[7]"][-1])


# ---------------------------------------------------------------------------
# e. the first events do not depend on the number of ranks
# ---------------------------------------------------------------------------

N_FIRST = 10


def test_small_case_breaks_on_both_ranks(tmp_path_factory):
    res = _run(tmp_path_factory, "small", 2)
    _check_decomposed(res, 2)
    ev = res.events
    assert len(ev["step"]) >= N_FIRST + 1
    first = slice(0, N_FIRST)
    assert np.any(ev["x"][first] < 0) and np.any(ev["x"][first] > 0)
    # the mirror-symmetric scene: the first step with a break has one on each side
    s0 = ev["step"][0]
    at0 = ev["step"] == s0
    assert at0.sum() == 2 and np.sort(np.sign(ev["x"][at0])).tolist() == [-1, 1], ev["x"][at0]
    for nprocs in (1, 2):
        _check_counters(_run(tmp_path_factory, "small", nprocs))


def test_first_events_same_at_1_and_2_ranks(tmp_path_factory):
    e1 = _run(tmp_path_factory, "small", 1).events
    e2 = _run(tmp_path_factory, "small", 2).events
    first = slice(0, N_FIRST)
    np.testing.assert_array_equal(e1["step"][first], e2["step"][first])
    np.testing.assert_array_equal(e1["tag"][first], e2["tag"][first])
    np.testing.assert_array_equal(e1["generation"][first], e2["generation"][first])
    np.testing.assert_array_equal(e1["partner"][first], e2["partner"][first])
    np.testing.assert_array_equal(e1["d"][first], e2["d"][first])
    for col in ("F_n", "F_lim"):
        np.testing.assert_allclose(e2[col][first], e1[col][first], rtol=1e-6)
    for col in ("x", "y", "z"):
        np.testing.assert_allclose(e2[col][first], e1[col][first], rtol=0, atol=1e-9)


def test_fragment_tags_same_at_1_and_2_ranks(tmp_path_factory):
    r1 = _run(tmp_path_factory, "small", 1)
    r2 = _run(tmp_path_factory, "small", 2)
    ev = r1.events
    every = SCENES["small"]["dump_every"]
    last = (int(ev["step"][N_FIRST - 1]) // every + 1) * every   # first dump after event 10
    for step in range(0, last + 1, every):
        f1, f2 = _frame(r1, step), _frame(r2, step)
        np.testing.assert_array_equal(f1["id"], f2["id"], err_msg=f"step {step}")
        for col in ("type", "radius", "mass", "f_crush[1]", "f_crush[2]"):
            np.testing.assert_array_equal(f1[col], f2[col], err_msg=f"{col} at step {step}")
        for col in ("x", "y", "z"):
            np.testing.assert_allclose(f2[col], f1[col], rtol=0, atol=1e-9,
                                       err_msg=f"{col} at step {step}")
    assert len(_frame(r1, last)) > len(r1.scene.grains) + 13 * (N_FIRST - 1)


def test_first_pair_tags_in_parent_tag_order(tmp_path_factory):
    """The two grains breaking in the first step (one per rank at 2 ranks) get
    fragment tags n0+1..n0+14 (lower parent tag) and n0+15..n0+28."""
    n0 = None
    for nprocs in (1, 2):
        res = _run(tmp_path_factory, "small", nprocs)
        ev = res.events
        n0 = len(res.scene.grains)
        s0 = int(ev["step"][0])
        parents = np.sort(ev["tag"][ev["step"] == s0])
        assert len(parents) == 2
        every = SCENES["small"]["dump_every"]
        before = _frame(res, (s0 // every) * every)
        after = _frame(res, (s0 // every + 1) * every)
        assert ev["step"][2] > after.timestep
        new = np.setdiff1d(after["id"], before["id"]).astype(int)
        np.testing.assert_array_equal(new, np.arange(n0 + 1, n0 + 29))
        for k, ptag in enumerate(parents):
            j = np.searchsorted(before["id"], ptag)
            xp = np.array([before["x"][j], before["y"][j], before["z"][j]])
            rp = before["radius"][j]
            sel = np.isin(after["id"], np.arange(n0 + 1 + 14 * k, n0 + 15 + 14 * k))
            pos = np.column_stack([after["x"][sel], after["y"][sel], after["z"][sel]])
            dist = np.linalg.norm(pos - xp, axis=1)
            assert np.all(dist < rp), (ptag, dist / rp)
            radii = np.sort(after["radius"][sel])
            np.testing.assert_allclose(radii[:8], cm.R2_RATIO * rp, rtol=1e-12)
            np.testing.assert_allclose(radii[8:], cm.R1_RATIO * rp, rtol=1e-12)
            # one parent on each side of x = 0 (on each rank at 2 ranks)
            assert np.all(np.sign(after["x"][sel]) == np.sign(xp[0]))


# ---------------------------------------------------------------------------
# p. periodic boundaries
# ---------------------------------------------------------------------------

def _straddles(ev, box):
    (xlo, xhi), (ylo, yhi) = box[0], box[1]
    r = 0.5 * ev["d"]
    sx = (ev["x"] - xlo < r) | (xhi - ev["x"] < r)
    sy = (ev["y"] - ylo < r) | (yhi - ev["y"] < r)
    return sx, sy


@pytest.mark.parametrize("nprocs", [1, 2])
def test_periodic_straddling_breaks(tmp_path_factory, nprocs):
    res = _run(tmp_path_factory, "periodic", nprocs)
    _check_decomposed(res, nprocs)
    assert not [e for e in res.errors], res.errors
    assert "Lost atoms" not in res.all_text
    blk, ev, sc = res.blk, res.events, res.scene
    assert blk["crush[1]"][-1] >= 30
    _check_counters(res)
    frame = _check_final_dump(res)
    # every atom is inside the periodic box in x and y (up to half a skin)
    (xlo, xhi), (ylo, yhi) = sc.box[0], sc.box[1]
    tol = 1e-4
    assert np.all((frame["x"] >= xlo - tol) & (frame["x"] <= xhi + tol))
    assert np.all((frame["y"] >= ylo - tol) & (frame["y"] <= yhi + tol))

    sx, sy = _straddles(ev, sc.box)
    assert sx.sum() >= 1 and sy.sum() >= 1, (sx.sum(), sy.sum())

    # fragments of straddling parents, in the first dump after their event,
    # lie within the parent in the minimum image; some end up on both sides
    n0 = len(sc.grains)
    first = n0 + 1 + 14 * np.arange(len(ev["step"]))
    L = np.array([xhi - xlo, yhi - ylo])
    every = SCENES["periodic"]["dump_every"]
    both_sides = 0
    for k in np.nonzero(sx | sy)[0]:
        step = (int(ev["step"][k]) // every + 1) * every
        if step > blk["Step"][-1]:
            continue
        f = _frame(res, step)
        sel = (f["id"] >= first[k]) & (f["id"] < first[k] + 14)
        if not np.any(sel):
            continue
        d = np.column_stack([f["x"][sel] - ev["x"][k], f["y"][sel] - ev["y"][k]])
        d -= L * np.round(d / L)
        dz = f["z"][sel] - ev["z"][k]
        dist = np.sqrt((d ** 2).sum(axis=1) + dz ** 2)
        assert np.all(dist < 0.5 * ev["d"][k]), (k, dist / (0.5 * ev["d"][k]))
        wrapped_x = np.any(f["x"][sel] < 0) and np.any(f["x"][sel] > 0) and sx[k]
        wrapped_y = np.any(f["y"][sel] < 0) and np.any(f["y"][sel] > 0) and sy[k]
        both_sides += bool(wrapped_x or wrapped_y)
    assert both_sides >= 1


def test_periodic_first_events_same_at_1_and_2_ranks(tmp_path_factory):
    e1 = _run(tmp_path_factory, "periodic", 1).events
    e2 = _run(tmp_path_factory, "periodic", 2).events
    first = slice(0, N_FIRST)
    np.testing.assert_array_equal(e1["step"][first], e2["step"][first])
    np.testing.assert_array_equal(e1["tag"][first], e2["tag"][first])
    np.testing.assert_allclose(e2["F_n"][first], e1["F_n"][first], rtol=1e-6)
