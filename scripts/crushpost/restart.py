# SPDX-License-Identifier: GPL-2.0-or-later
"""A chamber run in parts: going on from restart files (docs/cpt.md
"Restarting a run").

A jacking run with restart files (inputs/pile_jacking.in, restart_chunks > 0)
writes ``restart/jack_0.restart`` and ``restart/jack_1.restart`` in turn and,
after each is complete, ``restart/latest.txt`` ("STEP FILE"). A run killed
(a job's time limit, a session's end) goes on from that file as part 1, 2,
...; each part writes its own series files (``jack.part1.txt``,
``breakage_events.part1.txt``, ``spheres.part1.txt``, ``log.part1.liggghts``)
and the first run's are renamed ``*.part0.*`` when part 1 starts.
``restart/parts.json`` records every part: the restart file and step it
started from, when it started and, when it ended, its wall time.

When the last part has ended, :func:`merge_parts` writes the series of the
whole run under their usual names: part k's rows from its restart step on
replace the rows the parts before it wrote after that step (work that was
lost with the killed part), so the merged series is the run as if it had not
stopped. The logs are concatenated instead (``log.liggghts``), lost work
included: the particle-steps summed over it are what the run cost.
"""

import glob
import json
import os
import re
import shutil
import tarfile

import numpy as np

__all__ = ["LATEST", "PARTS", "SERIES", "latest_restart", "read_parts", "write_parts",
           "part_name", "keep_before", "merge_series_text", "merge_parts", "part_walls",
           "stale_snapshots", "clear_parts", "infer_parts", "part_files", "pack_carry",
           "unpack_carry", "carry_step", "holds_run"]

LATEST = os.path.join("restart", "latest.txt")
PARTS = os.path.join("restart", "parts.json")
# the step-stamped series a chamber run writes (first column: the step)
SERIES = ("jack.txt", "breakage_events.txt", "spheres.txt")
LOG = "log.liggghts"


class RestartError(ValueError):
    """A run folder's restart files are missing or do not fit together."""


def part_name(name, part):
    """``jack.txt`` -> ``jack.part2.txt``; ``log.liggghts`` -> ``log.part2.liggghts``."""
    stem, dot, ext = name.rpartition(".")
    if not dot:
        return "%s.part%d" % (name, part)
    return "%s.part%d.%s" % (stem, part, ext)


def part_files(part):
    """The files part k writes: {"log", "jack", "events", "spheres"} -> name
    (part 0, the first run: the usual names)."""
    names = {"log": LOG, "jack": SERIES[0], "events": SERIES[1], "spheres": SERIES[2]}
    return {k: (v if not part else part_name(v, part)) for k, v in names.items()}


def latest_restart(out):
    """(step, absolute path) of the last complete restart file of the run in
    ``out`` (restart/latest.txt); RestartError naming what is missing."""
    path = os.path.join(out, LATEST)
    if not os.path.exists(path):
        raise RestartError("%s: no such file: the run wrote no restart file (a run writes them "
                           "with restart_chunks > 0, examples/cpt_demo/run.py --restart-every)"
                           % path)
    with open(path) as f:
        words = f.read().split()
    if len(words) != 2 or not re.fullmatch(r"\d+", words[0]):
        raise RestartError("%s: expected 'STEP FILE', found %r" % (path, " ".join(words)))
    file_path = os.path.join(out, words[1])
    if not os.path.exists(file_path):
        raise RestartError("%s names %s, which does not exist" % (path, file_path))
    return int(words[0]), file_path


def read_parts(out):
    """The parts recorded in restart/parts.json (a list of dicts; [] if none)."""
    path = os.path.join(out, PARTS)
    if not os.path.exists(path):
        return []
    with open(path) as f:
        try:
            parts = json.load(f)
        except ValueError as exc:
            raise RestartError("%s: not JSON (%s)" % (path, exc)) from None
    if not isinstance(parts, list) or any("part" not in p or "step" not in p for p in parts):
        raise RestartError("%s: expected a list of {part, step, ...} records" % path)
    return parts


def write_parts(out, parts):
    os.makedirs(os.path.join(out, "restart"), exist_ok=True)
    with open(os.path.join(out, PARTS), "w") as f:
        json.dump(parts, f, indent=2)


def keep_before(steps, step_restart, steps_next):
    """Mask of the rows (their ``steps``) of the run so far that stay when a
    part goes on from ``step_restart``: every row before that step, and the
    rows at that step unless the next part (``steps_next``) writes that step
    again. Rows after it are the killed part's lost work."""
    steps = np.asarray(steps)
    again = np.isin(step_restart, np.asarray(steps_next))
    return (steps < step_restart) | ((steps == step_restart) & ~again)


def _split(text):
    """(header lines, data lines, their steps) of a series file whose data
    lines start with the step; comment lines (#) before the data are the
    header, later ones are dropped."""
    lines = text.splitlines(keepends=True)
    is_data = np.array([bool(ln.strip()) and not ln.lstrip().startswith("#") for ln in lines],
                       dtype=bool)
    first = int(np.argmax(is_data)) if is_data.any() else len(lines)
    header = lines[:first]
    data = [ln if ln.endswith("\n") else ln + "\n" for ln, d in zip(lines, is_data) if d]
    steps = (np.loadtxt(data, usecols=0, ndmin=1).astype(np.int64) if data
             else np.zeros(0, dtype=np.int64))
    return header, data, steps


def merge_series_text(texts, restart_steps):
    """One series from its parts' texts: ``texts[0]`` is the first run's,
    ``texts[k]`` that of part k, which went on from ``restart_steps[k-1]``.
    The header is the first run's; a RestartError if a part's step is not
    after the step it started from."""
    if len(restart_steps) != len(texts) - 1:
        raise RestartError("%d parts need %d restart steps, got %d"
                           % (len(texts), len(texts) - 1, len(restart_steps)))
    header, data, steps = _split(texts[0])
    data = np.array(data, dtype=object)
    for text, s in zip(texts[1:], restart_steps):
        _, d_next, st_next = _split(text)
        if len(st_next) and st_next.min() < s:
            raise RestartError("a part that went on from step %d has a row at step %d"
                               % (s, st_next.min()))
        keep = keep_before(steps, s, st_next)
        data = np.concatenate([data[keep], np.array(d_next, dtype=object)])
        steps = np.concatenate([steps[keep], st_next])
    return "".join(header) + "".join(data.tolist())


def part_walls(out, parts):
    """Wall time [s] of every part in ``parts`` (records with "part",
    "started" and "wall_s"; part 0 is the first run, whose log
    log.part0.liggghts is then): recorded when the part ended, else (a
    killed part) its log's last change less its start."""
    walls = []
    for p in parts:
        if p.get("wall_s") is not None:
            walls.append(float(p["wall_s"]))
        else:
            log = os.path.join(out, part_name(LOG, p["part"]))
            walls.append(max(0.0, os.path.getmtime(log) - p["started"]) if os.path.exists(log) else 0.0)
    return walls


def stale_snapshots(snapshots, step_restart):
    """The snapshot paths of ``snapshots`` (a list of (step, path), as
    crushpost.snapshot.list_snapshots gives) written after ``step_restart``:
    lost work that the next part may not write again."""
    return [path for step, path in snapshots if step > step_restart]


def merge_parts(out, names=SERIES, log=LOG):
    """Write the whole run's series (``names``, where part 0 has them) and
    its log from the parts recorded in restart/parts.json; returns the names
    written. The parts' own files stay."""
    parts = sorted(read_parts(out), key=lambda p: p["part"])
    if not parts:
        raise RestartError("%s: no parts recorded" % os.path.join(out, PARTS))
    numbers = [p["part"] for p in parts]
    if numbers != list(range(1, len(parts) + 1)):
        raise RestartError("%s: parts %s, expected 1..%d" % (os.path.join(out, PARTS), numbers,
                                                           len(parts)))
    steps = [int(p["step"]) for p in parts]
    written = []
    for name in names:
        paths = [os.path.join(out, part_name(name, k)) for k in range(len(parts) + 1)]
        if not os.path.exists(paths[0]):
            continue
        missing = [p for p in paths[1:] if not os.path.exists(p)]
        if missing:
            raise RestartError("%s exists but %s do(es) not" % (paths[0], ", ".join(missing)))
        texts = []
        for p in paths:
            with open(p, errors="replace") as f:
                texts.append(f.read())
        with open(os.path.join(out, name), "w") as f:
            f.write(merge_series_text(texts, steps))
        written.append(name)
    logs = [os.path.join(out, part_name(log, k)) for k in range(len(parts) + 1)]
    with open(os.path.join(out, log), "w") as f:
        for k, p in enumerate(logs):
            if k:
                f.write("# crushpost.restart: part %d goes on from %s at step %d\n"
                        % (k, parts[k - 1].get("restart_file", "?"), steps[k - 1]))
            if os.path.exists(p):
                with open(p, errors="replace") as g:
                    f.write(g.read())
    written.append(log)
    return written



def clear_parts(out):
    """Remove what an earlier run in ``out`` left for resuming (restart/ and
    the parts' files): a run that starts afresh there must not be resumed
    from another run's state."""
    shutil.rmtree(os.path.join(out, "restart"), ignore_errors=True)
    for name in SERIES + (LOG, "spheres.in"):
        stem, _, ext = name.rpartition(".")
        for path in glob.glob(os.path.join(out, "%s.part*.%s" % (stem, ext))):
            if re.fullmatch(r"part\d+", path[len(os.path.join(out, stem)) + 1:-len(ext) - 1]):
                os.remove(path)


def infer_parts(out):
    """The parts of a run resumed by hand (a paper deck run with ``-var resume
    1``, its series and logs named ``*.part<k>.*``): part k = 1, 2, ... for
    every log.part<k>.liggghts, its restart step the first thermo step of that
    log (read_restart sets the step; the first run is part 0)."""
    from .thermo import parse_log

    parts = []
    k = 1
    while os.path.exists(os.path.join(out, part_name(LOG, k))):
        path = os.path.join(out, part_name(LOG, k))
        with open(path, errors="replace") as f:
            blocks = [b for b in parse_log(f.read()) if "Step" in b and len(b["Step"])]
        if not blocks:
            raise RestartError("%s: no thermo output: the part's restart step is unknown" % path)
        parts.append({"part": k, "step": int(blocks[0]["Step"][0]), "restart_file": "?",
                      "started": None, "wall_s": None})
        k += 1
    if not parts:
        raise RestartError("%s: no %s: no part to merge" % (out, part_name(LOG, 1)))
    return parts


# --- carrying a killed run to another machine -------------------------------
# A run folder is not in git, and a session may get a new machine with the
# work tree laid anew: a study piece longer than a session would then start
# again from its packing every time. pack_carry writes what resuming reads
# (bench/error_vs_runtime/run.py --carry) into one compressed file that can
# be committed; unpack_carry lays it out again where the next part runs.
CARRY_SKIP = ("running.pid",)           # a claim of a live process, not state
# LIGGGHTS writes restart_forced_<name>_<step>.data when a signal stops it:
# a state after the last complete restart file, which resuming does not read
FORCED_RESTART = re.compile(r"restart_forced_.*\.data")


def carry_members(out):
    """The files of the run in ``out`` that resuming needs, as paths relative
    to ``out``: everything but the restart file that latest.txt does not name
    (the one being overwritten in turn) and CARRY_SKIP; RestartError if the
    run has no complete restart file or is complete (summary.json)."""
    out = os.fspath(out)
    step, latest = latest_restart(out)
    if os.path.exists(os.path.join(out, "summary.json")):
        raise RestartError("%s: the run is complete (summary.json): nothing to carry" % out)
    restart_dir = os.path.join(out, "restart")
    members = []
    for base, dirs, files in os.walk(out):
        dirs.sort()
        for name in sorted(files):
            path = os.path.join(base, name)
            if base == out and (name in CARRY_SKIP or FORCED_RESTART.fullmatch(name)):
                continue
            if (os.path.dirname(path) == restart_dir and name.endswith(".restart")
                    and os.path.abspath(path) != os.path.abspath(latest)):
                continue
            members.append(os.path.relpath(path, out))
    return members


def pack_carry(out, archive):
    """Write the resumable state of the run in ``out`` to ``archive`` (a
    .tar.xz; file times kept: a killed part's wall time ends at its log's last
    change, part_walls); returns the restart step it goes on from."""
    step, _ = latest_restart(out)
    members = carry_members(out)
    os.makedirs(os.path.dirname(os.path.abspath(archive)), exist_ok=True)
    tmp = archive + ".tmp"
    with tarfile.open(tmp, "w:xz") as tar:
        for rel in members:
            tar.add(os.path.join(out, rel), arcname=rel, recursive=False)
    os.replace(tmp, archive)
    return step


def _safe(name):
    parts = name.replace("\\", "/").split("/")
    return not (name.startswith("/") or ".." in parts or not name)


def carry_step(archive):
    """The restart step the carried run in ``archive`` goes on from (its
    restart/latest.txt); RestartError naming the file if it is not a carry."""
    try:
        with tarfile.open(archive, "r:*") as tar:
            f = tar.extractfile(LATEST.replace(os.sep, "/"))
            words = f.read().decode().split()
    except (OSError, KeyError, tarfile.TarError, AttributeError) as exc:
        raise RestartError("%s: not a carried run (%s)" % (archive, exc)) from None
    if len(words) != 2 or not re.fullmatch(r"\d+", words[0]):
        raise RestartError("%s: %s: expected 'STEP FILE', found %r" % (archive, LATEST, " ".join(words)))
    return int(words[0])


def holds_run(out):
    """Whether ``out`` holds a run of its own (a restart file to go on from,
    or a finished run's summary.json): no carry is laid out over it."""
    return any(os.path.exists(os.path.join(out, own)) for own in (LATEST, "summary.json"))


def unpack_carry(archive, out):
    """Lay the carried run in ``archive`` out in ``out`` to be resumed;
    returns its restart step. Refuses (RestartError) to overwrite a folder
    that holds a run of its own (restart/latest.txt or summary.json), and an
    archive with a member that is not a plain file or folder below ``out``."""
    if holds_run(out):
        own = LATEST if os.path.exists(os.path.join(out, LATEST)) else "summary.json"
        raise RestartError("%s exists: %s holds a run of its own; not overwritten by %s"
                           % (os.path.join(out, own), out, archive))
    step = carry_step(archive)
    with tarfile.open(archive, "r:*") as tar:
        members = tar.getmembers()
        bad = [m.name for m in members if not (m.isfile() or m.isdir()) or not _safe(m.name)]
        if bad:
            raise RestartError("%s: member(s) %s are not plain files below the run folder"
                               % (archive, ", ".join(bad)))
        os.makedirs(out, exist_ok=True)
        for m in members:
            dest = os.path.join(out, m.name)
            if m.isdir():
                os.makedirs(dest, exist_ok=True)
                continue
            os.makedirs(os.path.dirname(dest), exist_ok=True)
            with tar.extractfile(m) as src, open(dest + ".tmp", "wb") as dst:
                shutil.copyfileobj(src, dst)
            os.replace(dest + ".tmp", dest)
            os.utime(dest, (m.mtime, m.mtime))
    return step
