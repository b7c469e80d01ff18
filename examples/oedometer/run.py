#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-2.0-or-later
"""Oedometer scene: build the initial packing, run LIGGGHTS, post-process.

    examples/oedometer/run.py --out results/oedometer [--np 2] [--grains unbreakable]

Writes into --out: grains.data, plate.stl, log.liggghts, breakage_events.txt,
oedometer.h5 (path and PSD), e_log_sigma_v.png, Br_sigma_v.png, psd.png,
summary.json. All options are listed by --help.
"""

import argparse
import glob
import json
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(REPO, "scripts"))

import numpy as np  # noqa: E402

from crushpost import oedometer  # noqa: E402
from crushpost.breakage import (CRUSH_READING_PRINTED, GRAIN_MODELS,  # noqa: E402
                                effective_reading, grain_model_reading)
from crushpost.dump import read_crush_log, read_dump  # noqa: E402
from crushpost.materials import D_COMM_RATIO, D_MIN_BR, RHO_GRAIN  # noqa: E402
from crushpost.meshes import write_plate_stl  # noqa: E402
from crushpost.packing import D50_NE34, ne34_diameters, rsa_cylinder, write_lammps_data  # noqa: E402
from crushpost.prep import element_prep_summary, prep_time_step  # noqa: E402
from crushpost.runner import run_liggghts  # noqa: E402

RHO = RHO_GRAIN


def build(args, out):
    d50 = D50_NE34 * args.N
    R, H = args.R_d50 * d50, args.H_d50 * d50
    rng = np.random.default_rng(args.packing_seed)
    d = ne34_diameters(20 * int(R * R * H / d50 ** 3) + 100, args.N, rng=rng)
    # as many grains as fill the cell at the target porosity
    n = int(np.searchsorted(np.cumsum(np.pi / 6 * d ** 3), (1 - args.n_target) * math.pi * R * R * H))
    d = d[:n] * args.shrink  # placed small, then grown by radius expansion
    pos = rsa_cylinder(d, R, 0.0, H, rng=rng)
    L = 1.3 * R
    write_lammps_data(os.path.join(out, "grains.data"), pos, d, RHO,
                      (-L, L, -L, L, -0.05 * H, 1.05 * H), ntypes=4)
    write_plate_stl(os.path.join(out, "plate.stl"), 1.2 * R)
    return R, H, n


def run_deck(args, out, R, H):
    v = {"inputs": os.path.join(REPO, "inputs"), "N": args.N, "R_cell": R, "H_cell": H,
         "n_target": args.n_target, "s_prep": args.s_prep, "grain_model": args.grains,
         "seed": args.seed, "dt": args.dt, "v_load": args.v_load, "sv_max": args.sv_max,
         "chunk": args.chunk, "thermo_every": args.thermo_every, "dump_every": args.dump_every,
         "n_expand_max": args.prep_loops, "tangential_model": args.tangential_model,
         "dt_prep": args.dt_prep or prep_time_step(os.path.join(out, "grains.data"))}
    if args.d_scale_ref > 0:
        v["d_scale_ref"] = args.d_scale_ref
    if args.d_comm_ratio != D_COMM_RATIO:
        v["d_comm_ratio"] = args.d_comm_ratio
    reading = grain_model_reading(args.grains, args.crush_reading)
    if reading is not None:
        v["crush_reading"] = reading
    return run_liggghts(os.path.join(HERE, "in.oedometer"), out, v, np=args.np,
                        binary=args.liggghts, name="oedometer")


def postprocess(args, out, wall, n0):
    stress = oedometer.stress_path(os.path.join(out, "log.liggghts"))
    d50 = D50_NE34 * args.N
    psd = None
    util = None
    pattern = os.path.join(out, "dump.grains.*.txt")
    if args.dump_every > 0:
        sizes = np.geomspace(0.05 * d50, 2.5 * d50, 60)
        ev_path = os.path.join(out, "breakage_events.txt")
        if os.path.exists(ev_path):
            # the fines of each break spread as fix crush/particle counts them
            # for Br (fines_grading fractal, d_min of inputs/crushable_ne34.in)
            steps, F = oedometer.psd_snapshots(pattern, RHO, sizes, events=read_crush_log(ev_path),
                                               d_min=D_MIN_BR * args.N)
        else:
            steps, F = oedometer.psd_snapshots(pattern, RHO, sizes)
        sv = np.interp(steps, stress["Step"], stress["sv"])
        # a few snapshots on loading spread over log(stress)
        load_end = stress["Step"][stress["phase"] == 0][-1]
        on_load = (steps <= load_end) & (sv > 0)
        pick = []
        for target in np.geomspace(max(sv[on_load].min(), 1e5), sv[on_load].max(), 5):
            k = np.flatnonzero(on_load)[np.argmin(np.abs(np.log(sv[on_load] / target)))]
            if k not in pick:
                pick.append(k)
        psd = {"sizes": sizes, "steps": steps[pick], "sv": sv[pick], "F": F[pick]}
        # how far the contacts stand from their limits at 1, 10 and 30 MPa
        files = sorted(glob.glob(pattern))
        snaps = [(sn["timestep"], sn["atoms"]) for f in files for sn in read_dump(f)]
        util = oedometer.utilisation_at(snaps, stress, [1e6, 10e6, 30e6])
    load = stress["phase"] == 0
    summary = {
        "grains": args.grains, "tangential_model": args.tangential_model,
        "crush_reading": effective_reading(args.grains, args.crush_reading),
        "N": args.N, "n_particles_initial": int(n0),
        "n_particles_final": int(stress["Atoms"][-1]),
        "porosity_start_of_loading": float(stress["e_void"][0] / (1 + stress["e_void"][0])),
        "e_start": float(stress["e_void"][0]), "e_min": float(stress["e_void"].min()),
        "e_end": float(stress["e_void"][-1]),
        "sigma_v_max_MPa": float(stress["sv"][load].max() / 1e6),
        "n_break_events": int(stress["n_break"][-1]), "Br_final": float(stress["Br"][-1]),
        # void ratio on loading when sigma_v first reaches 10 and 30 MPa
        "e_at_10MPa": float(oedometer.loading_state_at(stress, 10e6)[0]),
        "e_at_30MPa": float(oedometer.loading_state_at(stress, 30e6)[0]),
        # the same for the core, farther than d50 from the walls (denser than
        # the whole cell, whose fringe at the walls is loose)
        "e_core_start": float(stress["e_core"][0]),
        "e_core_at_10MPa": float(oedometer.loading_state_at(stress, 10e6, key="e_core")[0]),
        "e_core_at_30MPa": float(oedometer.loading_state_at(stress, 30e6, key="e_core")[0]),
        "Br_at_10MPa": float(oedometer.loading_state_at(stress, 10e6, key="Br")[0]),
        "Br_at_30MPa": float(oedometer.loading_state_at(stress, 30e6, key="Br")[0]),
        # crushing begins: sigma_v where 1 % of the initial grains have broken
        # (and that of the first break), crushpost.oedometer.crushing_onset
        "sigma_v_crush_onset_MPa": oedometer.crushing_onset(stress, n0)[0] / 1e6,
        "sigma_v_first_break_MPa": oedometer.crushing_onset(stress, n0)[1] / 1e6,
        # the loading branch on a log grid of sigma_v (e_core, e_void, Br), so
        # that a study can draw several runs' curves without their logs
        "loading_curve": oedometer.loading_curve(stress),
        "utilisation_at_MPa": None if util is None else
        {"%g" % (k / 1e6): v for k, v in util.items()},
        "fines_mass": float(stress["fines"][-1]), "wall_time_s": wall, "mpi_ranks": args.np,
        "prep": prep_report(args, out),
    }
    oedometer.write_hdf5(os.path.join(out, "oedometer.h5"), stress, psd, summary)
    plots = oedometer.plot_all(out, stress, psd,
                               "oedometer, %s, N = %g" % (args.grains, args.N))
    summary["plots"] = [os.path.basename(p) for p in plots]
    with open(os.path.join(out, "summary.json"), "w") as f:
        json.dump(summary, f, indent=2)
    return summary


def prep_report(args, out):
    """The prepared specimen as the deck reported it (crushpost.prep.element_prep_summary)."""
    return element_prep_summary(os.path.join(out, "log.liggghts"), args.n_target, args.s_prep)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", default=os.path.join(REPO, "results", "oedometer"))
    p.add_argument("--np", type=int, default=2, help="MPI ranks")
    p.add_argument("--grains", default="crushable_ne34", choices=list(GRAIN_MODELS),
                   help="grain model (inputs/<name>.in, docs/grain_models.md)")
    p.add_argument("--tangential-model", default="history", choices=["history", "incremental"],
                   help="tangential contact law of grain contacts and walls: LIGGGHTS' "
                   "displacement-based 'history' (default) or PFC's force-increment "
                   "'incremental' (docs/tangential_incremental.md)")
    p.add_argument("--N", type=float, default=39.0, help="particle up-scaling factor")
    p.add_argument("--R-d50", type=float, default=5.0, help="cell radius in d50")
    p.add_argument("--H-d50", type=float, default=8.0, help="cell height in d50")
    p.add_argument("--n-target", type=float, default=0.385,
                   help="core porosity at the end of the radius expansion")
    p.add_argument("--s-prep", type=float, default=5e3, help="preparation stress (Pa)")
    p.add_argument("--prep-loops", type=int, default=150,
                   help="at most this many radius-expansion chunks (fast phase) and growth cycles "
                   "(docs/preparation.md)")
    p.add_argument("--dt-prep", type=float, default=None,
                   help="time step of the preparation (default 0.15 Rayleigh times of the smallest "
                   "grain as placed)")
    p.add_argument("--shrink", type=float, default=0.75, help="initial size factor before expansion")
    p.add_argument("--sv-max", type=float, default=30e6, help="vertical stress to load to (Pa)")
    p.add_argument("--v-load", type=float, default=1.0, help="platen speed (m/s)")
    p.add_argument("--dt", type=float, default=1.5e-7)
    p.add_argument("--chunk", type=int, default=2000)
    p.add_argument("--thermo-every", type=int, default=500)
    p.add_argument("--dump-every", type=int, default=5000, help="particle dumps (0 = none)")
    p.add_argument("--d-scale-ref", type=float, default=0.0,
                   help="density scaling of particles finer than this (m; fix crush/particle "
                   "density_scale); 0 = off")
    p.add_argument("--d-comm-ratio", type=float, default=D_COMM_RATIO,
                   help="comminution limit d_comm / d50 (docs/model.md §3: 0.55)")
    p.add_argument("--crush-reading", default=CRUSH_READING_PRINTED,
                   help="keywords of the criterion reading given to fix crush/particle "
                   "(docs/fix_crush_particle.md, Criterion readings), e.g. 'pressure peak "
                   "scatter truncated f_min 0.5'; default: the printed model")
    p.add_argument("--seed", type=int, default=15485863)
    p.add_argument("--packing-seed", type=int, default=2024)
    p.add_argument("--liggghts", default=None, help="LIGGGHTS binary (default build/liggghts)")
    args = p.parse_args(argv)
    try:
        grain_model_reading(args.grains, args.crush_reading)
    except ValueError as e:
        p.error(str(e))
    os.makedirs(args.out, exist_ok=True)
    R, H, n0 = build(args, args.out)
    wall = run_deck(args, args.out, R, H)
    summary = postprocess(args, args.out, wall, n0)
    print(json.dumps(summary, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
