# SPDX-License-Identifier: GPL-2.0-or-later
"""Run a LIGGGHTS deck of this package under mpirun, as the example drivers
(examples/*/run.py) do.

The log goes to ``log.liggghts`` in the run folder (LIGGGHTS may lose
messages on a piped stdout), the screen output is switched off, and a failed
run stops the driver with a message that names the log.
"""

import os
import subprocess
import sys
import time

__all__ = ["default_binary", "mpirun_command", "run_liggghts", "log_errors", "stop_on_failure",
           "snapshot_tree", "prune_trees", "remove_tree", "process_alive", "read_pid"]

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def default_binary():
    """``$LIGGGHTS_BIN`` if set, else ``build/liggghts`` of this checkout."""
    return os.environ.get("LIGGGHTS_BIN") or os.path.join(REPO, "build", "liggghts")


def _format(value):
    # floats keep every digit; everything else as LIGGGHTS would read it
    return repr(value) if isinstance(value, float) else str(value)


def mpirun_command(deck, variables, np=1, binary=None, log="log.liggghts", as_root=None):
    """The command line: ``mpirun [--allow-run-as-root] --oversubscribe
    --bind-to none -np NP BINARY -in DECK -log LOG -echo none -screen none
    -var k v ...``. Unbound: Open MPI binds the ranks of a run of 1 or 2
    ranks to the first cores, so runs started side by side (two 1-rank runs
    on a 2-core machine) would all share core 0 while the other idles."""
    if as_root is None:
        as_root = hasattr(os, "geteuid") and os.geteuid() == 0
    cmd = (["mpirun"] + (["--allow-run-as-root"] if as_root else [])
           + ["--oversubscribe", "--bind-to", "none", "-np", str(int(np))])
    cmd += [binary or default_binary(), "-in", str(deck), "-log", log, "-echo", "none", "-screen", "none"]
    for key, value in variables.items():
        cmd += ["-var", str(key), _format(value)]
    return cmd


def log_errors(log_path):
    """The ERROR lines of a LIGGGHTS log, in order, without the "ERROR: "
    prefix ([] if the log is missing)."""
    if not os.path.exists(log_path):
        return []
    with open(log_path, errors="replace") as f:
        return [ln.strip()[len("ERROR:"):].strip() for ln in f if ln.startswith("ERROR")]


def stop_on_failure(name, rc, log_path):
    """After a failed LIGGGHTS run: say where the log is and what its last
    ERROR line says (a lost atom, a preparation stage that missed its target,
    the blow-up detector...), then exit with LIGGGHTS' status."""
    errors = log_errors(log_path)
    sys.stderr.write("%s: LIGGGHTS failed (exit %d); see %s\n" % (name, rc, log_path))
    if errors:
        # a deck's own stop (inputs/prep_stop_1.in) reaches LIGGGHTS as an unknown command
        sys.stderr.write("%s: %s\n" % (name, errors[-1].replace("Unknown command: PREPARATION FAILED",
                                                                 "PREPARATION FAILED", 1)))
    sys.exit(rc)


def run_liggghts(deck, workdir, variables, np=1, binary=None, name="liggghts", log="log.liggghts"):
    """Run the deck in `workdir`; return the wall time in seconds. On failure
    print where the log is and exit with LIGGGHTS' exit code."""
    cmd = mpirun_command(deck, variables, np=np, binary=binary, log=log)
    env = dict(os.environ)
    env.setdefault("OMP_NUM_THREADS", "1")
    t0 = time.time()
    rc = subprocess.call(cmd, cwd=workdir, env=env, stdin=subprocess.DEVNULL)
    wall = time.time() - t0
    if rc != 0:
        stop_on_failure(name, rc, os.path.join(workdir, log))
    return wall


OWNER = "owner.pid"


def read_pid(path):
    """The pid a file (a claim, a copy's owner) names on its first line;
    None when the file is missing or holds no pid."""
    try:
        with open(path) as f:
            return int(f.read().split()[0])
    except (OSError, ValueError, IndexError):
        return None


def process_alive(pid):
    """Whether a process with this pid is running (a claim's or a copy's
    owner)."""
    try:
        os.kill(pid, 0)             # raises if no such process
    except ProcessLookupError:
        return False
    except PermissionError:
        return True                  # someone else's live process
    return True


def prune_trees(work):
    """Remove the copies (``_tree_*``) in WORK whose owner process is gone:
    a study killed at a restart point never reaches its own clean-up.
    Copies without an owner file are left alone (they may belong to a
    running call of an older version). Returns the removed paths."""
    import shutil

    removed = []
    if not os.path.isdir(work):
        return removed
    for name in sorted(os.listdir(work)):
        path = os.path.join(work, name)
        if not (name.startswith("_tree_") and os.path.isdir(path)):
            continue
        pid = read_pid(os.path.join(path, OWNER))
        if pid is not None and pid != os.getpid() and not process_alive(pid):
            shutil.rmtree(path, ignore_errors=True)
            removed.append(path)
    return removed


def snapshot_tree(work, subdirs):
    """Copy ``subdirs`` of this checkout (drivers, deck blocks, crushpost)
    into a new folder WORK/_tree_<time>_<random> and return it. LIGGGHTS
    reads an input file as it reaches it, so a study that runs for hours
    runs its drivers from such a copy: an edit of the checkout meanwhile
    must not reach a run under way. The copy names its owner (this
    process) in ``owner.pid``; copies of owners that are gone are removed
    first (prune_trees), and the caller removes its own when it ends
    (remove_tree)."""
    import shutil
    import tempfile

    # a fresh folder: two studies started in the same second must not share one
    os.makedirs(work, exist_ok=True)
    prune_trees(work)
    dst = tempfile.mkdtemp(prefix="_tree_%d_" % int(time.time()), dir=work)
    with open(os.path.join(dst, OWNER), "w") as f:
        f.write("%d\n" % os.getpid())
    for sub in subdirs:
        shutil.copytree(os.path.join(REPO, sub), os.path.join(dst, sub),
                        ignore=shutil.ignore_patterns("__pycache__", "results*"))
    return dst


def remove_tree(tree):
    """Remove a copy made by snapshot_tree (None: nothing to do)."""
    import shutil

    if tree and os.path.basename(tree).startswith("_tree_"):
        shutil.rmtree(tree, ignore_errors=True)
