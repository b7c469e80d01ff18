# SPDX-License-Identifier: GPL-2.0-or-later
"""ctest's TIMEOUT of each deck test file fits the file's own time budget
(issue 42 item 5). Every LIGGGHTS or driver run inside a test has its own
timeout, which says which run hung; the file's ctest TIMEOUT is a backstop
and must not cut a file before one of those fires. A file declares its
budget as a module constant `CTEST_TIMEOUT = <seconds>` (the sum of the
timeouts of the long runs it makes one after another), which
tests/CMakeLists.txt reads; without one it gets the default there. Checked
here: the budget is above every timeout the file gives a run (a literal
`timeout=`, a `*TIMEOUT` constant, harness.DEFAULT_TIMEOUT where a harness
call leaves it out), and, where the build folder is configured, ctest gives
each deck test the budget its file declares."""

import json
import os
import re
import shutil
import subprocess

import pytest

from conftest import REPO

INTEGRATION = REPO / "tests" / "integration"
MARGIN = 60          # s: the backstop fires this much after the longest run's own timeout


def default_timeout():
    text = (REPO / "tests" / "CMakeLists.txt").read_text()
    return int(re.search(r"set\(DECK_TEST_TIMEOUT_DEFAULT (\d+)\)", text).group(1))


def declared_budget(text):
    """The file's CTEST_TIMEOUT, or None (the same pattern CMake reads)."""
    m = re.search(r"^CTEST_TIMEOUT *= *(\d+)", text, re.M)
    return int(m.group(1)) if m else None


def run_timeouts(text):
    """Every timeout the file gives a run, in seconds."""
    out = [float(x) for x in re.findall(r"\btimeout\s*=\s*(\d+(?:\.\d*)?)\b", text)]
    out += [float(x) for name, x in re.findall(r"^([A-Z_]*TIMEOUT)\s*=\s*(\d+(?:\.\d*)?)", text, re.M)
            if name != "CTEST_TIMEOUT"]
    if re.search(r"harness\.(run_deck|expect_error)\(|\brun_deck\(|\bcd\.run\(", text):
        harness = (INTEGRATION / "harness.py").read_text()
        out.append(float(re.search(r"^DEFAULT_TIMEOUT = (\S+)", harness, re.M).group(1)))
    return out


FILES = sorted(INTEGRATION.glob("test_*.py"))


def test_parsers_on_text():
    text = ("CTEST_TIMEOUT = 2500   # chamber 1500 + resume 900\nRUN_TIMEOUT = 900\n"
            "x = run(cmd, timeout=1500)\ny = harness.run_deck(d, w, timeout = 60.5)\n")
    assert declared_budget(text) == 2500
    assert sorted(run_timeouts(text)) == [60.5, 300.0, 900.0, 1500.0]
    assert declared_budget("# CTEST_TIMEOUT = 5\n") is None
    assert run_timeouts("subprocess.run(cmd)\n") == []


@pytest.mark.parametrize("path", FILES, ids=[p.stem for p in FILES])
def test_budget_above_every_run_timeout(path):
    text = path.read_text()
    budget = declared_budget(text) or default_timeout()
    longest = max(run_timeouts(text), default=0.0)
    assert budget >= longest + MARGIN, (
        "%s: ctest TIMEOUT %d s, but a run inside may take %g s: declare CTEST_TIMEOUT"
        % (path.name, budget, longest))


def test_ctest_applies_the_declared_budgets():
    build = REPO / "build"
    ctest = shutil.which("ctest")
    if not (build / "tests" / "CTestTestfile.cmake").exists() or ctest is None:
        pytest.skip("no configured build folder")
    out = subprocess.run([ctest, "--show-only=json-v1"], cwd=str(build), capture_output=True,
                         text=True, timeout=120, env=dict(os.environ))
    assert out.returncode == 0, out.stderr
    got = {}
    for t in json.loads(out.stdout)["tests"]:
        props = {p["name"]: p["value"] for p in t.get("properties", [])}
        got[t["name"]] = props.get("TIMEOUT")
    checked = 0
    for path in FILES:
        name = "deck." + path.stem
        if name not in got:        # a file added since the last configure
            continue
        want = declared_budget(path.read_text()) or default_timeout()
        assert float(got[name]) == want, (name, got[name], want)
        checked += 1
    assert checked >= 1 and checked >= len(FILES) - 3, (checked, sorted(got))
