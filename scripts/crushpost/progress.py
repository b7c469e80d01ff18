# SPDX-License-Identifier: GPL-2.0-or-later
"""Progress of a chamber scene while LIGGGHTS runs (issue 10 item 4).

:class:`ChamberProgress` reads what the deck writes as it goes (the
preparation lines of log.liggghts, the rows of jack.txt, the lines of
breakage_events.txt) and returns one line per preparation stage and per
phase of the pile (end of each push, unload and pause) with the depth,
q_c, the breaks so far, the elapsed time and an estimate of the time left.
:func:`run_watched` runs a deck like :func:`crushpost.runner.run_liggghts`
and prints those lines while it waits.

The estimate of the time left is the jacking's wall time so far scaled by
the depth still to go (the deepest depth reached over the target depth):
pushes take most of the time, so it is rough until the first stroke is
done, and there is none during the preparation, whose length depends on
how soon the sample reaches its targets.
"""

import os
import subprocess
import time

from .runner import mpirun_command, stop_on_failure

__all__ = ["ChamberProgress", "run_watched", "format_seconds"]

_PREP = (("EXPANDED", "preparation: radius expansion done"),
         ("COMPRESSED", "preparation: 1-D compression done"),
         ("CHAMBER prepared:", "preparation: radial servo done, sample prepared"))
_PHASE = {0: "push", 1: "unload", 2: "pause", 3: "done"}


def format_seconds(s):
    """``m:ss`` or ``h:mm:ss``."""
    s = int(round(max(s, 0.0)))
    h, rem = divmod(s, 3600)
    m, sec = divmod(rem, 60)
    return "%d:%02d:%02d" % (h, m, sec) if h else "%d:%02d" % (m, sec)


class _Tail:
    """New complete lines of a growing text file."""

    def __init__(self, path):
        self.path = path
        self.pos = 0
        self.rest = ""

    def lines(self):
        try:
            with open(self.path, errors="replace") as f:
                f.seek(self.pos)
                chunk = f.read()
                self.pos = f.tell()
        except OSError:
            return []
        text = self.rest + chunk
        parts = text.split("\n")
        self.rest = parts.pop()          # an unfinished last line waits
        return parts


class ChamberProgress:
    """Lines of progress of a chamber run in ``out`` (see the module doc).

    ``depth``: the target depth [m]; ``R_pile``: pile radius [m] (for q_c);
    ``clock``: a function returning seconds (time.time); ``files``: the
    names of the log, the pile's series and the breakage events when they
    differ from log.liggghts, jack.txt and breakage_events.txt (a part of a
    run that goes on from a restart file, crushpost.restart)."""

    def __init__(self, out, depth, R_pile, clock=time.time, files=None):
        names = {"log": "log.liggghts", "jack": "jack.txt", "events": "breakage_events.txt"}
        names.update(files or {})
        self.out = out
        self.depth = depth
        self.area = 3.141592653589793 * R_pile ** 2
        self.clock = clock
        self.t0 = clock()
        self.t_jack0 = None
        self.log = _Tail(os.path.join(out, names["log"]))
        self.jack = _Tail(os.path.join(out, names["jack"]))
        self.events = _Tail(os.path.join(out, names["events"]))
        self.n_break = 0
        self.phase = None
        self.cycle = None
        self.row = None
        self.deepest = 0.0

    def _left(self):
        if self.t_jack0 is None or self.deepest <= 0.0 or not self.depth:
            return "time left: no estimate yet"
        f = min(self.deepest / self.depth, 1.0)
        spent = self.clock() - self.t_jack0
        return "about %s left" % format_seconds(spent * (1.0 - f) / max(f, 1e-9))

    def _phase_line(self, row, phase, cycle):
        depth, f_cone = row[2], row[3]
        what = _PHASE.get(phase, "phase %d" % phase)
        return ("%s %d ended: depth %.3g mm, q_c %.3g MPa, %d breaks so far, elapsed %s, %s"
                % (what, cycle, depth * 1e3, f_cone / self.area / 1e6,
                   self.n_break, format_seconds(self.clock() - self.t0), self._left()))

    def poll(self):
        """The new lines of progress since the last call (a list of str)."""
        out = []
        for line in self.log.lines():
            for marker, text in _PREP:
                if line.startswith(marker):
                    words = line[len(marker):].split()
                    vals = dict(zip(words[0::2], words[1::2]))
                    extra = ""
                    if "porosity_core" in vals:
                        extra = " (core porosity %s)" % vals["porosity_core"][:6]
                    out.append("%s%s, elapsed %s" % (text, extra,
                                                     format_seconds(self.clock() - self.t0)))
        self.n_break += sum(1 for ln in self.events.lines()
                            if ln.strip() and not ln.lstrip().startswith("#"))
        for line in self.jack.lines():
            if not line.strip() or line.startswith("#"):
                continue
            try:
                row = [float(w) for w in line.split()]
            except ValueError:
                continue
            if len(row) < 8:
                continue
            phase, cycle = int(row[6]), int(row[7])
            if self.t_jack0 is None:
                self.t_jack0 = self.clock()
                out.append("jacking started: target depth %.3g mm, elapsed %s"
                           % (self.depth * 1e3, format_seconds(self.clock() - self.t0)))
            if self.phase is not None and phase != self.phase:
                out.append(self._phase_line(self.row, self.phase, self.cycle))
            self.deepest = max(self.deepest, row[2])
            self.phase, self.cycle, self.row = phase, cycle, row
        return out

    def finish(self):
        """Lines for the end of the run (the last phase, if it did not end)."""
        out = self.poll()
        if self.row is not None and self.phase not in (None, 3):
            out.append(self._phase_line(self.row, self.phase, self.cycle))
        out.append("LIGGGHTS finished, elapsed %s, %d breaks"
                   % (format_seconds(self.clock() - self.t0), self.n_break))
        return out


def run_watched(deck, workdir, variables, progress, np=1, binary=None, name="liggghts",
                every=2.0, write=None, log="log.liggghts"):
    """:func:`crushpost.runner.run_liggghts` that prints ``progress``'s lines
    (a :class:`ChamberProgress`) every ``every`` seconds while LIGGGHTS
    runs. Returns the wall time [s]; a failed run exits with LIGGGHTS'
    status after naming the log."""
    write = write or (lambda line: print("%s: %s" % (name, line), flush=True))
    cmd = mpirun_command(deck, variables, np=np, binary=binary, log=log)
    env = dict(os.environ)
    env.setdefault("OMP_NUM_THREADS", "1")
    t0 = time.time()
    proc = subprocess.Popen(cmd, cwd=workdir, env=env, stdin=subprocess.DEVNULL)
    try:
        while True:
            try:
                rc = proc.wait(timeout=every)
                break
            except subprocess.TimeoutExpired:
                for line in progress.poll():
                    write(line)
    except KeyboardInterrupt:
        proc.terminate()
        raise
    wall = time.time() - t0
    for line in progress.finish() if rc == 0 else progress.poll():
        write(line)
    if rc != 0:
        stop_on_failure(name, rc, os.path.join(workdir, log))
    return wall
