#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-2.0-or-later
"""Input files of the paper-scale calibration chamber (docs/model.md §4.4-§4.5).

    examples/cpt_paper/make_chamber.py --out runs/cyclic [--case cyclic|monotonic|unbreakable]
                                       [--sector 360|180|90] [--np 64]

Writes into --out the loose packing grains.data (NE34 grading at N = 39,
porosity 0.385 at 0.75 of the final size, about 442,000 grains for the full
chamber: vectorised random sequential addition, a few minutes) and the meshes
read by inputs/chamber_walls.in (side.stl, top.stl, plug.stl, bottom.stl,
cone.stl, shaft.stl, and the symmetry planes sym_y.stl, sym_x.stl of a sector), plus run.sh with the mpirun command line for the case,
and chamber.json (grain count, box, sizes). Reduce --R-ch / --H-ch /
--depth for smaller scenes (the deck variables R_ch, H_ch and jack_args must
then be passed too; run.sh does it).
"""

import argparse
import json
import os
import shlex
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(REPO, "scripts"))

from crushpost.chamber import hole_radius, write_chamber  # noqa: E402
from crushpost.prep import prep_chunk_for, prep_time_step  # noqa: E402


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", required=True)
    p.add_argument("--case", default="cyclic", choices=["cyclic", "monotonic", "unbreakable"])
    p.add_argument("--sector", type=int, default=360, choices=[360, 180, 90])
    p.add_argument("--N", type=float, default=39.0)
    p.add_argument("--R-ch", type=float, default=0.216, help="chamber radius (m): 432 mm diameter")
    p.add_argument("--H-ch", type=float, default=1.0, help="chamber height (m)")
    p.add_argument("--R-pile", type=float, default=0.018)
    p.add_argument("--depth", type=float, default=0.8, help="final tip depth (m)")
    p.add_argument("--n-target", type=float, default=0.385)
    p.add_argument("--shrink", type=float, default=0.75)
    p.add_argument("--packing-seed", type=int, default=10103)
    p.add_argument("--np", type=int, default=64, help="MPI ranks written into run.sh")
    p.add_argument("--liggghts", default="liggghts", help="LIGGGHTS binary written into run.sh")
    a = p.parse_args(argv)

    t0 = time.time()
    c = write_chamber(a.out, a.N, a.R_ch, a.H_ch, a.R_pile, a.depth, n_target=a.n_target,
                      shrink=a.shrink, sector=a.sector, rng=a.packing_seed)
    c["generation_s"] = time.time() - t0
    if a.case == "monotonic":
        jack = "mode monotonic v 0.5 depth %g" % a.depth
    else:
        jack = "mode cyclic v 0.5 stroke 0.1 v_unload 0.05 pause 5e-3 depth %g zero_tol 1.0" % a.depth
    variables = {"inputs": os.path.join(REPO, "inputs"), "deck_dir": HERE, "N": a.N,
                 "R_ch": a.R_ch, "H_ch": a.H_ch, "R_pile": a.R_pile,
                 "R_hole": hole_radius(a.R_pile), "sector": a.sector, "jack_args": jack,
                 "n_target": a.n_target,
                 "dt_prep": "%.4g" % prep_time_step(os.path.join(a.out, "grains.data")),
                 "prep_chunk": prep_chunk_for(a.R_ch, a.H_ch)}
    cmd = ["mpirun", "-np", str(a.np), a.liggghts, "-in", os.path.join(HERE, "in." + a.case),
           "-log", "log.liggghts"]
    for k, v in variables.items():
        cmd += ["-var", k, str(v)]
    with open(os.path.join(a.out, "run.sh"), "w") as f:
        f.write("#!/bin/sh\n# %s chamber, %d grains, sector %d deg (made by make_chamber.py)\n"
                % (a.case, c["n"], a.sector))
        f.write("cd \"$(dirname \"$0\")\"\n")
        f.write(" ".join(shlex.quote(x) for x in cmd) + "\n")
    os.chmod(os.path.join(a.out, "run.sh"), 0o755)
    c.update({"case": a.case, "sector": a.sector, "R_ch": a.R_ch, "H_ch": a.H_ch, "N": a.N,
              "depth": a.depth, "command": cmd})
    with open(os.path.join(a.out, "chamber.json"), "w") as f:
        json.dump(c, f, indent=2)
    print(json.dumps({k: c[k] for k in ("n", "generation_s", "sector", "case")}, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
