# SPDX-License-Identifier: GPL-2.0-or-later
"""README.md's table of summary.json keys (issue 43 item 3) is in step with
the demo: every top-level key of the committed bench/demo/summary.json has a
row (with its meaning and unit), and every key the table names is one the
committed summary has or examples/cpt_demo/run.py can write (a renamed or
dropped key fails here)."""

import json
import re

from conftest import REPO

TABLE_INTRO = "`results/demo/summary.json` holds"


def readme_table_keys():
    """The backquoted names in the first column of the table that follows
    TABLE_INTRO, and the rows' column counts."""
    text = (REPO / "README.md").read_text()
    assert TABLE_INTRO in text, "README.md has no summary.json table after %r" % TABLE_INTRO
    rows = []
    for line in text.split(TABLE_INTRO, 1)[1].splitlines()[1:]:
        if not line.strip():
            if rows:
                break
            continue
        if not line.startswith("|"):
            break
        rows.append(line)
    body = [r for r in rows[2:]]                  # header and |---| first
    cells = [re.split(r"(?<!\\)\|", r.strip().strip("|")) for r in body]
    keys = set()
    for c in cells:
        assert len(c) == 3, "README.md summary.json table row without key, meaning, unit: %r" % c
        assert c[1].strip() and c[2].strip(), "README.md summary.json row lacks meaning or unit: %r" % c
        keys.update(re.findall(r"`([^`]+)`", c[0]))
    return keys


def test_every_summary_key_is_in_the_readme_table():
    summary = json.loads((REPO / "bench/demo/summary.json").read_text())
    missing = sorted(set(summary) - readme_table_keys())
    assert not missing, ("README.md's summary.json table lacks the keys %s of "
                         "bench/demo/summary.json: add a row (meaning, unit)" % missing)


def test_every_readme_key_is_written_by_the_demo():
    summary = json.loads((REPO / "bench/demo/summary.json").read_text())
    driver = (REPO / "examples/cpt_demo/run.py").read_text()
    stale = sorted(k for k in readme_table_keys()
                   if k not in summary and '"%s"' % k not in driver)
    assert not stale, ("README.md's summary.json table names %s, which neither "
                       "bench/demo/summary.json nor examples/cpt_demo/run.py has" % stale)
