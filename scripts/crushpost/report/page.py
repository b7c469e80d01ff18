# SPDX-License-Identifier: GPL-2.0-or-later
"""report.html: the run's settings, the headline numbers against a
reference, the problems and every figure with its caption."""

import html
import os

import numpy as np

from .common import HEADLINE_NAMES, _fmt


def _write_html(rep, ctx, reference):
    e = html.escape
    rows = []
    ref = dict(reference or {})
    names = list(rep.head.keys())
    for name in names:
        v = rep.head[name]
        unit = HEADLINE_NAMES.get(name, "-")
        r = ref.pop(name, None)
        if r is not None:
            dv = ("%+.1f %%" % (100.0 * (v - r["value"]) / r["value"])
                  if r["value"] not in (0, 0.0) and np.isfinite(v) else "")
            rcell = "%s %s" % (_fmt(r["value"]), e(r["unit"]))
            rsrc = e(r["source"])
        else:
            dv, rcell, rsrc = "", "", ""
        val = _fmt(v)
        if name == "qc_steady_MPa" and "qc_steady_err_MPa" in rep.head:
            val += " &plusmn; %s (fit s.e.)" % _fmt(rep.head["qc_steady_err_MPa"])
            if "qc_run_scatter_MPa" in rep.head:
                val += " &plusmn; %s (run to run)" % _fmt(rep.head["qc_run_scatter_MPa"])
        rows.append("<tr><td>%s</td><td>%s</td><td>%s</td><td>%s</td><td>%s</td><td>%s</td>"
                    "<td class=note>%s</td></tr>"
                    % (e(name), val, e(unit), rcell, dv, rsrc, e(rep.head_notes.get(name, ""))))
    for name, r in ref.items():
        rows.append("<tr><td>%s</td><td>not in this report</td><td></td><td>%s %s</td><td></td>"
                    "<td>%s</td><td></td></tr>" % (e(name), _fmt(r["value"]), e(r["unit"]),
                                                   e(r["source"])))
    settings = "".join("<tr><td>%s</td><td>%s</td></tr>" % (e(k), e(str(v)))
                       for k, v in rep.settings)
    probs = "".join("<li class=%s>%s</li>" % (k, e(m)) for k, m in rep.problems) or \
        "<li>none</li>"
    figs = "".join("<figure><h3>%s</h3><img src=\"%s\" alt=\"%s\"><figcaption>%s</figcaption>"
                   "</figure>" % (e(t), e(f), e(t), e(c)) for f, t, c in rep.figures)
    doc = """<!DOCTYPE html>
<html><head><meta charset="utf-8"><title>Chamber run report: %(run)s</title>
<style>body{font-family:sans-serif;max-width:1200px;margin:1em auto;font-size:14px}
table{border-collapse:collapse}td,th{border:1px solid #bbb;padding:2px 6px;vertical-align:top}
td.note{font-size:12px;color:#444}li.error{color:#a00}img{max-width:100%%}
figure{margin:1em 0;border-top:1px solid #ddd}figcaption{font-size:12px;color:#333}</style>
</head><body>
<h1>Chamber run report</h1>
<p>Made by <code>crushpost report</code>; the numbers behind every figure are in
<a href="fields.h5">fields.h5</a> (layout: docs/report.md).</p>
<h2>Settings</h2><table>%(settings)s</table>
<h2>Headline numbers</h2>
<table><tr><th>name</th><th>this run</th><th>unit</th><th>reference</th><th>run vs reference</th>
<th>reference source</th><th>how it was measured</th></tr>%(rows)s</table>
<h2>Inputs missing or bad</h2><ul>%(probs)s</ul>
<h2>Figures</h2>%(figs)s
</body></html>
""" % {"run": e(os.path.abspath(rep.run)), "settings": settings, "rows": "".join(rows),
       "probs": probs, "figs": figs}
    with open(os.path.join(rep.out, "report.html"), "w") as f:
        f.write(doc)
