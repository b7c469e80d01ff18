# SPDX-License-Identifier: GPL-2.0-or-later
"""Radial displacement increments between consecutive states."""

import math

import numpy as np

from ..fields import binned_mean, radial_increments
from .common import _pile_outline, _plt


def _fig_increments(rep, ctx):
    incr, R = ctx["incr"], ctx["R"]
    if not incr:
        return
    plt = _plt()
    n = len(incr)
    cols = min(n, 4)
    rows = int(math.ceil(n / cols))
    fig, axes = plt.subplots(rows, cols, figsize=(3.3 * cols, 3.6 * rows), squeeze=False)
    d_all = np.concatenate([c["dr"] for c in incr])
    lim = float(np.percentile(np.abs(d_all), 98)) / R if d_all.size else 1.0
    lim = lim or 1e-6
    for k, c in enumerate(incr):
        ax = axes[k // cols, k % cols]
        grp = "increments/%02d" % k
        rep.put(grp, dr_mean=c["mean"], count=c["count"])
        rep.attrs(grp, from_step=c["from"]["step"], to_step=c["to"]["step"],
                  from_kind=c["from"]["kind"], to_kind=c["to"]["kind"],
                  n_matched=c["n_matched"], n_gone=c["n_only0"], n_new=c["n_only1"])
        ref = c["z_tip"] if c["z_tip"] is not None else ctx["z_ref"]
        sc = ax.scatter(c["r0"] / R, (c["z0"] - ref) / R, c=c["dr"] / R, s=3, cmap="RdBu_r",
                        vmin=-lim, vmax=lim, rasterized=True, lw=0)
        if c["z_tip"] is not None:
            _pile_outline(ax, float(np.max((c["z0"] - ref) / R)) if c["z0"].size else 1.0)
        what = "push" if c["to"]["kind"] == "push_end" else \
            "unload + pause" if c["to"]["kind"] == "pause_end" else "increment"
        ax.set_title("%s %s (%d grains)" % (what, c["to"].get("cycle", ""), c["n_matched"]),
                     fontsize=8)
        ax.set_xlabel("r / R at the start (-)", fontsize=8)
        if k % cols == 0:
            ax.set_ylabel("h / R, above the apex at the end (-)" if c["z_tip"] is not None
                          else "(z - z_ref) / R (-)", fontsize=8)
    for k in range(n, rows * cols):
        axes[k // cols, k % cols].axis("off")
    fig.colorbar(sc, ax=axes.ravel().tolist(), label="radial increment dr / R (-)", shrink=0.8)
    rep.figure(fig, "radial_increments.png", "Radial displacement increments",
               "dr = r_end - r_start of each grain present in both states (matched by id: "
               "grains that broke in between and their fragments are left out), over every "
               "push and every unload + pause; colour scale clipped at the 98th percentile "
               "of |dr|. fields.h5 holds the ring means.")



def _increment_step(incr, prev, info, ids, x, r_edges, z_edges):
    """The radial displacement increments since the previous state (prev,
    None for the first) into ``incr``; returns this state as the next prev."""
    if prev is not None:
        inc = radial_increments(prev["ids"], prev["x"], ids, x)
        x0 = prev["x"][inc["rows0"]]
        r0 = np.hypot(x0[:, 0], x0[:, 1])
        mean, cnt = binned_mean(r0, x0[:, 2], inc["dr"], r_edges, z_edges)
        z_tip = info.get("z_tip")
        incr.append({"from": prev["info"], "to": info, "r0": r0, "z0": x0[:, 2],
                     "dr": inc["dr"], "mean": mean, "count": cnt, "z_tip": z_tip,
                     "n_matched": inc["n_matched"], "n_only0": inc["n_only0"],
                     "n_only1": inc["n_only1"]})
    return {"ids": ids, "x": x, "info": info}
