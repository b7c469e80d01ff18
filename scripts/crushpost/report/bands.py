# SPDX-License-Identifier: GPL-2.0-or-later
"""Breakage: Br in radial bands x layers through the states, the map of
where grains break relative to the tip, the events by zone, and the
grains' utilisation by zone."""

import math

import numpy as np

from ..breakage import break_fines
from ..formats import SUMMARY as S
from ..fields import cell_breakage, event_density
from ..pile import (UTILISATION_ZONES, ZONE_DEPTH_MIN, ZONE_H_BELOW, ZONE_R_MAX, events_by_zone,
                    inside_pile, relative_to_tip, utilisation_by_zone)
from .common import D_MAX_REAL, D_MIN_REAL, _pile_outline, _plt, _short_label, _state_label


def _band_edges(r_max, width):
    """Band edges in r/R from 1 (the shaft) to r_max by ``width``; the last
    band ends at r_max (one narrower than width/4 joins the band before)."""
    edges = list(np.arange(1.0, r_max, width))
    if r_max - edges[-1] < 0.25 * width and len(edges) > 1:
        edges[-1] = r_max
    else:
        edges.append(r_max)
    return np.array(edges)


def _band_cell(r_over_R, z, b_edges, z_edges):
    """Cell index band * n_z + layer of points (-1 outside)."""
    n_b, n_z = b_edges.size - 1, z_edges.size - 1
    i = np.searchsorted(b_edges, r_over_R, side="right") - 1
    k = np.searchsorted(z_edges, z, side="right") - 1
    ok = (i >= 0) & (i < n_b) & (k >= 0) & (k < n_z)
    return np.where(ok, i * n_z + k, -1)


def _bands_start(rep, ctx):
    """The record of Br in bands and the PSD through the states (sizes of
    the PSD in ctx["psd_sizes"]), or None (said) when N is unknown."""
    N = ctx["N"]
    if not N:
        rep.skip("Br in bands, PSD", "the up-scaling factor N is unknown (no summary.json): "
                 "give --N")
        return None
    d_min, d_max = D_MIN_REAL * N, D_MAX_REAL * N
    ctx["psd_sizes"] = np.geomspace(d_min, d_max, 60)
    if ctx["events"] is None:
        rep.skip("fines in Br and the PSD", "no event log: Br in bands and the PSD count the "
                 "grains only (right for unbreakable grains)")
    return {"d_min": d_min, "d_max": d_max, "sizes": ctx["psd_sizes"], "first": None,
            "rows": [], "psd_rows": [], "opt": rep.opt}


def _bands_step(ctx, bands, info, x, rad, ids, r_edges, z_edges):
    """Br of the state in bands x layers, whole bands and whole bands over
    the penetrated layers into bands["rows"]; returns the fines of the
    breaks since the first state (for the PSD; None without)."""
    R, events, opt = ctx["R"], ctx["events"], bands["opt"]
    d_min, d_max = bands["d_min"], bands["d_max"]
    n_z = z_edges.size - 1
    b_edges = _band_edges(r_edges[-1] / R, opt.band_width)
    rr = np.hypot(x[:, 0], x[:, 1]) / R
    cell = _band_cell(rr, x[:, 2], b_edges, z_edges)
    if bands["first"] is None:
        bands["first"] = {"cell": cell, "d": 2 * rad, "ids": ids, "step": info["step"],
                          "z": x[:, 2]}
    first = bands["first"]
    fines = None
    ev_sel = None
    if events is not None:
        # the breaks since the first state (earlier ones are in its grains)
        ev_sel = (events["step"] > first["step"]) & (events["step"] <= info["step"])
        erho = np.hypot(events["x"][ev_sel], events["y"][ev_sel]) / R
        ev_cell = _band_cell(erho, events["z"][ev_sel], b_edges, z_edges)
        pd = events["parent_diameter"][ev_sel]
        fines = break_fines(pd, density=opt.density) if pd.size else None
    else:
        ev_cell, pd = None, None
    n_cells = (b_edges.size - 1) * n_z
    br, M, M0 = cell_breakage(cell, 2 * rad, first["cell"], first["d"], n_cells, d_min,
                              d_max, ev_cell, pd, density=opt.density)
    # whole bands over the full height: a second pass with one layer
    cb = np.where(cell >= 0, cell // n_z, -1)
    cb0 = np.where(first["cell"] >= 0, first["cell"] // n_z, -1)
    evb = None if ev_cell is None else np.where(ev_cell >= 0, ev_cell // n_z, -1)
    br_b, _, _ = cell_breakage(cb, 2 * rad, cb0, first["d"], b_edges.size - 1, d_min,
                               d_max, evb, pd, density=opt.density)
    br_p = _band_penetrated(ctx, bands, info, x, rad, cb, cb0, evb, ev_sel, pd, b_edges)
    bands["rows"].append((br.reshape(-1, n_z), br_b, br_p))
    ctx["band_edges"] = b_edges
    return fines


def _band_penetrated(ctx, bands, info, x, rad, cb, cb0, evb, ev_sel, pd, b_edges):
    """Br of whole bands over the layers the tip has passed (z_tip < z <
    z_ref): the penetrated height, not the untouched sand below the tip."""
    first, opt, events = bands["first"], bands["opt"], ctx["events"]
    br_p = np.full(b_edges.size - 1, np.nan)
    z_tip = info.get("z_tip")
    if z_tip is not None and z_tip < ctx["z_ref"]:
        def passed(zz):
            return (zz > z_tip) & (zz < ctx["z_ref"])
        cp = np.where(passed(x[:, 2]), cb, -1)
        cp0 = np.where(passed(first["z"]), cb0, -1)
        evp = None if evb is None else np.where(passed(events["z"][ev_sel]), evb, -1)
        br_p, _, _ = cell_breakage(cp, 2 * rad, cp0, first["d"], b_edges.size - 1,
                                   bands["d_min"], bands["d_max"], evp, pd, density=opt.density)
    return br_p


def _bands_finish(rep, ctx, bands):
    """The states' Br into ctx and the headline Br of the penetrated bands."""
    rows = bands["rows"]
    ctx["Br_cells"] = np.array([b for b, _, _ in rows])
    ctx["Br_bands"] = np.array([b for _, b, _ in rows])
    ctx["Br_bands_penetrated"] = np.array([b for _, _, b in rows])
    last_pen = ctx["Br_bands_penetrated"][-1]
    b_edges = ctx["band_edges"]
    for lo, key in ((1.0, "Br_penetrated_1_2R"), (2.0, "Br_penetrated_2_3R")):
        k = np.flatnonzero(np.isclose(b_edges[:-1], lo) & np.isclose(b_edges[1:], lo + 1.0))
        if k.size and np.isfinite(last_pen[k[0]]):
            rep.head[key] = float(last_pen[k[0]])
            rep.head_notes[key] = (
                "Br of the band %g < r/R < %g over the layers the tip has passed (between the "
                "tip and the sand surface) at the last snapshot" % (lo, lo + 1))


def _utilisation_step(ctx, info, p, x):
    """Utilisation of the grains by zone around the tip (compute crush/atom
    through the decks' v_utilisation) at the ends of pushes."""
    u = p.get("values", {}).get("v_utilisation")
    if u is not None and info.get("z_tip") is not None and info.get("kind") == "push_end":
        hh_u, rr_u = relative_to_tip(x[:, 0], x[:, 1], x[:, 2], info["z_tip"], ctx["R"])
        ctx.setdefault("utilisation", []).append(
            (info, utilisation_by_zone(hh_u, rr_u, np.ravel(u))))


def _fig_bands(rep, ctx):
    if "Br_cells" not in ctx:
        return
    plt = _plt()
    states = ctx["states"]
    b_edges = ctx["band_edges"]
    br = ctx["Br_cells"]                  # (n_state, n_band, n_z)
    brb = ctx["Br_bands"]                 # (n_state, n_band)
    rep.put("breakage/bands", band_edges_over_R=b_edges, z_edges=ctx["z_edges"], Br=br,
            Br_band=brb, Br_band_penetrated=ctx["Br_bands_penetrated"])
    rep.attrs("breakage/bands", definition=(
        "bounded Einav Br of the grains whose centre is in band x layer now, plus the fines of "
        "the breaks whose parent was in it (fractal), against the grains in it in the first "
        "state; Br_band: the whole height; Br_band_penetrated: the layers between the tip and "
        "the sand surface (NaN for the prepared state)"))
    last = len(states) - 1
    z_tip = states[last].get("z_tip")
    bands = ["%.3g<r/R<%.3g" % (b_edges[i], b_edges[i + 1]) for i in range(b_edges.size - 1)]
    if z_tip is not None:
        k = int(np.clip(np.searchsorted(ctx["z_edges"], z_tip, side="right") - 1, 0,
                        ctx["z_mid"].size - 1))
        for i, b in enumerate(bands):
            name = "Br_band_%.3g_%.3g" % (b_edges[i], b_edges[i + 1])
            rep.head[name] = float(br[last, i, k])
            rep.head_notes[name] = (
                "Br of band %s in the layer that holds the final tip (%.4g < z < %.4g m)"
                % (b, ctx["z_edges"][k], ctx["z_edges"][k + 1]))
    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    bm = 0.5 * (b_edges[1:] + b_edges[:-1])
    cmap = plt.get_cmap("viridis")
    nz = ctx["z_mid"].size
    for z in range(nz):
        depth = (ctx["z_ref"] - ctx["z_mid"][z]) * 1e3
        axes[0].plot(bm, br[last, :, z], "-o", ms=3, color=cmap(z / max(nz - 1, 1)),
                     label="depth %.3g mm" % depth)
    axes[0].set_xlabel("band centre r / R (-)")
    axes[0].set_ylabel("Br (-)")
    axes[0].set_title(_state_label(states[last]), fontsize=9)
    axes[0].legend(fontsize=6)
    axes[0].grid(True, alpha=0.3)
    for i, b in enumerate(bands):
        axes[1].plot(np.arange(len(states)), brb[:, i], "-o", ms=3, label=b)
    axes[1].set_xticks(np.arange(len(states)))
    axes[1].set_xticklabels([_short_label(s) for s in states], fontsize=7, rotation=90)
    axes[1].set_ylabel("Br over the whole height (-)")
    axes[1].legend(fontsize=6)
    axes[1].grid(True, alpha=0.3)
    fig.tight_layout()
    rep.figure(fig, "br_bands.png", "Breakage in radial bands",
               "Bounded Br (Einav) per radial band and layer (depth of the layer centre below "
               "the sand surface) at the last state, and per band over the whole height "
               "through the states. A band's grading: its grains now (by centre) plus the fines "
               "of the breaks whose parent was in it, against its grains at the first state.")


def _zones(rep, zones):
    """Events by zone (crushpost.pile.events_by_zone): switch-on, entry, the
    crushing zone at the cone, along the shaft, beyond 5R below the tip;
    all zero for an empty event log (fraction_in_zone then undefined)."""
    for k in ("switch_on", "entry", "penetration", "in_zone", "along_shaft", "beyond_5R_below",
              "elsewhere"):
        rep.head["events_" + k] = zones[k]
    rep.head["fraction_in_zone"] = zones["fraction_in_zone"]
    rep.head_notes["events_in_zone"] = (
        "break events during penetration (after the first step, tip deeper than %gR) within "
        "r < %gR and -%gR < h < 1.73R (the cone's shoulder); crushpost.pile.break_zones"
        % (ZONE_DEPTH_MIN, ZONE_R_MAX, ZONE_H_BELOW))
    rep.put("breakage/zones", **{k: np.asarray(v) for k, v in zones.items()})


def _breakage_map(rep, ctx):
    events, jack, R = ctx["events"], ctx["jack"], ctx["R"]
    if events is None:
        return
    if jack is None:
        rep.skip("breakage density map", "no tip position (jack.txt)")
        return
    zones, hh, rr, z_tip = events_by_zone(
        events, jack["step"], jack["depth"], ctx["z_ref"], R, ctx.get("jack_first_step"),
        crushing_before=bool(ctx["summary"].get(S.crush_in_prep)))
    _zones(rep, zones)
    if events["step"].size == 0:
        # counted above: an empty log is a measurement (no break in any zone)
        rep.skip("breakage density map", "%s: no breakage event" % rep.path("breakage_events.txt"))
        return
    plt = _plt()
    inside = inside_pile(hh, rr)
    sector = ctx.get("sector") or rep.opt.sector or ctx["summary"].get(S.sector_deg) or 360
    r_edges = np.arange(0.0, max(2.0, float(rr.max())) + 0.25, 0.25)
    h_lo = math.floor(float(hh.min()) * 2) / 2
    h_hi = math.ceil(float(hh.max()) * 2) / 2 + 0.5
    h_edges = np.arange(h_lo, h_hi + 1e-9, 0.25)
    dens, cnt = event_density(hh, rr, h_edges, r_edges, sector)
    rep.put("breakage/events", step=events["step"], h_over_R=hh, r_over_R=rr,
            tip_depth=ctx["z_ref"] - z_tip, inside_pile=inside.astype(np.int8),
            parent_diameter=events["parent_diameter"], generation=events["generation"])
    rep.put("breakage/density", r_edges_over_R=r_edges, h_edges_over_R=h_edges, count=cnt,
            density_per_R3=dens)
    rep.attrs("breakage/density", definition="events per unit volume (R^3) of each (r/R, h/R) "
              "cell, a ring about the axis in the simulated sector of %d deg" % sector)
    fig, ax = plt.subplots(figsize=(5.2, 5))
    with np.errstate(divide="ignore"):
        m = ax.pcolormesh(r_edges, h_edges, np.ma.masked_equal(dens, 0).T, cmap="inferno_r",
                          shading="flat")
    fig.colorbar(m, ax=ax, label="breakage events per R^3")
    _pile_outline(ax, h_edges[-1])
    ax.axhline(0.0, color="k", lw=0.5, ls=":")
    ax.set_xlabel("r / R, distance from the pile axis (-)")
    ax.set_ylabel("h / R, height above the cone apex at the event (-)")
    ax.set_title("%d breakage events%s" % (hh.size, " (%d inside the pile!)" % inside.sum()
                                            if inside.any() else ""), fontsize=9)
    ax.set_ylim(h_edges[0], h_edges[-1])
    fig.tight_layout()
    rep.figure(fig, "breakage_density.png", "Where grains break",
               "Breakage events (breakage_events.txt: the parent's centre at the event) "
               "relative to the tip at the event's step, per unit volume of each ring-shaped "
               "(r/R, h/R) cell of 0.25 R x 0.25 R.")


def _fig_utilisation(rep, ctx):
    """How far the grains' contacts stand from their limits, by zone, at the
    last end of a push (steady penetration)."""
    rows = ctx.get("utilisation")
    if not rows:
        rep.skip("utilisation by zone", "the snapshots carry no v_utilisation (decks before "
                 "compute crush/atom, or unbreakable grains)")
        return
    info, zones = rows[-1]
    names = [z[0] for z in UTILISATION_ZONES]
    for z in names:
        for stat in ("median", "p90", "max"):
            rep.head["utilisation_%s_%s" % (z, stat)] = zones[z][stat]
    rep.head_notes["utilisation_below_tip_max"] = (
        "utilisation = the largest F_n / F_lim over a grain's contacts (compute crush/atom), "
        "at the last end of a push (step %d); zones in R around the apex: %s"
        % (info["step"], "; ".join("%s %g<=r<%g, %g<=h<%g" % z for z in UTILISATION_ZONES)))
    rep.put("utilisation", step=np.array([i["step"] for i, _ in rows]),
            **{"%s_%s" % (z, st): np.array([zz[z][st] for _, zz in rows])
               for z in names for st in ("n", "median", "p90", "max")})
    plt = _plt()
    fig, ax = plt.subplots(figsize=(5.6, 4.2))
    for z in names:
        v = np.sort(zones["values"][z])
        v = v[v > 0]
        if v.size:
            ax.step(v, np.arange(1, v.size + 1) / v.size, where="post",
                    label="%s (%d grains in contact)" % (z.replace("_", " "), v.size))
    ax.axvline(1.0, color="k", lw=0.8, ls=":")
    ax.set_xscale("log")
    ax.set_xlabel("utilisation: largest F_n / F_lim of the grain's contacts (-)")
    ax.set_ylabel("fraction of the zone's grains below (-)")
    ax.set_title("contacts against their limits, step %d" % info["step"], fontsize=9)
    ax.legend(fontsize=7)
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    rep.figure(fig, "utilisation.png", "Contacts against their limits",
               "Distribution of each grain's utilisation (its largest F_n / F_lim, with the run's "
               "criterion reading) by zone around the tip at the last end of a push; 1 (dotted) "
               "breaks the grain.")
