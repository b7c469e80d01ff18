# SPDX-License-Identifier: GPL-2.0-or-later
"""Lost atoms (issue 5 item 6, issue 42 item 1).

a. A plain deck (no fix crush/particle) runs exactly as with stock LIGGGHTS
   (docs/liggghts-patches.md): a grain that leaves the box through a fixed
   boundary stops the run with stock's "Lost atoms" under the settings of
   inputs/base.in, and also after a later thermo_style followed by
   `thermo_modify lost error`; without the latter the grain vanishes silently
   (LIGGGHTS' default, ignore: the control that shows the check is what
   stops it). Each is also run with Debian's stock binary (/usr/bin/liggghts,
   LIGGGHTS_STOCK_BIN for another): same thermo rows, same ERROR line.
b. A crushing run (fix crush/particle) that loses a grain stops with the
   fix's own message, under `lost error` and under `lost ignore` alike,
   printed once in the log file and once on the screen, and nothing else:
   no stock "Lost atoms", no second line with garbage bytes (LIGGGHTS 3.8's
   Error::all appends such a line to about one error in five;
   crush_error.h). The step it names is that of the first neighbour-list
   build after the grain's centre crossed the boundary (independent answer
   from the speed, the distance and the skin).
c. Every deck file of the repository (inputs/, examples/, bench/) runs every
   `run` under `thermo_modify lost error` (deck_lint.lost_error_problems,
   following the blocks it includes); decks written by tests are checked by
   harness.run_deck before they run.
d. deck_lint itself, on small decks with known answers.
"""

import os
import re
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import deck_lint  # noqa: E402
import harness  # noqa: E402
from crushpost.materials import RHO_GRAIN, SIGMA_LIM0  # noqa: E402
from harness import REPO  # noqa: E402

INPUTS = REPO / "inputs"
STOCK_BIN = Path(os.environ.get("LIGGGHTS_STOCK_BIN", "/usr/bin/liggghts"))

# one grain flying at 1 m/s towards the x boundary, 5 mm away: its centre
# leaves the box at step 5000 (dt 1e-6 s)
V, X0, X_BOX, DT, SKIN = 1.0, 0.005, 0.01, 1e-6, 0.001
ESCAPE = """\
variable        inputs index {inputs}
include         ${{inputs}}/base.in
boundary        f f f
region          box block -0.01 0.01 -0.01 0.01 -0.01 0.01 units box
create_box      4 box
include         ${{inputs}}/materials_ne34.in
neighbor        0.001 bin
neigh_modify    delay 0
create_atoms    1 single 0.005 0.0 0.0 units box
create_atoms    1 single 0.0 0.005 0.0 units box
set             atom * diameter 0.002 density {rho:g}
velocity        all set 1.0 0.0 0.0 units box
set             atom 2 vx 0.0
{crush}fix             integ all nve
timestep        1e-6
{thermo}
thermo          100
run             8000
"""
CRUSH = (f"fix             crush all crush/particle sigma_lim0 {SIGMA_LIM0:g} m 10 d0 2e-3 scale 1 "
         "var 0.36 d_comm 1e-3 seed 15485863\n")


def _escape_text(thermo="", crush=""):
    return ESCAPE.format(inputs=INPUTS, thermo=thermo, crush=crush, rho=RHO_GRAIN)


def _escape(tmp_path, thermo="", lost_ok=False, crush="", extra_args=None):
    return harness.run_deck(_escape_text(thermo, crush), tmp_path, timeout=120, lost_ok=lost_ok,
                            extra_args=extra_args)


def _stock(monkeypatch, tmp_path, thermo="", lost_ok=False):
    if not (STOCK_BIN.is_file() and os.access(str(STOCK_BIN), os.X_OK)):
        pytest.fail("stock LIGGGHTS not found at %s: run scripts/setup (installs Debian's "
                    "package liggghts), or set LIGGGHTS_STOCK_BIN" % STOCK_BIN)
    with monkeypatch.context() as m:
        m.setenv("LIGGGHTS_BIN", str(STOCK_BIN))
        return _escape(tmp_path, thermo, lost_ok)


def _errors(res):
    """ERROR lines without the '(file:line)' suffix (its path differs between builds)."""
    return [re.sub(r"\s*\([^()]*:\d+\)\s*$", "", e) for e in res.errors]


def _same_as_stock(res, stock):
    assert (res.returncode == 0) == (stock.returncode == 0), (res.summary(), stock.summary())
    assert _errors(res) == _errors(stock)
    assert len(res.thermo) == len(stock.thermo)
    for a, b in zip(res.thermo, stock.thermo):
        assert a.columns == b.columns
        keep = [j for j, c in enumerate(a.columns) if c != "CPU"]     # wall-clock time
        np.testing.assert_array_equal(a.data[:, keep], b.data[:, keep])


def test_base_settings_stop_on_a_lost_grain(tmp_path, monkeypatch):
    res = _escape(tmp_path / "build")
    assert res.returncode != 0
    # stock's wording: Comm::exchange has already recounted atom->natoms
    assert _errors(res) == ["ERROR: Lost atoms: original 1 current 1"], res.summary()
    # the grain left at step 5000, the check is at thermo output
    assert res.thermo[-1]["Step"][-1] == 5000 and res.thermo[-1]["Atoms"][-1] == 2
    _same_as_stock(res, _stock(monkeypatch, tmp_path / "stock"))


def test_lost_error_after_a_thermo_style_stops_on_a_lost_grain(tmp_path, monkeypatch):
    thermo = "thermo_style    custom step atoms ke\nthermo_modify   lost error"
    res = _escape(tmp_path / "build", thermo)
    assert _errors(res) == ["ERROR: Lost atoms: original 1 current 1"], res.summary()
    _same_as_stock(res, _stock(monkeypatch, tmp_path / "stock", thermo))


def test_thermo_style_alone_resets_to_ignore(tmp_path, monkeypatch):
    """The control: LIGGGHTS 3.8's thermo_style drops base.in's setting, and
    the grain vanishes silently; harness.run_deck refuses such a deck."""
    deck = "thermo_style    custom step atoms ke"
    with pytest.raises(harness.DeckError, match="lost error"):
        _escape(tmp_path / "refused", deck)
    res = _escape(tmp_path / "ran", deck, lost_ok=True)
    assert res.returncode == 0 and not res.errors, res.summary()
    # the moving grain is gone (its kinetic energy with it), and the Atoms
    # column follows the count (stock: recounted at every re-neighbouring)
    blk = res.thermo[-1]
    assert blk["KinEng"][0] > 0 and blk["KinEng"][-1] == 0.0
    assert blk["Atoms"][0] == 2 and blk["Atoms"][-1] == 1
    assert "for 8000 steps with 1 atoms" in res.log
    _same_as_stock(res, _stock(monkeypatch, tmp_path / "stock", deck, lost_ok=True))


LOST_MSG = re.compile(r"ERROR: fix crush/particle \(fix crush\): 1 atoms lost by step (\d+) "
                      r"\(expected 2, found 1\): grains left the simulation box")


@pytest.mark.parametrize("lost", ["error", "ignore"])
def test_crushing_run_stops_on_a_lost_grain_with_one_clean_message(tmp_path, lost):
    thermo = "thermo_style    custom step atoms ke f_crush[1]\nthermo_modify   lost %s" % lost
    # the screen to stdout (the harness passes -screen none; a later -screen wins)
    res = _escape(tmp_path, thermo, lost_ok=(lost == "ignore"), crush=CRUSH,
                  extra_args=["-screen", "/dev/stdout"])
    assert res.returncode != 0, res.summary()
    for name, text in (("log file", res.log), ("screen", res.stdout)):
        found = LOST_MSG.findall(text)
        assert len(found) == 1, (name, text[-2000:])
        # nothing else: one ERROR line, no line after it, only printable ASCII
        lines = [ln for ln in text.splitlines() if "ERROR" in ln or (
            re.search(r"fix_crush_particle\w*\.cpp:", ln) and not ln.startswith("WARNING"))]
        assert len(lines) == 1, (name, lines)
        assert text.rstrip("\n").splitlines()[-1] == lines[0], (name, text[-500:])
        assert all(c == "\n" or c == "\t" or " " <= c <= "~" for c in text), name
        # the first neighbour-list build after the centre crossed the boundary
        # (builds when a grain moved more than half the skin: every 501 steps)
        step = int(found[0])
        t_out = (X_BOX - X0) / V / DT
        assert t_out <= step <= t_out + 0.5 * SKIN / V / DT + 2, step
    # no break happened (d_comm 1 mm, no load): the count is the fix's own
    assert "Lost atoms" not in res.log + res.stdout


@pytest.mark.parametrize("d_frag_min, warned", [(5e-4, True), (4e-4, False)])
def test_d_frag_min_that_lowers_the_count_is_warned_about(tmp_path, d_frag_min, warned):
    """A break whose fragments all go to fines (d < d_frag_min / 0.414214, with
    0.414214 = 1/(1 + sqrt 2) the large-fragment ratio) lowers the atom count,
    which stock `lost error` takes for lost atoms. Possible exactly when
    d_frag_min > 0.414214 d_comm (d_comm 1 mm here: 0.414 mm)."""
    crush = CRUSH.replace("seed", "d_frag_min %r seed" % d_frag_min)
    text = _escape_text(crush=crush).replace("run             8000", "run             1")
    res = harness.run_deck(text, tmp_path, timeout=120, check=True)
    found = [w for w in res.warnings if "d_frag_min" in w]
    if not warned:
        assert not found, found
        return
    assert len(found) == 1, res.warnings
    assert "d_frag_min 0.0005 > 0.414 d_comm = 0.000414214" in found[0], found[0]
    assert "d_frag_min/0.414 = 0.00120711" in found[0], found[0]
    assert "thermo_modify lost ignore" in found[0]


def _deck_files():
    files = sorted(set(INPUTS.glob("*.in")) | set((REPO / "examples").glob("*/in.*"))
                   | set((REPO / "bench").glob("*/in.*")))
    assert len(files) > 15
    return files


@pytest.mark.parametrize("path", _deck_files(), ids=lambda p: str(p.relative_to(REPO)))
def test_every_deck_file_makes_lost_atoms_an_error(path):
    problems = deck_lint.lost_error_problems(path.read_text(), str(path.relative_to(REPO)),
                                             base=path.parent)
    assert not problems, "\n".join(problems)


def test_deck_lint_answers():
    ok = "thermo_style custom step\nthermo_modify format float %g lost error\nrun 10\n"
    assert deck_lint.lost_error_problems(ok) == []
    # a later thermo_style resets the setting
    bad = ok + "thermo_style custom step atoms\nrun 10\n"
    (p,) = deck_lint.lost_error_problems(bad)
    assert "deck:5" in p and "deck:4" in p
    # the default, an explicit ignore, and a continuation line
    assert len(deck_lint.lost_error_problems("run 1\n")) == 1
    assert len(deck_lint.lost_error_problems("thermo_modify lost ignore\nrun 1\n")) == 1
    assert deck_lint.lost_error_problems(
        "thermo_style custom step &\n   atoms\nthermo_modify norm no &\n  lost error\nrun 1\n") == []
    # a comment does not count
    assert len(deck_lint.lost_error_problems("thermo_modify norm no # lost error\nrun 1\n")) == 1
    # blocks of inputs/ are followed: base.in sets lost error
    assert deck_lint.lost_error_problems("include ${inputs}/base.in\nrun 1\n") == []
