# SPDX-License-Identifier: GPL-2.0-or-later
"""One home for the calibrated constants (issue "One topic per file", item 3):
no tracked source file but the homes writes out a copy of a distinctive
calibrated value (crushpost.materials.LINTED: the grain's G, E, mu and
density, the steel's G and E, sigma_lim0).

The rule: in the tracked files (git ls-files) named *.py, *.in or in.*, and
the *.cpp / *.h under src_liggghts_plugin/, every numeric literal (a token
such as an integer, a decimal or an e-notation number, not part of a name
or of a longer number) whose value as a float equals one of those values is a copy, in code
and comments alike. Allowed:

* the homes: scripts/crushpost/materials.py, inputs/materials_ne34.in and
  inputs/crushable_ne34.in (the deck block of fix crush/particle's
  parameters, sigma_lim0);
* the files of ``ALLOWED_FILES`` below, each with its reason;
* a line that carries the tag ``lint: calibrated-ok`` followed by its reason
  (in a comment of the file's language).

Documentation (docs/*.md) is not read: it quotes the values.
"""

import re
from pathlib import Path

import pytest

from crushpost import materials
from repo_files import tracked_files

REPO = Path(__file__).resolve().parents[2]

HOMES = ("scripts/crushpost/materials.py", "inputs/materials_ne34.in", "inputs/crushable_ne34.in")

#: path -> why it may keep its copies for now.
ALLOWED_FILES = {}      # none at present

TAG = re.compile(r"lint: calibrated-ok\s+\S")

# a number not glued to a name, a dot or another digit: 12, 12.0, .5, 1.2e3, 5e+07
NUMBER = re.compile(r"(?<![\w.])(\d+\.?\d*(?:[eE][+-]?\d+)?|\.\d+(?:[eE][+-]?\d+)?)(?![\w.])")


def _calibrated():
    return {float(getattr(materials, name)): name for name in materials.LINTED}


def _linted_files():
    out = []
    for n in tracked_files(REPO):
        base = n.rsplit("/", 1)[-1]
        if base.endswith((".py", ".in")) or base.startswith("in."):
            out.append(n)
        elif n.startswith("src_liggghts_plugin/") and base.endswith((".cpp", ".h")):
            out.append(n)
    return out


def copies(text, values):
    """(line number, literal, name) of each calibrated literal in ``text``
    whose line has no tag."""
    found = []
    for i, line in enumerate(text.splitlines(), 1):
        if TAG.search(line):
            continue
        for m in NUMBER.finditer(line):
            try:
                v = float(m.group(1))
            except ValueError:
                continue
            if v in values:
                found.append((i, m.group(1), values[v]))
    return found


def test_the_lint_finds_the_forms_of_a_value():
    values = _calibrated()
    rho = str(int(materials.RHO_GRAIN))
    g = "%.0e" % materials.G_GRAIN                       # e-notation with a sign
    text = "\n".join([f"rho = {rho}", f"rho = {rho}.0", f"x = {materials.RHO_GRAIN / 1e3}e3",
                      f"set atom 1 density {rho}", f"G = {g}", f"mu = {materials.MU_GRAIN}0",
                      f"a{rho} = 1; b_{rho}; {rho}1; 1{rho}; 0.{rho}",
                      f"ok = {rho}  # lint: calibrated-ok a reason"])
    assert [(n, name) for n, _, name in copies(text, values)] == [
        (1, "RHO_GRAIN"), (2, "RHO_GRAIN"), (3, "RHO_GRAIN"), (4, "RHO_GRAIN"),
        (5, "G_GRAIN"), (6, "MU_GRAIN")]
    assert copies(f"ok = {rho}  # lint: calibrated-ok", values)       # a tag needs a reason


def test_the_allowed_files_exist():
    names = set(tracked_files(REPO))
    for n in HOMES + tuple(ALLOWED_FILES):
        assert n in names, n


def test_no_copy_of_a_calibrated_value():
    values = _calibrated()
    bad = []
    for n in _linted_files():
        if n in HOMES or n in ALLOWED_FILES:
            continue
        p = REPO / n
        if p.is_symlink() or not p.is_file():
            continue
        for i, lit, name in copies(p.read_text(errors="replace"), values):
            bad.append(f"{n}:{i}: {lit} is crushpost.materials.{name}")
    assert not bad, ("calibrated values written out (import crushpost.materials, use the deck "
                     "variable, or tag the line 'lint: calibrated-ok <why>'):\n" + "\n".join(bad))


@pytest.mark.parametrize("name", sorted(ALLOWED_FILES))
def test_an_allowed_file_still_needs_it(name):
    """An entry of ALLOWED_FILES goes once the file has no copy left."""
    p = REPO / name
    assert copies(p.read_text(errors="replace"), _calibrated()), f"{name}: no copy left, drop it from ALLOWED_FILES"
