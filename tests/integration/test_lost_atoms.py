"""Lost atoms stop every run (issue 5 item 6).

a. LIGGGHTS: a grain that leaves the box through a fixed boundary stops the
   run with "Lost atoms" under the settings of inputs/base.in, and also after
   a later thermo_style followed by `thermo_modify lost error`. The same deck
   with `lost ignore` (the LIGGGHTS default) runs on with one atom fewer:
   the control that shows the check is what stops it.
b. Every deck file of the repository (inputs/, examples/, bench/) runs every
   `run` under `thermo_modify lost error` (deck_lint.lost_error_problems,
   following the blocks it includes); decks written by tests are checked by
   harness.run_deck before they run.
c. deck_lint itself, on small decks with known answers.
"""

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import deck_lint  # noqa: E402
import harness  # noqa: E402
from harness import REPO  # noqa: E402

INPUTS = REPO / "inputs"

# one grain flying at 1 m/s towards the x boundary, 5 mm away: it leaves the
# box after about 5000 steps of 1e-6 s
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
set             atom * diameter 0.002 density 2600
velocity        all set 1.0 0.0 0.0 units box
set             atom 2 vx 0.0
fix             integ all nve
timestep        1e-6
{thermo}
thermo          100
run             8000
"""


def _escape(tmp_path, thermo="", lost_ok=False):
    return harness.run_deck(ESCAPE.format(inputs=INPUTS, thermo=thermo), tmp_path, timeout=120,
                            lost_ok=lost_ok)


def test_base_settings_stop_on_a_lost_grain(tmp_path):
    res = _escape(tmp_path)
    assert res.returncode != 0
    assert any("Lost atoms: original 2 current 1" in e for e in res.errors), res.summary()


def test_lost_error_after_a_thermo_style_stops_on_a_lost_grain(tmp_path):
    res = _escape(tmp_path, "thermo_style    custom step atoms ke\nthermo_modify   lost error")
    assert any("Lost atoms: original 2 current 1" in e for e in res.errors), res.summary()


def test_thermo_style_alone_resets_to_ignore(tmp_path):
    """The control: LIGGGHTS 3.8's thermo_style drops base.in's setting, and
    the grain vanishes silently; harness.run_deck refuses such a deck."""
    deck = "thermo_style    custom step atoms ke"
    with pytest.raises(harness.DeckError, match="lost error"):
        _escape(tmp_path / "refused", deck)
    res = _escape(tmp_path / "ran", deck, lost_ok=True)
    assert res.returncode == 0 and not res.errors, res.summary()
    # the moving grain is gone (its kinetic energy with it); the thermo
    # column Atoms shows the bookkept total, as in LAMMPS
    ke = res.thermo[-1]["KinEng"]
    assert ke[0] > 0 and ke[-1] == 0.0
    assert "for 8000 steps with 1 atoms" in res.log


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
