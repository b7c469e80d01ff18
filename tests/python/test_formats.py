# SPDX-License-Identifier: GPL-2.0-or-later
"""crushpost.formats, the one definition of the files crushpost reads and
writes (issue "One topic per file", item 4): fields.h5 as the report writes
it on a synthetic run holds exactly the layout's groups, data sets and
attributes; the report refuses to write what the layout lacks; the event
log reader takes its columns from the definition. (The event log the C++
fix writes: tests/integration/test_event_log_format.py; summary.json's
keys: test_readme_summary_keys.py.)"""

import h5py
import pytest

from crushpost import formats
from crushpost.cli import main
from crushpost.dump import read_crush_log
from crushpost.report import HEADLINE_NAMES
from crushpost.report.common import ReportOptions, _Report

from test_report_cli import make_run


@pytest.fixture(scope="module")
def fields(tmp_path_factory):
    run = make_run(tmp_path_factory.mktemp("fmt") / "demo")
    out = run.parent / "report"
    assert main(["report", str(run), "--out", str(out), "--quiet"]) == 0
    return out / "fields.h5"


def _objects(f):
    groups, datasets = {}, {}

    def visit(name, obj):
        (datasets if isinstance(obj, h5py.Dataset) else groups)[name] = obj
    f.visititems(visit)
    return groups, datasets


def test_fields_h5_has_the_layout(fields):
    with h5py.File(fields, "r") as f:
        assert set(f.attrs) == set(formats.FIELDS_H5_ROOT_ATTRS)
        groups, datasets = _objects(f)
        seen = set()
        for name, ds in datasets.items():
            group, leaf = name.rsplit("/", 1)
            key = formats.fields_h5_group(group)
            assert key is not None, "%s: a group the layout lacks" % name
            formats.fields_h5_check(group, [leaf])
            seen.add(key)
        for name, g in groups.items():
            if name == formats.FIELDS_H5_HEADLINE or not g.attrs:
                continue
            formats.fields_h5_check(name, list(g.attrs), "attrs")
        # the synthetic run has every input but the snapshots' v_utilisation:
        # every other group of the layout is written
        assert seen | {"utilisation"} == set(formats.FIELDS_H5_GROUPS), \
            set(formats.FIELDS_H5_GROUPS) - seen
        pats = [formats._pattern(p) for p in formats.FIELDS_H5_HEADLINE_PATTERNS]
        for name in f[formats.FIELDS_H5_HEADLINE].attrs:
            assert name in HEADLINE_NAMES or any(p.match(name) for p in pats), name


def test_the_report_writes_nothing_outside_the_layout(tmp_path):
    rep = _Report(str(tmp_path), str(tmp_path), ReportOptions(), lambda m: None)
    rep.put("increments/03", dr_mean=[0.0])
    rep.put("utilisation", below_tip_p90=[1.0])
    rep.attrs("histories/r_over_R_2.5", r_over_R=2.5)
    with pytest.raises(KeyError):
        rep.put("qc", qc_typo=[1.0])
    with pytest.raises(KeyError):
        rep.put("no_such_group", step=[1])
    with pytest.raises(KeyError):
        rep.attrs("rings", no_such_attr=1)


def test_event_log_reader_uses_the_definition(tmp_path):
    cols = formats.EVENT_LOG_COLUMNS
    words = {c: "1" for c in cols}
    words["partner"] = formats.EVENT_LOG_PARTNERS[1]
    path = tmp_path / "events.txt"
    path.write_text("# fix crush/particle c: one line per breakage event\n# %s\n%s\n"
                    % (" ".join(cols), " ".join(words[c] for c in cols)))
    assert formats.event_log_header(path.read_text().splitlines()) == ("c", cols)
    ev = read_crush_log(path)
    assert set(cols) <= set(ev) and ev["partner_is_wall"].tolist() == [True]
    energy = cols + formats.EVENT_LOG_ENERGY_COLUMNS
    assert formats.event_log_columns(len(energy)) == energy
    with pytest.raises(ValueError):
        formats.event_log_header(["# step time", "# x"])
