# SPDX-License-Identifier: GPL-2.0-or-later
"""How much a run boundary (a split `run`, or write_restart + read_restart)
perturbs a crushing compression (docs/studies/stability.md, "Parallel edge cases").

The periodic scene of tests/integration/test_parallel_edges.py at 1 rank,
to step 12400, with dumps of v at steps 12001-12010 and every 50 steps after:
  uninterrupted  one `run` that also writes restart.12000.bin
  split          `run 12000` then `run 400` in the same deck
  restart        read_restart of restart.12000.bin, `run 400`
  restart, no crush fix   the same without `fix crush/particle` (no break is
                 pending between 12000 and 12010, so the fix does nothing there)
Prints, per variant and step, how many atoms' velocities differ from the
uninterrupted run and the largest difference.  Local damping `alpha` from the
command line (default 0: no damping, so it cannot be the cause).

    LIGGGHTS_BIN=build/liggghts python3 bench/run_boundary/run_boundary.py [alpha] [workdir]
"""

import shutil
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent.parent / "tests" / "integration"))
import crush_multi as cm  # noqa: E402
import harness  # noqa: E402
import test_parallel_edges as tpe  # noqa: E402

ALPHA = float(sys.argv[1]) if len(sys.argv) > 1 else 0.0
ROOT = Path(sys.argv[2] if len(sys.argv) > 2 else "/tmp/run_boundary")
R, END = 12000, 12400
KW = dict(tpe.SCENES["periodic"], thermo=100, dump_every=0, nsteps=END, alpha=ALPHA)
# dump every step from R+1 to R+10, then every 50
DUMP = (f'variable ds equal "(step<{R})*{R}+(step>={R})*(step<{R + 10})*(step+1)'
        f'+(step>={R + 10})*(step-(step%50)+50)"\n'
        "dump d2 all custom 1 dmp.*.txt id x y z vx vy vz\n"
        'dump_modify d2 sort id format "%d %.17g %.17g %.17g %.17g %.17g %.17g" every v_ds\n')
RUN = f"run             {END}"


def run(name, edit, restart_from=None):
    wd = ROOT / name
    shutil.rmtree(wd, ignore_errors=True)
    scene = cm.compression_scene(wd, **KW)
    if restart_from:
        shutil.copy(restart_from, wd / "restart.bin")
    harness.run_deck(edit(scene.deck), wd, nprocs=1, timeout=300,
                     extra_args=cm.MESH_ARGS, check=True)
    return wd


def restart_edit(crush):
    def edit(deck):
        lines = tpe.restart_deck(deck, "restart.bin", "* 1 1", END - R).splitlines()
        if not crush:
            lines = [l for l in lines if not l.startswith(("fix crush", "thermo_style", "thermo_modify"))]
            lines.insert(-1, "thermo_style custom step atoms\nthermo_modify lost error")
        lines.insert(-1, DUMP.rstrip("\n"))
        return "\n".join(lines) + "\n"
    return edit


N0 = len(cm.compression_scene(ROOT / "scene", **KW).grains)     # tags above are fragments
ref = run("uninterrupted", lambda d: d.replace(RUN, f"restart {R} restart.*.bin\n" + DUMP + RUN))
variants = {
    "split": run("split", lambda d: d.replace(RUN, f"run {R}\n" + DUMP + f"run {END - R}")),
    "restart": run("restart", restart_edit(True), ref / f"restart.{R}.bin"),
    "restart, no crush fix": run("restart_nocrush", restart_edit(False), ref / f"restart.{R}.bin"),
}
print(f"local damping alpha = {ALPHA}")
for name, wd in variants.items():
    for step in (R + 1, R + 2, R + 5, R + 10, R + 100, END):
        (a,) = harness.read_dump(ref / f"dmp.{step}.txt")
        (b,) = harness.read_dump(wd / f"dmp.{step}.txt")
        if not np.array_equal(a["id"], b["id"]):      # without the fix, later breaks are missing
            print(f"{name:22s} step {step}: other atoms (breaks differ)")
            continue
        dv = np.sqrt(sum((b[c] - a[c]) ** 2 for c in ("vx", "vy", "vz")))
        frag = a["id"][dv > 0] > N0
        print(f"{name:22s} step {step}: {int(np.sum(dv > 0)):3d} atoms differ "
              f"(fragments: {int(frag.sum())}), max |dv| {dv.max():.2e} m/s, "
              f"median |v| {np.median(np.sqrt(sum(a[c] ** 2 for c in ('vx', 'vy', 'vz')))):.2f} m/s")
