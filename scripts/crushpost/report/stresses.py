# SPDX-License-Identifier: GPL-2.0-or-later
"""Ring fields and stress paths: the states' ring averages into fields.h5
and the headline, the initial state, the stress contours over q_c, radial
profiles, stress histories along r/R lines, and q/p' at the measurement
spheres."""

import math
import os

import numpy as np

from ..fields import interp_columns, interp_radius
from ..pile import tip_z_at
from ..stress import invariants
from .common import COMPONENTS, LABEL, ReportInputError, _fmt, _hatch_low, _pile_outline, _plt, _state_label
from .inputs import read_spheres_checked
from .qc import _qc_norm


def _store_states(rep, ctx):
    states, A, R = ctx["states"], ctx["A"], ctx["R"]
    qn = _qc_norm(rep, ctx)
    ctx["qc_norm"] = qn
    st = {"step": np.array([s["step"] for s in states], dtype=np.int64),
          "time": np.array([s["time"] for s in states]),
          "kind": np.array([s["kind"] for s in states], dtype="S"),
          "file": np.array([s["file"] for s in states], dtype="S"),
          "qc_norm": qn}
    if "z_tip" in states[0]:
        st["depth"] = np.array([s["depth"] for s in states])
        st["z_tip"] = np.array([s["z_tip"] for s in states])
        st["cycle"] = np.array([s["cycle"] for s in states], dtype=np.int64)
        ctx["h_over_R"] = (ctx["z_mid"][None, :] - st["z_tip"][:, None]) / R
        rep.put("rings", h_over_R=ctx["h_over_R"])
    rep.put("states", **st)
    rep.put("rings", r_edges=ctx["r_edges"], z_edges=ctx["z_edges"], r_mid=ctx["r_mid"],
            z_mid=ctx["z_mid"], r_over_R=ctx["r_mid"] / R, **A)
    rep.attrs("rings", sector=ctx["sector"], ring_width=ctx["ring_width"],
              ring_height=rep.opt.ring_height, min_grains=rep.opt.min_grains,
              z_ref=ctx["z_ref"], R=R)
    ok = A["low_count"] == 0
    rot = np.where(ok, np.abs(A["rotation"]), np.nan)
    if np.any(np.isfinite(rot)):
        k = np.unravel_index(np.nanargmax(rot), rot.shape)
        rep.head["max_rotation_deg"] = float(A["rotation"][k])
        rep.head_notes["max_rotation_deg"] = (
            "largest |rotation| of the (r, z) major principal axis since the first state, over "
            "the rings with at least %d grains: ring r/R = %.2f, z = %.4g m, at the state of "
            "step %d" % (rep.opt.min_grains, ctx["r_mid"][k[1]] / R, ctx["z_mid"][k[2]],
                         states[k[0]]["step"]))
    if states[0]["kind"] == "initial":
        okr = ok[0]
        rep.head["porosity_initial"] = float(np.mean(A["porosity"][0][okr])) if okr.any() \
            else float(np.mean(A["porosity"][0]))
        for c in COMPONENTS:
            v = A[c][0][okr] if okr.any() else A[c][0].ravel()
            rep.head[c + "_initial_kPa"] = float(np.mean(v) / 1e3)
        note = ("mean over the rings of the prepared state with at least %d grains"
                % rep.opt.min_grains if okr.any() else "mean over all rings of the prepared "
                "state (none has %d grains)" % rep.opt.min_grains)
        for name in ("porosity_initial",) + tuple(c + "_initial_kPa" for c in COMPONENTS):
            rep.head_notes[name] = note


def _fig_initial(rep, ctx):
    states, A, R = ctx["states"], ctx["A"], ctx["R"]
    if states[0]["kind"] != "initial":
        return
    plt = _plt()
    z_ref = ctx["z_ref"]
    re_ = ctx["r_edges"] / R
    de = (ctx["z_edges"] - z_ref) / R
    fig, axes = plt.subplots(1, 4, figsize=(12, 3.8), sharey=True)
    panels = [("porosity", A["porosity"][0], "porosity (-)", 1.0)] + [
        (c, A[c][0] / 1e3, LABEL[c] + " (kPa)", 1.0) for c in COMPONENTS]
    low = A["low_count"][0]
    for ax, (name, v, lab, _) in zip(axes, panels):
        m = ax.pcolormesh(re_, de, v.T, shading="flat", cmap="viridis")
        _hatch_low(ax, re_, de, low)
        fig.colorbar(m, ax=ax, label=lab, shrink=0.85)
        ax.set_xlabel("r / R (-)")
        ax.set_title(lab.split(" (")[0])
    axes[0].set_ylabel("(z - z_ref) / R, height above the sand surface (-)")
    fig.suptitle("prepared state (step %d): ring averages" % states[0]["step"], fontsize=10)
    fig.tight_layout()
    rep.figure(fig, "initial_state.png", "Initial state",
               "Ring averages of the prepared state (snapshots/prep_<step>.h5): porosity "
               "(1 - solid volume / ring volume, exact sphere-ring intersections) and the "
               "cylindrical stresses. Hatched rings hold fewer than %d grains (centres)."
               % rep.opt.min_grains)


def _fig_contours(rep, ctx):
    states, A, R = ctx["states"], ctx["A"], ctx["R"]
    if "h_over_R" not in ctx:
        rep.skip("stress contours", "no tip position (jack.txt)")
        return
    plt = _plt()
    qn = ctx["qc_norm"]
    re_ = ctx["r_edges"] / R
    names = []
    for k, s in enumerate(states):
        if s["kind"] == "initial":
            continue
        if not qn[k] > 0:
            rep.skip("stresses over q_c at the %s" % _state_label(s),
                     "q_c at the end of the last push is %s (the cone touched no grain; "
                     "--qc-norm steady normalises by the trend's plateau)" % _fmt(qn[k]))
            continue
        he = (ctx["z_edges"] - s["z_tip"]) / R
        fig, axes = plt.subplots(1, 3, figsize=(12, 4.2), sharey=True)
        for ax, c in zip(axes, COMPONENTS):
            v = A[c][k] / qn[k]
            m = ax.pcolormesh(re_, he, v.T, shading="flat", cmap="magma_r")
            finite = np.isfinite(v)
            # contour lines only on grids fine enough to draw them
            if finite.all() and min(v.shape) >= 4:
                rc = 0.5 * (re_[1:] + re_[:-1])
                hc = 0.5 * (he[1:] + he[:-1])
                try:
                    cs = ax.contour(rc, hc, v.T, colors="w", linewidths=0.6, levels=6)
                    ax.clabel(cs, fontsize=6, fmt="%.2g")
                except (ValueError, TypeError):
                    pass
            _hatch_low(ax, re_, he, A["low_count"][k])
            _pile_outline(ax, he[-1])
            fig.colorbar(m, ax=ax, label=LABEL[c] + " / q_c (-)", shrink=0.85)
            ax.set_xlabel("r / R (-)")
            ax.set_xlim(0, re_[-1])
            ax.set_ylim(he[0], he[-1])
        axes[0].set_ylabel("h / R, height above the cone apex (-)")
        fig.suptitle("%s: stresses over q_c = %.3g MPa" % (_state_label(s), qn[k] / 1e6),
                     fontsize=10)
        fig.tight_layout()
        name = "stress_%s%s.png" % ({"push_end": "push", "pause_end": "pause"}.get(
            s["kind"], "state"), s.get("cycle", ""))
        if name in names:
            name = name[:-4] + "_step%d.png" % s["step"]
        rep.figure(fig, name, "Stresses around the pile, %s" % _state_label(s),
                   "Ring averages of sigma_r, sigma_theta, sigma_z over q_c (%s) in (r/R, h/R); "
                   "h is the height above the cone apex at this state. Hatched: fewer than %d "
                   "grains in the ring."
                   % ("q_c at the end of the last push" if rep.opt.qc_norm == "push"
                      else "steady q_c", rep.opt.min_grains))
        names.append(name)


def _fig_profiles(rep, ctx):
    states, A, R = ctx["states"], ctx["A"], ctx["R"]
    if "h_over_R" not in ctx:
        return
    plt = _plt()
    qn = ctx["qc_norm"]
    hs = np.array(rep.opt.profile_h, dtype=float)
    rmid = ctx["r_mid"] / R
    ks = [k for k, s in enumerate(states) if s["kind"] != "initial" and qn[k] > 0]
    if not ks:
        return
    prof = np.full((len(states), hs.size, rmid.size, 3), np.nan)
    for k in ks:
        zt = states[k]["z_tip"] + hs * R
        for j, c in enumerate(COMPONENTS):
            prof[k, :, :, j] = interp_columns(A[c][k], ctx["z_mid"], zt) / qn[k]
    rep.put("profiles", h_over_R=hs, r_over_R=rmid, values=prof)
    rep.attrs("profiles", layout="values[state, h, ring column, component]; components "
              "sigma_r, sigma_theta, sigma_z over q_c; linear in z between layer centres, "
              "NaN outside them")
    fig, axes = plt.subplots(hs.size, 3, figsize=(11, 2.6 * hs.size), squeeze=False,
                             sharex=True)
    cmap = plt.get_cmap("viridis")
    for i, h in enumerate(hs):
        for j, c in enumerate(COMPONENTS):
            ax = axes[i, j]
            for n, k in enumerate(ks):
                ls = "-" if states[k]["kind"] == "push_end" else ":"
                ax.plot(rmid, prof[k, i, :, j], ls, marker=".", color=cmap(n / max(len(ks) - 1, 1)),
                        label=_state_label(states[k]) if i == 0 and j == 0 else None)
            ax.set_title("%s / q_c at h/R = %g" % (LABEL[c], h), fontsize=9)
            ax.grid(True, alpha=0.3)
            if i == hs.size - 1:
                ax.set_xlabel("r / R (-)")
    axes[0, 0].legend(fontsize=6)
    fig.tight_layout()
    rep.figure(fig, "radial_profiles.png", "Radial profiles",
               "Ring-averaged stresses over q_c against r/R at chosen heights h/R above the "
               "apex (--profile-h), linear in z between layer centres; solid: ends of pushes, "
               "dotted: ends of pauses. Gaps: the height is outside the sample.")


def _fig_histories(rep, ctx):
    states, A, R = ctx["states"], ctx["A"], ctx["R"]
    if "h_over_R" not in ctx:
        return
    plt = _plt()
    qn = ctx["qc_norm"]
    ks = [k for k, s in enumerate(states) if s["kind"] != "initial" and qn[k] > 0]
    re_ = ctx["r_edges"] / R
    rm = ctx["r_mid"] / R
    lines = []
    for r in rep.opt.history_r:
        if not re_[0] <= r <= re_[-1]:
            rep.skip("stress history at r/R = %g" % r, "outside this chamber (r/R <= %.3g)"
                     % re_[-1])
            continue
        lines.append(r)
    if not lines or not ks:
        return
    fig, axes = plt.subplots(len(lines), 3, figsize=(11, 2.8 * len(lines)), squeeze=False)
    n_z = ctx["z_mid"].size
    cmap = plt.get_cmap("plasma")
    hr = ctx["h_over_R"][ks]                           # (n_k, n_z)
    for a, r in enumerate(lines):
        grp = "histories/r_over_R_%g" % r
        # linear in r between the centres of the two ring columns around r
        vals = {c: interp_radius(A[c][ks], rm, r, axis=1) / qn[ks][:, None] for c in COMPONENTS}
        rep.put(grp, state=np.array(ks), h_over_R=hr, **vals)
        rep.attrs(grp, r_over_R=r)
        for j, c in enumerate(COMPONENTS):
            ax = axes[a, j]
            for z in range(n_z):
                ax.plot(vals[c][:, z], hr[:, z], "-o", ms=2.5, lw=0.8,
                        color=cmap(z / max(n_z - 1, 1)),
                        label="layer z = %.3g m" % ctx["z_mid"][z] if a == 0 and j == 0 else None)
            ax.axhline(0.0, color="k", lw=0.5, ls=":")
            ax.set_title("%s / q_c at r/R = %g" % (LABEL[c], r), fontsize=9)
            ax.set_ylabel("h / R (-)")
            ax.grid(True, alpha=0.3)
    axes[0, 0].legend(fontsize=6)
    fig.tight_layout()
    rep.figure(fig, "stress_history.png", "Stress histories along r/R lines",
               "Each curve follows one fixed point (a layer's centre height on the line r/R, "
               "linear in r between the two ring columns around it) through the states (ends "
               "of pushes and pauses): its stress over q_c against its height h/R above the "
               "apex, which rises as the tip goes down past it.")


def _spheres(rep, ctx):
    block, series = rep.path("spheres.in"), rep.path("spheres.txt")
    if not os.path.exists(block) or not os.path.exists(series):
        missing = block if not os.path.exists(block) else series
        rep.skip("measurement spheres", "%s: no such file" % missing)
        return
    try:
        centres, radius, steps, sigma = read_spheres_checked(block, series)
    except ReportInputError as exc:
        rep.error(str(exc))
        return
    inv = invariants(sigma)
    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = np.where(inv.p > 0, inv.q / inv.p, np.nan)
    grp = {"step": steps, "centres": centres, "p": inv.p, "q": inv.q, "q_over_p": ratio}
    jack, R = ctx["jack"], ctx["R"]
    plt = _plt()
    fig, ax = plt.subplots(figsize=(5.2, 4.4))
    if jack is not None:
        z_tip = tip_z_at(steps, jack["step"], jack["depth"], ctx["z_ref"])
        hr = (centres[None, :, 2] - z_tip[:, None]) / R
        grp["h_over_R"] = hr
        for s in range(centres.shape[0]):
            ax.plot(ratio[:, s], hr[:, s], "-", lw=1,
                    label="sphere %d: r/R = %.2f, z = %.3g m"
                    % (s + 1, math.hypot(centres[s, 0], centres[s, 1]) / R, centres[s, 2]))
        ax.set_ylabel("h / R, sphere centre above the apex (-)")
        ax.axhline(0.0, color="k", lw=0.5, ls=":")
    else:
        for s in range(centres.shape[0]):
            ax.plot(steps, ratio[:, s], "-", lw=1, label="sphere %d" % (s + 1))
        ax.set_ylabel("step")
    ax.set_xlabel("q / p' (-)")
    ax.legend(fontsize=7)
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    rep.put("spheres", **grp)
    rep.attrs("spheres", radius=radius)
    if np.any(np.isfinite(ratio)):
        k = np.unravel_index(np.nanargmax(ratio), ratio.shape)
        rep.head["peak_q_over_p"] = float(ratio[k])
        rep.head_notes["peak_q_over_p"] = (
            "largest q/p' of the measurement spheres (sphere %d, step %d); q = sqrt(3 J2)"
            % (k[1] + 1, steps[k[0]]))
    rep.figure(fig, "spheres_q_over_p.png", "q/p' at the measurement spheres",
               "Stress ratio q/p' (q = sqrt(3 J2), p' = tr/3) of each measurement sphere "
               "(spheres.txt; radius %.3g mm) against its height above the apex." % (radius * 1e3))
