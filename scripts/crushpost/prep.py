# SPDX-License-Identifier: GPL-2.0-or-later
"""The prepared sample (docs/model.md §4.1 and §4.7; docs/preparation.md):
porosity of the whole sample and of its core, coordination number, and the
ring statistics of the stress that the source paper reports for its chamber
(mean and standard deviation of sigma_z, sigma_r, sigma_theta over annular
rings of width R and height 25 mm).

The core is the part of the sample farther than one d50 from every wall
(lateral wall, bottom, top and the symmetry planes of a sector): the decks'
preparation aims at its porosity (inputs/core_cylinder.in), since walls
loosen the packing next to them.

Lengths in m, stresses in Pa (any consistent units work).
"""

import math
import re

import numpy as np

from .materials import G_GRAIN, NU_GRAIN, RHO_GRAIN, rayleigh_time
from .stress import ring_averages, sphere_ring_volume

__all__ = ["cap_fraction", "core_area", "core_volumes", "sample_porosities", "ring_edges",
           "ring_statistics", "coordination", "read_prep_report", "snapshot_prep_summary",
           "prep_cost", "data_file_diameters", "rayleigh_time", "prep_time_step",
           "prep_chunk_for", "PAPER_PREPARED"]

# The source paper's prepared chamber (docs/model.md §4.1): porosity, and
# [mean, sd] of the ring-averaged stresses [kPa].
PAPER_PREPARED = {"porosity": 0.383, "sigma_z_kPa": [152.9, 12.0], "sigma_r_kPa": [76.7, 4.9],
                  "sigma_theta_kPa": [76.8, 5.1]}


def cap_fraction(h, r):
    """Fraction of a sphere of radius ``r`` on the side of a plane that its
    centre is at signed distance ``h`` from (h > 0: the centre is on that
    side): ``(1 + t)^2 (2 - t) / 4`` with ``t = clip(h / r, -1, 1)``."""
    t = np.clip(np.asarray(h, dtype=float) / np.asarray(r, dtype=float), -1.0, 1.0)
    return 0.25 * (1.0 + t) ** 2 * (2.0 - t)


def core_area(R_wall, d50, sector=360):
    """Cross-section of the core of a chamber (sector) of radius ``R_wall``:
    the disc of radius ``a = R_wall - d50`` less the strips within ``d50`` of
    the symmetry planes (y = 0 for sector 180; x = 0 and y = 0 for 90)."""
    a, c = R_wall - d50, d50
    if a <= c:
        raise ValueError("the chamber (R = %g) has no core: R must exceed 2 d50 = %g" % (R_wall, 2 * d50))
    s = math.sqrt(a * a - c * c)
    if sector == 360:
        return math.pi * a * a
    if sector == 180:
        return a * a * math.acos(c / a) - c * s
    if sector == 90:
        return 0.5 * a * a * (math.acos(c / a) - math.asin(c / a)) - c * (s - c)
    raise ValueError("sector must be 360, 180 or 90 degrees, got %r" % (sector,))


def core_volumes(centres, radii, R_wall, H, d50, sector=360, z_bottom=0.0):
    """Volume of each sphere inside the core: ``r < R_wall - d50`` from the
    z axis, ``z_bottom + d50 < z < z_bottom + H - d50``, and (sector 180/90)
    farther than ``d50`` from the symmetry planes.

    The cylinder part is exact (:func:`crushpost.stress.sphere_ring_volume`);
    a symmetry plane multiplies it by the sphere's fraction beyond the plane
    at ``d50`` (:func:`cap_fraction`), exact for a sphere that only that
    plane cuts (spheres cut by two core boundaries at once, along the core's
    edges, get the product of the two fractions).
    """
    c = np.asarray(centres, dtype=float).reshape(-1, 3)
    r = np.broadcast_to(np.asarray(radii, dtype=float), (c.shape[0],))
    v = sphere_ring_volume(c, r, 0.0, R_wall - d50, z_bottom + d50, z_bottom + H - d50)
    if sector < 360:
        v = v * cap_fraction(c[:, 1] - d50, r)
    if sector < 180:
        v = v * cap_fraction(c[:, 0] - d50, r)
    return v


def sample_porosities(centres, radii, R_wall, H, d50, sector=360, z_bottom=0.0):
    """Porosity of the whole sample (chamber or sector of radius ``R_wall``,
    height ``H``) and of its core. Returns a dict: porosity_all,
    porosity_core, V_sample, V_core, V_grains, V_core_grains [m^3]."""
    r = np.asarray(radii, dtype=float)
    v_grains = float(np.sum(4.0 / 3.0 * np.pi * r ** 3))
    v_sample = sector / 360.0 * math.pi * R_wall ** 2 * H
    v_core = core_area(R_wall, d50, sector) * (H - 2.0 * d50)
    v_core_grains = float(np.sum(core_volumes(centres, r, R_wall, H, d50, sector, z_bottom)))
    return {"porosity_all": 1.0 - v_grains / v_sample, "porosity_core": 1.0 - v_core_grains / v_core,
            "V_sample": v_sample, "V_core": v_core, "V_grains": v_grains,
            "V_core_grains": v_core_grains}


def ring_edges(width, extent, start=0.0):
    """Edges of rings (or layers) of ``width`` from ``start`` over ``extent``.

    A remainder narrower than half a width joins the last ring; a wider one
    is a ring of its own (so no ring is narrower than width/2, none wider
    than 1.5 width). The paper's chamber (R_ch = 12 R, H = 40 x 25 mm) has no
    remainder.
    """
    if width <= 0 or extent <= 0:
        raise ValueError("width and extent must be > 0")
    n = int(math.floor(extent / width + 1e-9))
    if n == 0:
        return np.array([start, start + extent])
    edges = start + width * np.arange(n + 1, dtype=float)
    rem = extent - n * width
    if rem > 0.5 * width:
        edges = np.append(edges, start + extent)
    else:
        edges[-1] = start + extent
    return edges


def _mean_sd(values):
    v = np.asarray(values, dtype=float).ravel()
    sd = float(np.std(v, ddof=1)) if v.size > 1 else 0.0
    return [float(np.mean(v)), sd]


def ring_statistics(sigma_p, centres, radii, R_pile, R_wall, H, dz=0.025, sector=360,
                    z_bottom=0.0, axis_xy=(0.0, 0.0)):
    """Ring-averaged cylindrical stresses of a chamber and their statistics.

    Rings of width ``R_pile`` from the axis to the lateral wall (``R_wall``)
    and layers of height ``dz`` from ``z_bottom`` to ``z_bottom + H``
    (:func:`ring_edges` for the remainders); in each, the volume average of
    the particle stresses ``sigma_p`` (N, 3, 3, compression positive)
    counting the part of each particle inside
    (:func:`crushpost.stress.ring_averages`, sector-aware).

    Returns a dict: r_edges, z_edges; sigma_r, sigma_theta, sigma_z, tau_rz
    (n_r, n_z) arrays [Pa]; "all": {name: [mean, sd]} over every ring
    (sample standard deviation, ddof = 1); "interior": the same over the
    rings that touch no wall (neither the outermost ring nor the bottom or
    top layer), the ones to read when the particle stresses lack the wall
    contacts.
    """
    r_e = ring_edges(R_pile, R_wall)
    z_e = ring_edges(dz, H, z_bottom)
    avg = ring_averages(sigma_p, centres, radii, r_e, z_e, axis_xy, "cylindrical", sector)
    comp = {"sigma_r": avg[..., 0, 0], "sigma_theta": avg[..., 1, 1], "sigma_z": avg[..., 2, 2],
            "tau_rz": 0.5 * (avg[..., 0, 2] + avg[..., 2, 0])}
    out = {"r_edges": r_e, "z_edges": z_e}
    out.update(comp)
    out["all"] = {k: _mean_sd(v) for k, v in comp.items()}
    inner = (slice(0, max(len(r_e) - 2, 0)), slice(1, max(len(z_e) - 2, 1)))
    out["interior"] = ({k: _mean_sd(v[inner]) for k, v in comp.items()}
                       if comp["sigma_r"][inner].size else None)
    return out


def coordination(snapshot):
    """Mean number of particle-particle contacts per particle, 2 N_c / N, of a
    snapshot of fix snapshot/hdf5 written with contacts (wall contacts not
    counted)."""
    n = len(snapshot["particles"]["id"])
    pp = snapshot["contacts"]["pp"]
    return 2.0 * len(pp["id"]) / n if n else 0.0


_REPORT = re.compile(r"^(EXPANDED|COMPRESSED|CHAMBER prepared:)\s+(.*)$")


def read_prep_report(log_path):
    """The preparation lines a deck printed into its log, as dicts of numbers:
    ``{"expanded": {...}, "compressed": {...}, "prepared": {...}}`` (keys
    as printed: porosity_core, porosity_all, p, sv, sr, K0, coordination,
    ke_rel, ...). Missing lines are missing keys; a deck that stopped with
    "PREPARATION FAILED" has no "prepared"."""
    names = {"EXPANDED": "expanded", "COMPRESSED": "compressed", "CHAMBER prepared:": "prepared"}
    out = {}
    with open(log_path, errors="replace") as f:
        for line in f:
            m = _REPORT.match(line.strip())
            if not m:
                continue
            words = m.group(2).split()
            d = {}
            for k, v in zip(words[0::2], words[1::2]):
                try:
                    d[k] = float(v)
                except ValueError:
                    d[k] = v
            out[names[m.group(1)]] = d
    return out


def snapshot_prep_summary(snapshot, R_pile, R_wall, H, d50, sector=360, dz=0.025):
    """Porosities, coordination and ring statistics [kPa] of a snapshot of the
    prepared chamber (inputs/snapshot_prep.in). Returns a dict ready for
    JSON."""
    from .snapshot import snapshot_particle_stress

    p = snapshot["particles"]
    x, r = p["x"], p["radius"]
    por = sample_porosities(x, r, R_wall, H, d50, sector)
    sig = snapshot_particle_stress(snapshot)
    rings = ring_statistics(sig, x, r, R_pile, R_wall, H, dz, sector)
    pw = snapshot["contacts"]["pw"]
    walls = pw is not None and len(pw["id"]) > 0
    kpa = {k: [v / 1e3 for v in rings["all"][k]] for k in ("sigma_z", "sigma_r", "sigma_theta")}
    out = {"porosity_core": por["porosity_core"], "porosity_all": por["porosity_all"],
           "coordination": coordination(snapshot),
           "sigma_z_kPa": kpa["sigma_z"], "sigma_r_kPa": kpa["sigma_r"],
           "sigma_theta_kPa": kpa["sigma_theta"],
           "rings": {"n_r": len(rings["r_edges"]) - 1, "n_z": len(rings["z_edges"]) - 1,
                     "r_edges_m": rings["r_edges"].tolist(), "z_edges_m": rings["z_edges"].tolist(),
                     "wall_contacts": walls,
                     "sigma_z_kPa": (rings["sigma_z"] / 1e3).tolist(),
                     "sigma_r_kPa": (rings["sigma_r"] / 1e3).tolist(),
                     "sigma_theta_kPa": (rings["sigma_theta"] / 1e3).tolist()}}
    if rings["interior"] is not None:
        out["rings"]["interior"] = {k + "_kPa": [v / 1e3 for v in rings["interior"][k]]
                                    for k in ("sigma_z", "sigma_r", "sigma_theta")}
    return out


_LOOP = re.compile(r"^Loop time of ([\d.eE+-]+) on (\d+) procs for (\d+) steps")


def prep_cost(log_path, marker="CHAMBER prepared:"):
    """LIGGGHTS time [s] and steps of the runs of a log up to the line that
    starts with ``marker`` (the whole log if it is not there), summed over
    its "Loop time" lines: ``(seconds, steps)``."""
    seconds, steps = 0.0, 0
    with open(log_path, errors="replace") as f:
        for line in f:
            if line.startswith(marker):
                break
            m = _LOOP.match(line)
            if m:
                seconds += float(m.group(1))
                steps += int(m.group(3))
    return seconds, steps


def data_file_diameters(path):
    """Diameters of the atoms of a LAMMPS data file written by
    :func:`crushpost.packing.write_lammps_data` (atom_style granular: id type
    diameter density x y z)."""
    d = []
    with open(path) as f:
        in_atoms = False
        for line in f:
            w = line.split()
            if not w:
                continue
            if w[0] == "Atoms":
                in_atoms = True
                continue
            if in_atoms:
                if len(w) < 7:
                    break
                d.append(float(w[2]))
    return np.array(d)


def element_prep_summary(log_path, n_target, s_prep):
    """The prepared specimen of an element test (oedometer, triaxial) as its
    deck reported it (inputs/prepare_expand.in's EXPANDED line): porosity of
    the core (farther than one d50 from every wall) and of the whole
    specimen, static mean stress [Pa], mean coordination number (grain-grain
    contacts per grain), the friction the expansion ended with, LIGGGHTS time
    and steps of the preparation; with the targets ``n_target`` and
    ``s_prep`` [Pa]."""
    exp = read_prep_report(log_path).get("expanded", {})
    seconds, steps = prep_cost(log_path, marker="EXPANDED")
    return {"n_target": n_target, "s_prep": s_prep,
            "porosity_core": exp.get("porosity_core"), "porosity_all": exp.get("porosity_all"),
            "p_static": exp.get("p"), "coordination": exp.get("coordination"),
            "mu_prep_final": exp.get("mu_prep"), "liggghts_time_s": seconds, "steps": steps}


def prep_time_step(data_file, fraction=0.15, rho=RHO_GRAIN, G=G_GRAIN, nu=NU_GRAIN):
    """Time step of the preparation: ``fraction`` of the Rayleigh time of the
    smallest grain as placed (no crushing, so no fragment, before the
    jacking; the grains only grow). The chamber walls have the grain's
    stiffness (materials_ne34.in, type 3)."""
    return fraction * rayleigh_time(0.5 * float(data_file_diameters(data_file).min()), rho, G, nu)


def prep_chunk_for(R_wall, H, reference=0.1, base=2000):
    """Steps per growth cycle of the radius expansion for a chamber of radius
    ``R_wall`` and height ``H`` (docs/preparation.md): ``base`` steps for a
    chamber whose larger dimension is ``reference`` (the demo's 0.1 m, where
    the dynamic stress of growing grains has died out 1000 steps into the
    hold), in proportion to the larger dimension above it (the stress waves
    that have to die out cross it), a multiple of 80 (so that a quarter of it
    is a multiple of 20)."""
    n = base * max(1.0, max(R_wall, H) / reference)
    return int(80 * math.ceil(n / 80.0))
