# SPDX-License-Identifier: GPL-2.0-or-later
"""crushpost.progress: the lines a chamber driver prints while LIGGGHTS runs
(issue 10 item 4), on a run folder whose files grow as a deck's would."""

import math

from crushpost.progress import ChamberProgress, format_seconds

R = 0.018
AREA = math.pi * R * R


class Clock:
    def __init__(self):
        self.t = 1000.0

    def __call__(self):
        return self.t


def _append(path, text):
    with open(path, "a") as f:
        f.write(text)


def _row(step, depth, qc, phase, cycle):
    return "%d %g %.10g %.10g 0 %.10g %d %d -1\n" % (step, step * 1e-7, depth, qc * AREA,
                                                      qc * AREA, phase, cycle)


def test_format_seconds():
    assert format_seconds(59.6) == "1:00"
    assert format_seconds(3725) == "1:02:05"


def test_a_line_per_stage_and_phase_with_a_time_estimate(tmp_path):
    clock = Clock()
    prog = ChamberProgress(str(tmp_path), depth=0.02, R_pile=R, clock=clock)
    assert prog.poll() == []                          # nothing written yet
    log, jack, ev = tmp_path / "log.liggghts", tmp_path / "jack.txt", tmp_path / "breakage_events.txt"
    clock.t += 30
    _append(log, "EXPANDED porosity_core 0.390635414046778 porosity_all 0.43\n")
    lines = prog.poll()
    assert lines == ["preparation: radius expansion done (core porosity 0.3906), elapsed 0:30"]
    _append(log, "COMPRESSED sv 150003.9 sr 64963.9 K0 0.43\nCHAMBER prepared: sv 1.5e5 sr 7.6e4 "
            "porosity_core 0.3891\n")
    clock.t += 30
    assert [ln.split(",")[0] for ln in prog.poll()] == [
        "preparation: 1-D compression done", "preparation: radial servo done"]
    # jacking: a push to 10 mm (half the target) in 100 s, an unload, a pause
    _append(jack, "# fix jack/pile jack: mode cyclic\n# z_ref 0.1 m: depth\n# step ...\n")
    _append(jack, _row(100, 0.001, 1e6, 0, 1))
    assert prog.poll() == ["jacking started: target depth 20 mm, elapsed 1:00"]
    clock.t += 100
    _append(jack, _row(200, 0.01, 3e6, 0, 1))
    _append(ev, "# step time ...\n138002 0.063 253 0.006 0.01 0.04 0.05 6.2 0.1 particle 0\n"
            "138003 0.063 254 0.006 0.01 0.04 0.05 6.2 0.1 particle 0\n")
    _append(jack, _row(300, 0.0098, 0.0, 1, 1))
    lines = prog.poll()
    assert lines == ["push 1 ended: depth 10 mm, q_c 3 MPa, 2 breaks so far, elapsed 2:40, "
                     "about 1:40 left"]
    _append(jack, _row(400, 0.0098, 0.0, 2, 1) + _row(500, 0.0098, 0.0, 0, 2))
    lines = prog.poll()
    assert [ln.split(":")[0] for ln in lines] == ["unload 1 ended", "pause 1 ended"]
    # an unfinished row is not read until its line is complete
    _append(jack, "600 6e-05 0.015 ")
    assert prog.poll() == []
    _append(jack, "1 0 1 0 2 -1\n")
    assert prog.poll() == [] and prog.deepest == 0.015
    fin = prog.finish()
    assert fin[0].startswith("push 2 ended: depth 15 mm")
    assert fin[-1] == "LIGGGHTS finished, elapsed 2:40, 2 breaks"
