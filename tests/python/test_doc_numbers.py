# SPDX-License-Identifier: GPL-2.0-or-later
"""The numbers README.md and docs/ quote from runs match the committed
results files they come from (issue 42 item 6): the registry
tests/python/doc_numbers.py lists each quote, its file and its key. A
changed result (a rerun that moved a number) or an edited doc (a number
retyped, a quote reworded away) fails here, naming both. A few statements
that are not numbers (FACTS) are checked against the files they describe."""

import json
import math
import re

import pytest

import doc_numbers
from conftest import REPO


def quote_regex(pattern):
    """The pattern with every literal space matching any run of whitespace
    (markdown wraps lines anywhere)."""
    return re.compile(pattern.replace(" ", r"\s+"))


def parse_quoted(text):
    """A quoted number and the size of a unit of its last digit:
    '1,586' -> (1586, 1), '0.0320' -> (0.032, 1e-4), '1.73e6' -> (1.73e6, 1e4)."""
    t = text.replace(",", "")
    mant, _, exp = t.partition("e")
    decimals = len(mant.split(".")[1]) if "." in mant else 0
    scale = 10.0 ** int(exp) if exp else 1.0
    return float(mant) * scale, 10.0 ** -decimals * scale


def lookup(data, path):
    """A value by a dotted path; a segment name[k=v,k2=v2] picks the one
    element of list `name` whose fields k, k2 print as v, v2."""
    for seg in path.split("."):
        m = re.fullmatch(r"([^\[]+)\[(.+)\]", seg)
        if not m:
            data = data[seg]
            continue
        want = dict(kv.split("=", 1) for kv in m.group(2).split(","))
        hits = [e for e in data[m.group(1)] if all(str(e.get(k)) == v for k, v in want.items())]
        assert len(hits) == 1, (seg, len(hits))
        data = hits[0]
    return data


def source_value(entry):
    with open(REPO / entry["source"]) as f:
        data = json.load(f)
    v = entry["value"](data) if callable(entry["value"]) else lookup(data, entry["value"])
    return float(v) * entry["scale"]


def agrees(quoted_text, value):
    q, unit = parse_quoted(quoted_text)
    return math.isfinite(value) and abs(q - value) <= 0.5 * unit * (1 + 1e-9)


def _id(e):
    return "%s:%s" % (e["doc"], e["pattern"][:40])


@pytest.mark.parametrize("entry", doc_numbers.ENTRIES, ids=[_id(e) for e in doc_numbers.ENTRIES])
def test_quoted_number_matches_its_results_file(entry):
    text = (REPO / entry["doc"]).read_text()
    found = quote_regex(entry["pattern"]).findall(text)
    assert found, "%s no longer quotes %r (move the pattern in tests/python/doc_numbers.py)" % (
        entry["doc"], entry["pattern"])
    value = source_value(entry)
    for q in found:
        assert agrees(q, value), "%s quotes %s, %s gives %.6g (%s)" % (
            entry["doc"], q, entry["source"], value, entry["value"] if isinstance(
                entry["value"], str) else "computed")


@pytest.mark.parametrize("fact", doc_numbers.FACTS, ids=[_id(f) for f in doc_numbers.FACTS])
def test_stated_fact_still_holds(fact):
    text = (REPO / fact["doc"]).read_text()
    assert quote_regex(fact["pattern"]).search(text), (
        "%s no longer states %r" % (fact["doc"], fact["pattern"]))
    assert fact["holds"](REPO), "%s states %r, but no longer: %s" % (
        fact["doc"], fact["pattern"], fact["what"])


@pytest.mark.parametrize("pending", doc_numbers.PENDING, ids=[p["doc"] for p in doc_numbers.PENDING])
def test_numbers_without_a_results_file_are_marked(pending):
    text = " ".join((REPO / pending["doc"]).read_text().split())
    marked = " ".join(pending["marker"].split()) in text
    if (REPO / pending["source"]).exists():
        assert not marked, ("%s is committed: quote its numbers in %s and move its entries "
                            "(doc_numbers.DEMO_ENTRIES) into ENTRIES" % (pending["source"],
                                                                        pending["doc"]))
    else:
        assert marked, "%s quotes numbers of %s, which is not committed, without the marker %r" % (
            pending["doc"], pending["source"], pending["marker"])


def test_parsing_and_rounding():
    assert parse_quoted("1,586") == (1586.0, 1.0)
    assert parse_quoted("0.0320") == (0.032, pytest.approx(1e-4))
    q, u = parse_quoted("1.73e6")
    assert q == pytest.approx(1.73e6) and u == pytest.approx(1e4)
    assert agrees("3.6", 3.602961) and not agrees("3.7", 3.602961)
    assert agrees("15.97", 15.9657785) and not agrees("15.96", 15.9657785)
    assert agrees("1,586", 1585.94) and not agrees("1,585", 1585.94)
    assert not agrees("1.0", float("nan"))
    assert quote_regex("a b").search("a\n  b")
    d = {"rows": [{"np": 16, "g": "* * 1", "x": 1}, {"np": 16, "g": "8 1 2", "x": 2}]}
    assert lookup(d, "rows[np=16,g=8 1 2].x") == 2


def test_every_source_is_committed():
    import subprocess
    files = sorted({e["source"] for e in doc_numbers.ENTRIES})
    out = subprocess.run(["git", "ls-files", "--error-unmatch"] + files, cwd=str(REPO),
                         capture_output=True, text=True)
    if out.returncode != 0 and "not a git repository" in out.stderr:
        pytest.skip("not a git checkout")
    assert out.returncode == 0, out.stderr
