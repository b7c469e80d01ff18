# SPDX-License-Identifier: GPL-2.0-or-later
"""Error against run time: the pure functions of bench/error_vs_runtime.

A study runs one reference setting and variants that change one thing at a
time (docs/studies/error-vs-runtime.md). For every run it records what it cost
(wall time, core-seconds, particle-steps) and a few result numbers; this
module turns those into errors relative to the reference, says which errors
lie inside the reference's own seed-to-seed scatter (noise), and marks the
Pareto front of error against cost. Everything here is vectorised numpy on
plain arrays; the reading of run folders is in `chamber_metrics` and
`oedometer_metrics`, that of the study's committed results table (the
run-to-run scatter a single run's report quotes) in `qc_run_scatter`.
"""

import json
import os
import warnings

import numpy as np

from .formats import FIELDS_H5_HEADLINE, SUMMARY as S, fields_h5_group, fields_h5_path


def particle_steps(step, atoms):
    """Particle-steps of a run from its thermo lines: the number of grains
    integrated over the steps (trapezoid between lines, so a count that
    grows by breakage is followed). step, atoms: 1-D arrays in step order."""
    step = np.asarray(step, float)
    atoms = np.asarray(atoms, float)
    if step.size < 2:
        return 0.0
    return float(np.sum(0.5 * (atoms[1:] + atoms[:-1]) * np.diff(step)))


def relative_error(value, reference):
    """(value - reference) / |reference|, elementwise; NaN where the
    reference is 0 or not finite."""
    v = np.asarray(value, float)
    r = np.asarray(reference, float)
    ok = np.isfinite(r) & (r != 0)
    return np.where(ok, (v - r) / np.where(ok, np.abs(r), 1.0), np.nan)


def seed_scatter(values):
    """Relative scatter of one setting over packing seeds: half the range
    over the mean magnitude (for two seeds, |a - b| / |a + b|). A variant's
    error inside this is noise. values: (n_seeds,) or (n_seeds, n_metrics)."""
    v = np.asarray(values, float)
    with warnings.catch_warnings():      # a metric no seed recorded: NaN, said below
        warnings.simplefilter("ignore", RuntimeWarning)
        mean = np.nanmean(v, axis=0)
        half = 0.5 * (np.nanmax(v, axis=0) - np.nanmin(v, axis=0))
    ok = np.isfinite(mean) & (mean != 0)
    return np.where(ok, half / np.where(ok, np.abs(mean), 1.0), np.nan)


def replicate_spread(values):
    """Mean and relative sample standard deviation (ddof 1, over the mean's
    magnitude) of runs that repeat one setting, NaN-aware, along axis 0.
    Two seeds give a thin estimate of how far a single chamber run lands
    from another; runs that perturb the trajectory without a systematic
    effect (docs/studies/error-vs-runtime.md) add replicates. NaN where fewer than
    two runs recorded the metric or the mean is 0.
    values: (n_runs,) or (n_runs, n_metrics). Returns (mean, rel_std)."""
    v = np.asarray(values, float)
    n = np.sum(np.isfinite(v), axis=0)
    with warnings.catch_warnings():      # a metric no run recorded: NaN, said below
        warnings.simplefilter("ignore", RuntimeWarning)
        mean = np.nanmean(v, axis=0)
        sd = np.nanstd(v, axis=0, ddof=1)
    ok = (n >= 2) & np.isfinite(mean) & (mean != 0)
    return mean, np.where(ok, sd / np.where(ok, np.abs(mean), 1.0), np.nan)


def is_noise(error, scatter):
    """True where |error| is inside the reference's scatter (elementwise)."""
    e = np.abs(np.asarray(error, float))
    s = np.asarray(scatter, float)
    return np.isfinite(e) & np.isfinite(s) & (e <= s)


def pareto_front(cost, error):
    """Boolean mask of the runs that no other run beats: another run
    dominates run i when it costs no more and errs no more (|error|), and
    is strictly better in one of the two. NaN errors are never on the front."""
    c = np.asarray(cost, float)
    e = np.abs(np.asarray(error, float))
    ok = np.isfinite(c) & np.isfinite(e)
    ci, cj = c[:, None], c[None, :]
    ei, ej = e[:, None], e[None, :]
    dom = (cj <= ci) & (ej <= ei) & ((cj < ci) | (ej < ei)) & ok[None, :]
    return ok & ~np.any(dom, axis=1)


def paired_ratio(keys_num, num, keys_den, den):
    """num / den for the settings run with both grain models (issue 11: the
    ratio of unbreakable to crushable steady q_c, per setting). keys_*: the
    setting of each run (e.g. "ref", "dt_frac=0.2"), num/den: its value.
    Returns (keys, ratio) for the keys in both, in the order of keys_num;
    NaN where den is 0 or a value is not finite."""
    kn = np.asarray(keys_num, dtype=object).astype(str)
    kd = np.asarray(keys_den, dtype=object).astype(str)
    _, i_n, i_d = np.intersect1d(kn, kd, assume_unique=True, return_indices=True)
    order = np.argsort(i_n)
    i_n, i_d = i_n[order], i_d[order]
    a = np.asarray(num, float)[i_n]
    b = np.asarray(den, float)[i_d]
    ok = np.isfinite(a) & np.isfinite(b) & (b != 0)
    return kn[i_n].tolist(), np.where(ok, a / np.where(ok, b, 1.0), np.nan)


def bilinear(values, x_mid, y_mid, x, y):
    """Value of a field given at cell centres (values[i, j] at x_mid[i],
    y_mid[j], both increasing) at the point (x, y), linear in each
    direction between centres; NaN outside the centres or where a corner
    is NaN."""
    v = np.asarray(values, float)
    xm = np.asarray(x_mid, float)
    ym = np.asarray(y_mid, float)
    if not (xm[0] <= x <= xm[-1] and ym[0] <= y <= ym[-1]):
        return float("nan")
    i = int(np.clip(np.searchsorted(xm, x, side="right") - 1, 0, xm.size - 2)) if xm.size > 1 else 0
    j = int(np.clip(np.searchsorted(ym, y, side="right") - 1, 0, ym.size - 2)) if ym.size > 1 else 0
    tx = (x - xm[i]) / (xm[i + 1] - xm[i]) if xm.size > 1 else 0.0
    ty = (y - ym[j]) / (ym[j + 1] - ym[j]) if ym.size > 1 else 0.0
    i1, j1 = min(i + 1, xm.size - 1), min(j + 1, ym.size - 1)
    return float((1 - tx) * (1 - ty) * v[i, j] + tx * (1 - ty) * v[i1, j]
                 + (1 - tx) * ty * v[i, j1] + tx * ty * v[i1, j1])


def band_value(band_edges, values, lo, hi):
    """The value of the band [lo, hi] among bands with the given edges
    (values[k] for band_edges[k]..band_edges[k+1]); NaN if no band has
    exactly those edges (to 1e-9)."""
    e = np.asarray(band_edges, float)
    k = np.flatnonzero(np.isclose(e[:-1], lo, atol=1e-9) & np.isclose(e[1:], hi, atol=1e-9))
    return float(np.asarray(values, float)[k[0]]) if k.size else float("nan")


def chamber_metrics(summary, fields_path, r_over_R=2.0, h_over_R=0.5, band=(1.0, 2.0)):
    """The study's numbers of one chamber run: steady q_c (the trend fit's a,
    MPa, with b h at the final depth: levelled off when > 3), Br of the band
    1 < r/R < 2 over the whole height at the last state, and the radial
    stress at r = 2R, h/R = 0.5 above the apex at the last end of a push
    (kPa, and over q_c at that state); the mean q_c of virgin penetration
    in depth bands of the rings' height (MPa, from the surface down) and
    over the last three of them, which lean on no fit; the breaks at the
    first step of jacking (crushing's switch-on). summary: the dict of
    summary.json; fields_path: fields.h5 of `crushpost report`."""
    import h5py
    out = {"qc_steady_MPa": summary.get(S.qc_steady_MPa),
           "qc_fit_b_per_m": summary.get(S.qc_fit_b),
           "b_h": (summary.get(S.qc_fit_b) or float("nan")) * summary.get(S.final_depth_m, float("nan")),
           "qc_levelled_off": summary.get(S.qc_levelled_off),
           "n_break_events": summary.get(S.n_break_events)}
    with h5py.File(fields_path, "r") as f:
        kinds = np.array([k.decode() if isinstance(k, bytes) else str(k) for k in f[fields_h5_path("states", "kind")][()]])
        push = np.flatnonzero(kinds == "push_end")
        if fields_h5_path("qc", "band_mean") in f:
            out["qc_band_means_MPa"] = [None if not np.isfinite(v) else float(v) / 1e6
                                        for v in f[fields_h5_path("qc", "band_mean")][()]]
            out["qc_band_height_m"] = float(f["qc"].attrs["band_height"])
        head = f[FIELDS_H5_HEADLINE].attrs if FIELDS_H5_HEADLINE in f else {}
        if "qc_last3_bands_MPa" in head:
            out["qc_last3_bands_MPa"] = float(head["qc_last3_bands_MPa"])
        if "n_break_events_first_step" in head:
            out["n_break_events_first_step"] = int(head["n_break_events_first_step"])
        if "n_break_events_prep" in head:
            out["n_break_events_prep"] = int(head["n_break_events_prep"])
        # events by zone and Br over the penetrated layers (crushpost.pile.break_zones)
        for k in ("events_switch_on", "events_entry", "events_penetration", "events_in_zone",
                  "events_along_shaft", "events_beyond_5R_below", "events_elsewhere",
                  "fraction_in_zone", "Br_penetrated_1_2R", "Br_penetrated_2_3R"):
            if k in head:
                v = head[k]
                if k.startswith(("fraction", "Br")):
                    # undefined (no penetration event): null, not NaN, in the records
                    out[k] = float(v) if np.isfinite(v) else None
                else:
                    out[k] = int(v)
        if fields_h5_group("breakage/bands") in f:
            g = f["breakage/bands"]
            out["Br_band_1_2"] = band_value(g["band_edges_over_R"][()], g["Br_band"][()][-1], *band)
        sigma_r, h_R = fields_h5_path("rings", "sigma_r"), fields_h5_path("rings", "h_over_R")
        if push.size and sigma_r in f and h_R in f:
            k = int(push[-1])
            sr = f[sigma_r][()][k]                         # (ring, layer)
            hR = f[h_R][()][k]                             # (layer,)
            rR = f[fields_h5_path("rings", "r_over_R")][()]
            order = np.argsort(hR)
            val = bilinear(sr[:, order], rR, hR[order], r_over_R, h_over_R)
            out["sigma_r_2R_kPa"] = val / 1e3
            qn = f[fields_h5_path("states", "qc_norm")][()][k]
            out["sigma_r_2R_over_qc"] = val / qn if np.isfinite(qn) and qn else float("nan")
    return out


def oedometer_metrics(summary):
    """The study's numbers of one oedometer run (summary.json of
    examples/oedometer/run.py): void ratio at 10 and 30 MPa on loading, of
    the core (farther than d50 from the walls: independent of the cell's
    width, docs/studies/calibration.md) and of the whole cell, Br at 30 MPa and at
    the end, and the loading curve (crushpost.oedometer.loading_curve). Keys
    a summary lacks (runs before e_core or the curve was written) are None."""
    return {k: summary.get(k) for k in ("e_core_at_10MPa", "e_core_at_30MPa", "e_at_10MPa",
                                         "e_at_30MPa", "Br_at_10MPa", "Br_at_30MPa", "Br_final",
                                         "n_break_events", "porosity_start_of_loading",
                                         "sigma_v_crush_onset_MPa", "sigma_v_first_break_MPa",
                                         "utilisation_at_MPa", "loading_curve")}


# ---------------------------------------------------------------------------
# the study's run-to-run scatter of steady q_c, for a single run's report

#: results_table.json of bench/error_vs_runtime (written by `run.py --table`):
#: its "chamber_spread" holds the pooled run-to-run spread of the reference
#: setting (replicate_spread over its four runs: two packing seeds, two time
#: steps). Found from this module's place in the checkout (scripts/crushpost).
STUDY_TABLE_NAME = "bench/error_vs_runtime/results_table.json"
STUDY_TABLE = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(
    os.path.abspath(__file__)))), *STUDY_TABLE_NAME.split("/"))


def qc_run_scatter(grains, path=None):
    """The study's run-to-run scatter of steady q_c for the grain model
    `grains` ('crushable_ne34' or 'unbreakable', summary.json "grains"): the
    relative sample standard deviation of one chamber run, pooled over the
    runs of the reference setting, read from the committed results table
    (`path`, default STUDY_TABLE). Returns a dict (rel_sd, mean_MPa, runs,
    source) or None when the file or the grain model is not there (a
    crushpost installed away from its checkout, or an unknown model)."""
    path = path or STUDY_TABLE
    try:
        with open(path) as f:
            spread = json.load(f)["chamber_spread"]
        m = spread["models"][grains]
        rel = float(m["rel_std"]["qc_steady_MPa"])
    except (OSError, ValueError, KeyError, TypeError):
        return None
    if not np.isfinite(rel):
        return None
    return {"rel_sd": rel, "mean_MPa": float(m["mean"]["qc_steady_MPa"]),
            "runs": list(m.get("runs", [])), "source": path}


def qc_uncertainty(qc, fit_se, rel_sd):
    """A steady q_c's two uncertainties side by side: the fit's standard
    error `fit_se` (how well the trend pins the plateau of this one run) and
    the run-to-run scatter `rel_sd * |qc|` (how far another packing of the
    same setting would land). Elementwise. Returns (scatter, scatter_dominates):
    the scatter in the units of qc, and True where it exceeds the standard
    error (False where it does not, or either is not finite)."""
    qc = np.asarray(qc, float)
    se = np.asarray(fit_se, float)
    scatter = np.asarray(rel_sd, float) * np.abs(qc)
    return scatter, np.isfinite(scatter) & np.isfinite(se) & (scatter > se)
