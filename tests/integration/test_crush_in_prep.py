# SPDX-License-Identifier: GPL-2.0-or-later
"""Crushing during the preparation (issue 41 item 2; docs/cpt.md "Crushing
during preparation"): examples/cpt_demo/run.py --crush-in-prep, deck
variable crush_in_prep 1, defines the grain model (fix crush/particle,
inputs/crushable_ne34.in) at the start of the preparation's stage 3 (the
radial servo, inputs/chamber_servo.in) and runs that stage at the jacking's
time step; pile_jacking.in then does not define it again, and a run resumed
from a restart file defines it in chamber_resume.in.

Scene: a reduced test_chamber_small.py (that chamber takes many minutes at 2
ranks): half the chamber (sector 180, frictionless symmetry plane) of
R = 40 mm, H = 50 mm, N = 39 (358 grains), core porosity 0.39, a pile of
R = 12 mm pushed monotonically 20 mm into the sand, 1 MPI rank, a restart
file every jacking chunk. The grains are weakened by the criterion reading
`pressure peak` (F_lim / 3.375, docs/fix_crush_particle.md "Criterion
readings") so that the prepared state does break some (at the printed
strength this small sample may break none before jacking: the test would
then see nothing): 5 break in the preparation (4 at the first step of
stage 3, the grains that break at the first step of jacking without the
option), 2 more while jacking (2026-12-06). The run takes about 35 s on one
core, the resumed part about 15 s.

Checks:
1. crushing is on before jacking: fix crush/particle's initialisation line
   comes after the 1-D compression's COMPRESSED line and before "CHAMBER
   prepared"; its dt / T_R times T_R is the jacking's dt (1.5e-7 s); the
   events file holds events at steps before the jacking's first step, as
   many as the fix's count in the jacking's first thermo row, and run.py
   counts them as n_break_events_prep and break_zones "prep", none as
   switch-on;
2. the demo's checks pass (exit 0): mass balance, the atom count = the
   count at the start of jacking + 13 per break while jacking, no grain
   outside, no event inside the pile; the count at the start of jacking is
   the packing's plus 13 per break of the preparation;
3. fines and Br: the fix's fines are those of the events
   (crushpost.breakage.break_fines, at the start of jacking and at the end),
   the summary's fines fraction is the fines over the sample's mass (the
   grains' at the start of jacking plus the preparation's fines), and Br at the start of jacking is already above 0;
4. a run resumed from its last restart file (run.py --resume) passes the
   demo checks with the preparation's breaks still counted apart.
"""

import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
from harness import REPO  # noqa: E402

from crushpost.breakage import break_fines  # noqa: E402
from crushpost.dump import read_crush_log  # noqa: E402
from crushpost.materials import RHO_GRAIN  # noqa: E402
from crushpost.thermo import read_log  # noqa: E402

RUN_TIMEOUT = 300
DT = 1.5e-7                      # run.py's default --dt: the jacking's time step
RHO = RHO_GRAIN
WEAK_READING = "pressure peak force normal size_law printed scatter normal"
SCENE = ["--np", "1", "--sector", "180", "--R-ch", "0.04", "--H-ch", "0.05", "--R-pile", "0.012",
         "--n-target", "0.39", "--mode", "monotonic", "--depth", "0.02", "--snapshots", "no",
         "--spheres", "no", "--thermo-every", "500", "--jack-every", "50",
         "--crush-reading", WEAK_READING, "--restart-every", "1", "--crush-in-prep"]
FIX_INIT = re.compile(r"fix crush/particle: smallest radius that can occur \S+, its Rayleigh "
                      r"time T_R (\S+), dt/T_R = (\S+)")


def _run_py(args, timeout):
    cmd = [sys.executable, str(REPO / "examples" / "cpt_demo" / "run.py")] + args
    if os.environ.get("LIGGGHTS_BIN"):
        cmd += ["--liggghts", os.environ["LIGGGHTS_BIN"]]
    return subprocess.run(cmd, timeout=timeout, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          universal_newlines=True)


@pytest.fixture(scope="module")
def chamber(tmp_path_factory):
    out = tmp_path_factory.mktemp("crush_in_prep")
    proc = _run_py(["--out", str(out)] + SCENE, RUN_TIMEOUT)
    assert (out / "summary.json").exists(), proc.stdout[-3000:]
    blocks = read_log(out / "log.liggghts")
    with open(out / "summary.json") as f:
        summary = json.load(f)
    return {"out": out, "summary": summary, "log": (out / "log.liggghts").read_text(),
            "jack_blocks": [b for b in blocks if "qc" in b],
            "events": read_crush_log(out / "breakage_events.txt"),
            "returncode": proc.returncode, "stdout": proc.stdout}


def test_crushing_is_on_before_jacking(chamber):
    log = chamber["log"]
    compressed = log.index("COMPRESSED sv")
    prepared = log.index("CHAMBER prepared")
    init = FIX_INIT.search(log)
    assert init, "no fix crush/particle initialisation line in log.liggghts"
    # defined at the start of stage 3: after the 1-D compression, before the
    # prepared state (and so before jacking)
    assert compressed < init.start() < prepared, (compressed, init.start(), prepared)
    # stage 3 runs at the jacking's time step (the line has 6 digits)
    T_R, ratio = float(init.group(1)), float(init.group(2))
    assert T_R * ratio == pytest.approx(DT, rel=1e-5)
    # events before the jacking's first step: the fix's count at its first row
    first = chamber["jack_blocks"][0]
    s0 = int(first["Step"][0])
    steps = chamber["events"]["step"]
    n_prep = int((steps <= s0).sum())
    print("events: %d in the preparation, %d while jacking" % (n_prep, (steps > s0).sum()))
    assert n_prep > 0, "no breakage event before jacking (step %d): %s" % (s0, steps)
    assert n_prep == int(first["n_break"][0])
    # and breaks while jacking, so that the counts below split a real run
    assert (steps > s0).sum() > 0, "no breakage event while jacking: %s" % steps
    s = chamber["summary"]
    assert s["crush_in_prep"] is True
    assert s["n_break_events_prep"] == n_prep
    assert s["break_zones"]["prep"] == n_prep
    assert s["break_zones"]["switch_on"] == 0
    assert s["break_zones"]["n_events"] == len(steps) == s["n_break_events"]


def test_demo_checks_pass(chamber):
    s = chamber["summary"]
    assert chamber["returncode"] == 0, chamber["stdout"][-3000:]
    assert s["failed_checks"] == [], s["failed_checks"]
    assert s["prep"]["prepared"]
    assert s["mass_balance_rel_error"] < 1e-12
    n_prep = s["n_break_events_prep"]
    assert s["n_particles_jacking_start"] == s["n_particles_initial"] + 13 * n_prep
    assert s["n_particles_final"] == (s["n_particles_jacking_start"]
                                      + 13 * (s["n_break_events"] - n_prep))
    assert s["n_grains_outside"] == 0 and s["n_events_inside_pile"] == 0


def test_fines_and_br_count_every_break(chamber):
    ev, first, last = chamber["events"], chamber["jack_blocks"][0], chamber["jack_blocks"][-1]
    s0 = int(first["Step"][0])
    fines = break_fines(ev["parent_diameter"], density=RHO).lost
    prep = ev["step"] <= s0
    assert first["fines"][0] == pytest.approx(fines[prep].sum(), rel=1e-9)
    assert last["fines"][-1] == pytest.approx(fines.sum(), rel=1e-9)
    # the sample's mass: the grains' at the start of jacking plus the fines
    # the events of the preparation made (the packing of grains.data is the
    # one before the radius expansion)
    M = first["M_grains"][0] + fines[prep].sum()
    assert chamber["summary"]["fines_mass_fraction"] == pytest.approx(last["fines"][-1] / M,
                                                                      rel=1e-9)
    assert first["Br"][0] > 0.0 and last["Br"][-1] >= first["Br"][0]


def test_resumed_run_keeps_the_preparation_breaks_apart(chamber, tmp_path_factory):
    """run.py --resume from the run's last restart file (written while
    jacking): chamber_resume.in defines the grain model again (it takes its
    state from the file), pile_jacking.in does not."""
    out = tmp_path_factory.mktemp("resumed") / "run"
    shutil.copytree(str(chamber["out"]), str(out))
    (out / "summary.json").unlink()
    assert (out / "restart" / "latest.txt").exists(), "the run wrote no restart file"
    proc = _run_py(["--out", str(out), "--resume", "--np", "1"], RUN_TIMEOUT)
    assert (out / "summary.json").exists(), proc.stdout[-3000:]
    s = json.loads((out / "summary.json").read_text())
    assert proc.returncode == 0, proc.stdout[-3000:]
    assert s["failed_checks"] == [], s["failed_checks"]
    assert len(s["parts"]) == 1
    part_log = (out / "log.part1.liggghts").read_text()
    assert FIX_INIT.search(part_log), "the resumed part did not define fix crush/particle"
    first = chamber["summary"]
    assert s["n_break_events_prep"] == first["n_break_events_prep"]
    assert s["break_zones"]["prep"] == first["n_break_events_prep"]
    assert s["n_particles_jacking_start"] == first["n_particles_jacking_start"]
    # a grain near its strength may break in one run and not in the other
    assert abs(s["n_break_events"] - first["n_break_events"]) <= 1
