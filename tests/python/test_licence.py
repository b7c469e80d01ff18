# SPDX-License-Identifier: GPL-2.0-or-later
"""The licence (issue 43): LICENSE holds the GNU GPL version 2 text, README's
Licence section says GPL-2.0-or-later, and every source file carries an
``SPDX-License-Identifier: GPL-2.0-or-later`` line in its first five lines,
as a comment of its language (``//`` in C++, ``#`` in Python, CMake, shell
scripts and LIGGGHTS decks), after a shebang where there is one.

The source files are found here on their own, not with scripts/add_spdx
(which puts the lines in): the tracked files (git ls-files; outside a
checkout every file but build/ and deps/) named *.cpp, *.h, *.py, *.cmake,
CMakeLists.txt, *.sh, *.in or in.*, and the files under scripts/ and .ci/
that start with #!."""

import re
from pathlib import Path

from repo_files import tracked_files

REPO = Path(__file__).resolve().parents[2]
LINE = re.compile(r"^(//|#) SPDX-License-Identifier: GPL-2\.0-or-later\s*$")


def _files():
    names = tracked_files(REPO)
    found = []
    for n in names:
        p = REPO / n
        if p.is_symlink() or not p.is_file():
            continue
        base = p.name
        if base.endswith((".cpp", ".h")):
            found.append((n, "//"))
        elif (base.endswith((".py", ".cmake", ".sh", ".in")) or base == "CMakeLists.txt"
              or base.startswith("in.")):
            found.append((n, "#"))
        elif n.split("/")[0] in ("scripts", ".ci") and p.read_bytes()[:2] == b"#!":
            found.append((n, "#"))
    return found


def test_licence_file_is_the_gpl_2():
    text = (REPO / "LICENSE").read_text()
    assert text.lstrip().startswith("GNU GENERAL PUBLIC LICENSE")
    assert "Version 2, June 1991" in text
    assert "TERMS AND CONDITIONS FOR COPYING, DISTRIBUTION AND MODIFICATION" in text
    assert "END OF TERMS AND CONDITIONS" in text
    assert len(text.splitlines()) > 300          # the whole text, not a notice


def test_readme_says_gpl_2_or_later():
    readme = (REPO / "README.md").read_text()
    section = readme.split("## Licence", 1)[1].split("\n## ", 1)[0]
    assert "GPL-2.0-or-later" in section and "LICENSE" in section


def test_every_source_file_has_the_spdx_line():
    files = _files()
    assert len(files) > 100, len(files)
    bad = []
    for rel, comment in files:
        lines = (REPO / rel).read_text(errors="replace").splitlines()
        head = lines[:5]
        hits = [k for k, line in enumerate(head) if LINE.match(line)]
        if not hits or not head[hits[0]].startswith(comment + " "):
            bad.append(rel)
        elif lines[0].startswith("#!") and hits[0] == 0:
            bad.append(rel + " (before the shebang)")
    assert not bad, "%d of %d source files lack '%s SPDX-License-Identifier: " \
        "GPL-2.0-or-later' in their first 5 lines (scripts/add_spdx adds it): %s" \
        % (len(bad), len(files), "#|//", ", ".join(bad[:20]))
