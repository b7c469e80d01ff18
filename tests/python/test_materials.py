# SPDX-License-Identifier: GPL-2.0-or-later
"""crushpost.materials and the deck blocks under inputs/ hold the same
calibrated values (docs/model.md §3): every entry of materials.DECK is read
from its block (``variable NAME index VALUE``, ``variable NAME equal EXPR``
evaluated at N = 1, or a keyword of the ``fix crush all crush/particle``
command) and compared as a float, exactly."""

import math
import re
from pathlib import Path

import pytest

from crushpost import materials

INPUTS = Path(__file__).resolve().parents[2] / "inputs"


def _lines(block):
    """The commands of a deck block: comments dropped, '&' continuations joined."""
    out, cont = [], ""
    for raw in (INPUTS / block).read_text().splitlines():
        line = raw.split("#", 1)[0].rstrip()
        if line.endswith("&"):
            cont += line[:-1] + " "
            continue
        line = cont + line
        cont = ""
        if line.strip():
            out.append(line.split())
    return out


def _variables(block, style):
    return {w[1]: " ".join(w[3:]) for w in _lines(block) if w[0] == "variable" and w[2] == style}


def _deck_value(block, how, name):
    if how == "index":
        return float(_variables(block, "index")[name])
    if how == "equal":
        index = _variables(block, "index")
        index["N"] = "1"
        expr = re.sub(r"\$\{(\w+)\}", lambda m: index[m.group(1)], _variables(block, "equal")[name])
        assert re.fullmatch(r"[0-9eE.+\-*/() ]+", expr), expr
        return float(eval(expr))          # plain arithmetic, checked above
    if how == "fix crush":
        fixes = [w for w in _lines(block) if w[:4] == ["fix", "crush", "all", "crush/particle"]]
        assert len(fixes) == 1
        w = fixes[0]
        return float(w[w.index(name) + 1])
    raise AssertionError(how)


@pytest.mark.parametrize("name", sorted(materials.DECK))
def test_python_and_deck_agree(name):
    block, how, deck_name = materials.DECK[name]
    assert _deck_value(block, how, deck_name) == getattr(materials, name), (name, block, deck_name)


def test_every_value_with_a_deck_home_is_listed():
    """Every constant of the module but those with no deck value is in DECK."""
    no_deck = {"CU", "E_MAX", "E_MIN"}
    names = {n for n in materials.__all__ if n.isupper() and n not in ("DECK", "LINTED")}
    assert names - no_deck == set(materials.DECK)
    assert set(materials.LINTED) <= names


def test_rayleigh_time():
    """docs/model.md §5: T_R = pi r sqrt(rho / G) / (0.1631 nu + 0.8766), by
    default of the NE34 grain."""
    r = 0.5e-3
    assert materials.rayleigh_time(r) == (math.pi * r * math.sqrt(materials.RHO_GRAIN / materials.G_GRAIN)
                                          / (0.1631 * materials.NU_GRAIN + 0.8766))
    assert materials.rayleigh_time(r, rho=4 * materials.RHO_GRAIN) == pytest.approx(2 * materials.rayleigh_time(r))
    assert materials.rayleigh_time(r, G=4 * materials.G_GRAIN) == pytest.approx(0.5 * materials.rayleigh_time(r))
