# SPDX-License-Identifier: GPL-2.0-or-later
"""README.md's table of summary.json keys (issue 43 item 3) is in step with
the demo and with the keys' one definition, crushpost.formats.SUMMARY_KEYS
(issue "One topic per file", item 4): the table has a row (with its meaning
and unit) for every defined key and names no other; every top-level key of
the committed bench/demo/summary.json is defined; every defined key is one
examples/cpt_demo/run.py writes (a renamed or dropped key fails here)."""

import json
import re

from conftest import REPO

from crushpost.formats import SUMMARY_KEYS, SUMMARY_PREP_ONLY_KEYS

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


def test_the_readme_table_is_the_definition():
    table = readme_table_keys()
    missing = sorted(set(SUMMARY_KEYS) - table)
    extra = sorted(table - set(SUMMARY_KEYS))
    assert not missing, ("README.md's summary.json table lacks the keys %s of "
                         "crushpost.formats.SUMMARY_KEYS: add a row (meaning, unit)" % missing)
    assert not extra, ("README.md's summary.json table names %s, which "
                       "crushpost.formats.SUMMARY_KEYS does not define" % extra)


def test_every_summary_key_is_defined():
    summary = json.loads((REPO / "bench/demo/summary.json").read_text())
    undefined = sorted(set(summary) - set(SUMMARY_KEYS))
    assert not undefined, ("bench/demo/summary.json has the keys %s, which "
                           "crushpost.formats.SUMMARY_KEYS does not define" % undefined)


def test_every_defined_key_is_written_by_the_demo():
    driver = (REPO / "examples/cpt_demo/run.py").read_text()
    stale = sorted(k for k in SUMMARY_KEYS + SUMMARY_PREP_ONLY_KEYS if '"%s"' % k not in driver)
    assert not stale, ("crushpost.formats.SUMMARY_KEYS defines %s, which "
                       "examples/cpt_demo/run.py does not write" % stale)
