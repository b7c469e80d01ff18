# SPDX-License-Identifier: GPL-2.0-or-later
"""Stock decks run as in stock (issue 42 item 1; docs/liggghts-patches.md).

Every deck of LIGGGHTS 3.8's own tutorials (examples/LIGGGHTS/Tutorials_public
of the source that scripts/setup unpacks) is run with Debian's stock binary
(/usr/bin/liggghts, package `liggghts`, installed by scripts/setup; another
one with LIGGGHTS_STOCK_BIN) and with this build (LIGGGHTS_BIN), each in its
own copy of the tutorial folder, twice: with the deck's own `thermo_modify
lost ignore` and with `lost error` instead (`thermo_modify lost error` also
added after every thermo_style, for the decks that set nothing and so run
under LIGGGHTS' default, ignore). The Atoms column and every other thermo
column must agree at every thermo row, the steps of the rows must be the
same, and both runs must end the same way (exit status, ERROR lines).

The independent answer is the stock binary itself: Debian builds the same
LIGGGHTS 3.8.0 sources, so whatever this build's changes to those sources
(cmake/PrepareLiggghtsSource.cmake) do to a stock deck shows here.

Changes made to every deck, the same for both binaries:
* `thermo_modify format float %.17g` after every thermo_style, so that the
  columns are compared to the last bit rather than to the 8 digits of the
  default format;
* run lengths lowered, so that the whole test takes a few minutes on two
  cores: every `run N` with N > 1 becomes floor(s N) (s per deck below;
  `upto` targets scale with it), or a variable that sets the run length is
  lowered (ts_move, growts, nStepsRun). Each deck still reaches the
  insertions after its first (the three decks that showed the defect of the
  earlier comm.cpp patch, conveyor, insert_stream and chute_wear, differed
  from their first thermo rows on, and stopped with "Lost atoms" under
  `lost error` at their first insertion).

Tolerance: rtol 1e-10. Both binaries are GCC 12 builds of the same sources
for x86-64 (SSE2 arithmetic, no fused multiply-add without -mfma), so they
do the same floating-point operations in the same order: measured, every
column of every deck agrees to all 17 digits (the test prints the largest
relative difference it saw). 1e-10 leaves room for another libm or compiler
version, while a real change of behaviour shows in the first digits (an atom
count, a force, an energy). The CPU column (wall-clock time) is not compared.
"""

import math
import os
import re
import shutil
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import harness  # noqa: E402
from harness import REPO  # noqa: E402

TUTORIALS = REPO / "deps" / "LIGGGHTS-PUBLIC-3.8.0" / "examples" / "LIGGGHTS" / "Tutorials_public"
STOCK_BIN = Path(os.environ.get("LIGGGHTS_STOCK_BIN", "/usr/bin/liggghts"))
RTOL = 1e-10
NOT_COMPARED = {"CPU"}       # wall-clock seconds
TIMEOUT = 300


class Deck:
    """One tutorial input: folder/name, run-length scale s, the values of
    the variables that some `run ${name}` commands use (scaled there, while
    the variable keeps its value elsewhere: e.g. hydrogel's piston speed is
    the stroke over ts_move), text replacements (exact text of the deck ->
    new text),
    decks to run first in the same folder (a restart file they write), the
    number of ranks, why stock LIGGGHTS cannot run it (None: it can), and
    the -var values the deck asks for."""

    def __init__(self, path, scale=1.0, replace=(), before=(), nprocs=1, stock_fails=None,
                 include_only=False, variables=None, run_vars=None):
        self.path = path
        self.folder, self.name = path.rsplit("/", 1)
        self.scale = scale
        self.replace = tuple(replace)
        self.before = tuple(before)
        self.nprocs = nprocs
        self.stock_fails = stock_fails
        self.include_only = include_only
        self.variables = dict(variables or {})
        self.run_vars = dict(run_vars or {})

    def __repr__(self):
        return self.path


DECKS = [
    Deck("chute_wear/in.chute_wear", 0.1),
    Deck("cohesion/in.cohesion", 0.1),
    Deck("cohesion/in.noCohesion", 0.1),
    Deck("contactModels/in.newModels", 0.1),
    # the pair style syntax of LIGGGHTS 2 (pair_style gran/hertz/history)
    Deck("contactModels/in.oldModels", 0.1, stock_fails="Invalid pair style"),
    Deck("conveyor/in.conveyor", 0.2),
    Deck("heatTransfer_1/in.heatGran", 0.1),
    Deck("heatTransfer_2/in.heatGran", 0.1),
    Deck("hydrogel_multicontact/in.hydrogel_default", 0.05, run_vars={"ts_move": 30000}),
    # the multicontact model costs about 16 ms a step here
    Deck("hydrogel_multicontact/in.hydrogel_multicontact", 40 / 30000.0,
         run_vars={"ts_move": 30000}),
    Deck("hysteresis/in.hysteresis", 0.1),
    Deck("hysteresis/in.noHysteresis", 0.1),
    Deck("insert_stream/in.insert_stream", 0.1),
    Deck("insert_stream/in.insert_stream_reset_timestep", 0.05,
         before=["in.insert_stream"]),
    Deck("meshGran/in.meshGran", 0.1),
    Deck("mesh_tet/in.mesh_tet", 0.2),
    Deck("movingMeshGran/in.movingMeshGran", 0.05),
    Deck("multisphere_stone_restitution/in.multisphere", 0.5),
    Deck("packing/in.packing", 0.1, run_vars={"growts": 50000, "relaxts": 20000}),
    Deck("sph_1/in.sph_1", 0.005),
    Deck("sph_2/in.sph_2", 0.005),
    # Debian's build (and this one) leave out the superquadric particles
    Deck("superquadric/in.particle_particle", 1.0,
         replace=[("variable nStepsRun    equal 1.0/${dt}",
                   "variable nStepsRun    equal 0.03/${dt}")],
         variables={"blockiness1": 2, "blockiness2": 2, "angle": 0},
         stock_fails="Invalid atom style"),
    # ParScale: in.DEM holds the variables the two others include; in.pascal
    # are inputs of ParScale itself (a separate program), not LIGGGHTS decks
    Deck("ParScale/fluidizedBedTempParScale/in.DEM", include_only=True),
    Deck("ParScale/fluidizedBedTempParScale/pascal/in.pascal", include_only=True),
    Deck("ParScale/heatTransferBed_paScal/pascal/in.pascal", include_only=True),
    Deck("ParScale/fluidizedBedTempParScale/in.liggghts_init", 0.05),
    # needs the ParScale coupling library, which neither binary has
    Deck("ParScale/fluidizedBedTempParScale/in.liggghts_run", nprocs=2,
         before=["in.liggghts_init"], stock_fails='Invalid fix style: "couple/pascal"'),
    Deck("ParScale/heatTransferBed_paScal/in.liggghts", 0.05,
         stock_fails="invalid radius random style"),
]
BY_PATH = {d.path: d for d in DECKS}
RUNNABLE = [d for d in DECKS if not d.include_only]


def _require_inputs():
    if not TUTORIALS.is_dir():
        pytest.fail("LIGGGHTS tutorials not found at %s: run scripts/setup" % TUTORIALS)
    if not (STOCK_BIN.is_file() and os.access(str(STOCK_BIN), os.X_OK)):
        pytest.fail("stock LIGGGHTS not found at %s: run scripts/setup (installs Debian's "
                    "package liggghts), or set LIGGGHTS_STOCK_BIN" % STOCK_BIN)


# --------------------------------------------------------------------------
# deck text
# --------------------------------------------------------------------------

_RUN = re.compile(r"^(\s*run\s+)(\d+|\$\{(\w+)\})(\s.*)?$")


def _after_thermo_style(lines, extra):
    """Insert `extra` after every thermo_style command (and its continuation lines)."""
    out, i = [], 0
    while i < len(lines):
        line = lines[i]
        out.append(line)
        if line.split()[:1] == ["thermo_style"]:
            while line.rstrip().endswith("&") and i + 1 < len(lines):
                i += 1
                line = lines[i]
                out.append(line)
            out.append(extra)
        i += 1
    return out


def rewrite(text, deck, lost):
    """A deck's text as this test runs it (see the module's docstring)."""
    for old, new in deck.replace:
        assert old in text, (deck, old)
        text = text.replace(old, new)
    lines = []
    for line in text.splitlines():
        m = _RUN.match(line)
        if m and (m.group(3) is None or m.group(3) in deck.run_vars):
            n = deck.run_vars[m.group(3)] if m.group(3) else int(m.group(2))
            if n > 1 and deck.scale != 1.0:
                n = max(1, int(math.floor(n * deck.scale)))
            line = "%s%d%s" % (m.group(1), n, m.group(4) or "")
        lines.append(line)
    lines = _after_thermo_style(lines, "thermo_modify\tformat float %.17g")
    if lost == "error":
        lines = [re.sub(r"\blost\s+ignore\b", "lost error", ln) for ln in lines]
        lines = _after_thermo_style(lines, "thermo_modify\tlost error")
    return "\n".join(lines) + "\n"


def deck_text(deck, lost):
    return rewrite((TUTORIALS / deck.folder / deck.name).read_text(), deck, lost)


# --------------------------------------------------------------------------
# running
# --------------------------------------------------------------------------

class Run:
    def __init__(self, workdir, rc, log, out):
        self.workdir, self.rc, self.log, self.out = workdir, rc, log, out

    @property
    def errors(self):
        """ERROR lines of the log (or, when the log has none, of the output),
        without the '(file:line)' suffix, whose path differs between builds."""
        src = self.log if "ERROR" in self.log else self.out
        return [re.sub(r"\s*\([^()]*:\d+\)\s*$", "", ln.strip())
                for ln in src.splitlines() if ln.strip().startswith("ERROR")]

    def tail(self, n=25):
        return "%s: exit %s\n%s" % (self.workdir, self.rc,
                                    "\n".join((self.log or self.out).splitlines()[-n:]))


def _env():
    env = dict(os.environ)
    env.update(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1", OMP_NUM_THREADS="1")
    return env


def _run_one(binary, workdir, name, nprocs, variables):
    log = "log." + name
    cmd = harness.mpirun_cmd(nprocs) + [str(binary), "-in", name, "-log", log]
    for k, v in variables.items():
        cmd += ["-var", str(k), str(v)]
    try:
        p = subprocess.run(cmd, cwd=str(workdir), env=_env(), stdin=subprocess.DEVNULL,
                           stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=TIMEOUT,
                           universal_newlines=True, errors="replace")
        rc, out = p.returncode, p.stdout
    except subprocess.TimeoutExpired as exc:
        rc, out = "timeout", (exc.stdout or b"").decode(errors="replace") if isinstance(
            exc.stdout, bytes) else (exc.stdout or "")
    logp = workdir / log
    text = logp.read_text(errors="replace") if logp.exists() else ""
    return Run(workdir, rc, text, out)


def run_deck(binary, deck, lost, workdir):
    """Copy the deck's folder to `workdir`, write the decks as this test runs
    them, run the decks it needs first and then the deck itself."""
    shutil.copytree(str(TUTORIALS / deck.folder), str(workdir))
    (workdir / "post").mkdir(exist_ok=True)
    for name in deck.before:
        (workdir / name).write_text(deck_text(BY_PATH[deck.folder + "/" + name], lost))
    (workdir / deck.name).write_text(deck_text(deck, lost))
    for name in deck.before:
        before = BY_PATH[deck.folder + "/" + name]
        first = _run_one(binary, workdir, name, before.nprocs, before.variables)
        if first.rc != 0:
            return first
    return _run_one(binary, workdir, deck.name, deck.nprocs, deck.variables)


def run_both(deck, lost, tmp_path):
    jobs = [(STOCK_BIN, tmp_path / "stock"), (harness.liggghts_bin(), tmp_path / "build")]
    with ThreadPoolExecutor(max_workers=2) as pool:
        futures = [pool.submit(run_deck, b, deck, lost, w) for b, w in jobs]
        return [f.result() for f in futures]


# --------------------------------------------------------------------------
# comparing
# --------------------------------------------------------------------------

def compare(stock, build, label):
    """Problems found between the two runs (empty: the same), and the largest
    relative difference of the compared values."""
    problems = []
    if stock.rc != build.rc:
        problems.append("exit status: stock %s, this build %s" % (stock.rc, build.rc))
    if stock.errors != build.errors:
        problems.append("ERROR lines: stock %s, this build %s" % (stock.errors, build.errors))
    a_blocks, b_blocks = harness.parse_thermo(stock.log), harness.parse_thermo(build.log)
    if len(a_blocks) != len(b_blocks):
        problems.append("thermo blocks: stock %d, this build %d" % (len(a_blocks), len(b_blocks)))
    worst = 0.0
    for k, (a, b) in enumerate(zip(a_blocks, b_blocks)):
        if a.columns != b.columns:
            problems.append("block %d columns: %s against %s" % (k, a.columns, b.columns))
            continue
        sa, sb = a["Step"], b["Step"]
        if len(sa) != len(sb) or np.any(sa != sb):
            problems.append("block %d steps: stock %s, this build %s" % (k, sa.tolist(), sb.tolist()))
        n = min(len(sa), len(sb))
        for col in a.columns:
            if col in NOT_COMPARED:
                continue
            x, y = a[col][:n], b[col][:n]
            same = (x == y) | np.isclose(y, x, rtol=RTOL, atol=0.0)
            with np.errstate(divide="ignore", invalid="ignore"):
                rel = np.where(x == y, 0.0, np.abs(y - x) / np.maximum(np.abs(x), np.abs(y)))
            if n:
                worst = max(worst, float(np.nanmax(rel)))
            if not np.all(same):
                i = int(np.argmin(same))
                problems.append("block %d column %s differs from step %d on: stock %r, this build %r"
                                % (k, col, int(sa[i]), x[i], y[i]))
    if not any(len(b) for b in a_blocks):
        problems.append("no thermo rows in the stock run")
    # the end-of-run statistics (Finish, where finish.cpp is changed to compile)
    sa, sb = _finish_lines(stock.log), _finish_lines(build.log)
    if sa != sb:
        problems.append("end-of-run lines: stock %s, this build %s" % (sa[:6], sb[:6]))
    return problems, worst


_FINISH = re.compile(r"^(Loop time of \S+ on \d+ procs for .*|Total # of neighbors = .*|"
                     r"Ave neighs/atom = .*|Neighbor list builds = .*|Dangerous builds = .*)$")


def _finish_lines(log):
    """The lines of the end-of-run statistics that do not depend on timing."""
    out = []
    for line in log.splitlines():
        if _FINISH.match(line.strip()):
            out.append(re.sub(r"^Loop time of \S+ ", "Loop time of * ", line.strip())
                       .split(", finish time")[0])
    return out


# --------------------------------------------------------------------------
# tests
# --------------------------------------------------------------------------

def test_every_tutorial_deck_is_listed():
    """No tutorial deck is left out silently: the list above is the folder's."""
    _require_inputs()
    found = sorted(str(p.relative_to(TUTORIALS)) for p in TUTORIALS.rglob("in.*") if p.is_file())
    assert found == sorted(BY_PATH), (found, sorted(BY_PATH))


def test_rewrite_changes_only_run_lengths_format_and_lost():
    """The rewriting itself, on a small deck with known answers."""
    text = ("variable n equal 30000\nthermo_style custom step &\n  atoms\n"
            "thermo_modify lost ignore norm no\nrun 1\nrun 15000 upto\nrun\t\t999 # c\n"
            "run ${n}\nrun ${m} upto\nrun 0\n")
    deck = Deck("x/in.x", 0.1, replace=[("equal 30000", "equal 40")], run_vars={"n": 30000})
    assert rewrite(text, deck, "ignore").splitlines() == [
        "variable n equal 40", "thermo_style custom step &", "  atoms",
        "thermo_modify\tformat float %.17g", "thermo_modify lost ignore norm no",
        "run 1", "run 1500 upto", "run\t\t99 # c", "run 3000", "run ${m} upto", "run 0"]
    assert rewrite(text, deck, "error").splitlines()[3:6] == [
        "thermo_modify\tlost error", "thermo_modify\tformat float %.17g",
        "thermo_modify lost error norm no"]
    with pytest.raises(AssertionError):
        rewrite(text, Deck("x/in.x", replace=[("not there", "")]), "ignore")


@pytest.mark.parametrize("lost", ["ignore", "error"])
@pytest.mark.parametrize("deck", RUNNABLE, ids=lambda d: d.path)
def test_tutorial_runs_as_with_stock_liggghts(deck, lost, tmp_path):
    _require_inputs()
    if deck.stock_fails:
        stock = run_deck(STOCK_BIN, deck, lost, tmp_path / "stock")
        assert stock.rc != 0 and any(deck.stock_fails in e for e in stock.errors), (
            "stock LIGGGHTS was expected to stop with %r:\n%s" % (deck.stock_fails, stock.tail()))
        pytest.skip("stock LIGGGHTS cannot run it: %s" % stock.errors[0])
    stock, build = run_both(deck, lost, tmp_path)
    assert stock.rc == 0, "stock LIGGGHTS failed on a deck it is expected to run:\n" + stock.tail()
    problems, worst = compare(stock, build, deck.path)
    rows = sum(len(b) for b in harness.parse_thermo(stock.log))
    print("%s, lost %s: %d thermo rows, exit %s, largest relative difference %.3g"
          % (deck.path, lost, rows, stock.rc, worst))
    assert not problems, "%s, lost %s:\n  %s\n--- stock ---\n%s\n--- this build ---\n%s" % (
        deck.path, lost, "\n  ".join(problems[:8]), stock.tail(), build.tail())
