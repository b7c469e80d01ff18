#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-2.0-or-later
"""Extreme loading and the energy budget of breaks (issue 12, items 1 and 3;
docs/stability.md and the study docs/studies/stability.md, "Energy of breaks",
"Energy budget" and "Extreme loading").

    /usr/bin/python3 bench/extreme_loading/run.py            # all scenes, results.json here
    /usr/bin/python3 bench/extreme_loading/run.py --scenes oedometer --np 2

Needs build/liggghts (or --liggghts) built with fix crush/particle's
`energy` keywords. Scenes (small, minutes on one core):

oedometer  grains (d 0.8-1.2 mm, var 0.36) on a loose cubic lattice in a
           rigid box with frictionless walls, the calibrated friction
           between grains (crushpost.materials.MU_GRAIN), local damping 0.05, a frictionless steel platen pushed
           down at constant speed until the vertical stress passes
           --sigma (100 MPa); fragments of fragments break again
           (d_comm 0.35 mm; fragments finer than d_frag_min 0.14 mm go to
           fines: d_frag_min <= 0.414 d_comm, so that every break keeps its
           6 large fragments, the atom count never falls and the deck runs
           under `thermo_modify lost error`). Reports: atoms lost (fix crush/particle stops on a loss),
           the mass balance, breaks, and the energy budget
               W_platen = dE_elastic + dE_kinetic + D_damping + D_friction + R_breaks
           integrated every step (W_platen from the platen force,
           f_crush[14] elastic, compute ke, f_damp (fix damp/local energy
           yes), f_crush[15] friction (energy_budget yes), f_crush[11]
           released by breaks).
same_step  a simple cubic stack of 5 x 5 x 3 equal grains (var 0,
           frictionless) pressed by a platen: dozens of grains break in the
           same step next to each other.
pile_tip   a steel cone (60 degrees, interface friction 0.5) pushed into a
           cubic stack of equal grains (var 0) topped by a layer in its
           hollows, in a closed box: the grain under the tip breaks at its
           contact with the cone while it touches four grains below, and
           more follow.
oedometer_small  the 64-grain oedometer of the test (e.g. --np 2
           --processors "2 1 1": the budget at 2 ranks).
oedometer_big  the oedometer with 9 x 9 x 9 grains (--scenes oedometer_big;
           not in the default set: about 10 minutes).
For every scene: the largest fragment speed (over energy_window steps after
each break) and the energy released by the breaks.
"""

import argparse
import json
import math
import os
import shutil
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(REPO, "scripts"))

from crushpost.materials import (D0, D_COMM_RATIO, D_LOC, E_GRAIN, E_STEEL, M_SIZE, MU_GRAIN,  # noqa: E402
                                 RHO_GRAIN, SIGMA_LIM0, VAR, rayleigh_time)
from crushpost.materials import NU_GRAIN as NU  # noqa: E402  (the steel's is the same, NU_STEEL)

RHO = RHO_GRAIN
SEED = 15485863


def header(box, mu_gg, mu_gs, skin):
    """Types: 1 grain, 2 steel (platen, cone), 3 frictionless wall with the
    grain's stiffness. Restitution 1: no contact viscous damping."""
    mu = [[mu_gg, mu_gs, 0.0], [mu_gs, 0.0, 0.0], [0.0, 0.0, 0.0]]
    mus = " ".join(repr(float(v)) for row in mu for v in row)
    return f"""\
units si
hard_particles yes
atom_style granular
atom_modify map array
boundary f f f
newton off
communicate single vel yes
region box block {box} units box
create_box 3 box
neighbor {skin!r} bin
neigh_modify delay 0
thermo_modify lost error
fix m1 all property/global youngsModulus peratomtype {E_GRAIN!r} {E_STEEL!r} {E_GRAIN!r}
fix m2 all property/global poissonsRatio peratomtype {NU!r} {NU!r} {NU!r}
fix m3 all property/global coefficientRestitution peratomtypepair 3 1.0 1.0 1.0 1.0 1.0 1.0 1.0 1.0 1.0
fix m4 all property/global coefficientFriction peratomtypepair 3 {mus}
pair_style gran model hertz tangential history
pair_coeff * *
"""


def plate_stl(half, z=0.0):
    h, zz = repr(float(half)), repr(float(z))
    return (f"solid plate\nfacet normal 0 0 1\nouter loop\nvertex -{h} -{h} {zz}\nvertex {h} -{h} {zz}\n"
            f"vertex {h} {h} {zz}\nendloop\nendfacet\nfacet normal 0 0 1\nouter loop\nvertex -{h} -{h} {zz}\n"
            f"vertex {h} {h} {zz}\nvertex -{h} {h} {zz}\nendloop\nendfacet\nendsolid plate\n")


def cone_stl(R, height_cyl, n=24, half_angle_deg=30.0):
    """A closed-tip pile: cone of base radius R (apex at the origin, pointing
    down, apex half-angle 30 deg = 60 degree cone) and a cylinder of height
    height_cyl above it. Facet normals point outwards."""
    hc = R / math.tan(math.radians(half_angle_deg))
    out = ["solid pile"]

    def facet(a, b, c):
        nrm = np.cross(np.subtract(b, a), np.subtract(c, a))
        nrm = nrm / np.linalg.norm(nrm)
        out.append("facet normal %r %r %r\nouter loop" % tuple(float(v) for v in nrm))
        for p in (a, b, c):
            out.append("vertex %r %r %r" % tuple(float(v) for v in p))
        out.append("endloop\nendfacet")

    for k in range(n):
        t0, t1 = 2 * math.pi * k / n, 2 * math.pi * (k + 1) / n
        p0 = (R * math.cos(t0), R * math.sin(t0), hc)
        p1 = (R * math.cos(t1), R * math.sin(t1), hc)
        facet((0.0, 0.0, 0.0), p1, p0)
        q0 = (p0[0], p0[1], hc + height_cyl)
        q1 = (p1[0], p1[1], hc + height_cyl)
        facet(p0, p1, q1)
        facet(p0, q1, q0)
    out.append("endsolid pile")
    return "\n".join(out) + "\n", hc


def lattice(n, spacing, z0=0.0):
    nx, ny, nz = n
    c = lambda m: (np.arange(m) - (m - 1) / 2.0) * spacing  # noqa: E731
    return np.array([(x, y, z0 + (k + 0.5) * spacing) for k in range(nz) for x in c(nx) for y in c(ny)])


def atoms_text(pos, diam):
    out = []
    for k, (p, d) in enumerate(zip(pos, diam)):
        out.append(f"create_atoms 1 single {p[0]!r} {p[1]!r} {p[2]!r} units box")
        out.append(f"set atom {k + 1} diameter {d!r} density {RHO!r}")
    return "\n".join(out) + "\n"


def side_walls(half):
    return "".join(
        f"fix w{k} all wall/gran model hertz tangential history primitive type 3 {w}\n"
        for k, w in enumerate((f"xplane {-half!r}", f"xplane {half!r}", f"yplane {-half!r}", f"yplane {half!r}",
                               "zplane 0.0")))


def crush_line(var, d_comm, extra):
    return (f"fix crush all crush/particle sigma_lim0 {SIGMA_LIM0:g} m {M_SIZE:g} d0 {D0:g} scale 1 var {var!r} "
            f"d_comm {d_comm!r} seed {SEED} events events.txt energy yes energy_window 20 {extra}\n")


# --------------------------------------------------------------------------
# scenes
# --------------------------------------------------------------------------

def oedometer(n=(6, 6, 6), d_mean=1.0e-3, spread=0.2, spacing=1.25e-3, speed=2.0, sigma=100e6,
              var=VAR, d_comm=0.35e-3, d_frag_min=0.14e-3, chunk=2000, max_steps=400000, seed=1):
    rng = np.random.default_rng(seed)
    pos = lattice(n, spacing)
    diam = d_mean * (1.0 - spread + 2.0 * spread * rng.random(len(pos)))
    half = 0.5 * n[0] * spacing
    H = n[2] * spacing
    r_min = 0.5 * min(d_frag_min, d_comm * 0.414214)
    dt = 0.15 * rayleigh_time(r_min)
    area = (2 * half) ** 2
    text = header(f"{-half - 1e-4!r} {half + 1e-4!r} {-half - 1e-4!r} {half + 1e-4!r} -1e-4 {H + 2e-3!r}",
                  MU_GRAIN, 0.0, 0.1e-3)
    text += f"timestep {dt!r}\n" + atoms_text(pos, diam)
    text += f"""\
fix top all mesh/surface/stress file plate.stl type 2 move 0 0 {H!r}
fix walls all wall/gran model hertz tangential history mesh n_meshes 1 meshes top
{side_walls(half)}fix mv all move/mesh mesh top linear 0. 0. {-speed!r}
fix integrate all nve
{crush_line(var, d_comm, f"d_frag_min {d_frag_min!r} energy_budget yes")}fix damp all damp/local alpha {D_LOC:g} energy yes
compute ke all ke
variable sv equal f_top[3]/{area!r}
variable st equal step
variable E_el equal f_crush[14]
variable D_fr equal f_crush[15]
variable R_br equal f_crush[11]
variable v_max equal f_crush[13]
variable M_p equal f_crush[4]
variable M_f equal f_crush[3]
thermo_style custom step atoms f_top[3] c_ke v_E_el f_damp v_D_fr v_R_br f_crush[1] v_M_p v_M_f v_v_max v_sv
thermo_modify format float %.17g lost error
thermo 1
label loop
run {chunk}
if "${{sv}} > {sigma!r}" then "jump SELF done"
if "${{st}} > {max_steps}" then "jump SELF done"
jump SELF loop
label done
"""
    files = {"plate.stl": plate_stl(half * 1.02)}
    return text, files, {"dt": dt, "speed": speed, "area": area, "mass0": float(np.sum(
        RHO * math.pi / 6.0 * diam ** 3)), "grains": len(pos)}


def same_step(n=(5, 5, 3), d=1.0e-3, speed=0.2):
    spacing = 1.001 * d
    pos = lattice(n, spacing)
    pos[:, 2] = np.repeat((np.arange(n[2]) + 0.5) * d, n[0] * n[1])
    half = 0.5 * n[0] * spacing + 3e-3
    H = n[2] * d + 0.002 * d
    dt = 0.15 * rayleigh_time(0.5 * d * 0.230093)
    # travel to the grain-grain limit of a column (Hertz, docs/model.md §2.4)
    sig = SIGMA_LIM0 * (d / D0) ** (-3.0 / M_SIZE)
    Es_gg = 1.0 / (2 * (1 - NU ** 2) / E_GRAIN)
    Es_gs = 1.0 / ((1 - NU ** 2) / E_GRAIN + (1 - NU ** 2) / E_STEEL)
    F = (math.pi * sig) ** 3 * (3 * (d / 4) / (4 * Es_gg)) ** 2
    ov = lambda F, R, E: (3 * F / (4 * E * math.sqrt(R))) ** (2 / 3)  # noqa: E731
    travel = 0.002 * d + 2 * ov(F, d / 2, Es_gs) + (n[2] - 1) * ov(F, d / 4, Es_gg)
    steps = int(travel / (speed * dt))
    text = header(f"{-half!r} {half!r} {-half!r} {half!r} -0.004 {H + 0.004!r}", 0.0, 0.0, 0.5e-3)
    text += f"timestep {dt!r}\n" + atoms_text(pos, np.full(len(pos), d))
    text += f"""\
fix top all mesh/surface/stress file plate.stl type 2 move 0 0 {H!r}
fix walls all wall/gran model hertz tangential history mesh n_meshes 1 meshes top
fix bottom all wall/gran model hertz tangential history primitive type 2 zplane 0.0
fix mv all move/mesh mesh top linear 0. 0. {-speed!r}
fix integrate all nve
{crush_line(0.0, D_COMM_RATIO * d, "")}thermo_style custom step atoms f_crush[1] f_crush[11] f_crush[13]
thermo_modify format float %.17g lost error
thermo 1000
run {steps + 150}
"""
    return text, {"plate.stl": plate_stl(half * 0.95)}, {"dt": dt, "grains": len(pos)}


def pile_tip(n=(6, 6, 3), d=1.0e-3, speed=0.5, R_pile=1.5e-3):
    # a cubic stack and, on top, a layer in its hollows: the grain under the
    # tip rests on four grains, so its contact with the cone carries more
    # force than each of its grain contacts and reaches its limit first
    spacing = 1.001 * d
    pos = lattice(n, spacing)
    pos[:, 2] = np.repeat((np.arange(n[2]) + 0.5) * d, n[0] * n[1])
    top = lattice((n[0] - 1, n[1] - 1, 1), spacing)
    top[:, 2] = (n[2] - 0.5) * d + math.sqrt(d * d - 0.5 * spacing * spacing)
    pos = np.vstack([pos, top])
    half = 0.5 * n[0] * spacing
    H = top[0, 2] + 0.5 * d
    dt = 0.15 * rayleigh_time(0.5 * d * 0.230093)
    stl, hc = cone_stl(R_pile, 2e-3)
    # tip starts just above the top layer, on the axis of the centre column
    z0 = H + 0.01e-3
    depth = 2.5e-3
    steps = int(depth / (speed * dt))
    text = header(f"{-half - 1e-4!r} {half + 1e-4!r} {-half - 1e-4!r} {half + 1e-4!r} -1e-4 {H + hc + 4e-3!r}",
                  MU_GRAIN, 0.5, 0.3e-3)
    text += f"timestep {dt!r}\n" + atoms_text(pos, np.full(len(pos), d))
    text += f"""\
fix pile all mesh/surface/stress file pile.stl type 2 move 0 0 {z0!r}
fix walls all wall/gran model hertz tangential history mesh n_meshes 1 meshes pile
{side_walls(half)}fix lid all wall/gran model hertz tangential history primitive type 3 zplane {H + 2e-3!r}
fix mv all move/mesh mesh pile linear 0. 0. {-speed!r}
fix integrate all nve
{crush_line(0.0, D_COMM_RATIO * d, "")}fix damp all damp/local alpha {D_LOC:g}
thermo_style custom step atoms f_crush[1] f_crush[11] f_crush[13] f_pile[3]
thermo_modify format float %.17g lost error
thermo 1000
run {steps}
"""
    return text, {"pile.stl": stl}, {"dt": dt, "grains": len(pos)}


def oedometer_small():
    """The 64-grain oedometer of tests/integration/test_energy.py."""
    return oedometer(n=(4, 4, 4), chunk=1000)


def oedometer_big():
    """The oedometer with 729 grains: thousands of breaks."""
    return oedometer(n=(9, 9, 9))


SCENES = {"oedometer": oedometer, "same_step": same_step, "pile_tip": pile_tip, "oedometer_big": oedometer_big,
          "oedometer_small": oedometer_small}


# --------------------------------------------------------------------------
# running and reading
# --------------------------------------------------------------------------

def run_deck(text, files, workdir, liggghts, nprocs):
    os.makedirs(workdir, exist_ok=True)
    for name, content in files.items():
        with open(os.path.join(workdir, name), "w") as f:
            f.write(content)
    with open(os.path.join(workdir, "in.deck"), "w") as f:
        f.write(text)
    cmd = ["mpirun", "-np", str(nprocs)]
    if hasattr(os, "geteuid") and os.geteuid() == 0:
        cmd += ["--allow-run-as-root"]
    cmd += ["--oversubscribe", liggghts, "-in", "in.deck", "-log", "log.liggghts", "-echo", "none",
            "-screen", "screen.txt"]
    t0 = time.time()
    p = subprocess.run(cmd, cwd=workdir, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                       universal_newlines=True)
    wall = time.time() - t0
    log = open(os.path.join(workdir, "log.liggghts")).read()
    if p.returncode != 0:
        errs = [l for l in log.splitlines() if "ERROR" in l]
        raise RuntimeError("run failed in %s: %s" % (workdir, errs or p.stdout[-2000:]))
    return log, wall


def thermo_rows(log):
    """All thermo rows (numbers only) after 'Step' headers, in order, without
    the repeated first row of each run."""
    rows, cols, seen = [], None, set()
    for line in log.splitlines():
        w = line.split()
        if w and w[0] == "Step":
            cols = w
            continue
        if cols is None:
            continue
        if len(w) != len(cols):
            cols = None if not w or not w[0].isdigit() else cols
            continue
        try:
            vals = [float(v) for v in w]
        except ValueError:
            cols = None
            continue
        if vals[0] in seen:
            continue
        seen.add(vals[0])
        rows.append(vals)
    return np.array(rows)


def read_events(path):
    ev = []
    for line in open(path):
        if line.startswith("#") or not line.strip():
            continue
        w = line.split()
        ev.append({"step": int(w[0]), "tag": int(w[2]), "d": float(w[3]), "partner": w[9],
                   "generation": int(w[10]), "E_el_before": float(w[11]), "E_el_after": float(w[12]),
                   "KE_before": float(w[13]), "KE_frag0": float(w[14]), "KE_gain": float(w[15]),
                   "v_max": float(w[16])})
    return ev


def event_summary(events):
    steps = {}
    for e in events:
        steps[e["step"]] = steps.get(e["step"], 0) + 1
    rel = [e["E_el_before"] + e["KE_before"] - e["E_el_after"] - e["KE_frag0"] for e in events]
    return {
        "breaks": len(events),
        "most_breaks_in_one_step": max(steps.values()) if steps else 0,
        "breaks_at_walls": sum(1 for e in events if e["partner"] == "wall"),
        "largest_fragment_speed_m_s": max((e["v_max"] for e in events), default=0.0),
        "energy_released_J": float(sum(rel)),
        "largest_release_one_break_J": float(max(rel, default=0.0)),
        "kinetic_gain_J": float(sum(e["KE_gain"] for e in events)),
        "elastic_before_J": float(sum(e["E_el_before"] for e in events)),
        "elastic_after_J": float(sum(e["E_el_after"] for e in events)),
        "breaks_that_raised_energy": sum(1 for r in rel if r < 0.0),
    }


def analyse_oedometer(rows, info):
    # columns: step atoms Fz ke E_el damp fric R breaks M_p M_f v_max sv
    step, Fz, ke, Uel, Dd, Df, R = rows[:, 0], rows[:, 2], rows[:, 3], rows[:, 4], rows[:, 5], rows[:, 6], rows[:, 7]
    assert np.all(np.diff(step) == 1), "thermo every step expected"
    # work of the platen on the grains: it moves down at `speed`, the grains
    # push it up with Fz; trapezoid over the steps
    W = np.concatenate([[0.0], np.cumsum(0.5 * (Fz[1:] + Fz[:-1]) * info["speed"] * info["dt"])])
    E = ke + Uel
    rhs = (E - E[0]) + Dd + Df + R
    resid = W - rhs
    i = len(W) - 1
    mass = rows[:, 9] + rows[:, 10]
    out = {
        "steps": int(step[-1]), "grains": info["grains"], "atoms_end": int(rows[-1, 1]),
        "breaks": int(rows[-1, 8]), "sigma_v_end_MPa": float(rows[-1, 12] / 1e6),
        "mass_balance_rel_max": float(np.max(np.abs(mass - info["mass0"])) / info["mass0"]),
        "W_platen_J": float(W[i]), "elastic_J": float(Uel[i]), "kinetic_J": float(ke[i]),
        "damping_J": float(Dd[i]), "friction_J": float(Df[i]), "released_by_breaks_J": float(R[i]),
        "budget_residual_J": float(resid[i]),
        "budget_residual_rel": float(resid[i] / W[i]),
        "budget_residual_rel_max_over_run": float(np.max(np.abs(resid[W > 0.05 * W[i]]) / W[W > 0.05 * W[i]])),
    }
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scenes", nargs="+", default=["oedometer", "same_step", "pile_tip"], choices=list(SCENES))
    ap.add_argument("--liggghts", default=os.path.join(REPO, "build", "liggghts"))
    ap.add_argument("--np", type=int, default=1)
    ap.add_argument("--processors", default=None, help='LIGGGHTS processor grid, e.g. "2 1 1"')
    ap.add_argument("--work", default=os.path.join("/tmp", "extreme_loading"))
    ap.add_argument("--out", default=os.path.join(HERE, "results.json"))
    a = ap.parse_args(argv)
    results = {}
    if os.path.exists(a.out):
        results = json.load(open(a.out))
    keys = []
    for name in a.scenes:
        text, files, info = SCENES[name]()
        if a.processors:
            text = text.replace("newton off\n", "newton off\nprocessors %s\n" % a.processors)
        key = name if a.np == 1 else "%s_np%d" % (name, a.np)
        keys.append(key)
        wd = os.path.join(a.work, key)
        shutil.rmtree(wd, ignore_errors=True)
        log, wall = run_deck(text, files, wd, a.liggghts, a.np)
        res = {"ranks": a.np, "wall_s": round(wall, 1), "dt": info["dt"], "grains": info["grains"],
               "date": time.strftime("%Y-%m-%d")}
        res.update(event_summary(read_events(os.path.join(wd, "events.txt"))))
        if name.startswith("oedometer"):
            res.update(analyse_oedometer(thermo_rows(log), info))
        res["lost_atoms"] = 0  # the decks stop with an error at the first lost atom
        results[key] = res
        print(key, json.dumps(res, indent=1))
    cmds = results.setdefault("_commands", {})
    # keyed by the results' keys, so that a scene run at 1 and at 2 ranks keeps both commands
    cmds[", ".join(keys)] = "/usr/bin/python3 bench/extreme_loading/run.py " + " ".join(argv or sys.argv[1:])
    with open(a.out, "w") as f:
        json.dump(results, f, indent=1, sort_keys=True)


if __name__ == "__main__":
    main()
