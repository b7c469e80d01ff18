#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-2.0-or-later
"""Drained triaxial compression scene: build the initial packing (and, for the
cell with rigid plates, the six plates), run LIGGGHTS, post-process.

    examples/triaxial/run.py --out results/triaxial [--np 2] [--grains unbreakable] [--small]
    examples/triaxial/run.py --out results/triaxial_walls --cell walls

The default cell is periodic (in.triaxial_periodic: no walls, the whole
specimen at the density of the preparation); --cell walls puts the specimen
between six rigid frictionless plates (in.triaxial). docs/studies/calibration.md
gives the study behind the choice.

Writes into --out: grains.data, plate_*.stl (walls), log.liggghts, breakage_events.txt
(crushable grains), triaxial.h5 (shearing path and summary),
q_p_eps_a.png (q/p' and eps_v against eps_a), stress_path.png (q - p'),
summary.json. All options are listed by --help; docs/triaxial.md explains the
scene and the servo.
"""

import argparse
import json
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(REPO, "scripts"))

import numpy as np  # noqa: E402

from crushpost import triaxial  # noqa: E402
from crushpost.breakage import (CRUSH_READING_PRINTED, GRAIN_MODELS,  # noqa: E402
                                effective_reading, grain_model_reading)
from crushpost.materials import D_COMM_RATIO, RHO_GRAIN, rayleigh_time  # noqa: E402
from crushpost.meshes import write_rectangle_stl  # noqa: E402
from crushpost.packing import D50_NE34, ne34_diameters, rsa_box, write_lammps_data  # noqa: E402
from crushpost.prep import element_prep_summary  # noqa: E402
from crushpost.runner import run_liggghts  # noqa: E402

RHO = RHO_GRAIN
FRAGMENT_SMALL = 0.230093     # radius of the small Apollonian fragment / parent radius
D_COMM_D50 = D_COMM_RATIO     # comminution limit / d50 (docs/model.md §3)

# Plate spans relative to the specimen (see docs/triaxial.md): lateral plates
# reach LATERAL_Z_SPAN * H / 2 from mid-height and LATERAL_SPAN * W / 2 across;
# the end plates reach END_SPAN * W / 2. The box encloses all of them.
LATERAL_SPAN = 1.6
LATERAL_Z_SPAN = 1.4
END_SPAN = 1.8

# specimen (W, H) in d50. The default is the smallest size whose peak
# stress ratio lies within the packing-seed scatter of the largest size
# studied (docs/studies/calibration.md: periodic cells of 6-16 d50; the peak falls
# with size up to 12 d50 and stays at 16 d50; the ratio at 25 % axial strain
# varies by up to 1.6 degrees between sizes from 8 d50 on, without a trend).
SIZES = {
    "default": (12.0, 12.0),
    "small": (6.0, 6.0),
}


def auto_dt(grains, N, d_placed_min, fraction=0.15):
    """Time steps (dt, dt_prep): `fraction` of the Rayleigh time of the smallest
    grain that can exist in each part of the run (docs/model.md §5).

    dt_prep, the preparation (no crushing fix yet): the smallest grain as
    placed (d_placed_min, before radius expansion). dt, from consolidation on:
    for crushable grains the smallest fragment of the smallest breakable grain
    (radius 0.230093 d_comm / 2), otherwise the same as dt_prep.
    """
    dt_prep = fraction * rayleigh_time(0.5 * d_placed_min)
    if GRAIN_MODELS[grains] is not None:
        r_frag = FRAGMENT_SMALL * 0.5 * D_COMM_D50 * D50_NE34 * N
        return min(dt_prep, fraction * rayleigh_time(r_frag)), dt_prep
    return dt_prep, dt_prep


def build(args, out):
    d50 = D50_NE34 * args.N
    W, H = args.W_d50 * d50, args.H_d50 * d50
    rng = np.random.default_rng(args.packing_seed)
    d = ne34_diameters(20 * int(W * W * H / d50 ** 3) + 100, args.N, rng=rng)
    # as many grains as fill the box at the target porosity
    n = int(np.searchsorted(np.cumsum(np.pi / 6 * d ** 3), (1 - args.n_target) * W * W * H))
    d = d[:n]
    pos = rsa_box(d * args.shrink, (-W / 2, -W / 2, 0.0), (W / 2, W / 2, H), rng=rng)
    if args.cell == "periodic":
        # the box is the specimen, periodic in x, y and z: no plates
        write_lammps_data(os.path.join(out, "grains.data"), pos, d * args.shrink, RHO,
                          (-W / 2, W / 2, -W / 2, W / 2, 0.0, H), ntypes=4)
        return W, H, n, float(d.min())
    box = (-END_SPAN * W / 2 - 0.1 * W, END_SPAN * W / 2 + 0.1 * W) * 2 + \
        (H / 2 - LATERAL_Z_SPAN * H / 2 - 0.1 * H, H / 2 + LATERAL_Z_SPAN * H / 2 + 0.1 * H)
    box = (box[0], box[1], box[0], box[1], box[4], box[5])
    write_lammps_data(os.path.join(out, "grains.data"), pos, d * args.shrink, RHO, box, ntypes=4)
    centre = (0.0, 0.0, H / 2)
    # lateral plates: x plates span (y, z); y plates span (z, x) in cyclic order
    write_rectangle_stl(os.path.join(out, "plate_xm.stl"), 0, -W / 2, centre,
                        LATERAL_SPAN * W / 2, LATERAL_Z_SPAN * H / 2, +1, "plate_xm")
    write_rectangle_stl(os.path.join(out, "plate_xp.stl"), 0, W / 2, centre,
                        LATERAL_SPAN * W / 2, LATERAL_Z_SPAN * H / 2, -1, "plate_xp")
    write_rectangle_stl(os.path.join(out, "plate_ym.stl"), 1, -W / 2, centre,
                        LATERAL_Z_SPAN * H / 2, LATERAL_SPAN * W / 2, +1, "plate_ym")
    write_rectangle_stl(os.path.join(out, "plate_yp.stl"), 1, W / 2, centre,
                        LATERAL_Z_SPAN * H / 2, LATERAL_SPAN * W / 2, -1, "plate_yp")
    write_rectangle_stl(os.path.join(out, "plate_zm.stl"), 2, 0.0, centre,
                        END_SPAN * W / 2, END_SPAN * W / 2, +1, "plate_zm")
    write_rectangle_stl(os.path.join(out, "plate_zp.stl"), 2, H, centre,
                        END_SPAN * W / 2, END_SPAN * W / 2, -1, "plate_zp")
    return W, H, n, float(d.min())


def liggghts_variables(args, W, H, dt, dt_prep):
    v = {"inputs": os.path.join(REPO, "inputs"), "N": args.N, "W": W, "H": H,
         "n_target": args.n_target, "s_prep": args.s_prep, "grain_model": args.grains,
         "seed": args.seed, "dt": dt, "dt_prep": dt_prep, "p_iso": args.p_iso, "sigma3": args.sigma3,
         "rate": args.rate, "eps_a_max": args.eps_a_max, "g_P": args.g_P, "g_I": args.g_I,
         "e_u_max": args.e_u_max, "e_u_cons": args.e_u_cons,
         "cons_tol": args.cons_tol, "cons_loops": args.cons_loops,
         "chunk": args.chunk, "thermo_every": args.thermo_every,
         "dump_every": args.dump_every, "n_expand_max": args.prep_loops,
         "D_loc_shear": args.D_loc, "rotation": int(args.rotation),
         "tangential_model": args.tangential_model,
         "incremental_shear": int(args.incremental_shear)}
    reading = grain_model_reading(args.grains, args.crush_reading)
    if reading is not None:     # a named grain model sets its own (docs/grain_models.md)
        v["crush_reading"] = reading
    return v


def run_deck(args, out, W, H, dt, dt_prep):
    if args.incremental_shear and args.cell != "periodic":
        # in.triaxial's plates are a wall fix of their own, which the switch would not reach
        raise SystemExit("--incremental-shear: only with --cell periodic")
    deck = "in.triaxial_periodic" if args.cell == "periodic" else "in.triaxial"
    return run_liggghts(os.path.join(HERE, deck), out,
                        liggghts_variables(args, W, H, dt, dt_prep), np=args.np,
                        binary=args.liggghts, name="triaxial")


def postprocess(args, out, wall, n0, dt, dt_prep):
    path = triaxial.shear_path(os.path.join(out, "log.liggghts"))
    res = triaxial.analyse(path, sigma3=args.sigma3, cs_window=args.cs_window,
                           dil_window=args.dil_window, settle=args.settle)
    summary = {
        "grains": args.grains, "crush_reading": effective_reading(args.grains, args.crush_reading),
        "cell": args.cell, "W_d50": args.W_d50, "H_d50": args.H_d50,
        "N": args.N, "n_particles_initial": int(n0),
        "n_particles_final": int(path["Atoms"][-1]), "mpi_ranks": args.np,
        "wall_time_s": wall, "dt": dt, "dt_prep": dt_prep, "axial_strain_rate": args.rate,
        "inertial_number": args.rate * D50_NE34 * args.N * math.sqrt(RHO / args.sigma3),
        "p_iso": args.p_iso, "sigma3_target": args.sigma3, "D_loc": args.D_loc,
        "rotation": bool(args.rotation), "tangential_model": args.tangential_model,
        "incremental_shear": bool(args.incremental_shear),
        "packing_seed": args.packing_seed,
        "porosity_start_of_shearing": float(path["porosity"][0]),
        "prep": prep_report(args, out),
        "e_start_of_shearing": float(path["e_void"][0]),
        "n_break_events": int(path["n_break"][-1]), "Br_final": float(path["Br"][-1]),
        # q/p, eps_v and Br every 0.5 % of axial strain, so that a study can
        # draw several runs' curves without their logs
        "shear_curve": triaxial.shear_curve(path),
    }
    summary.update(res)
    triaxial.write_hdf5(os.path.join(out, "triaxial.h5"), path, summary)
    plots = triaxial.plot_all(out, path, res, "triaxial, %s, N = %g, %d grains"
                              % (args.grains, args.N, n0))
    summary["plots"] = [os.path.basename(p) for p in plots]
    with open(os.path.join(out, "summary.json"), "w") as f:
        json.dump(summary, f, indent=2)
    return summary


def prep_report(args, out):
    """The prepared specimen as the deck reported it (crushpost.prep.element_prep_summary)."""
    return element_prep_summary(os.path.join(out, "log.liggghts"), args.n_target, args.s_prep)


def parse_args(argv=None):
    p = argparse.ArgumentParser(description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", default=os.path.join(REPO, "results", "triaxial"))
    p.add_argument("--np", type=int, default=2, help="MPI ranks")
    p.add_argument("--grains", default="crushable_ne34", choices=list(GRAIN_MODELS),
                   help="grain model (inputs/<name>.in, docs/grain_models.md)")
    p.add_argument("--crush-reading", default=CRUSH_READING_PRINTED,
                   help="keywords of the criterion reading given to fix crush/particle "
                   "(docs/fix_crush_particle.md, Criterion readings), e.g. 'pressure peak "
                   "scatter truncated f_min 0.5'; default: the printed model")
    p.add_argument("--cell", default="periodic", choices=["periodic", "walls"],
                   help="specimen between six rigid frictionless plates (in.triaxial), or a "
                   "periodic cell whose stresses are the grains' own (in.triaxial_periodic)")
    p.add_argument("--N", type=float, default=39.0, help="particle up-scaling factor")
    p.add_argument("--small", action="store_true",
                   help="small specimen (W x W x H = %g x %g x %g d50, a few hundred grains) "
                   "instead of %g x %g x %g d50"
                   % ((SIZES["small"][0],) + SIZES["small"] + (SIZES["default"][0],) + SIZES["default"]))
    p.add_argument("--W-d50", type=float, default=None, help="specimen width in d50")
    p.add_argument("--H-d50", type=float, default=None, help="specimen height in d50")
    p.add_argument("--n-target", type=float, default=0.385,
                   help="core porosity at the end of the radius expansion")
    p.add_argument("--s-prep", type=float, default=5e3, help="preparation stress (Pa)")
    p.add_argument("--prep-loops", type=int, default=150,
                   help="at most this many radius-expansion chunks (fast phase) and growth cycles "
                   "(docs/preparation.md)")
    p.add_argument("--shrink", type=float, default=0.75, help="initial size factor before expansion")
    p.add_argument("--p-iso", type=float, default=100e3, help="isotropic consolidation stress (Pa)")
    p.add_argument("--sigma3", type=float, default=100e3, help="cell pressure while shearing (Pa)")
    p.add_argument("--rate", type=float, default=5.0, help="axial strain rate (1/s)")
    p.add_argument("--eps-a-max", type=float, default=0.25, help="axial strain to shear to")
    p.add_argument("--D-loc", type=float, default=0.05,
                   help="local damping coefficient from consolidation on (docs/model.md §3: D_loc = 0.05; "
                   "the preparation keeps 0.05)")
    p.add_argument("--tangential-model", default="history", choices=["history", "incremental"],
                   help="tangential contact law of grain contacts and walls: LIGGGHTS' "
                   "displacement-based 'history' (default) or PFC's force-increment "
                   "'incremental' (docs/tangential_incremental.md), for the whole run")
    p.add_argument("--incremental-shear", action="store_true",
                   help="periodic cell only: switch the grain contacts to 'tangential incremental' "
                   "from consolidation on, on the specimen prepared with --tangential-model "
                   "(a diagnostic, docs/studies/calibration.md item 4)")
    p.add_argument("--rotation", action="store_true",
                   help="let the grains rotate from consolidation on (a diagnostic: docs/model.md §2.2 "
                   "inhibits rotation)")
    p.add_argument("--g-P", type=float, default=40.0, help="proportional servo gain (1/s)")
    p.add_argument("--g-I", type=float, default=3.2e5, help="integral servo gain (1/s^2)")
    p.add_argument("--e-u-max", type=float, default=None,
                   help="servo speed cap while shearing, as a plate strain rate "
                   "(1/s; default 2.5 x rate)")
    p.add_argument("--e-u-cons", type=float, default=None,
                   help="servo speed cap during consolidation, as a plate strain rate "
                   "(1/s; default: rate)")
    p.add_argument("--cons-tol", type=float, default=0.02,
                   help="consolidation ends when every plate is within this relative error")
    p.add_argument("--cons-loops", type=int, default=60, help="max consolidation chunks")
    p.add_argument("--dt", type=float, default=None,
                   help="time step (default: 0.15 Rayleigh times of the smallest grain that "
                   "can exist, see auto_dt)")
    p.add_argument("--chunk", type=int, default=2000, help="steps between consolidation checks")
    p.add_argument("--thermo-every", type=int, default=500)
    p.add_argument("--dump-every", type=int, default=0, help="particle dumps (0 = none)")
    p.add_argument("--seed", type=int, default=15485863)
    p.add_argument("--packing-seed", type=int, default=2024)
    p.add_argument("--cs-window", type=float, default=0.05,
                   help="critical state: mean over the last this much axial strain")
    p.add_argument("--dil-window", type=float, default=0.02,
                   help="dilatancy: local linear fit of eps_v(eps_a) over this strain window")
    p.add_argument("--settle", type=float, default=0.01,
                   help="servo errors: averaged from this axial strain on")
    p.add_argument("--liggghts", default=None, help="LIGGGHTS binary (default build/liggghts)")
    args = p.parse_args(argv)
    try:
        grain_model_reading(args.grains, args.crush_reading)
    except ValueError as e:
        p.error(str(e))
    if args.e_u_max is None:
        args.e_u_max = 2.5 * args.rate
    if args.e_u_cons is None:
        args.e_u_cons = args.rate
    size = SIZES["small" if args.small else "default"]
    if args.W_d50 is None:
        args.W_d50 = size[0]
    if args.H_d50 is None:
        args.H_d50 = size[1]
    return args


def main(argv=None):
    args = parse_args(argv)
    os.makedirs(args.out, exist_ok=True)
    W, H, n0, d_min = build(args, args.out)
    dt, dt_prep = auto_dt(args.grains, args.N, args.shrink * d_min)
    if args.dt:
        dt = dt_prep = args.dt
    wall = run_deck(args, args.out, W, H, dt, dt_prep)
    summary = postprocess(args, args.out, wall, n0, dt, dt_prep)
    print(json.dumps(summary, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
