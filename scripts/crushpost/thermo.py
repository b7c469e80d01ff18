# SPDX-License-Identifier: GPL-2.0-or-later
"""Thermo output of LIGGGHTS / LAMMPS log files (one-line thermo style).

A block starts at a line whose first word is ``Step`` and ends at the line
starting with ``Loop time``. Inside a block, lines that are not all numbers
with the header's field count (warnings, INFO lines, progress messages) are
skipped. A block cut short (run killed, error) is still returned.
"""

from pathlib import Path

import numpy as np

__all__ = ["parse_log", "read_log", "concat_blocks", "summarize"]


def _numbers(words):
    try:
        return [float(w) for w in words]
    except ValueError:
        return None


def _finish(columns, rows):
    data = np.array(rows, dtype=float).reshape(len(rows), len(columns))
    block = {}
    for k, name in enumerate(columns):
        col = data[:, k]
        # Step counts are integers; keep them exact for step comparisons.
        block[name] = col.astype(np.int64) if name == "Step" else col
    return block


def parse_log(text):
    """All thermo blocks of a log given as a string.

    Returns a list (one per run) of dicts mapping each column name of the
    header (e.g. "Step", "Atoms", "KinEng", "c_qc") to a 1-D numpy array;
    "Step" is int64, the rest float64. Column names repeated in one header
    keep only the last column.
    """
    blocks = []
    columns = None
    rows = []
    for line in text.splitlines():
        words = line.split()
        if columns is None:
            if words and words[0] == "Step":
                columns, rows = words, []
            continue
        if words and words[0] == "Loop" and line.lstrip().startswith("Loop time"):
            blocks.append(_finish(columns, rows))
            columns = None
            continue
        if len(words) == len(columns):
            vals = _numbers(words)
            if vals is not None:
                rows.append(vals)
    if columns is not None:
        blocks.append(_finish(columns, rows))
    return blocks


def read_log(path):
    """:func:`parse_log` of a log file (``log.liggghts``, ``log.lammps``)."""
    return parse_log(Path(path).read_text(errors="replace"))


def concat_blocks(blocks, drop_repeated_steps=True):
    """Join blocks of successive runs into one dict of arrays.

    Columns are the union over blocks in order of first appearance; a column
    missing from a block is filled with NaN there (Step stays int64 and must
    exist in every block). Each run reprints the last step of the previous
    one as its first row; with ``drop_repeated_steps`` the rows of a block
    whose Step is not beyond the previous block's last Step are dropped.
    """
    if not blocks:
        return {}
    names = []
    for b in blocks:
        names += [n for n in b if n not in names]
    parts = {n: [] for n in names}
    last = None
    for b in blocks:
        if "Step" not in b:
            raise KeyError("every thermo block needs a Step column")
        keep = np.ones(b["Step"].size, dtype=bool)
        if drop_repeated_steps and last is not None:
            keep = b["Step"] > last
        if b["Step"].size:
            last = b["Step"][-1] if last is None else max(last, b["Step"][-1])
        n = int(keep.sum())
        for name in names:
            parts[name].append(b[name][keep] if name in b else np.full(n, np.nan))
    return {n: np.concatenate(parts[n]) for n in names}


def summarize(data):
    """Per-column summary rows ``(name, n, first, last, min, max)`` of a dict of arrays."""
    rows = []
    for name, col in data.items():
        col = np.asarray(col, dtype=float)
        fin = col[np.isfinite(col)]
        if fin.size:
            rows.append((name, col.size, col[0], col[-1], fin.min(), fin.max()))
        else:
            rows.append((name, col.size, np.nan, np.nan, np.nan, np.nan))
    return rows
