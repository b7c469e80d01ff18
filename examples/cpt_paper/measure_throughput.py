#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-2.0-or-later
"""Throughput of the chamber deck in its jacking phase (crushable grains), for
the cost estimate of the paper runs in docs/cpt.md ("Cost"; the measurements:
docs/studies/cpt-cost.md).

    examples/cpt_paper/measure_throughput.py --out /tmp/tp --np 1 2 [--R-ch 0.108 --H-ch 0.2]

Makes a reduced chamber with make_chamber.py (N = 39; 0.108 m by 0.2 m is
about 20,000 grains), runs in.monotonic with a short preparation (a few fast
radius-expansion chunks and growth cycles, two servo chunks per stage, with
prep_strict 0: the packing is near, not at, the prepared state, and the deck
reports the stages it did not finish instead of stopping) and then jacking
in chunks of 2000 steps, and
reports for each rank count: grains, particle-steps per core-second over the
jacking chunks (atoms * steps / (loop time * ranks)), and LIGGGHTS' memory
per rank. Writes throughput.json into --out.
"""

import argparse
import json
import os
import re
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", required=True)
    p.add_argument("--np", type=int, nargs="+", default=[1, 2])
    p.add_argument("--R-ch", type=float, default=0.108)
    p.add_argument("--H-ch", type=float, default=0.2)
    p.add_argument("--jack-steps", type=int, default=6000)
    p.add_argument("--expand-chunks", type=int, default=5,
                   help="radius-expansion chunks and growth cycles at most (prep_strict 0)")
    p.add_argument("--liggghts", default=os.path.join(REPO, "build", "liggghts"))
    p.add_argument("--proc-grid", default=None,
                   help="LIGGGHTS processors grid, e.g. '16 1 1' (default '* * 1', 1 1 1 at 1 rank)")
    a = p.parse_args(argv)
    dt, v = 1.5e-7, 0.5
    depth = a.jack_steps * v * dt
    subprocess.run([sys.executable, os.path.join(HERE, "make_chamber.py"), "--out", a.out, "--case",
                    "monotonic", "--R-ch", str(a.R_ch), "--H-ch", str(a.H_ch), "--depth", str(depth)],
                   check=True, stdout=subprocess.DEVNULL)
    results = []
    for n in a.np:
        log = "log_np%d.liggghts" % n
        cmd = ["mpirun", "--oversubscribe", "-np", str(n)]
        if os.geteuid() == 0:
            cmd.insert(1, "--allow-run-as-root")
        cmd += [a.liggghts, "-in", os.path.join(HERE, "in.monotonic"), "-log", log, "-screen", "none"]
        var = {"inputs": os.path.join(REPO, "inputs"), "deck_dir": HERE, "R_ch": a.R_ch, "H_ch": a.H_ch,
               "jack_args": "mode monotonic v %g depth %g" % (v, depth), "n_expand_max": a.expand_chunks,
               "prep_strict": 0, "prep_chunk": 2000, "servo_loops": 2, "jack_chunk": 2000,
               "output_block": "none", "prep_snapshot_block": "none",
               "thermo_every": 1000, "proc_grid": a.proc_grid or ("* * 1" if n > 1 else "1 1 1")}
        for k, val in var.items():
            cmd += ["-var", k, str(val)]
        subprocess.run(cmd, check=True, cwd=a.out)
        text = open(os.path.join(a.out, log)).read()
        jack_part = text[text.index("fix jack all jack/pile"):]
        loops = re.findall(r"Loop time of ([\d.eE+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms", jack_part)
        mem = re.findall(r"Memory usage per processor = ([\d.]+) Mbytes", jack_part)
        rates = [int(s) * int(at) / (float(t) * int(pr)) for t, pr, s, at in loops if int(s) > 0]
        por = re.findall(r"porosity_core ([\d.]+)", text)
        results.append({"np": n, "atoms": int(loops[-1][3]), "chunks": len(rates),
                        "porosity_after_servo": float(por[-1]) if por else None,
                        "particle_steps_per_core_s": rates, "best": max(rates),
                        "median": sorted(rates)[len(rates) // 2],
                        "memory_MB_per_rank": float(mem[-1]) if mem else None})
        print(json.dumps(results[-1]))
    with open(os.path.join(a.out, "throughput.json"), "w") as f:
        json.dump(results, f, indent=2)
    return 0


if __name__ == "__main__":
    sys.exit(main())
