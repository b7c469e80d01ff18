# SPDX-License-Identifier: GPL-2.0-or-later
"""The rotation of the principal axes of the ring averages (figure)."""

import numpy as np

from .common import _hatch_low, _pile_outline, _plt, _short_label, _state_label


def _fig_rotation(rep, ctx):
    states, A, R = ctx["states"], ctx["A"], ctx["R"]
    if len(states) < 2:
        return
    plt = _plt()
    last = len(states) - 1
    re_ = ctx["r_edges"] / R
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    if "h_over_R" in ctx:
        ye = (ctx["z_edges"] - states[last]["z_tip"]) / R
        ylab = "h / R at the last state (-)"
    else:
        ye = (ctx["z_edges"] - ctx["z_ref"]) / R
        ylab = "(z - z_ref) / R (-)"
    rot = A["rotation"][last]
    lim = max(90.0, float(np.nanmax(np.abs(rot))) if np.any(np.isfinite(rot)) else 90.0)
    m = axes[0].pcolormesh(re_, ye, rot.T, cmap="RdBu_r", vmin=-lim, vmax=lim, shading="flat")
    _hatch_low(axes[0], re_, ye, A["low_count"][last])
    if "h_over_R" in ctx:
        _pile_outline(axes[0], ye[-1])
        axes[0].set_ylim(ye[0], ye[-1])
    fig.colorbar(m, ax=axes[0], label="rotation since the first state (deg)")
    axes[0].set_xlabel("r / R (-)")
    axes[0].set_ylabel(ylab)
    axes[0].set_title(_state_label(states[last]), fontsize=9)
    ok = A["low_count"] == 0
    steps = np.arange(len(states))
    cand = np.where(ok.all(axis=0), np.nanmax(np.abs(A["rotation"]), axis=0), -1.0)
    top = np.argsort(cand.ravel())[::-1][:6]
    for f in top:
        i, z = np.unravel_index(f, cand.shape)
        if cand[i, z] < 0:
            continue
        axes[1].plot(steps, A["rotation"][:, i, z], "-o", ms=3,
                     label="r/R = %.2f, z = %.3g m" % (ctx["r_mid"][i] / R, ctx["z_mid"][z]))
    axes[1].set_xticks(steps)
    axes[1].set_xticklabels([_short_label(s) for s in states], fontsize=7, rotation=90)
    axes[1].set_ylabel("rotation of the major axis (deg)")
    axes[1].set_title("the rings that turned most", fontsize=9)
    axes[1].grid(True, alpha=0.3)
    axes[1].legend(fontsize=6)
    fig.tight_layout()
    rep.figure(fig, "rotation.png", "Rotation of the principal axes",
               "Angle of the major principal direction of the (sigma_r, tau_rz; tau_rz, "
               "sigma_z) ring average from the vertical, unwrapped through the states (each "
               "step the smallest change modulo 180 deg) and taken relative to the first state, "
               "at fixed rings. Needs states close enough that the axis turns < 90 deg between "
               "two (docs/report.md).")
