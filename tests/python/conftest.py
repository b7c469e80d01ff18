# SPDX-License-Identifier: GPL-2.0-or-later
"""Shared fixtures of the Python tests."""

import importlib.util
import pathlib

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]


def _load_script(relpath, name=None):
    """Import a script of the repository that is not in a package (a bench
    or example driver) as a module, by its path from the repository root."""
    path = REPO / relpath
    spec = importlib.util.spec_from_file_location(name or path.stem + "_under_test", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@pytest.fixture(scope="session")
def load_script():
    return _load_script


@pytest.fixture
def dead_pid():
    """The pid of a process that has exited (a killed call's claim or copy)."""
    import subprocess
    import sys

    child = subprocess.Popen([sys.executable, "-c", "pass"])
    child.wait()
    return child.pid


def write_events_file(path, events):
    """A breakage_events.txt of fix crush/particle's layout with one line per
    (step, x, y, z) of `events` (parent tags 1, 2, ...; other columns fixed):
    the synthetic runs of the chamber driver's tests."""
    with open(path, "w") as f:
        f.write("# step time parent_tag parent_diameter x y z F_n F_lim partner generation\n")
        for k, (st, x, y, z) in enumerate(events):
            f.write("%d %g %d 0.008 %.17g %.17g %.17g 1 1 particle 0\n" % (st, st * 1e-7, k + 1,
                                                                          x, y, z))
