#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-2.0-or-later
"""Where do grains leave the calibration chamber? (docs/studies/cpt-lost-grains.md)

    /usr/bin/python3 bench/lost_grains/run.py --out results/lost_grains/old --hole 1.25
    /usr/bin/python3 bench/lost_grains/run.py --out results/lost_grains/new --hole 1.0

A diagnostic, not a test. It builds the chamber of examples/cpt_demo (by
default a quarter sector, 54 mm = 3 R in radius, 120 mm high, N = 39) with
the top wall's hole set to --hole times the pile radius R, and runs
examples/cpt_demo/in.cpt (preparation, servo, a monotonic push) with a
tracking block hooked in where the deck takes its measurement-sphere block:
every --every steps it writes

* escape.txt: step, grains whose centre is outside the chamber (above the top
  wall, below the bottom, beyond the lateral wall, across a symmetry plane),
  of those above the top wall, the number of grains in the box, the top
  wall's z, the tip depth;
* escaped.txt: a dump (id, position, velocity, radius) of the grains outside.

and then reports, for every grain that got outside, where it was first seen
(distance from the pile axis, height above the top wall), its diameter, and
the depth of the tip then, into escape_summary.json. Grains that leave the
simulation box are lost: with a LIGGGHTS whose lost-atom check works the run
stops at the first one (the tracking files show what happened before).
"""

import argparse
import json
import math
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(REPO, "scripts"))

import numpy as np  # noqa: E402

from crushpost.breakage import GRAIN_MODELS  # noqa: E402
from crushpost.chamber import write_chamber  # noqa: E402
from crushpost.dump import read_dump  # noqa: E402
from crushpost.meshes import read_stl, write_stl  # noqa: E402
from crushpost.runner import mpirun_command  # noqa: E402

TRACK = """\
# grains outside the chamber, every {every} steps (bench/lost_grains/run.py)
variable esc_top  atom z>v_H_s
variable esc_any  atom (z>v_H_s)||(z<0.0)||(x*x+y*y>v_R_fixed*v_R_fixed)||((${{sector}}<360)&&(y<0.0))||((${{sector}}<=90)&&(x<0.0))
variable esc_one  atom 1.0
compute  esc_n   all reduce sum v_esc_any
compute  esc_nt  all reduce sum v_esc_top
compute  esc_all all reduce sum v_esc_one
fix      esc_log all ave/time {every} 1 {every} c_esc_n c_esc_nt c_esc_all v_H_s f_jack[2] file escape.txt
dump     esc all custom {every} escaped.txt id x y z vx vy vz radius
dump_modify esc thresh v_esc_any > 0.5
"""


def set_hole(path, r_hole):
    """Move the inner ring of the top wall's annulus to radius r_hole."""
    _, tri = read_stl(path)
    r = np.hypot(tri[..., 0], tri[..., 1])
    inner = np.abs(r - r.min()) < 1e-9 * r.max()
    tri[inner, 0] *= r_hole / r[inner]
    tri[inner, 1] *= r_hole / r[inner]
    write_stl(path, [tuple(map(tuple, t)) for t in tri], "top")


def first_sightings(path, every):
    """For each grain ever outside: the first frame it appears in."""
    seen = {}
    for snap in read_dump(path):
        at = snap["atoms"]
        for k, tag in enumerate(at.get("id", [])):
            if int(tag) not in seen:
                seen[int(tag)] = {key: float(at[key][k]) for key in at if key != "id"}
                seen[int(tag)]["step"] = snap["timestep"]
    return seen


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", required=True)
    p.add_argument("--hole", type=float, default=1.0, help="hole radius / pile radius")
    p.add_argument("--np", type=int, default=1)
    p.add_argument("--N", type=float, default=39.0)
    p.add_argument("--R-ch", type=float, default=0.054)
    p.add_argument("--H-ch", type=float, default=0.12)
    p.add_argument("--R-pile", type=float, default=0.018)
    p.add_argument("--sector", type=int, default=90, choices=[360, 180, 90])
    p.add_argument("--depth", type=float, default=0.08)
    p.add_argument("--v-push", type=float, default=1.0)
    p.add_argument("--grains", default="crushable_ne34", choices=list(GRAIN_MODELS))
    p.add_argument("--prep-loops", type=int, default=40)
    p.add_argument("--servo-steps", type=int, default=20000)
    p.add_argument("--every", type=int, default=500, help="steps between tracking outputs")
    p.add_argument("--lid", action="store_true",
                   help="prototype: keep the plug over the hole until the cone's base has passed "
                   "the top wall (plug_lid.in)")
    p.add_argument("--jack-args", default=None,
                   help="fix jack/pile arguments instead of a monotonic push to --depth")
    p.add_argument("--thermo-every", type=int, default=1000)
    p.add_argument("--jack-every", type=int, default=200)
    p.add_argument("--packing-seed", type=int, default=2024)
    p.add_argument("--liggghts", default=None)
    a = p.parse_args(argv)
    out = os.path.abspath(a.out)
    if a.liggghts:
        a.liggghts = os.path.abspath(a.liggghts)      # LIGGGHTS runs in --out
    os.makedirs(out, exist_ok=True)
    c = write_chamber(out, a.N, a.R_ch, a.H_ch, a.R_pile, a.depth, sector=a.sector,
                      rng=a.packing_seed, fast=False)
    r_hole = a.hole * a.R_pile
    set_hole(os.path.join(out, "top.stl"), r_hole)
    track = os.path.join(out, "track.in")
    with open(track, "w") as f:
        f.write(TRACK.format(every=a.every))
        if a.lid:
            f.write(open(os.path.join(HERE, "plug_lid.in")).read())
    v = {"inputs": os.path.join(REPO, "inputs"), "N": a.N, "R_ch": a.R_ch, "H_ch": a.H_ch,
         "R_pile": a.R_pile, "R_hole": r_hole, "sector": a.sector, "grain_model": a.grains,
         "proc_grid": "* * 1", "servo_steps": a.servo_steps, "n_expand_max": a.prep_loops,
         "s_prep": 50e3, "jack_every": a.jack_every, "thermo_every": a.thermo_every,
         "jack_args": a.jack_args or "mode monotonic v %g depth %g" % (a.v_push, a.depth),
         "spheres_file": track}
    cmd = mpirun_command(os.path.join(REPO, "examples", "cpt_demo", "in.cpt"), v, np=a.np,
                         binary=a.liggghts)
    t0 = time.time()
    rc = subprocess.call(cmd, cwd=out, stdin=subprocess.DEVNULL)
    wall = time.time() - t0
    log = open(os.path.join(out, "log.liggghts"), errors="replace").read()
    errors = [ln for ln in log.splitlines() if ln.startswith("ERROR")]
    esc = np.loadtxt(os.path.join(out, "escape.txt"), comments="#", ndmin=2)
    seen = first_sightings(os.path.join(out, "escaped.txt"), a.every)
    depth_at = lambda s: float(np.interp(s, esc[:, 0], esc[:, 5]))  # noqa: E731
    top_at = lambda s: float(np.interp(s, esc[:, 0], esc[:, 4]))  # noqa: E731
    grains = []
    for tag, g in sorted(seen.items(), key=lambda kv: kv[1]["step"]):
        grains.append({"id": tag, "step": g["step"], "tip_depth_m": depth_at(g["step"]),
                       "r_over_R": math.hypot(g["x"], g["y"]) / a.R_pile,
                       "z_above_top_wall_m": g["z"] - top_at(g["step"]),
                       "diameter_m": 2 * g["radius"],
                       "speed_m_s": math.sqrt(g["vx"] ** 2 + g["vy"] ** 2 + g["vz"] ** 2)})
    n_break = [ln for ln in log.splitlines() if ln.startswith("CHAMBER") or ln.startswith("LID")]
    summary = {"hole_over_R": a.hole, "lid": a.lid, "jack_args": v["jack_args"], "R_hole_m": r_hole, "grains": c["n"], "sector": a.sector,
               "R_ch": a.R_ch, "H_ch": a.H_ch, "depth_target_m": a.depth,
               "grain_model": a.grains, "exit_code": rc, "errors": errors, "wall_s": wall,
               "final_step": int(esc[-1, 0]), "final_tip_depth_m": float(esc[-1, 5]),
               "max_outside": int(esc[:, 1].max()), "max_above_top": int(esc[:, 2].max()),
               "atoms_first": int(esc[0, 3]), "atoms_last": int(esc[-1, 3]),
               "grains_ever_outside": grains, "chamber_lines": n_break}
    with open(os.path.join(out, "escape_summary.json"), "w") as f:
        json.dump(summary, f, indent=2)
    print(json.dumps(summary, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
