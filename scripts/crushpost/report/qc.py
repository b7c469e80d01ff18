# SPDX-License-Identifier: GPL-2.0-or-later
"""Tip resistance q_c: the series, band means, the trend fit and its figure,
the run-to-run scatter, and the q_c that normalises the states' stresses."""

import math

import numpy as np

from ..fields import qc_reference, qc_trend_band
from ..formats import SUMMARY as S
from ..pile import PHASE_PUSH
from ..study import STUDY_TABLE, STUDY_TABLE_NAME, qc_run_scatter, qc_uncertainty
from ..trend import fit_qc_trend, mean_of_last_bands, qc_band_means, virgin_mask
from .common import _plt


def _qc(rep, ctx):
    jack, R = ctx["jack"], ctx["R"]
    if jack is None:
        return
    plt = _plt()
    depth, phase = jack["depth"], jack["phase"]
    qc = jack["F_cone"] / (math.pi * R ** 2)
    ctx["qc_series"] = qc
    virgin = virgin_mask(depth, phase) & (depth > 0)
    rep.put("qc", step=jack["step"], time=jack["time"], depth=depth, qc=qc, phase=phase,
            virgin=virgin.astype(np.int8))
    rep.head["final_depth_mm"] = float(depth.max() * 1e3)
    # band means: a plateau read that assumes no shape of q_c(h), on the
    # layers of the rings (the fit below can run away when q_c has not
    # levelled off; the bands cannot)
    dz = rep.opt.ring_height
    if virgin.any():
        bottom, mean, count = qc_band_means(depth[virgin], qc[virgin], dz)
        rep.put("qc", band_bottom=bottom, band_mean=mean, band_count=count)
        rep.attrs("qc", band_height=dz)
        last3 = mean_of_last_bands(mean, count, 3)
        if last3 is not None:
            rep.head["qc_last3_bands_MPa"] = last3 / 1e6
            rep.head_notes["qc_last3_bands_MPa"] = (
                "mean q_c of virgin penetration over the last three %g mm bands, %g-%g mm"
                % (dz * 1e3, (bottom[-1] - 3 * dz) * 1e3, bottom[-1] * 1e3))
    if virgin.sum() < 3:
        rep.skip("q_c trend fit", "%s: %d points of virgin penetration; need 3"
                 % (rep.path("jack.txt"), int(virgin.sum())))
        return
    h_max = float(depth[virgin].max())
    try:
        fit = fit_qc_trend(depth[virgin], qc[virgin], b_min=1.0 / h_max)
    except (ValueError, RuntimeError) as exc:
        rep.skip("q_c trend fit", "%s: the fit failed (%s)" % (rep.path("jack.txt"), exc))
        return
    ctx["fit"] = fit
    h = np.linspace(0.0, float(depth.max()), 200)
    band, cov = qc_trend_band(h, depth[virgin], qc[virgin], fit.a, fit.b)
    levelled = bool(fit.b * h_max > 3.0)
    rep.put("qc", fit_h=h, fit_qc=fit.a * -np.expm1(-fit.b * h), fit_qc_std=band, fit_cov=cov)
    rep.attrs("qc", a=fit.a, b=fit.b, a_err=fit.a_err, b_err=fit.b_err,
              levelled_off=int(levelled), R=R,
              model="q_c = a (1 - exp(-b h)) on virgin penetration; b >= 1 / max depth")
    rep.head["qc_steady_MPa"] = fit.a / 1e6
    rep.head["qc_steady_err_MPa"] = fit.a_err / 1e6
    rep.head["qc_fit_b_per_m"] = fit.b
    rep.head_notes["qc_steady_MPa"] = (
        "a of q_c = a (1 - exp(-b h)) fitted to %d points of virgin penetration; %s"
        % (int(virgin.sum()), "levelled off (b h_max = %.1f > 3)" % (fit.b * h_max) if levelled
           else "NOT levelled off (b h_max = %.2f): a lower estimate of the plateau"
           % (fit.b * h_max)))
    rep.head_notes["qc_steady_err_MPa"] = "standard error of a from the fit's covariance"
    _qc_scatter(rep, ctx, fit)
    fig, ax = plt.subplots(figsize=(5.5, 4.6))
    push = phase == PHASE_PUSH
    ax.plot(qc / 1e6, depth * 1e3, "-", lw=0.7, color="0.65", label="all phases")
    ax.plot(qc[push & ~virgin] / 1e6, depth[push & ~virgin] * 1e3, "x", ms=3, color="C1",
            label="re-push after an unload (not fitted)")
    ax.plot(qc[virgin] / 1e6, depth[virgin] * 1e3, ".", ms=2, color="C0",
            label="virgin penetration (fitted)")
    trend = fit.a * -np.expm1(-fit.b * h)
    ax.fill_betweenx(h * 1e3, (trend - band) / 1e6, (trend + band) / 1e6, color="k", alpha=0.15,
                     lw=0, label="trend +- 1 s.d. (fit covariance)")
    ax.plot(trend / 1e6, h * 1e3, "k--", lw=1.0,
            label="a (1 - exp(-b h)): a = %.3g +- %.2g MPa" % (fit.a / 1e6, fit.a_err / 1e6))
    ax.invert_yaxis()
    ax.set_xlabel("tip resistance q_c (MPa)")
    ax.set_ylabel("tip depth below the sand surface (mm)")
    ax.legend(fontsize=7, loc="lower left")
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    rep.figure(fig, "qc_depth.png", "Tip resistance against depth",
               "q_c = F_cone / (pi R^2) from jack.txt; the trend is fitted to virgin "
               "penetration only (pushing, tip at its deepest so far); the band is one standard "
               "deviation of the trend from the fit's covariance. %s"
               % rep.head_notes["qc_steady_MPa"])


def _qc_scatter(rep, ctx, fit):
    """The run-to-run scatter of steady q_c measured by the error-vs-runtime
    study (pooled over the runs of its reference setting, read from its
    committed results table) next to the fit's standard error, and which of
    the two dominates."""
    grains = ctx["summary"].get(S.grains)
    if grains is None:
        rep.skip("q_c run-to-run scatter", "%s names no grain model ('grains')"
                 % rep.path("summary.json"))
        return
    sc = qc_run_scatter(grains)
    if sc is None:
        rep.skip("q_c run-to-run scatter", "no pooled spread of steady q_c for grains %r in %s"
                 % (grains, STUDY_TABLE))
        return
    scatter, dominates = qc_uncertainty(fit.a, fit.a_err, sc["rel_sd"])
    which = "run-to-run scatter" if dominates else "fit standard error"
    rep.head["qc_run_scatter_MPa"] = float(scatter) / 1e6
    rep.head_notes["qc_run_scatter_MPa"] = (
        "one run's standard deviation of steady q_c between packings of the same setting, "
        "%.1f %% of q_c (%s grains: sample sd over the %d runs of the error-vs-runtime study's "
        "reference chamber, two packing seeds and two time steps; %s, chamber_spread); against "
        "the fit's standard error %.3g MPa the %s dominates"
        % (100.0 * sc["rel_sd"], grains, len(sc["runs"]),
           STUDY_TABLE_NAME if sc["source"] == STUDY_TABLE else sc["source"],
           fit.a_err / 1e6, which))
    rep.attrs("qc", run_scatter_rel=sc["rel_sd"], run_scatter=float(scatter),
              uncertainty_dominated_by=which)


def _qc_norm(rep, ctx):
    """q_c that normalises each state's stresses (NaN for the initial state)."""
    states = ctx["states"]
    steps = np.array([s["step"] for s in states])
    if rep.opt.qc_norm == "steady" and "fit" in ctx:
        out = np.full(steps.shape, ctx["fit"].a)
    elif rep.opt.qc_norm == "steady":
        rep.skip("--qc-norm steady", "no trend fit of q_c; the stresses are over q_c at the "
                 "end of the last push")
        out = _qc_norm_push(ctx, steps)
    else:
        out = _qc_norm_push(ctx, steps)
    kinds = np.array([s["kind"] for s in states])
    return np.where(kinds == "initial", np.nan, out)


def _qc_norm_push(ctx, steps):
    if ctx["jack"] is None:
        return np.full(steps.shape, np.nan)
    return qc_reference(steps, ctx["jack"]["step"], ctx["qc_series"], ctx["jack"]["phase"])
