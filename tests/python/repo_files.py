# SPDX-License-Identifier: GPL-2.0-or-later
"""The files of the repository that the repository-wide checks read
(test_licence, test_self_contained): git's tracked files, or, outside a git
checkout (an unpacked archive), every file but build/, deps/ and .git/."""

import os
import subprocess
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]


def tracked_files(repo=REPO):
    """Sorted paths, relative to `repo`."""
    try:
        out = subprocess.run(["git", "ls-files", "-z"], cwd=repo, capture_output=True, check=True,
                             timeout=60).stdout.decode()
        names = [n for n in out.split("\0") if n]
    except (OSError, subprocess.CalledProcessError):
        names = []
        for d, dirs, files in os.walk(repo):
            if Path(d) == Path(repo):
                dirs[:] = [x for x in dirs if x not in ("build", "deps", ".git")]
            names += [str((Path(d) / f).relative_to(repo)) for f in files]
    return sorted(names)
