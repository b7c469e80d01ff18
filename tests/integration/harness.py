# SPDX-License-Identifier: GPL-2.0-or-later
"""Shared helpers for deck-level integration tests of the LIGGGHTS plugin styles.

Every test writes its input deck inline, runs it in its own pytest ``tmp_path``
with :func:`run_deck`, and checks the result against an exact answer.

Binary lookup
    ``LIGGGHTS_BIN`` if set, else ``<repo>/build/liggghts`` where ``<repo>`` is
    ``CRUSH_REPO`` if set, else two levels above this file.

Main entry points
    run_deck(deck, workdir, nprocs=1, variables=None, timeout=300) -> RunResult
    expect_error(deck, workdir, pattern, nprocs=1, ...) -> RunResult
    parse_thermo(log_text) -> list[ThermoBlock]
    read_dump(path) -> list[DumpFrame]

The run writes its log with ``-log log.liggghts`` and reads it back after the
run: LIGGGHTS may lose messages on a piped stdout when it exits through
``error->all`` (MPI_Finalize + exit), but the log file is flushed and closed.
"""

import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

if str(Path(__file__).resolve().parent) not in sys.path:      # deck_lint beside this file
    sys.path.insert(0, str(Path(__file__).resolve().parent))
import deck_lint  # noqa: E402

__all__ = [
    "REPO", "liggghts_bin", "mpirun_cmd", "RunResult", "ThermoBlock",
    "DumpFrame", "run_deck", "expect_error", "parse_thermo", "read_dump",
    "read_dumps", "DeckError",
]

REPO = Path(os.environ.get("CRUSH_REPO",
                           Path(__file__).resolve().parent.parent.parent)).resolve()

DEFAULT_TIMEOUT = 300.0
LOG_NAME = "log.liggghts"
DECK_NAME = "in.deck"


class DeckError(AssertionError):
    """A deck run did not end the way the test expected."""


def liggghts_bin(wait_s=120.0):
    """Path of the LIGGGHTS binary with the plugin styles.

    The build tree may be rebuilt concurrently, so a binary that is briefly
    missing is waited for (up to ``wait_s`` seconds) before giving up.
    """
    env_bin = os.environ.get("LIGGGHTS_BIN")
    path = Path(env_bin) if env_bin else REPO / "build" / "liggghts"
    deadline = time.monotonic() + wait_s
    while not (path.is_file() and os.access(str(path), os.X_OK)):
        if time.monotonic() >= deadline:
            raise FileNotFoundError(
                "LIGGGHTS binary not found or not executable: %s "
                "(set LIGGGHTS_BIN or CRUSH_REPO)" % path)
        time.sleep(5.0)
    return path.resolve()


def mpirun_cmd(nprocs):
    """The mpirun prefix for ``nprocs`` ranks (Open MPI flags; unbound, so
    that tests run side by side (ctest -j) do not share one core)."""
    mpirun = shutil.which("mpirun") or "mpirun"
    return [mpirun, "--allow-run-as-root", "--oversubscribe", "--bind-to", "none",
            "-np", str(int(nprocs))]


def _child_env(extra=None):
    env = dict(os.environ)
    env["OMPI_ALLOW_RUN_AS_ROOT"] = "1"
    env["OMPI_ALLOW_RUN_AS_ROOT_CONFIRM"] = "1"
    # keep runs quiet and independent of the host's core count
    env.setdefault("OMP_NUM_THREADS", "1")
    env.setdefault("OMPI_MCA_rmaps_base_oversubscribe", "1")
    if extra:
        env.update({k: str(v) for k, v in extra.items()})
    return env


# --------------------------------------------------------------------------
# thermo log parsing
# --------------------------------------------------------------------------

class ThermoBlock:
    """One thermo table of a log: from the 'Step ...' header to 'Loop time'.

    ``columns`` is the header list, ``data`` a 2-D float array (rows = output
    steps).  ``block["v_x"]`` (or ``block["x"]``: LIGGGHTS drops the v_/c_/f_
    prefix in the header) gives one column as a 1-D array.
    """

    def __init__(self, columns, rows):
        self.columns = list(columns)
        self.data = np.array(rows, dtype=float).reshape(len(rows), len(self.columns))

    def _index(self, name):
        # LIGGGHTS prints 'v_foo', 'c_foo', 'f_foo' thermo keywords as 'foo';
        # accept either spelling.
        if name in self.columns:
            return self.columns.index(name)
        if name[:2] in ("v_", "c_", "f_") and name[2:] in self.columns:
            return self.columns.index(name[2:])
        return None

    def __getitem__(self, name):
        j = self._index(name)
        if j is None:
            raise KeyError("thermo column %r not in %s" % (name, self.columns))
        return self.data[:, j]

    def __contains__(self, name):
        return self._index(name) is not None

    def __len__(self):
        return self.data.shape[0]

    def as_dict(self):
        return {c: self.data[:, j] for j, c in enumerate(self.columns)}

    def __repr__(self):
        return "ThermoBlock(columns=%s, rows=%d)" % (self.columns, len(self))


_FLOAT_RE = re.compile(r"^[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$|^[-+]?(nan|inf)$", re.I)


def parse_thermo(log_text):
    """All thermo blocks of a LIGGGHTS/LAMMPS log (one-line thermo style).

    A block starts at a line whose first word is 'Step' and ends at the line
    starting with 'Loop time'.  Lines inside a block that are not all numbers
    with the header's field count (warnings, progress lines) are skipped.  A
    block cut short by an error (no 'Loop time') is still returned.
    """
    blocks = []
    columns = None
    rows = []
    for line in log_text.splitlines():
        words = line.split()
        if columns is None:
            if words and words[0] == "Step":
                columns = words
                rows = []
            continue
        if line.startswith("Loop time"):
            blocks.append(ThermoBlock(columns, rows))
            columns = None
            continue
        if len(words) == len(columns) and all(_FLOAT_RE.match(w) for w in words):
            rows.append([float(w) for w in words])
    if columns is not None:
        blocks.append(ThermoBlock(columns, rows))
    return blocks


# --------------------------------------------------------------------------
# text dumps
# --------------------------------------------------------------------------

class DumpFrame:
    """One snapshot of a LAMMPS text dump (``dump atom``/``dump custom``).

    ``timestep``, ``natoms``, ``box`` (3x2 array of lo/hi), ``columns`` and
    ``data`` (2-D float array, rows sorted by ``id`` when an id column exists).
    ``frame["vx"]`` gives one column.
    """

    def __init__(self, timestep, natoms, box, columns, rows):
        self.timestep = timestep
        self.natoms = natoms
        self.box = np.array(box, dtype=float)
        self.columns = list(columns)
        data = np.array(rows, dtype=float).reshape(len(rows), len(self.columns))
        if "id" in self.columns and len(rows):
            data = data[np.argsort(data[:, self.columns.index("id")], kind="stable")]
        self.data = data

    def __getitem__(self, name):
        try:
            j = self.columns.index(name)
        except ValueError:
            raise KeyError("dump column %r not in %s" % (name, self.columns))
        return self.data[:, j]

    def __len__(self):
        return self.data.shape[0]

    def __repr__(self):
        return "DumpFrame(step=%d, atoms=%d, columns=%s)" % (
            self.timestep, len(self), self.columns)


def read_dump(path):
    """All frames of one LAMMPS text dump file (list of :class:`DumpFrame`)."""
    lines = Path(path).read_text().splitlines()
    frames = []
    i = 0
    n = len(lines)
    while i < n:
        if not lines[i].startswith("ITEM: TIMESTEP"):
            i += 1
            continue
        timestep = int(lines[i + 1].split()[0])
        i += 2
        natoms = 0
        box = []
        columns = []
        rows = []
        while i < n and not lines[i].startswith("ITEM: TIMESTEP"):
            line = lines[i]
            if line.startswith("ITEM: NUMBER OF ATOMS"):
                natoms = int(lines[i + 1].split()[0])
                i += 2
            elif line.startswith("ITEM: BOX BOUNDS"):
                box = [[float(w) for w in lines[i + k].split()[:2]] for k in (1, 2, 3)]
                i += 4
            elif line.startswith("ITEM: ATOMS"):
                columns = line.split()[2:]
                i += 1
                for _ in range(natoms):
                    if i >= n:
                        break
                    rows.append([float(w) for w in lines[i].split()])
                    i += 1
            else:
                i += 1
        frames.append(DumpFrame(timestep, natoms, box, columns, rows))
    return frames


def read_dumps(pattern_dir, glob):
    """Frames of all dump files matching ``glob`` in a folder (one file per
    snapshot, e.g. ``dump.*.txt``), ordered by timestep."""
    frames = []
    for p in Path(pattern_dir).glob(glob):
        frames.extend(read_dump(p))
    frames.sort(key=lambda f: f.timestep)
    return frames


# --------------------------------------------------------------------------
# running decks
# --------------------------------------------------------------------------

class RunResult:
    """Outcome of one deck run.

    returncode, stdout, stderr, log (text of the -log file, '' if none),
    workdir (Path), cmd (list), thermo (list of ThermoBlock, parsed lazily),
    errors / warnings (lines of the log and output starting with ERROR/WARNING).
    """

    def __init__(self, cmd, workdir, returncode, stdout, stderr, log):
        self.cmd = cmd
        self.workdir = Path(workdir)
        self.returncode = returncode
        self.stdout = stdout
        self.stderr = stderr
        self.log = log
        self._thermo = None

    @property
    def thermo(self):
        if self._thermo is None:
            self._thermo = parse_thermo(self.log)
        return self._thermo

    @property
    def all_text(self):
        """Log, stdout and stderr together (for message searches)."""
        return "\n".join((self.log, self.stdout, self.stderr))

    def _lines(self, prefix):
        seen = []
        for line in self.all_text.splitlines():
            s = line.strip()
            if s.startswith(prefix) and s not in seen:
                seen.append(s)
        return seen

    @property
    def errors(self):
        return self._lines("ERROR")

    @property
    def warnings(self):
        return self._lines("WARNING")

    @property
    def ok(self):
        return self.returncode == 0

    def path(self, name):
        return self.workdir / name

    def summary(self, tail=40):
        """Short text for assertion messages: command, return code, log tail."""
        src = self.log or self.stdout
        tail_lines = "\n".join(src.splitlines()[-tail:])
        err = "\n".join(self.stderr.splitlines()[-10:])
        return ("cmd: %s\nworkdir: %s\nreturncode: %s\n--- log tail ---\n%s\n"
                "--- stderr tail ---\n%s" % (" ".join(map(str, self.cmd)), self.workdir,
                                             self.returncode, tail_lines, err))

    def check(self):
        """Raise DeckError unless the run succeeded; returns self."""
        if self.returncode != 0 or self.errors:
            raise DeckError("deck run failed\n" + self.summary())
        return self


def run_deck(deck_text, workdir, nprocs=1, variables=None, timeout=DEFAULT_TIMEOUT,
             check=False, extra_args=None, env=None, lost_ok=False):
    """Write ``deck_text`` to ``workdir/in.deck`` and run it with mpirun.

    variables: dict NAME -> value, passed as ``-var NAME VALUE`` (the value may
    be a list/tuple for index-style variables with several strings).
    check: if True, raise :class:`DeckError` when the run fails.
    lost_ok: the deck may run with lost atoms not an error (only for a deck
    that removes atoms on purpose); otherwise a deck with a `run` that is not
    under `thermo_modify lost error` is refused (deck_lint.py).
    Returns a :class:`RunResult`; a run past ``timeout`` seconds raises
    :class:`DeckError` with whatever log was written.
    """
    if not lost_ok:
        problems = deck_lint.lost_error_problems(
            deck_text, DECK_NAME, {k: str(v) for k, v in (variables or {}).items()},
            base=workdir)
        if problems:
            raise DeckError("every deck must make lost atoms an error (LIGGGHTS 3.8's "
                            "thermo_style resets thermo_modify):\n  " + "\n  ".join(problems))
    workdir = Path(workdir)
    workdir.mkdir(parents=True, exist_ok=True)
    (workdir / DECK_NAME).write_text(deck_text if deck_text.endswith("\n") else deck_text + "\n")
    log_path = workdir / LOG_NAME
    if log_path.exists():
        log_path.unlink()

    cmd = mpirun_cmd(nprocs) + [str(liggghts_bin()), "-in", DECK_NAME, "-log", LOG_NAME,
                                "-echo", "none", "-screen", "none"]
    for name, value in (variables or {}).items():
        vals = value if isinstance(value, (list, tuple)) else [value]
        cmd += ["-var", str(name)] + [_fmt_var(v) for v in vals]
    if extra_args:
        cmd += [str(a) for a in extra_args]

    try:
        proc = subprocess.run(cmd, cwd=str(workdir), env=_child_env(env),
                              stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE, timeout=timeout,
                              universal_newlines=True, errors="replace")
    except subprocess.TimeoutExpired as exc:
        log = log_path.read_text(errors="replace") if log_path.exists() else ""
        raise DeckError("deck run timed out after %s s\ncmd: %s\n--- log tail ---\n%s"
                        % (timeout, " ".join(cmd), "\n".join(log.splitlines()[-40:]))) from exc

    log = log_path.read_text(errors="replace") if log_path.exists() else ""
    result = RunResult(cmd, workdir, proc.returncode, proc.stdout, proc.stderr, log)
    if check:
        result.check()
    return result


def _fmt_var(v):
    if isinstance(v, float):
        return repr(v)
    return str(v)


def expect_error(deck_text, workdir, pattern, nprocs=1, variables=None,
                 timeout=DEFAULT_TIMEOUT, regex=False):
    """Run a deck that must fail and check the error text.

    The run must end with a non-zero return code *and* an 'ERROR' line, and
    ``pattern`` (a plain substring, or a regular expression if ``regex``)
    must occur in the log file, stdout or stderr.  Returns the RunResult.
    """
    res = run_deck(deck_text, workdir, nprocs=nprocs, variables=variables, timeout=timeout)
    if res.returncode == 0:
        raise DeckError("deck was expected to fail (pattern %r) but ran successfully\n%s"
                        % (pattern, res.summary()))
    if not res.errors:
        raise DeckError("deck failed without an ERROR line (expected %r)\n%s"
                        % (pattern, res.summary()))
    text = res.all_text
    found = re.search(pattern, text) if regex else (pattern in text)
    if not found:
        raise DeckError("error text does not contain %r; errors were:\n  %s\n%s"
                        % (pattern, "\n  ".join(res.errors), res.summary()))
    return res
