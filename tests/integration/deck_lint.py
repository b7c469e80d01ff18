# SPDX-License-Identifier: GPL-2.0-or-later
"""Every deck must make lost atoms an error (issue 5 item 6).

LIGGGHTS 3.8 ignores lost atoms by default (`thermo_modify lost ignore`), and
every `thermo_style` command creates a new thermo object with the defaults
again, dropping earlier `thermo_modify` settings. So a deck is safe only if
every `run` comes after a `thermo_modify ... lost error` with no
`thermo_style` in between. :func:`lost_error_problems` checks that on the
text of a deck, following `include` files it can resolve (``${inputs}/...``
and plain paths); an unresolved include is assumed to leave the setting
alone. harness.run_deck applies it to every deck a test writes; the decks
of the repository are checked by tests/integration/test_lost_atoms.py.
"""

import re
import shlex
from pathlib import Path

__all__ = ["lost_error_problems", "REPO_INPUTS"]

REPO_INPUTS = Path(__file__).resolve().parent.parent.parent / "inputs"

_VAR = re.compile(r"\$\{(\w+)\}|\$(\w)")


def _commands(text):
    """(line number, words) of each command: comments stripped, `&`
    continuations joined."""
    out, buf, start = [], "", None
    for k, raw in enumerate(text.splitlines(), 1):
        line = raw.split("#", 1)[0].rstrip()
        if start is None:
            start = k
        if line.endswith("&"):
            buf += line[:-1] + " "
            continue
        buf += line
        try:
            words = shlex.split(buf, posix=True)
        except ValueError:
            words = buf.split()
        if words:
            out.append((start, words))
        buf, start = "", None
    return out


def _resolve(path, variables):
    def sub(m):
        name = m.group(1) or m.group(2)
        return variables.get(name, m.group(0))
    p = _VAR.sub(sub, path)
    return None if "$" in p else Path(p)


def lost_error_problems(text, name="deck", variables=None, base=None, _state=None, _depth=0):
    """Problems (list of str) with the lost-atoms setting of a deck's runs.

    ``variables``: values for ``${name}`` in include paths (``inputs``
    defaults to the repository's inputs/); ``base``: folder that relative
    include paths are taken from. Returns [] when every `run` executes with
    `lost error` in force.
    """
    variables = dict({"inputs": str(REPO_INPUTS)}, **(variables or {}))
    state = _state if _state is not None else {"lost_error": False, "style_line": None}
    problems = []
    for line, words in _commands(text):
        cmd = words[0]
        if cmd == "variable" and len(words) >= 4 and words[2] == "index" \
                and words[1] not in variables:
            variables[words[1]] = words[3]
        elif cmd == "thermo_style":
            state["lost_error"] = False
            state["style_line"] = "%s:%d" % (name, line)
        elif cmd == "thermo_modify":
            for k in range(1, len(words) - 1):
                if words[k] == "lost":
                    state["lost_error"] = words[k + 1] == "error"
        elif cmd == "run":
            if not state["lost_error"]:
                after = (" after the thermo_style at %s" % state["style_line"]
                         if state["style_line"] else "")
                problems.append("%s:%d: run without 'thermo_modify lost error'%s"
                                % (name, line, after))
        elif cmd == "include" and len(words) >= 2 and _depth < 8:
            p = _resolve(words[1], variables)
            if p is not None and not p.is_absolute() and base is not None:
                p = Path(base) / p
            if p is not None and p.is_file():
                problems += lost_error_problems(p.read_text(), str(p), variables, p.parent,
                                                state, _depth + 1)
    return problems
