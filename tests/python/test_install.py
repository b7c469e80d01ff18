# SPDX-License-Identifier: GPL-2.0-or-later
"""crushpost installs with pip as a user would (pyproject.toml): into a fresh
virtual environment that sees the system's numpy, scipy, h5py and
matplotlib, from a copy of the repository's Python sources, with nothing
downloaded. The installed `crushpost` command then works from any folder and
imports the installed copy, not the checkout."""

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def venv(tmp_path_factory):
    base = tmp_path_factory.mktemp("install")
    # A copy, so that the build's egg-info and build/ folders stay out of the checkout.
    src = base / "src"
    (src / "scripts").mkdir(parents=True)
    for name in ("pyproject.toml", "README.md"):
        shutil.copy(REPO / name, src / name)
    shutil.copytree(REPO / "scripts" / "crushpost", src / "scripts" / "crushpost",
                    ignore=shutil.ignore_patterns("__pycache__"))
    env_dir = base / "venv"
    system_python = "/usr/bin/python3" if os.path.exists("/usr/bin/python3") else sys.executable
    subprocess.run([system_python, "-m", "venv", "--system-site-packages", str(env_dir)],
                   check=True, timeout=300)
    res = subprocess.run([str(env_dir / "bin" / "python"), "-m", "pip", "install", "-q",
                          "--disable-pip-version-check", "--no-build-isolation", "--no-index",
                          str(src)], capture_output=True, text=True, timeout=600)
    assert res.returncode == 0, res.stdout + res.stderr
    return env_dir


def _clean_env():
    env = dict(os.environ)
    env.pop("PYTHONPATH", None)
    return env


def test_command_runs_outside_the_checkout(venv, tmp_path):
    h = np.linspace(0.0, 0.2, 60)
    np.savetxt(tmp_path / "qc.txt", np.column_stack([h, 7.0e6 * (1.0 - np.exp(-20.0 * h))]))
    res = subprocess.run([str(venv / "bin" / "crushpost"), "fit-qc", "qc.txt"], cwd=str(tmp_path),
                         env=_clean_env(), capture_output=True, text=True, timeout=120)
    assert res.returncode == 0, res.stderr
    fit = json.loads(res.stdout)
    assert fit["a"] == pytest.approx(7.0e6, rel=1e-6) and fit["b"] == pytest.approx(20.0, rel=1e-6)


def test_imports_the_installed_copy_with_system_numpy(venv, tmp_path):
    code = "import crushpost, numpy, scipy, h5py, matplotlib; print(crushpost.__file__)"
    res = subprocess.run([str(venv / "bin" / "python"), "-c", code], cwd=str(tmp_path),
                         env=_clean_env(), capture_output=True, text=True, timeout=120)
    assert res.returncode == 0, res.stderr
    where = Path(res.stdout.strip()).resolve()
    assert str(where).startswith(str(venv.resolve())), where
    assert "site-packages" in where.parts


def test_help_lists_the_commands(venv):
    res = subprocess.run([str(venv / "bin" / "crushpost"), "--help"], env=_clean_env(),
                         capture_output=True, text=True, timeout=120)
    assert res.returncode == 0, res.stderr
    for command in ("br", "fit-qc", "thermo", "pile", "spheres"):
        assert "    %s " % command in res.stdout, res.stdout
