# SPDX-License-Identifier: GPL-2.0-or-later
"""scripts/add_spdx (issue 43) puts the licence line into each kind of source
file with that language's comment, after a shebang and a Python encoding
line, and changes nothing else, byte for byte; a second run changes
nothing. The expected files are written out by hand below, and on a copy of
the repository's own sources the only difference is the one line."""

import os
import py_compile
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
ADDER = REPO / "scripts" / "add_spdx"
CPP = b"// SPDX-License-Identifier: GPL-2.0-or-later\n"
HASH = b"# SPDX-License-Identifier: GPL-2.0-or-later\n"

# (relative path, content before, content expected after)
CASES = [
    ("src_liggghts_plugin/fix_a.cpp", b"/* a fix */\n#include <cmath>\n",
     CPP + b"/* a fix */\n#include <cmath>\n"),
    ("src_liggghts_plugin/fix_a.h", b"#ifndef A_H\n#define A_H\n#endif\n",
     CPP + b"#ifndef A_H\n#define A_H\n#endif\n"),
    ("scripts/crushpost/mod.py", b'"""doc."""\nX = 1\n', HASH + b'"""doc."""\nX = 1\n'),
    ("bench/x/run.py", b"#!/usr/bin/env python3\n\"\"\"doc.\"\"\"\n",
     b"#!/usr/bin/env python3\n" + HASH + b"\"\"\"doc.\"\"\"\n"),
    ("bench/x/enc.py", b"# -*- coding: utf-8 -*-\nX = '\xc3\xa9'\n",
     b"# -*- coding: utf-8 -*-\n" + HASH + b"X = '\xc3\xa9'\n"),
    ("bench/x/both.py", b"#!/usr/bin/python3\n# vim: set fileencoding=utf-8 :\nX = 2\n",
     b"#!/usr/bin/python3\n# vim: set fileencoding=utf-8 :\n" + HASH + b"X = 2\n"),
    # an encoding-like line on line 3 is no encoding line
    ("bench/x/late.py", b"#!/usr/bin/python3\nX = 1\n# coding: latin-1\n",
     b"#!/usr/bin/python3\n" + HASH + b"X = 1\n# coding: latin-1\n"),
    ("scripts/tool", b"#!/usr/bin/env bash\nset -e\necho hi\n",
     b"#!/usr/bin/env bash\n" + HASH + b"set -e\necho hi\n"),
    (".ci/run", b"#!/bin/sh\nexec true", b"#!/bin/sh\n" + HASH + b"exec true"),
    ("bench/device/go.sh", b"echo no shebang\n", HASH + b"echo no shebang\n"),
    ("CMakeLists.txt", b"cmake_minimum_required(VERSION 3.16)\n",
     HASH + b"cmake_minimum_required(VERSION 3.16)\n"),
    ("cmake/Prep.cmake", b"function(f)\nendfunction()\n", HASH + b"function(f)\nendfunction()\n"),
    ("inputs/base.in", b"units si\r\natom_style granular\r\n",
     b"# SPDX-License-Identifier: GPL-2.0-or-later\r\nunits si\r\natom_style granular\r\n"),
    ("examples/cpt_demo/in.cpt", b"variable a index 1", HASH + b"variable a index 1"),
    ("scripts/crushpost/empty.py", b"", HASH),
    ("scripts/only_shebang", b"#!/bin/bash", b"#!/bin/bash\n" + HASH),
    # the tag quoted in a docstring is no SPDX line
    ("scripts/crushpost/doc.py", b'"""Puts ``SPDX-License-Identifier: X`` lines."""\n',
     HASH + b'"""Puts ``SPDX-License-Identifier: X`` lines."""\n'),
    # already there (anywhere in the first lines): untouched
    ("tests/unit/test_b.cpp", b"/* x */\n// SPDX-License-Identifier: GPL-2.0-or-later\nint a;\n",
     b"/* x */\n// SPDX-License-Identifier: GPL-2.0-or-later\nint a;\n"),
]
# not source files: left alone
OTHERS = [("docs/a.md", b"# A\n"), ("bench/x/data.json", b"{}\n"), ("pyproject.toml", b"[x]\n"),
          ("scripts/notes.txt", b"text\n"), ("tests/data/plain", b"no shebang\n")]


def _adder(*args, cwd=None):
    return subprocess.run([sys.executable, str(ADDER)] + [str(a) for a in args],
                          capture_output=True, text=True, timeout=300, cwd=cwd)


def _tree(base, files):
    for rel, data in files:
        p = base / rel
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_bytes(data)


def test_each_kind_gets_its_comment_and_nothing_else_changes(tmp_path):
    _tree(tmp_path, [(r, b) for r, b, _ in CASES] + OTHERS)
    (tmp_path / "scripts" / "tool").chmod(0o755)
    res = _adder("--check", "--root", tmp_path)
    assert res.returncode == 1
    listed = set(res.stdout.split())
    assert listed == {r for r, b, a in CASES if a != b}
    res = _adder("--root", tmp_path)
    assert res.returncode == 0, res.stderr
    for rel, _, after in CASES:
        assert (tmp_path / rel).read_bytes() == after, rel
    for rel, data in OTHERS:
        assert (tmp_path / rel).read_bytes() == data, rel
    assert os.access(tmp_path / "scripts" / "tool", os.X_OK)
    # a second run changes nothing, and the check passes
    res = _adder("--root", tmp_path)
    assert res.returncode == 0
    for rel, _, after in CASES:
        assert (tmp_path / rel).read_bytes() == after, rel
    assert _adder("--check", "--root", tmp_path).returncode == 0


def test_another_licence_is_reported_and_kept(tmp_path):
    data = b"# SPDX-License-Identifier: MIT\nX = 1\n"
    _tree(tmp_path, [("scripts/crushpost/m.py", data)])
    res = _adder("--root", tmp_path)
    assert res.returncode == 2 and "MIT" in res.stderr
    assert (tmp_path / "scripts/crushpost/m.py").read_bytes() == data


def _tracked():
    try:
        out = subprocess.run(["git", "ls-files", "-z"], cwd=REPO, capture_output=True,
                             check=True, timeout=60).stdout
    except (OSError, subprocess.CalledProcessError):
        pytest.skip("not a git checkout")
    return [n for n in out.decode().split("\0") if n and (REPO / n).is_file()
            and not (REPO / n).is_symlink()]


def test_on_a_copy_of_the_repository_only_the_line_is_added(tmp_path):
    names = _tracked()
    for n in names:
        (tmp_path / n).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(REPO / n, tmp_path / n)
    before = {n: (tmp_path / n).read_bytes() for n in names}
    res = _adder("--root", tmp_path)
    assert res.returncode == 0, res.stderr
    n_source = 0
    for n in names:
        after = (tmp_path / n).read_bytes()
        old = before[n]
        if after == old:
            # a source file that has the line already (after the lead's run), or not a source
            n_source += any(line.rstrip(b"\r\n") in (CPP.rstrip(), HASH.rstrip())
                            for line in old.splitlines()[:5])
            continue
        n_source += 1
        new_lines, old_lines = after.splitlines(True), old.splitlines(True)
        assert len(new_lines) == len(old_lines) + 1, n
        k = next(i for i, line in enumerate(new_lines) if b"SPDX-License-Identifier" in line)
        assert k <= 2, n
        if old.startswith(b"#!"):           # the shebang stays the first line
            assert k >= 1 and new_lines[0].rstrip(b"\r\n") == old_lines[0].rstrip(b"\r\n"), n
        assert new_lines[k].rstrip(b"\r\n") in (CPP.rstrip(), HASH.rstrip()), n
        rest = new_lines[:k] + new_lines[k + 1:]
        # the shebang line of a one-line script gets its newline: the only other change
        assert b"".join(rest) in (old, old + b"\n"), n
        if n.endswith(".py"):
            py_compile.compile(str(tmp_path / n), doraise=True,
                               cfile=str(tmp_path / "pyc" / (n.replace("/", "_") + "c")))
        if old.startswith(b"#!") and b"sh" in old.split(b"\n", 1)[0]:
            assert subprocess.run(["bash", "-n", str(tmp_path / n)]).returncode == 0, n
    assert n_source > 100          # the repository's sources (changed or with the line already)
    # the copy is not a git checkout: the adder walked it; a second run changes nothing
    assert _adder("--check", "--root", tmp_path).returncode == 0
