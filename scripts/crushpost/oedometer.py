# SPDX-License-Identifier: GPL-2.0-or-later
"""Oedometer (one-dimensional compression) results: the loading/unloading path
from the thermo output of examples/oedometer/in.oedometer, grading curves from
its particle dumps, HDF5 output and the standard plots.

Thermo columns used (LIGGGHTS drops the v_ prefix in the header):
``Step Time Atoms z_top sv e_void e_core n_break fines Br V_grains``: e_void is
the whole cell's void ratio, e_core that of its core (farther than d50 from
the walls and platens; NaN in the path of a log without it).
"""

import glob
import json
import os

import numpy as np

from .breakage import break_fines, psd_curve
from .dump import read_dump, true_mass
from .thermo import read_log

PATH_COLUMNS = ("Step", "Time", "Atoms", "z_top", "sv", "e_void", "e_core", "n_break", "fines", "Br")
# columns a log of an older deck may lack: NaN, not 0
NAN_IF_MISSING = ("e_core",)


def stress_path(log_path):
    """Loading and unloading path: dict of arrays plus 'phase' (0 load, 1 unload).

    The preparation blocks (no 'sv' column) are skipped; the first block with
    'sv' is loading, later ones continue it until the platen speed changes
    sign (z_top starts to rise), which marks unloading.
    """
    blocks = [b for b in read_log(log_path) if "sv" in b and "z_top" in b]
    if not blocks:
        raise ValueError("%s: no oedometer thermo blocks (columns sv, z_top)" % log_path)
    out = {k: [] for k in PATH_COLUMNS}
    last_step = None
    for b in blocks:
        keep = np.ones(len(b["Step"]), bool)
        if last_step is not None:
            keep &= b["Step"] > last_step  # each run repeats its first step
        for k in PATH_COLUMNS:
            if k in b:
                out[k].append(np.asarray(b[k])[keep])
            else:
                out[k].append(np.full(keep.sum(), np.nan if k in NAN_IF_MISSING else 0.0))
        if len(b["Step"]):
            last_step = b["Step"][-1]
    path = {k: np.concatenate(v) for k, v in out.items()}
    dz = np.diff(path["z_top"], prepend=path["z_top"][0])
    rising = np.cumsum(dz > 0) > 0
    path["phase"] = rising.astype(int)
    return path


def crushing_onset(path, n0, fraction=0.01):
    """Vertical stress at which crushing begins, on the loading branch
    (phase 0): the largest sigma_v the sample has carried by the time the
    breakage events reach `fraction` of the initial grains n0, and by the
    time of the first event. (The largest so far, not the current value: a
    break relaxes the stress for a moment, and the first contacts with the
    platen are dynamic.) NaN when loading never gets there. Returns
    (sv_onset, sv_first) in Pa."""
    load = np.asarray(path["phase"]) == 0
    sv = np.maximum.accumulate(np.asarray(path["sv"], float)[load])
    nb = np.asarray(path["n_break"], float)[load]
    need = max(1.0, fraction * float(n0))
    k = np.flatnonzero(nb >= need)
    k1 = np.flatnonzero(nb >= 1)
    return (float(sv[k[0]]) if k.size else float("nan"),
            float(sv[k1[0]]) if k1.size else float("nan"))


def loading_state_at(path, sv_targets, key="e_void"):
    """Value of `key` (void ratio by default) on the loading branch (phase 0)
    when the vertical stress first reaches each of `sv_targets` (Pa): linear
    in sigma_v between the two thermo lines that bracket the first crossing.
    The running maximum of sigma_v is used, so a stress drop after a break
    does not give a second crossing. NaN for a target the loading never
    reaches (or reached at its first line already). Vectorised over targets."""
    load = np.asarray(path["phase"]) == 0
    sv = np.maximum.accumulate(np.asarray(path["sv"], float)[load])
    y = np.asarray(path[key], float)[load]
    t = np.atleast_1d(np.asarray(sv_targets, float))
    k = np.searchsorted(sv, t, side="left")        # first line with sv >= target
    ok = (k > 0) & (k < sv.size)
    kk = np.clip(k, 1, max(sv.size - 1, 1))
    s0, s1 = sv[kk - 1], sv[kk]
    w = np.where(s1 > s0, (t - s0) / np.where(s1 > s0, s1 - s0, 1.0), 1.0)
    out = y[kk - 1] + w * (y[kk] - y[kk - 1])
    return np.where(ok, out, np.nan)


#: the loading curve a summary keeps (loading_curve): points per decade of sigma_v
CURVE_POINTS_PER_DECADE = 8


def loading_curve(path, sv_from=0.1e6, keys=("e_core", "e_void", "Br")):
    """The loading branch sampled on a log grid of sigma_v, compact enough for
    a summary or a study's record (curves of several runs drawn together):
    {"sigma_v_MPa": [...], key: [...]} from `sv_from` (Pa) to the largest
    stress reached, CURVE_POINTS_PER_DECADE points a decade, each value read
    as loading_state_at reads it (first crossing); None where a value is NaN
    (not reached, or a column the log lacks)."""
    load = np.asarray(path["phase"]) == 0
    sv_max = float(np.max(np.asarray(path["sv"], float)[load]))
    if not sv_max > sv_from:
        return {"sigma_v_MPa": [], **{k: [] for k in keys}}
    n = int(np.ceil(np.log10(sv_max / sv_from) * CURVE_POINTS_PER_DECADE - 1e-9)) + 1
    grid = np.geomspace(sv_from, sv_max, n)
    out = {"sigma_v_MPa": (grid / 1e6).tolist()}
    for k in keys:
        y = loading_state_at(path, grid, key=k) if k in path else np.full(n, np.nan)
        out[k] = [None if not np.isfinite(v) else float(v) for v in y]
    return out


def utilisation_at(snapshots, path, sv_targets, column="v_utilisation"):
    """The grains' utilisation (largest F_n / F_lim over their contacts,
    compute crush/atom) in the dump snapshot nearest to where the loading
    branch first reaches each target stress: {target_Pa: {"step", "sv",
    "n_contact", "median", "p90", "max", "frac_above_0.5"}} over the grains
    with a contact (utilisation > 0); None for a target no snapshot on the
    loading branch reaches, or when the dumps lack the column.

    snapshots: [(step, atoms dict)]; path: the thermo path (stress_path)."""
    load = np.asarray(path["phase"]) == 0
    steps_l = np.asarray(path["Step"], float)[load]
    sv_l = np.maximum.accumulate(np.asarray(path["sv"], float)[load])
    snaps = [(st, a) for st, a in snapshots if column in a and st <= steps_l.max()]
    out = {}
    if not snaps:
        return {float(t): None for t in np.atleast_1d(sv_targets)}
    s_steps = np.array([st for st, _ in snaps], float)
    s_sv = np.interp(s_steps, steps_l, sv_l)
    for t in np.atleast_1d(np.asarray(sv_targets, float)):
        if sv_l.max() < t:
            out[float(t)] = None
            continue
        k = int(np.argmin(np.abs(np.log(np.maximum(s_sv, 1.0) / t))))
        u = np.asarray(snaps[k][1][column], float)
        u = u[u > 0]
        out[float(t)] = {"step": int(s_steps[k]), "sv": float(s_sv[k]), "n_contact": int(u.size),
                         "median": float(np.median(u)) if u.size else float("nan"),
                         "p90": float(np.percentile(u, 90)) if u.size else float("nan"),
                         "max": float(u.max()) if u.size else float("nan"),
                         "frac_above_0.5": float(np.mean(u > 0.5)) if u.size else float("nan")}
    return out


def psd_snapshots(dump_pattern, density, sizes, fines_by_step=None, events=None,
                  d_min=None, fines_grading="fractal", d_frag_min=0.0):
    """Grading curves (mass fraction finer than each size) of every dump.

    fines_by_step: callable step -> fines mass, counted as finer than every
    size (fines without sizes, as before fines_grading existed).
    events: the event log of fix crush/particle (dict of
    :func:`crushpost.dump.read_crush_log`) instead: the fines of the breaks up
    to each snapshot enter as the fix counts them for Br (``fines_grading``
    'fractal' spreads them over ``[d_min, small fragment]``, needs ``d_min``;
    'd_min' puts them below every size); ``d_frag_min`` as given to the fix.
    Returns steps (n,), curves (n, len(sizes)).
    """
    if events is not None and fines_by_step is not None:
        raise ValueError("give either fines_by_step or events, not both")
    files = sorted(glob.glob(dump_pattern), key=lambda p: int(''.join(c for c in os.path.basename(p) if c.isdigit()) or 0))
    steps, curves = [], []
    for f in files:
        for snap in read_dump(f):
            a = snap["atoms"]
            d = 2.0 * a["radius"]
            m = true_mass(a, density, f)    # never the scaled `mass`
            fines = fines_by_step(snap["timestep"]) if fines_by_step else 0.0
            broken = None
            if events is not None:
                sel = events["step"] <= snap["timestep"]
                broken = break_fines(events["parent_diameter"][sel], density=density,
                                     d_frag_min=d_frag_min)
            steps.append(snap["timestep"])
            curves.append(psd_curve(d, m, fines, sizes, fines=broken,
                                    fines_grading=fines_grading, d_min=d_min))
    order = np.argsort(steps)
    return np.asarray(steps)[order], np.asarray(curves).reshape(len(steps), len(sizes))[order]


def write_hdf5(path, stress, psd=None, attrs=None):
    """HDF5 file: group 'path' (one dataset per column), group 'psd' (sizes,
    steps, sv, F), root attributes from attrs (JSON-able values; dicts, lists
    and None stored as JSON strings: HDF5 has no null attribute)."""
    import h5py
    with h5py.File(path, "w") as h:
        g = h.create_group("path")
        for k, v in stress.items():
            g.create_dataset(k, data=v)
        if psd is not None:
            p = h.create_group("psd")
            for k, v in psd.items():
                p.create_dataset(k, data=v)
        for k, v in (attrs or {}).items():
            h.attrs[k] = json.dumps(v) if v is None or isinstance(v, (dict, list)) else v


def plot_all(out_dir, stress, psd=None, title=""):
    """PNG plots: e - log sv, Br - sv, PSD evolution. Returns the file names."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    files = []
    load = stress["phase"] == 0
    sv = stress["sv"] / 1e6
    pos = sv > 0
    fig, ax = plt.subplots(figsize=(5.5, 4))
    ax.semilogx(sv[load & pos], stress["e_void"][load & pos], "-", label="loading")
    ax.semilogx(sv[~load & pos], stress["e_void"][~load & pos], "-", label="unloading")
    if "e_core" in stress and np.isfinite(stress["e_core"]).any():
        ax.semilogx(sv[load & pos], stress["e_core"][load & pos], "--", color="C0",
                    label="loading, core (> d50 from walls)")
        ax.semilogx(sv[~load & pos], stress["e_core"][~load & pos], "--", color="C1",
                    label="unloading, core")
    ax.set_xlabel("vertical stress $\\sigma_v$ (MPa)")
    ax.set_ylabel("void ratio e (-)")
    ax.set_title(title or "oedometer")
    ax.legend()
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    files.append(os.path.join(out_dir, "e_log_sigma_v.png"))
    fig.savefig(files[-1], dpi=120)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(5.5, 4))
    ax.plot(sv[load], stress["Br"][load], "-")
    ax.set_xlabel("vertical stress $\\sigma_v$ (MPa)")
    ax.set_ylabel("breakage index Br (-)")
    ax.set_title(title or "oedometer")
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    files.append(os.path.join(out_dir, "Br_sigma_v.png"))
    fig.savefig(files[-1], dpi=120)
    plt.close(fig)

    if psd is not None and len(psd["steps"]):
        fig, ax = plt.subplots(figsize=(5.5, 4))
        for k in range(len(psd["steps"])):
            ax.semilogx(psd["sizes"] * 1e3, 100 * psd["F"][k], "-",
                        label="$\\sigma_v$ = %.1f MPa" % (psd["sv"][k] / 1e6))
        ax.set_xlabel("diameter d (mm)")
        ax.set_ylabel("mass finer than d (%)")
        ax.set_title(title or "grading")
        ax.legend(fontsize=8)
        ax.grid(True, which="both", alpha=0.3)
        fig.tight_layout()
        files.append(os.path.join(out_dir, "psd.png"))
        fig.savefig(files[-1], dpi=120)
        plt.close(fig)
    return files
