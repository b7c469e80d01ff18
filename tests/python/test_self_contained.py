# SPDX-License-Identifier: GPL-2.0-or-later
"""The repository stands on its own (issue 43 item 1): the model is
docs/model.md, inside the repository, and nothing points outside it.

a. No tracked file (git ls-files; outside a checkout every file but build/,
   deps/ and .git/) names a path that leaves the repository (the parent's
   shared folder, or the outside specification file) or cites the outside
   specification by its name in capitals. LICENSE (legal text) and binary
   files are skipped.
b. Every reference to a section of the model, ``docs/model.md §4.7``,
   ``model.md §2``, ``model §2.4`` (a chain such as ``§4.4-§4.5`` or
   ``§4.6, §4.7`` included), and every markdown link ``model.md#<anchor>``
   names a heading of docs/model.md; inside docs/model.md every ``§N.M`` and
   every ``(#anchor)`` link does too. Anchors are GitHub's: the heading text
   in lower case, punctuation other than hyphens, underscores and spaces
   dropped, spaces turned into hyphens.

Each failure lists every offending file:line."""

import re
from pathlib import Path

from repo_files import tracked_files

REPO = Path(__file__).resolve().parents[2]
MODEL = "docs/model.md"

# The patterns are assembled from pieces so that this file does not match
# them itself.
_SPEC_WORD = "SP" + "EC"
OUTSIDE_PATH = re.compile(r"\.\./" + "shared" + r"|" + "shared/" + _SPEC_WORD)
OUTSIDE_CITE = re.compile(r"\b" + _SPEC_WORD + r"\b")      # "SPECIAL" has no word end there

# "model.md §4.7", "model §2", "model.md\n# §4.1 and §4.4" (a reference
# broken over comment lines), with chains of further sections
_SEC = r"§\d+(?:\.\d+)?"
MODEL_REF = re.compile(r"\bmodel(?:\.md)?(?:\s|#|//|\*)+(" + _SEC + r"(?:(?:\s*-\s*|,\s*|\s+and\s+)" + _SEC + r")*)")
SECTION = re.compile(r"§(\d+(?:\.\d+)?)")
ANCHOR_LINK = re.compile(r"model\.md#([A-Za-z0-9_\-]+)")
LOCAL_ANCHOR_LINK = re.compile(r"\]\(#([A-Za-z0-9_\-]+)\)")
HEADING = re.compile(r"^(#{1,6})\s+(.*?)\s*#*\s*$")

EXPECTED_HEADINGS = [
    "# The crushable-grain model",
    "## 1. Scope",
    "## 2. Grain and contact model",
    "### 2.1 Contact law",
    "### 2.2 Rotation inhibition",
    "### 2.3 Local damping",
    "### 2.4 Breakage criterion",
    "### 2.5 Strength law and scatter",
    "### 2.6 Fragments",
    "### 2.7 Mass accounting and comminution limit",
    "### 2.8 Breakage index Br",
    "## 3. Calibrated parameters (NE34)",
    "## 4. Scenes and analyses",
    "### 4.1 Preparation",
    "### 4.2 Oedometer",
    "### 4.3 Drained triaxial",
    "### 4.4 Calibration chamber",
    "### 4.5 Pile, jacking and q_c",
    "### 4.6 Measurement spheres",
    "### 4.7 Stress fields",
    "### 4.8 Breakage maps",
    "### 4.9 Radial displacement increments",
    "## 5. Numerical stability",
    "## References",
]


def _text_files():
    """(relative path, text) of every tracked text file but LICENSE."""
    out = []
    for rel in tracked_files(REPO):
        if rel == "LICENSE":
            continue
        p = REPO / rel
        if p.is_symlink() or not p.is_file():
            continue
        data = p.read_bytes()
        if b"\0" in data:
            continue
        try:
            out.append((rel, data.decode("utf-8")))
        except UnicodeDecodeError:
            continue
    return out


def _line_of(text, pos):
    return text.count("\n", 0, pos) + 1


def _model_headings():
    lines = (REPO / MODEL).read_text(encoding="utf-8").splitlines()
    heads, in_code = [], False
    for line in lines:
        if line.startswith("```"):
            in_code = not in_code
            continue
        if not in_code and HEADING.match(line):
            heads.append(line.rstrip())
    return heads


def github_anchor(heading_text):
    """GitHub's anchor of a heading: lower case, punctuation other than
    hyphens, underscores and spaces dropped, spaces turned into hyphens."""
    s = heading_text.strip().lower()
    s = re.sub(r"[^\w\- ]", "", s)
    return s.replace(" ", "-")


def _model_sections_and_anchors():
    sections, anchors, seen = set(), set(), {}
    for h in _model_headings():
        text = HEADING.match(h).group(2)
        m = re.match(r"(\d+(?:\.\d+)?)\.?\s", text)
        if m:
            sections.add(m.group(1))
        a = github_anchor(text)
        n = seen.get(a, 0)
        seen[a] = n + 1
        anchors.add(a if n == 0 else "%s-%d" % (a, n))
    return sections, anchors


def test_github_anchor():
    assert github_anchor("2.4 Breakage criterion") == "24-breakage-criterion"
    assert github_anchor("3. Calibrated parameters (NE34)") == "3-calibrated-parameters-ne34"
    assert github_anchor("4.5 Pile, jacking and q_c") == "45-pile-jacking-and-q_c"


def test_model_page_has_its_sections():
    """docs/model.md exists with the headings other pages link to."""
    assert (REPO / MODEL).is_file(), MODEL + " is missing"
    assert _model_headings() == EXPECTED_HEADINGS


def test_no_path_leaves_the_repository():
    bad = []
    for rel, text in _text_files():
        for m in OUTSIDE_PATH.finditer(text):
            bad.append("%s:%d: %s" % (rel, _line_of(text, m.start()),
                                      text.splitlines()[_line_of(text, m.start()) - 1].strip()[:120]))
    assert not bad, "%d place(s) name a path outside the repository (the model is %s):\n%s" \
        % (len(bad), MODEL, "\n".join(bad))


def test_no_citation_of_the_outside_specification():
    bad = []
    for rel, text in _text_files():
        for k, line in enumerate(text.splitlines(), 1):
            if OUTSIDE_CITE.search(line):
                bad.append("%s:%d: %s" % (rel, k, line.strip()[:120]))
    assert not bad, ("%d line(s) cite the specification outside the repository; cite %s "
                     "(e.g. 'docs/model.md §2.4') instead:\n%s" % (len(bad), MODEL, "\n".join(bad)))


def test_model_section_references_resolve():
    sections, _ = _model_sections_and_anchors()
    bad, n = [], 0
    for rel, text in _text_files():
        found = []
        for m in MODEL_REF.finditer(text):
            found += [(m.start(), s) for s in SECTION.findall(m.group(1))]
        if rel == MODEL:
            found += [(m.start(), m.group(1)) for m in SECTION.finditer(text)]
        for pos, s in found:
            n += 1
            if s not in sections:
                bad.append("%s:%d: §%s" % (rel, _line_of(text, pos), s))
    assert n > 0, "no reference to a section of %s found" % MODEL
    assert not bad, "%d reference(s) to a section %s does not have (it has %s):\n%s" \
        % (len(bad), MODEL, " ".join(sorted(sections, key=lambda x: [int(p) for p in x.split(".")])),
           "\n".join(bad))


def test_model_anchor_links_resolve():
    _, anchors = _model_sections_and_anchors()
    bad = []
    for rel, text in _text_files():
        hits = [(m.start(), m.group(1)) for m in ANCHOR_LINK.finditer(text)]
        if rel == MODEL:
            hits += [(m.start(), m.group(1)) for m in LOCAL_ANCHOR_LINK.finditer(text)]
        for pos, a in hits:
            if a not in anchors:
                bad.append("%s:%d: #%s" % (rel, _line_of(text, pos), a))
    assert not bad, "%d link(s) to an anchor %s does not have:\n%s\nanchors: %s" \
        % (len(bad), MODEL, "\n".join(bad), " ".join(sorted(anchors)))
