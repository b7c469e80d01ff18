# SPDX-License-Identifier: GPL-2.0-or-later
"""Drained triaxial compression: the shearing path from the thermo output of
examples/triaxial/in.triaxial, its standard measures, HDF5 output and plots.

Conventions: compression positive for stresses and strains. The specimen is a
cuboid between six plates; x and y are lateral, z is axial. With the plate
positions ``xm < xp``, ``ym < yp``, ``zb < zt`` (the plates' reference points)
and the values at the start of shearing (index ``ref``):

* axial strain ``eps_a = 1 - Lz / Lz0``, lateral strains ``eps_x = 1 - Lx / Lx0``,
  ``eps_y = 1 - Ly / Ly0``, volumetric strain ``eps_v = 1 - V / V0`` with
  ``V = Lx Ly Lz`` (engineering strains from the start of shearing);
* ``sigma_1`` the axial stress (mean of the two end plates), ``sigma_3`` the
  mean of the four lateral plates, ``p' = (sigma_1 + 2 sigma_3) / 3`` (the mean
  of the three normal stresses), ``q = sigma_1 - sigma_3``, ``eta = q / p'``;
* friction angle in triaxial compression ``sin(phi) = 3 eta / (6 + eta)``;
* dilatancy ``D = -d eps_v / d eps_a`` (positive when the sample dilates),
  from a least-squares line through the points within a strain window, and the
  dilatancy angle ``sin(psi) = D / (2 + D)`` (Schanz & Vermeer 1996, from
  ``sin psi = -d eps_v / (2 d eps_1 - d eps_v)``);
* critical state: means over the last ``cs_window`` of axial strain; the
  dilatancy over that window (``dilatancy_cs``, a line fitted to eps_v) tells
  whether the volume has indeed stopped changing.

The periodic cell (examples/triaxial/in.triaxial_periodic) writes the same
columns: the box faces as "plates" (``xm = xlo`` ...), each face pair's
stress the cell's own stress component (``sxm = sxp = sigma_xx`` ...), from
the grains' contacts (:func:`cell_stress_from_contacts` recomputes it from a
dump of the contacts).

Thermo columns used (LIGGGHTS drops the v_ prefix in the header):
``Step Time Atoms phase xm xp ym yp zb zt sxm sxp sym syp szb szt uxm uxp uym
uyp uzb uzt porosity e_void n_break fines Br eps_a eps_v``.
"""

import json
import os

import numpy as np

from .thermo import concat_blocks, read_log

__all__ = [
    "PLATES", "shear_path", "strains_from_positions", "triaxial_invariants",
    "friction_angle", "stress_ratio", "dilatancy_angle", "local_slope",
    "dilatancy", "peak_state", "critical_state", "path_slope", "servo_errors",
    "analyse", "write_hdf5", "plot_all", "smoothed_peak", "read_local_dump",
    "cell_stress_from_contacts",
]

PLATES = ("xm", "xp", "ym", "yp", "zb", "zt")


def strains_from_positions(xm, xp, ym, yp, zb, zt, ref=0):
    """Engineering strains (compression positive) from the plate positions,
    relative to index ``ref``: dict eps_a, eps_x, eps_y, eps_v, volume."""
    Lx = np.asarray(xp, float) - np.asarray(xm, float)
    Ly = np.asarray(yp, float) - np.asarray(ym, float)
    Lz = np.asarray(zt, float) - np.asarray(zb, float)
    V = Lx * Ly * Lz
    return {"eps_a": 1.0 - Lz / Lz[ref], "eps_x": 1.0 - Lx / Lx[ref],
            "eps_y": 1.0 - Ly / Ly[ref], "eps_v": 1.0 - V / V[ref], "volume": V}


def triaxial_invariants(s_axial, s_x, s_y):
    """sigma_1, sigma_3, p', q, eta from the axial and the two lateral stresses."""
    s1 = np.asarray(s_axial, float)
    s3 = 0.5 * (np.asarray(s_x, float) + np.asarray(s_y, float))
    p = (s1 + 2.0 * s3) / 3.0
    q = s1 - s3
    with np.errstate(divide="ignore", invalid="ignore"):
        eta = np.where(p != 0, q / p, np.nan)
    return {"sigma_1": s1, "sigma_3": s3, "p": p, "q": q, "eta": eta}


def friction_angle(eta):
    """Mobilised friction angle (degrees) in triaxial compression, sin phi = 3 eta / (6 + eta)."""
    eta = np.asarray(eta, float)
    return np.degrees(np.arcsin(3.0 * eta / (6.0 + eta)))


def stress_ratio(phi_deg):
    """Inverse of :func:`friction_angle`: eta = 6 sin phi / (3 - sin phi)."""
    s = np.sin(np.radians(np.asarray(phi_deg, float)))
    return 6.0 * s / (3.0 - s)


def dilatancy_angle(D):
    """Dilatancy angle (degrees) from D = -d eps_v / d eps_a: sin psi = D / (2 + D)."""
    D = np.asarray(D, float)
    return np.degrees(np.arcsin(D / (2.0 + D)))


def local_slope(x, y, window):
    """dy/dx at each point: least-squares line through the points with
    |x - x_i| <= window / 2. Returns (slope, full) where ``full`` marks points
    whose window lies wholly inside the data (not cut by either end)."""
    x = np.asarray(x, float)
    y = np.asarray(y, float)
    n = x.size
    slope = np.full(n, np.nan)
    full = np.zeros(n, bool)
    h = 0.5 * window
    tol = 1e-9 * window    # points on the window edges count (round-off)
    for i in range(n):
        m = np.abs(x - x[i]) <= h + tol
        if m.sum() >= 3 and np.ptp(x[m]) > 0:
            xm = x[m] - x[m].mean()
            slope[i] = np.dot(xm, y[m] - y[m].mean()) / np.dot(xm, xm)
        full[i] = (x[i] - h >= x.min() - tol) and (x[i] + h <= x.max() + tol)
    return slope, full


def dilatancy(eps_a, eps_v, window=0.02):
    """D = -d eps_v / d eps_a (see :func:`local_slope`); returns (D, full)."""
    s, full = local_slope(eps_a, eps_v, window)
    return -s, full


def peak_state(eps_a, eta):
    """Index, strain and value of the largest stress ratio."""
    eta = np.asarray(eta, float)
    i = int(np.nanargmax(eta))
    return i, float(np.asarray(eps_a)[i]), float(eta[i])


def critical_state(eps_a, values, window=0.05):
    """Mean of each array in ``values`` (dict) over the last ``window`` of axial
    strain (eps_a >= max(eps_a) - window). Returns dict of means."""
    eps_a = np.asarray(eps_a, float)
    m = eps_a >= np.nanmax(eps_a) - window
    return {k: float(np.nanmean(np.asarray(v, float)[m])) for k, v in values.items()}


def path_slope(p, q):
    """Slope dq/dp' and intercept of the straight stress path q = slope p' + intercept.

    The least-squares line is fitted as p' against q and inverted: q spans the
    large range, while the servo's fluctuations of sigma_3 enter p' (p' =
    sigma_3 + q/3 in drained compression), so regressing p' on q keeps them in
    the dependent variable and does not bias the slope (regressing q on p'
    would attenuate it). Returns (slope, intercept) of q(p').
    """
    b, a = np.polyfit(np.asarray(q, float), np.asarray(p, float), 1)   # p' = a + b q
    return float(1.0 / b), float(-a / b)


def servo_errors(stresses, target):
    """Relative errors of servo-controlled stresses against ``target``.

    stresses: dict name -> array (already restricted to the steps of interest).
    Returns dict name -> {"mean": time-mean relative error,
    "rms": root-mean-square relative error, "max_abs": largest |error|}.
    """
    out = {}
    for k, s in stresses.items():
        e = np.asarray(s, float) / target - 1.0
        out[k] = {"mean": float(np.mean(e)), "rms": float(np.sqrt(np.mean(e * e))),
                  "max_abs": float(np.max(np.abs(e)))}
    return out


# columns that a run's set-up row gets wrong: LIGGGHTS 3.8 adds the wall
# forces of the set-up force computation to the plates' force sums once more,
# so the first thermo row of every run shows about twice the plate stresses
# (and the servo speeds computed from them)
SETUP_COLUMNS = ("sxm", "sxp", "sym", "syp", "szb", "szt", "uxm", "uxp", "uym", "uyp", "uzb", "uzt")


def shear_path(log_path):
    """The shearing phase of a triaxial log as a dict of arrays.

    Keeps the thermo blocks that have an ``eps_a`` column and joins them (the
    first row of each later run repeats the last of the previous one and is
    dropped). The first row, the set-up of the first shearing run, takes the
    plate stresses and servo speeds of the last row of the run before it (the
    end of consolidation, same step), see SETUP_COLUMNS. Adds: sigma_x,
    sigma_y, sigma_z (plate-pair means), the invariants of
    :func:`triaxial_invariants`, and the strains recomputed from the plate
    positions (``eps_a_pos``, ``eps_v_pos``, ``eps_x``, ``eps_y``, relative
    to the first row).
    """
    every = read_log(log_path)
    idx = [i for i, b in enumerate(every) if "eps_a" in b and len(b["Step"])]
    if not idx:
        raise ValueError("%s: no shearing thermo blocks (column eps_a)" % log_path)
    path = concat_blocks([every[i] for i in idx])
    if idx[0] > 0:
        prev = every[idx[0] - 1]
        if len(prev["Step"]) and prev["Step"][-1] == path["Step"][0]:
            for k in SETUP_COLUMNS:
                if k in prev and k in path:
                    path[k][0] = prev[k][-1]
    path["sigma_x"] = 0.5 * (path["sxm"] + path["sxp"])
    path["sigma_y"] = 0.5 * (path["sym"] + path["syp"])
    path["sigma_z"] = 0.5 * (path["szb"] + path["szt"])
    path.update(triaxial_invariants(path["sigma_z"], path["sigma_x"], path["sigma_y"]))
    st = strains_from_positions(*(path[k] for k in PLATES))
    path["eps_a_pos"] = st["eps_a"]
    path["eps_v_pos"] = st["eps_v"]
    path["eps_x"] = st["eps_x"]
    path["eps_y"] = st["eps_y"]
    return path


def analyse(path, sigma3, cs_window=0.05, dil_window=0.02, settle=0.01):
    """Standard measures of a shearing path (dict from :func:`shear_path` or
    any dict with eps_a, eps_v, p, q, eta, sigma_x, sigma_y, sxm ... syp).

    settle: servo errors and the stress-path slope use the points with
    eps_a >= settle (after the start-of-shearing transient).
    Returns a JSON-able dict.
    """
    ea = np.asarray(path["eps_a"], float)
    ev = np.asarray(path["eps_v"], float)
    eta = np.asarray(path["eta"], float)
    i_pk, ea_pk, eta_pk = peak_state(ea, eta)
    cs = critical_state(ea, {"eta": eta, "p": path["p"], "q": path["q"], "eps_v": ev}, cs_window)
    D, full = dilatancy(ea, ev, dil_window)
    Dm = np.where(full, D, np.nan)
    if np.all(np.isnan(Dm)):
        Dm = D
    i_d = int(np.nanargmax(Dm))
    # dilatancy over the critical-state window: ~0 if the volume has settled
    m_cs = ea >= ea.max() - cs_window
    D_cs = -np.polyfit(ea[m_cs], ev[m_cs], 1)[0] if m_cs.sum() >= 3 else float("nan")
    late = ea >= settle
    slope, intercept = path_slope(np.asarray(path["p"])[late], np.asarray(path["q"])[late])
    plates = {k: np.asarray(path[k])[late] for k in ("sxm", "sxp", "sym", "syp") if k in path}
    pairs = {"x": np.asarray(path["sigma_x"])[late], "y": np.asarray(path["sigma_y"])[late]}
    try:
        pk_s, ea_pk_s = smoothed_peak(ea, eta, 0.01)
    except ValueError:
        pk_s, ea_pk_s = float("nan"), float("nan")
    return {
        "eta_peak_smooth": pk_s, "eps_a_peak_smooth": ea_pk_s,
        "phi_peak_smooth_deg": float(friction_angle(pk_s)) if np.isfinite(pk_s) else float("nan"),
        "eps_a_final": float(ea[-1]),
        "eps_v_final": float(ev[-1]),
        "q_start": float(path["q"][0]), "p_start": float(path["p"][0]),
        "eta_peak": eta_pk, "eps_a_peak": ea_pk, "q_peak": float(path["q"][i_pk]),
        "p_peak": float(path["p"][i_pk]),
        "phi_peak_deg": float(friction_angle(eta_pk)),
        "eta_cs": cs["eta"], "p_cs": cs["p"], "q_cs": cs["q"], "eps_v_cs": cs["eps_v"],
        "phi_cs_deg": float(friction_angle(cs["eta"])),
        "cs_window": cs_window, "dilatancy_cs": float(D_cs),
        "dilatancy_max": float(Dm[i_d]), "eps_a_dilatancy_max": float(ea[i_d]),
        "psi_max_deg": float(dilatancy_angle(Dm[i_d])),
        "dil_window": dil_window,
        "stress_path_slope": slope, "stress_path_intercept": intercept,
        "stress_path_p0": -intercept / slope,   # p' where the fitted line has q = 0
        "settle_eps_a": settle,
        "servo_pairs": servo_errors(pairs, sigma3),
        "servo_plates": servo_errors(plates, sigma3),
    }


#: the shearing curve a summary keeps (shear_curve): spacing of axial strain
CURVE_EPS_STEP = 0.005


def shear_curve(path, step=CURVE_EPS_STEP, keys=("eta", "eps_v", "Br")):
    """The shearing path sampled every `step` of axial strain, compact enough
    for a summary or a study's record (curves of several runs drawn together):
    {"eps_a": [0, step, ...], key: [...]} up to the largest axial strain
    reached, each value interpolated linearly in eps_a (which only grows under
    strain control); None where the path lacks a column."""
    ea = np.maximum.accumulate(np.asarray(path["eps_a"], float))
    grid = np.arange(0.0, ea[-1] + 0.5 * step, step)
    grid = grid[grid <= ea[-1]]
    out = {"eps_a": [round(float(g), 12) for g in grid]}
    for k in keys:
        if k not in path:
            out[k] = [None] * grid.size
            continue
        y = np.interp(grid, ea, np.asarray(path[k], float), left=np.nan)
        out[k] = [None if not np.isfinite(v) else float(v) for v in y]
    return out


def write_hdf5(path_h5, path, attrs=None):
    """HDF5 file: group 'shear' (one dataset per column of the path), root
    attributes from ``attrs`` (dicts, lists and None stored as JSON strings:
    HDF5 has no null attribute)."""
    import h5py
    with h5py.File(path_h5, "w") as h:
        g = h.create_group("shear")
        for k, v in path.items():
            g.create_dataset(k, data=np.asarray(v))
        for k, v in (attrs or {}).items():
            h.attrs[k] = json.dumps(v) if v is None or isinstance(v, (dict, list)) else v


def plot_all(out_dir, path, res=None, title=""):
    """PNG plots: q/p' and eps_v against eps_a (q_p_eps_a.png), and the q - p'
    stress path with the slope-3 line of constant sigma_3 (stress_path.png).
    Returns the file names."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    files = []
    ea = 100 * np.asarray(path["eps_a"])
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(5.5, 6.5), sharex=True)
    a1.plot(ea, path["eta"], "-", lw=1.2)
    if res:
        a1.plot([100 * res["eps_a_peak"]], [res["eta_peak"]], "o", ms=5,
                label="peak %.3f ($\\phi$ = %.1f$^\\circ$)" % (res["eta_peak"], res["phi_peak_deg"]))
        a1.axhline(res["eta_cs"], ls="--", lw=0.8, color="k",
                   label="critical state %.3f ($\\phi$ = %.1f$^\\circ$)" % (res["eta_cs"],
                                                                             res["phi_cs_deg"]))
        a1.legend(fontsize=8, loc="lower right")
    a1.set_ylabel("stress ratio q/p' (-)")
    a1.set_title(title or "drained triaxial compression")
    a1.grid(True, alpha=0.3)
    a2.plot(ea, 100 * np.asarray(path["eps_v"]), "-", lw=1.2)
    a2.set_xlabel("axial strain $\\varepsilon_a$ (%)")
    a2.set_ylabel("volumetric strain $\\varepsilon_v$ (%)\n(compression +)")
    a2.grid(True, alpha=0.3)
    fig.tight_layout()
    files.append(os.path.join(out_dir, "q_p_eps_a.png"))
    fig.savefig(files[-1], dpi=120)
    plt.close(fig)

    p = np.asarray(path["p"]) / 1e3
    q = np.asarray(path["q"]) / 1e3
    fig, ax = plt.subplots(figsize=(5.5, 4.5))
    ax.plot(p, q, "-", lw=1.2, label="DEM")
    s3 = float(np.asarray(path["sigma_3"])[0]) / 1e3
    pp = np.array([s3, max(p.max(), s3 + 1e-9)])
    ax.plot(pp, 3 * (pp - s3), "k--", lw=0.8, label="slope 3 (constant $\\sigma_3$)")
    if res:
        ax.plot(pp, res["eta_cs"] * pp, ":", lw=0.8, color="C3",
                label="q = %.3f p' (critical state)" % res["eta_cs"])
        ax.text(0.03, 0.93, "fitted slope %.3f" % res["stress_path_slope"],
                transform=ax.transAxes, fontsize=8)
    ax.set_xlabel("p' (kPa)")
    ax.set_ylabel("q (kPa)")
    ax.set_title(title or "stress path")
    ax.legend(fontsize=8, loc="lower right")
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    files.append(os.path.join(out_dir, "stress_path.png"))
    fig.savefig(files[-1], dpi=120)
    plt.close(fig)
    return files


def smoothed_peak(eps_a, eta, window=0.01):
    """Peak of the running mean of eta over `window` of axial strain:
    (largest mean, its centre strain). Only windows wholly inside the data
    count. A single stick-slip spike of a few hundred grains cannot make
    this peak; :func:`peak_state` takes the raw largest value."""
    ea = np.asarray(eps_a, float)
    eta = np.asarray(eta, float)
    lo = np.searchsorted(ea, ea - window / 2.0, side="left")
    hi = np.searchsorted(ea, ea + window / 2.0, side="right")
    csum = np.concatenate([[0.0], np.cumsum(eta)])
    ok = (ea - window / 2.0 >= ea[0]) & (ea + window / 2.0 <= ea[-1]) & (hi > lo)
    if not np.any(ok):
        raise ValueError("smoothed_peak: the path spans less than the window %g" % window)
    mean = np.where(ok, (csum[hi] - csum[lo]) / np.maximum(hi - lo, 1), -np.inf)
    i = int(np.argmax(mean))
    return float(mean[i]), float(ea[i])


def read_local_dump(path):
    """One snapshot of a LIGGGHTS local dump (``dump local``): dict with
    ``timestep``, ``box`` ((3, 2) bounds) and ``entries`` (name -> column
    array, names as in the header)."""
    with open(path) as fh:
        lines = fh.read().splitlines()
    if not lines or not lines[0].startswith("ITEM: TIMESTEP"):
        raise ValueError("%s: not a LIGGGHTS local dump" % path)
    step = int(lines[1].split()[0])
    n = int(lines[3].split()[0])
    box = np.array([[float(v) for v in lines[5 + k].split()[:2]] for k in range(3)])
    names = lines[8].split()[2:]
    body = lines[9:9 + n]
    if len(body) < n:
        raise ValueError("%s: %d of %d entries" % (path, len(body), n))
    data = np.array(" ".join(body).split(), float).reshape(n, len(names)) if n else \
        np.zeros((0, len(names)))
    return {"timestep": step, "box": box,
            "entries": {k: data[:, i] for i, k in enumerate(names)}}


def cell_stress_from_contacts(x_i, x_j, force_on_i, box_lengths):
    """Stress of a periodic cell from its contacts (Love-Weber),
    ``sigma_ab = -(1/V) sum_c F_a (x_j - x_i)_b``, compression positive, with
    the branch vector taken as the nearest periodic image (grains are much
    smaller than half the cell) and V the cell volume. Each contact once.

    x_i, x_j: (n, 3) centres (wrapped into the cell); force_on_i: (n, 3) force
    of j on i; box_lengths: (3,). Returns (3, 3) [Pa].
    """
    L = np.asarray(box_lengths, float)
    branch = np.asarray(x_j, float) - np.asarray(x_i, float)
    branch -= L * np.round(branch / L)
    f = np.asarray(force_on_i, float)
    return -np.einsum("ca,cb->ab", f, branch) / float(np.prod(L))

