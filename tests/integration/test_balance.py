# SPDX-License-Identifier: GPL-2.0-or-later
"""Deck-level tests of the command `balance/grains` (static load balancing,
issue 13 item 1; docs/balance_grains.md).

a. Counts. Grains at rest (no gravity, no contacts: random sequential
   addition with gaps) with a strongly non-uniform density along the split
   axes: falling along x (1 - 0.8 x/L before the addition flattens it) at 2
   and 4 ranks (`* 1 1`), along x and y at 4 ranks (`2 2 1`), and two
   chamber-like packings at 4 ranks: a quarter cylinder (sector 90) cut in
   x slabs (`4 1 1`), and a full cylinder whose sand fills the lower half of
   a box twice as tall (the pile's shaft above it) cut in z slabs (`1 1 4`:
   uniform cuts leave two ranks empty). Uniform cuts give max/mean > 1.1
   (shown from the log before the command acts); after `balance/grains`
   every rank holds within 10 % of the mean. The per-rank counts the
   command writes (`out`) equal the counts of the grains' data-file
   positions in the grid cells of the cuts it prints (numpy, independent of
   LIGGGHTS), so every grain ended on the rank that owns its position; after
   a run they are the same (the run's set-up found every grain in place).
b. Rank independence. A compression by a mesh platen (crush_multi's scene
   with the columns of test_crush_parallel's "small" case) in a box that
   extends far beyond the grains on the +x side, so that uniform cuts leave
   ranks empty and balancing moves the cuts by up to two sub-domains: the
   platen's two triangles (centres at x = -L/3 and +L/3) change ranks, one
   exchange step per sub-domain. The deck balances after `run 0` and again
   mid-way; the first 10 breakage events (steps, tags, generations,
   partners, diameters exactly; forces to 1e-6, positions to 1e-9 m) are
   those of the same deck at 1 rank, at 2 and 4 ranks.
c. Restart. LIGGGHTS 3.8's read_restart sets uniform cuts again (it calls
   Comm::set_proc_grid): a balanced run written to a restart file and read
   back is imbalanced until the deck calls balance/grains again, which
   restores the same cuts and counts.
d. One rank: a cheap no-op that says so. Bad keywords: errors naming the
   keyword and the allowed values.
"""

import math
import re
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import crush_multi as cm  # noqa: E402
import harness  # noqa: E402

D_MIN, D_MAX = 8e-4, 1.2e-3
BOX = ((0.0, 0.040), (0.0, 0.012), (0.0, 0.012))
N_GRAINS = 1200

LINE_RE = re.compile(
    r"balance/grains: grains per rank before min/mean/max (\d+)/([\d.]+)/(\d+) "
    r"\(max/mean ([\d.]+)\), after min/mean/max (\d+)/([\d.]+)/(\d+) \(max/mean ([\d.]+)\)")
KEPT_RE = re.compile(r"balance/grains: grains per rank min/mean/max (\d+)/([\d.]+)/(\d+) "
                     r"\(max/mean ([\d.]+)\): within thresh")
CUTS_RE = re.compile(r"cuts \(fractions of the box\):(.*)")


def rsa_grains(n, box, density, seed):
    """n grains (x, y, z, d) placed one by one at random where they keep a
    gap of 5 % of the larger diameter to every other grain; position drawn
    from `density(u)` (u: fractions of the box, rejection sampling)."""
    rng = np.random.RandomState(seed)
    lo = np.array([b[0] for b in box]) + 0.6 * D_MAX
    hi = np.array([b[1] for b in box]) - 0.6 * D_MAX
    pos = np.zeros((n, 3))
    dia = np.zeros(n)
    k = 0
    while k < n:
        u = rng.uniform(size=3)
        if rng.uniform() > density(u):
            continue
        p = lo + u * (hi - lo)
        d = rng.uniform(D_MIN, D_MAX)
        if k:
            dist = np.linalg.norm(pos[:k] - p, axis=1)
            if np.any(dist < 1.05 * np.maximum(dia[:k], d) ):
                continue
        pos[k], dia[k] = p, d
        k += 1
    return np.column_stack([pos, dia])


def still_deck(processors, balance_args="", restart=None):
    """Grains at rest: balance, run 100 steps, report the counts again."""
    return cm.header(processors=processors) + f"""\
timestep        1e-7
fix integ all nve
thermo_style    custom step atoms
thermo_modify   lost error
run 0
balance/grains {balance_args} out balance.txt
run 100
balance/grains {balance_args}
""" + (f"write_restart {restart}\n" if restart else "")


def counts_in_cells(grains, box, cuts):
    """Grains in each cell of the tensor-product cuts {dim: fractions}
    (half-open cells, as LIGGGHTS assigns them), sorted."""
    idx = []
    for d in range(3):
        lo, hi = box[d]
        f = (grains[:, d] - lo) / (hi - lo)
        s = cuts.get(d, [0.0, 1.0])
        idx.append(np.clip(np.searchsorted(s, f, side="right") - 1, 0, len(s) - 2))
    shape = tuple(len(cuts.get(d, [0.0, 1.0])) - 1 for d in range(3))
    flat = np.ravel_multi_index(idx, shape)
    return np.sort(np.bincount(flat, minlength=int(np.prod(shape))))


def parse_cuts(log):
    (text,) = CUTS_RE.findall(log)[:1]
    cuts = {}
    for dim, vals in re.findall(r"([xyz]):((?: [-+\d.eE]+)+)", text):
        cuts["xyz".index(dim)] = [float(v) for v in vals.split()]
    return cuts


def read_out(path):
    rows = [l.split() for l in Path(path).read_text().splitlines() if l and l[0] != "#"]
    return [(int(r[0]), float(r[1]), float(r[2]), np.array([float(v) for v in r[3:]])) for r in rows]


# --------------------------------------------------------------------------
# a. counts within 10 % of the mean
# --------------------------------------------------------------------------

DENSITY_X = (lambda u: 1.0 - 0.8 * u[0])
DENSITY_XY = (lambda u: (1.0 - 0.8 * u[0]) * (1.0 - 0.8 * u[1]))
# chamber-like: a quarter cylinder (sector 90) of radius 20 mm in a box of
# 20 x 20 x 10 mm, and a full cylinder of radius 10 mm and 12 mm of sand in a
# box twice as tall (the pile's shaft above the sand)
BOX_QUARTER = ((0.0, 0.020), (0.0, 0.020), (0.0, 0.010))
QUARTER = (lambda u: float(u[0] ** 2 + u[1] ** 2 <= 1.0))
BOX_TALL = ((-0.010, 0.010), (-0.010, 0.010), (0.0, 0.024))
TALL = (lambda u: float((2 * u[0] - 1) ** 2 + (2 * u[1] - 1) ** 2 <= 1.0 and u[2] <= 0.5))

COUNT_CASES = {
    # name: ranks, processors, box, density (uniform cuts give max/mean
    # 1.15 to 2.1 on these packings; the test asks for > 1.1)
    "x_2": (2, "* 1 1", BOX, DENSITY_X),
    "x_4": (4, "* 1 1", BOX, DENSITY_X),
    "xy_4": (4, "2 2 1", BOX, DENSITY_XY),
    "quarter_4": (4, "4 1 1", BOX_QUARTER, QUARTER),
    "tall_4": (4, "1 1 4", BOX_TALL, TALL),
}


@pytest.mark.parametrize("case", sorted(COUNT_CASES))
def test_counts_within_10_percent(tmp_path, case):
    nprocs, processors, box, density = COUNT_CASES[case]
    grains = rsa_grains(N_GRAINS, box, density, seed=2027)
    cm.write_data(tmp_path / "grains.data", grains, box)
    res = harness.run_deck(still_deck(processors), tmp_path, nprocs=nprocs, check=True,
                           timeout=120)
    m = LINE_RE.search(res.log)
    assert m, res.summary()
    mean = N_GRAINS / nprocs
    # uniform cuts: far from balanced (the scene is a test of something)
    assert float(m.group(4)) > 1.1, m.group(0)
    # balanced: every rank within 10 % of the mean
    after = [float(m.group(k)) for k in (5, 6, 7)]
    assert after[1] == pytest.approx(mean)
    assert after[0] >= 0.9 * mean and after[2] <= 1.1 * mean, m.group(0)
    # the command's per-rank counts are those of the positions in the cells
    # of its cuts: every grain is on the rank that owns its position
    ((step, imb0, imb1, per_rank),) = read_out(res.path("balance.txt"))
    assert step == 0 and imb1 == pytest.approx(max(per_rank) / mean, abs=1e-6)
    cuts = parse_cuts(res.log)
    np.testing.assert_array_equal(np.sort(per_rank), counts_in_cells(grains, box, cuts))
    # after a run with them: the same counts, within the threshold, cuts kept
    k = KEPT_RE.search(res.log)
    assert k, res.summary()
    assert [float(k.group(i)) for i in (1, 3)] == [after[0], after[2]]


# --------------------------------------------------------------------------
# b. the same first breakage events at 1, 2 and 4 ranks, balanced
# --------------------------------------------------------------------------

N_FIRST = 10
SMALL = dict(nx=4, ny=2, height=0.006, dmin=6e-4, dmax=1.2e-3, nsteps=21000,
             var=0.0, mirror=True, thermo=250)
N_BEFORE_SECOND = 16500    # second balance/grains: after 4 events, before the 10th


def _events_scene(workdir):
    scene = cm.compression_scene(workdir, processors="* 1 1", **SMALL)
    # the box extends 3 L beyond the grains on the +x side: uniform cuts
    # leave the grains on the first ranks and the platen's triangles
    # (centres at -L/3, +L/3) on rank 0 or 1
    (xlo, xhi), yb, zb = scene.box
    box = ((xlo, xhi + 3.0 * (xhi - xlo)), tuple(yb), tuple(zb))
    cm.write_data(Path(workdir) / "grains.data", scene.grains, box)
    deck = scene.deck.replace(
        f"run             {SMALL['nsteps']}\n",
        "run 0\nbalance/grains out balance.txt\n"
        f"run {N_BEFORE_SECOND}\nbalance/grains thresh 1 out balance.txt\n"
        f"run {SMALL['nsteps'] - N_BEFORE_SECOND}\n")
    assert deck != scene.deck
    return scene, deck


_EVENT_RUNS = {}


def _events_run(tmp_path_factory, nprocs):
    if nprocs not in _EVENT_RUNS:
        wd = tmp_path_factory.mktemp(f"events_np{nprocs}")
        scene, deck = _events_scene(wd)
        res = harness.run_deck(deck, wd, nprocs=nprocs, timeout=600, check=True,
                               extra_args=cm.MESH_ARGS)
        res.events = cm.read_events(wd / "events.txt")
        res.scene = scene
        _EVENT_RUNS[nprocs] = res
    return _EVENT_RUNS[nprocs]


@pytest.mark.parametrize("nprocs", [2, 4])
def test_first_events_same_at_1_and_balanced_ranks(tmp_path_factory, nprocs):
    r1 = _events_run(tmp_path_factory, 1)
    rn = _events_run(tmp_path_factory, nprocs)
    assert "balance/grains: 1 rank, nothing to balance" in r1.log
    # the balancing moved the cuts a long way: imbalance before >= 2 (ranks
    # without grains), after close to 1; the mesh moved in exchange steps
    out = read_out(rn.path("balance.txt"))
    assert out[0][0] == 0 and out[0][1] >= 2.0 and out[0][2] < 1.1, out
    steps = [int(v) for v in re.findall(r"\((\d+) mesh exchange step\(s\)\)", rn.log)]
    if nprocs == 2:
        # the cut moves from 0.5 to 0.125 of the box: one step
        assert steps[0] == 1, rn.summary()
    else:
        # cuts from 0.25, 0.5, 0.75 to about 0.06, 0.125, 0.19: the last one
        # passes two old cuts, three steps; mid-way, after 4 breaks, the
        # fragments have moved the counts off and the cuts move again
        assert steps[0] == 3, rn.summary()
        assert len(out) == 2 and out[1][0] == N_BEFORE_SECOND and out[1][1] > 1.0, out
    e1, en = r1.events, rn.events
    assert len(e1["step"]) >= N_FIRST and e1["step"][N_FIRST - 1] > N_BEFORE_SECOND
    first = slice(0, N_FIRST)
    for col in ("step", "tag", "generation", "partner", "d"):
        np.testing.assert_array_equal(en[col][first], e1[col][first], err_msg=col)
    for col in ("F_n", "F_lim"):
        np.testing.assert_allclose(en[col][first], e1[col][first], rtol=1e-6)
    for col in ("x", "y", "z"):
        np.testing.assert_allclose(en[col][first], e1[col][first], rtol=0, atol=1e-9)
    # and both sides of the original x = 0 split break
    assert np.any(en["x"][first] < 0) and np.any(en["x"][first] > 0)


# --------------------------------------------------------------------------
# b2. a mesh wall across cuts that move by more than one sub-domain
# --------------------------------------------------------------------------

def write_strip_stl(path, box, n):
    """The plane z = box z-lo as a strip of 2 n triangles along x."""
    (xlo, xhi), (ylo, yhi), (z, _) = box
    xs = np.linspace(xlo, xhi, n + 1)
    out = ["solid strip"]
    for a, b in zip(xs[:-1], xs[1:]):
        for tri in (((a, ylo), (b, ylo), (b, yhi)), ((a, ylo), (b, yhi), (a, yhi))):
            out += ["facet normal 0 0 1", "outer loop"]
            out += [f"vertex {x!r} {y!r} {z!r}" for x, y in tri]
            out += ["endloop", "endfacet"]
    out.append("endsolid strip")
    Path(path).write_text("\n".join(out) + "\n")


def test_mesh_wall_across_moved_cuts(tmp_path_factory):
    """Grains only in the first quarter of the box in x, falling at 2 m/s
    onto a plate of 32 triangles spanning the box, at 4 ranks (`* 1 1`).
    Uniform cuts put every grain on rank 0 and 8 triangles on each rank;
    balancing puts all four sub-domains into the first quarter, so the
    triangles of ranks 1 and 2 move two and one ranks (LIGGGHTS moves mesh
    elements to neighbour ranks only: the command moves the cuts in steps).
    The grains do not touch each other (gaps of 5 %), so each bounces off
    the plate on its own: the plate's force at every thermo output equals
    that of the same deck at 1 rank to round-off of the sum."""
    box = ((0.0, 0.040), (0.0, 0.012), (-0.0002, 0.012))
    grains = rsa_grains(400, ((0.0, 0.010), (0.0, 0.012), (0.0, 0.012)),
                        lambda u: 1.0, seed=2029)
    dt = 0.15 * cm.rayleigh_time(0.5 * D_MIN)
    results = {}
    for nprocs in (1, 4):
        wd = tmp_path_factory.mktemp(f"mesh_np{nprocs}")
        cm.write_data(wd / "grains.data", grains, box, vz=-2.0)
        write_strip_stl(wd / "plate.stl", box, 16)
        deck = cm.header(processors="* 1 1") + f"""\
timestep        {dt!r}
fix plate all mesh/surface/stress file plate.stl type 2
fix walls all wall/gran model hertz tangential history mesh n_meshes 1 meshes plate
fix integ all nve
thermo_style    custom step atoms f_plate[3]
thermo_modify   format float %.17g lost error norm no
thermo          50
run 0
balance/grains out balance.txt
run 4000
"""
        res = harness.run_deck(deck, wd, nprocs=nprocs, check=True, timeout=300,
                               extra_args=cm.MESH_ARGS)
        results[nprocs] = res
    r4 = results[4]
    m = LINE_RE.search(r4.log)
    assert m and float(m.group(4)) == pytest.approx(4.0) and float(m.group(8)) < 1.1, r4.summary()
    assert "(3 mesh exchange step(s))" in r4.log, r4.summary()
    f1 = results[1].thermo[-1]["f_plate[3]"]
    f4 = r4.thermo[-1]["f_plate[3]"]
    assert np.max(np.abs(f1)) > 0.0          # the grains hit the plate
    np.testing.assert_allclose(f4, f1, rtol=1e-9, atol=1e-12 * np.max(np.abs(f1)))


# --------------------------------------------------------------------------
# c. restart: read_restart makes the cuts uniform; the deck balances again
# --------------------------------------------------------------------------

def test_restart_recomputes_the_cuts(tmp_path):
    grains = rsa_grains(N_GRAINS, BOX, DENSITY_X, seed=2027)
    cm.write_data(tmp_path / "grains.data", grains, BOX)
    first = harness.run_deck(still_deck("* 1 1", restart="restart.bin"), tmp_path, nprocs=2,
                             check=True, timeout=120)
    m1 = LINE_RE.search(first.log)
    cuts1 = parse_cuts(first.log)
    deck = cm.header(processors="* 1 1").replace("read_data       grains.data",
                                                "read_restart    restart.bin") + """\
timestep        1e-7
fix integ all nve
thermo_style    custom step atoms
thermo_modify   lost error
run 0
balance/grains out balance2.txt
run 100
"""
    res = harness.run_deck(deck, tmp_path, nprocs=2, check=True, timeout=120)
    m2 = LINE_RE.search(res.log)
    assert m2, res.summary()
    # read back with uniform cuts: imbalanced as before the first balancing
    assert float(m2.group(4)) == pytest.approx(float(m1.group(4)), abs=1e-4)
    # balanced again: the same cuts and the same counts
    assert parse_cuts(res.log) == cuts1
    assert m2.group(5, 7) == m1.group(5, 7)


# --------------------------------------------------------------------------
# d. one rank, bad input
# --------------------------------------------------------------------------

def test_one_rank_is_a_no_op(tmp_path):
    grains = rsa_grains(200, BOX, DENSITY_X, seed=2027)
    cm.write_data(tmp_path / "grains.data", grains, BOX)
    res = harness.run_deck(still_deck("* 1 1"), tmp_path, nprocs=1, check=True, timeout=60)
    assert res.log.count("balance/grains: 1 rank, nothing to balance") == 2
    assert not res.path("balance.txt").exists()


@pytest.mark.parametrize("args,pattern", [
    ("dim w", "keyword 'dim' must be 'x', 'y', 'z', 'xy', 'xz', 'yz' or 'xyz', got 'w'"),
    ("bins 5", "keyword 'bins'"),
    ("thresh 0.5", "keyword 'thresh'"),
    ("group nosuch", "group 'nosuch' does not exist"),
    ("foo 1", "foo"),
])
def test_bad_keywords(tmp_path, args, pattern):
    grains = rsa_grains(50, BOX, DENSITY_X, seed=2027)
    cm.write_data(tmp_path / "grains.data", grains, BOX)
    deck = cm.header(processors="* 1 1") + f"balance/grains {args}\n"
    res = harness.expect_error(deck, tmp_path, pattern, nprocs=1, timeout=60)
    assert "balance/grains" in "\n".join(res.errors)
