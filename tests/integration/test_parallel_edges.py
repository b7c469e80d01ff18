# SPDX-License-Identifier: GPL-2.0-or-later
"""Parallel edge cases of `fix crush/particle` (issue 12, item 4; results in
docs/studies/stability.md, section "Parallel edge cases").

Scenes are crush_multi.compression_scene (columns of grains pressed by a
descending mesh platen, see test_crush_parallel.py), at 4 MPI ranks,
oversubscribed on a 2-core machine:

a. "mirror" (4 x 3 columns, height 10 mm, var 0, x < 0 the mirror image of
   x > 0, walls on every side, 30000 steps) and "periodic" (4 x 4 columns,
   height 6 mm, periodic in x and y, the first row and column straddling the
   periodic boundaries, 24000 steps), both at `processors 2 2 1`: cuts at
   x = 0 and y = 0 (in the mirror scene y = 0 runs through the centres of the
   middle row).  Each: breaks on every rank and parents straddling the cuts
   (and the periodic boundaries), every tag of the final dump unique and
   equal to initial tags - parents + 14 per event, mass balance to 1e-12 at
   every thermo output, no atom lost (`thermo_modify lost error` and atoms ==
   initial + created - events), and the first 10 events (steps, parent tags,
   generations, F_n, positions) the same as at 1 rank.
b. restart at another rank count: the periodic scene at 1 rank writes restart
   files at steps 12000 and 24000 while running on uninterrupted (`restart`
   command); a 2-rank run reads the step-12000 file and goes on to 24000,
   writing a restart file at 18000; a 4-rank run reads that and goes on to
   24000.  Each restarted run is compared with the run that wrote its file
   (which ran on uninterrupted): the state read back (tags, radii, masses,
   strengths, generations, positions) bitwise, the counters f_crush[1..3]
   exactly and the mass to 1e-14 at the restart step, mass balance over the
   whole run, the next N_AFTER events (steps, parent tags, generations,
   partner, F_lim; F_n to F_N_RTOL_AFTER and positions to 1e-9 m: a run
   boundary perturbs fragment contacts, see docs/studies/stability.md), the counters
   until then, the strength and generation of every initial grain and of
   every fragment of an event both runs share in the final dumps, and the tag
   bookkeeping of the final dump against all events since step 0.
   A restart deck with another seed is an error naming 'seed'.

The restart decks follow docs/fix_crush_particle.md: the same header without
units/atom_style/boundary, `read_restart` instead of `read_data`, the same
material fixes, pair style, time step and fixes with the same IDs (the crush
fix state, the mesh and move/mesh state and contact histories come from the
file), another events file.
"""

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import crush_multi as cm  # noqa: E402
import harness  # noqa: E402
import test_crush_parallel as tcp  # noqa: E402  (mass/tag checks shared with d, e, p)

MASS_RTOL = 1e-12
N_FIRST = 10          # first events compared between rank counts
N_AFTER = 10          # events compared after a restart
F_N_RTOL_AFTER = 1e-3  # F_n of those: other summation order, amplified by the contacts

SCENES = {
    "mirror": dict(nx=4, ny=3, height=0.010, dmin=6e-4, dmax=1.2e-3, nsteps=30000,
                   var=0.0, mirror=True, thermo=500, dump_every=30000),
    "periodic": dict(nx=4, ny=4, height=0.006, dmin=6e-4, dmax=1.2e-3, nsteps=24000,
                     periodic=True, thermo=500, dump_every=6000),
}
PROCESSORS = {("mirror", 4): "2 2 1", ("periodic", 4): "2 2 1", ("periodic", 2): "2 1 1"}
# restart chain: 1 rank writes at R1 (uninterrupted run), 2 ranks read R1 and
# write at R2, 4 ranks read R2
R1, R2 = 12000, 18000

_RUNS = {}


def _finish(res, scene, workdir, events_name="events.txt"):
    res.scene = scene
    res.events = cm.read_events(Path(workdir) / events_name)
    (res.blk,) = res.thermo
    assert res.blk["Step"][-1] == scene.nsteps, res.summary()
    return res


def _run(tmp_path_factory, name, nprocs):
    """A scene from step 0 at nprocs ranks.  The 1-rank periodic run also
    writes the restart files (trajectory-neutral: no remap, no rebuild)."""
    key = (name, nprocs)
    if key not in _RUNS:
        kw = dict(SCENES[name])
        kw["processors"] = PROCESSORS.get(key, "* 1 1")
        workdir = tmp_path_factory.mktemp(f"{name}_np{nprocs}")
        scene = cm.compression_scene(workdir, **kw)
        deck = scene.deck
        if name == "periodic" and nprocs == 1:
            deck = _with_restart_output(deck, R1)
        res = harness.run_deck(deck, workdir, nprocs=nprocs, timeout=300,
                               extra_args=cm.MESH_ARGS, check=True)
        _RUNS[key] = _finish(res, scene, workdir)
        if nprocs > 1:
            assert "%s MPI processor grid" % kw["processors"].replace(" ", " by ") in res.log
    return _RUNS[key]


def _with_restart_output(deck, every):
    run = [l for l in deck.splitlines() if l.startswith("run ")]
    assert len(run) == 1
    return deck.replace(run[0], f"restart {every} restart.*.bin\n{run[0]}")


def restart_deck(deck, restart_file, processors, nsteps_left, events="events_restart.txt"):
    """The deck of a compression scene turned into one that continues from
    `restart_file` at another processor grid."""
    out = []
    for line in deck.splitlines():
        w = line.split()
        if w and w[0] in ("units", "atom_style", "boundary"):
            continue                      # stored in the restart file
        if w[:1] == ["processors"]:
            line = f"processors      {processors}"
        elif w[:1] == ["read_data"]:
            line = f"read_restart    {restart_file}"
        elif w[:1] == ["run"]:
            line = f"run             {nsteps_left}"
        elif w[:3] == ["fix", "crush", "all"]:
            line = line.replace("events events.txt", f"events {events}")
        out.append(line)
    return "\n".join(out) + "\n"


def _restarted(tmp_path_factory, nprocs):
    """2 ranks from the 1-rank file at R1 (writing at R2); 4 ranks from the
    2-rank file at R2."""
    key = ("restart", nprocs)
    if key not in _RUNS:
        if nprocs == 2:
            src, R = _run(tmp_path_factory, "periodic", 1), R1
        else:
            src, R = _restarted(tmp_path_factory, 2), R2
        workdir = tmp_path_factory.mktemp(f"restart_np{nprocs}")
        scene = cm.compression_scene(workdir, **SCENES["periodic"])   # data, STL
        proc = PROCESSORS[("periodic", nprocs)]
        deck = restart_deck(scene.deck, "restart.bin", proc, scene.nsteps - R)
        if nprocs == 2:
            deck = _with_restart_output(deck, R2)
        (workdir / "restart.bin").write_bytes(src.path(f"restart.{R}.bin").read_bytes())
        res = harness.run_deck(deck, workdir, nprocs=nprocs, timeout=300,
                               extra_args=cm.MESH_ARGS, check=True)
        assert "%s MPI processor grid" % proc.replace(" ", " by ") in res.log
        res = _finish(res, scene, workdir, "events_restart.txt")
        res.R = R
        assert res.blk["Step"][0] == R
        _RUNS[key] = res
    return _RUNS[key]


def _owner_counts(ev, cuts_x, cuts_y):
    """Events per subdomain of a regular grid (by the parent position)."""
    ix = np.searchsorted(cuts_x, ev["x"])
    iy = np.searchsorted(cuts_y, ev["y"])
    n = np.zeros((len(cuts_x) + 1, len(cuts_y) + 1), dtype=int)
    np.add.at(n, (ix, iy), 1)
    return n


def _straddle_cut(ev, cuts, col):
    r = 0.5 * ev["d"]
    return np.array([np.any(np.abs(ev[col][k] - np.asarray(cuts)) < r[k])
                     for k in range(len(r))], dtype=bool)


# ---------------------------------------------------------------------------
# a. 4 ranks, processor and periodic boundaries
# ---------------------------------------------------------------------------

def test_mirror_4_ranks_tags_and_mass(tmp_path_factory):
    res = _run(tmp_path_factory, "mirror", 4)
    ev, sc = res.events, res.scene
    assert not res.errors and "Lost atoms" not in res.all_text
    tcp._check_counters(res)
    tcp._check_final_dump(res)
    # breaks on every rank; the middle row of columns (y = 0) sits on the cut
    # y = 0, so its parents straddle it (fragments made on both sides)
    per_rank = _owner_counts(ev, [0.0], [0.0])
    on_cut = _straddle_cut(ev, [0.0], "y")
    assert len(ev["step"]) >= 40 and per_rank.min() >= 8, per_rank
    assert on_cut.sum() >= 8, on_cut.sum()
    frame = tcp._frame(res, sc.nsteps)
    ids = frame["id"].astype(np.int64)
    frag = ids > len(sc.grains)
    k = (ids[frag] - len(sc.grains) - 1) // 14
    both = [np.ptp(np.sign(frame["y"][frag][k == j])) > 0 for j in np.nonzero(on_cut)[0]]
    assert sum(both) >= 3, sum(both)
    print("mirror, 4 ranks: events", len(ev["step"]), "per rank", per_rank.ravel().tolist(),
          "parents on the cut y = 0", int(on_cut.sum()),
          "of which fragments now on both sides", int(sum(both)))


def test_periodic_4_ranks_tags_and_mass(tmp_path_factory):
    res = _run(tmp_path_factory, "periodic", 4)
    ev, sc = res.events, res.scene
    assert not res.errors and "Lost atoms" not in res.all_text
    tcp._check_counters(res)
    frame = tcp._check_final_dump(res)
    (xlo, xhi), (ylo, yhi) = sc.box[0], sc.box[1]
    tol = 1e-4                       # atoms may sit outside by up to half a skin
    assert np.all((frame["x"] >= xlo - tol) & (frame["x"] <= xhi + tol))
    assert np.all((frame["y"] >= ylo - tol) & (frame["y"] <= yhi + tol))
    per_rank = _owner_counts(ev, [0.0], [0.0])
    assert per_rank.min() >= 5, per_rank
    # parents straddling the internal cuts (x = 0, y = 0) and the periodic
    # boundaries (x = xlo/xhi, y = ylo/yhi)
    sx0, sy0 = _straddle_cut(ev, [0.0], "x"), _straddle_cut(ev, [0.0], "y")
    sxp, syp = _straddle_cut(ev, [xlo, xhi], "x"), _straddle_cut(ev, [ylo, yhi], "y")
    assert (sx0 | sy0).sum() >= 3 and sxp.sum() >= 1 and syp.sum() >= 1, \
        ((sx0 | sy0).sum(), sxp.sum(), syp.sum())
    print("periodic, 4 ranks: events", len(ev["step"]), "per rank", per_rank.ravel().tolist(),
          "straddling x=0/y=0", int((sx0 | sy0).sum()), "periodic x/y", int(sxp.sum()),
          int(syp.sum()))


@pytest.mark.parametrize("name", ["mirror", "periodic"])
def test_first_events_same_at_1_and_4_ranks(tmp_path_factory, name):
    e1 = _run(tmp_path_factory, name, 1).events
    e4 = _run(tmp_path_factory, name, 4).events
    first = slice(0, N_FIRST)
    for col in ("step", "tag", "generation", "partner", "d"):
        np.testing.assert_array_equal(e4[col][first], e1[col][first], err_msg=col)
    np.testing.assert_allclose(e4["F_n"][first], e1["F_n"][first], rtol=1e-6)
    for col in ("x", "y", "z"):
        np.testing.assert_allclose(e4[col][first], e1[col][first], rtol=0, atol=1e-9)
    if name == "mirror":
        # the mirror pairs break in the same step, on ranks 0/3 or 1/2
        assert e4["step"][0] == e4["step"][1]
        assert e4["x"][0] == pytest.approx(-e4["x"][1], abs=1e-9)


# ---------------------------------------------------------------------------
# b. restart mid-crushing read at another rank count
# ---------------------------------------------------------------------------

def _frame(res, step):
    (frame,) = harness.read_dump(res.path(f"dump.{step}.txt"))
    assert frame.timestep == step
    return frame


def _thermo_row(res, step):
    i = int(np.nonzero(res.blk["Step"] == step)[0][0])
    return {c: res.blk[c][i] for c in res.blk.columns}


def _leading_same_events(ea, eb):
    """Number of leading events with the same step and parent tag."""
    n = min(len(ea["step"]), len(eb["step"]))
    same = (ea["step"][:n] == eb["step"][:n]) & (ea["tag"][:n] == eb["tag"][:n])
    return n if same.all() else int(np.argmin(same))


def _source(tmp_path_factory, nprocs):
    """The run a restarted run read its file from (uninterrupted from there on)."""
    if nprocs == 2:
        return _run(tmp_path_factory, "periodic", 1)
    return _restarted(tmp_path_factory, 2)


def _history(tmp_path_factory, res):
    """Every event of a run since step 0 (a restarted run: its source's
    events up to the restart step, then its own)."""
    R = getattr(res, "R", None)
    if R is None:
        return res.events
    nprocs = {R1: 2, R2: 4}[R]
    before = _history(tmp_path_factory, _source(tmp_path_factory, nprocs))
    keep = before["step"] <= R
    return {k: np.concatenate([v[keep], res.events[k]]) for k, v in before.items()}


@pytest.mark.parametrize("nprocs", [2, 4])
def test_restart_other_rank_count_state(tmp_path_factory, nprocs):
    """The state read back equals the writing run's at the restart step, and
    the restarted run keeps the mass balance and the atom count."""
    src = _source(tmp_path_factory, nprocs)
    res = _restarted(tmp_path_factory, nprocs)
    R, sc = res.R, res.scene
    box_l = np.array([sc.box[0][1] - sc.box[0][0], sc.box[1][1] - sc.box[1][0]])
    hist = _history(tmp_path_factory, src)
    n_before = int(np.sum(hist["step"] <= R))
    assert n_before >= 15 and len(hist["step"]) - n_before >= 10     # breaks on both sides

    a, b = _frame(src, R), _frame(res, R)
    np.testing.assert_array_equal(b["id"], a["id"])
    for col in ("type", "radius", "mass", "f_crush[1]", "f_crush[2]"):
        np.testing.assert_array_equal(b[col], a[col], err_msg=col)
    assert np.all(a["f_crush[1]"] > 0) and a["f_crush[2]"].max() >= 1
    dxy = np.column_stack([b["x"] - a["x"], b["y"] - a["y"]])
    dxy -= box_l * np.round(dxy / box_l)       # an atom may be remapped into the box
    assert np.abs(dxy).max() == 0.0 and np.array_equal(b["z"], a["z"])

    ta, tb = _thermo_row(src, R), _thermo_row(res, R)
    assert ta["crush[1]"] == n_before
    for col in ("Atoms", "crush[1]", "crush[2]", "crush[3]"):
        assert tb[col] == ta[col], col
    assert tb["crush[3]"] > 0
    assert tb["crush[4]"] == pytest.approx(ta["crush[4]"], rel=1e-14)   # summation order
    assert tb["crush[5]"] == pytest.approx(ta["crush[5]"], rel=1e-12)
    # the whole restarted run: mass balance to the initial mass, no atom lost
    blk = res.blk
    err = np.abs(blk["crush[4]"] + blk["crush[3]"] - sc.mass0) / sc.mass0
    assert err.max() <= MASS_RTOL, err.max()
    np.testing.assert_array_equal(blk["Atoms"], len(sc.grains) + blk["crush[2]"] - blk["crush[1]"])
    np.testing.assert_array_equal(blk["crush[2]"], 14 * blk["crush[1]"])
    assert not res.errors and "Lost atoms" not in res.all_text
    print(f"restart at {R}, {nprocs} ranks: events before {n_before}, mass error {err.max():.2e}")


@pytest.mark.parametrize("nprocs", [2, 4])
def test_restart_other_rank_count_continues(tmp_path_factory, nprocs):
    """After the restart: the same events as the run that wrote the file and
    ran on uninterrupted, the same strengths per tag, and the tag bookkeeping
    of the final dump."""
    src = _source(tmp_path_factory, nprocs)
    res = _restarted(tmp_path_factory, nprocs)
    R, sc = res.R, res.scene
    ea = {k: v[v_step > R] for v_step in [src.events["step"]] for k, v in src.events.items()}
    eb = res.events
    assert np.all(eb["step"] > R)
    k = N_AFTER
    assert len(ea["step"]) >= k and len(eb["step"]) >= k, (len(ea["step"]), len(eb["step"]))
    for col in ("step", "tag", "generation", "partner", "d"):
        np.testing.assert_array_equal(eb[col][:k], ea[col][:k], err_msg=col)
    np.testing.assert_allclose(eb["F_lim"][:k], ea["F_lim"][:k], rtol=1e-12)
    # forces and positions: the restarted run sums in another order
    fn = np.abs(eb["F_n"][:k] / ea["F_n"][:k] - 1).max()
    dx = max(np.abs(eb[c][:k] - ea[c][:k]).max() for c in ("x", "y", "z"))
    print(f"restart at {R}, {nprocs} ranks: first {k} events after it: "
          f"F_n rel diff {fn:.1e}, position diff {dx:.1e} m")
    assert fn < F_N_RTOL_AFTER and dx < 1e-9

    # counters at every thermo output before the k-th event after the restart
    same_until = eb["step"][k - 1]
    for step in res.blk["Step"][res.blk["Step"] < same_until]:
        ta, tb = _thermo_row(src, step), _thermo_row(res, step)
        for col in ("Atoms", "crush[1]", "crush[2]", "crush[3]"):
            assert tb[col] == ta[col], (col, step)
        assert tb["crush[4]"] == pytest.approx(ta["crush[4]"], rel=MASS_RTOL)

    # strengths and generations depend on the tag and diameter only: the same
    # for every initial grain left in both final dumps and every fragment of
    # an event the two runs share (a fragment's tag follows the event order,
    # which can differ once trajectories part: compare tags of the same parent)
    ha, hb = _history(tmp_path_factory, src), _history(tmp_path_factory, res)
    n_same = _leading_same_events(ha, hb)
    fa, fb = _frame(src, sc.nsteps), _frame(res, sc.nsteps)
    common, ia, ib = np.intersect1d(fa["id"], fb["id"], return_indices=True)
    n0 = len(sc.grains)
    keep = (common <= n0) | ((common - n0 - 1) // 14 < n_same)
    ia, ib = ia[keep], ib[keep]
    assert len(ia) >= 0.5 * max(len(fa), len(fb)), (len(ia), len(fa))
    for col in ("radius", "f_crush[1]", "f_crush[2]"):
        np.testing.assert_array_equal(fb[col][ib], fa[col][ia], err_msg=col)
    print(f"  events the same as the writing run after the restart: "
          f"{n_same - int(np.sum(ha['step'] <= R))} of {len(eb['step'])}; "
          f"tags compared at the end {len(ia)} of {len(fb)}; "
          f"final events {len(ha['step'])} / {len(hb['step'])}")

    # tag bookkeeping of the restarted run's final dump against every event
    # since step 0
    own = res.events
    res.events = _history(tmp_path_factory, res)
    try:
        tcp._check_final_dump(res)
    finally:
        res.events = own


def test_restart_with_another_seed_is_an_error(tmp_path_factory):
    """Strengths are keyed by the seed: continuing with another one mixes two
    draws in one run.  Like the Br settings, a changed seed is an error
    naming 'seed' (accepted silently before the check in restart())."""
    src = _run(tmp_path_factory, "periodic", 1)
    workdir = tmp_path_factory.mktemp("restart_other_seed")
    scene = cm.compression_scene(workdir, **SCENES["periodic"])
    deck = restart_deck(scene.deck, "restart.bin", "* 1 1", 0)
    assert f"seed {cm.SEED_FIX}" in deck
    deck = deck.replace(f"seed {cm.SEED_FIX}", "seed 15485867")      # another prime
    (workdir / "restart.bin").write_bytes(src.path(f"restart.{R1}.bin").read_bytes())
    res = harness.run_deck(deck, workdir, nprocs=1, timeout=120, extra_args=cm.MESH_ARGS)
    assert res.returncode != 0 and any("seed" in e for e in res.errors), res.summary()
