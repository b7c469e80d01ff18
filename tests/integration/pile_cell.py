# SPDX-License-Identifier: GPL-2.0-or-later
"""A small cylindrical cell of NE34-shaped grains settled under 100 g, shared
by the deck tests of the pile styles (test_jack_pile.py, test_snapshot_hdf5.py).

Grains are 10x softer than NE34 (G_grain 9e8): a larger time step with the
same contact law; 100 g makes stresses quasi-static in a tiny cell, as in a
centrifuge.
"""

import math
from pathlib import Path

import numpy as np

import harness
from crushpost.materials import RHO_GRAIN
from crushpost.packing import ne34_diameters, rsa_cylinder, write_lammps_data

INPUTS = harness.REPO / "inputs"
N_SCALE = 39
SOLID = 0.6
G_GRAIN = 9e8
G_ACC = 981.0
RHO = RHO_GRAIN


def header(data_file, R_cell, dt):
    """Materials, a frictionless bottom and side, gravity (no integration)."""
    return f"""\
variable        inputs index {INPUTS}
variable        G_grain index {G_GRAIN!r}
include         ${{inputs}}/base.in
boundary        f f f
read_data       {data_file}
include         ${{inputs}}/materials_ne34.in
neighbor        0.002 bin
neigh_modify    delay 0
timestep        {dt!r}
fix             bottom all wall/gran model hertz tangential history primitive type 3 zplane 0.0
fix             side all wall/gran model hertz tangential history primitive type 3 zcylinder {R_cell!r} 0 0
fix             grav all gravity {G_ACC!r} vector 0 0 -1
"""


def settle_deck(R_cell, dt, steps):
    """Settle grains.data and write settled.data."""
    return header("grains.data", R_cell, dt) + f"""\
include         ${{inputs}}/integrate.in
thermo_style    custom step atoms ke
thermo_modify   lost error
thermo          5000
run             {steps}
write_data      settled.data
"""


def data_atoms(path):
    """Atoms section of a write_data file: id type diameter density x y z."""
    rows = []
    lines = Path(path).read_text().splitlines()
    i = next(k for k, line in enumerate(lines) if line.startswith("Atoms")) + 1
    for line in lines[i:]:
        w = line.split()
        if not w:
            if rows:
                break
            continue
        if not w[0].isdigit():
            break
        rows.append([float(x) for x in w[:7]])
    return np.array(rows)


def settle(wd, R_cell, H_pack, H_rsa, dt, steps, seed, z_box_top):
    """Random loose grains in the cell, settled; returns (run result, atoms of
    settled.data). The grain count fills H_pack at solid fraction SOLID."""
    rng = np.random.default_rng(seed)
    d = ne34_diameters(2000, N_SCALE, rng=rng)
    vol = math.pi * R_cell ** 2 * H_pack * SOLID
    n = int(np.searchsorted(np.cumsum(math.pi / 6 * d ** 3), vol))
    d = d[:n]
    pos = rsa_cylinder(d, R_cell, 0.0, H_rsa, rng=rng)
    L = 1.2 * R_cell
    write_lammps_data(Path(wd) / "grains.data", pos, d, RHO, (-L, L, -L, L, -0.005, z_box_top),
                      ntypes=4)
    res = harness.run_deck(settle_deck(R_cell, dt, steps), wd, timeout=300, check=True)
    atoms = data_atoms(Path(wd) / "settled.data")
    assert len(atoms) == n
    return res, atoms


def read_series(path, columns):
    """A whitespace time-series file (fix jack/pile 'file') as a dict of columns."""
    data = np.loadtxt(path, comments="#", ndmin=2)
    assert data.shape[1] == len(columns), data.shape
    return {c: data[:, j] for j, c in enumerate(columns)}


# An empty box with the materials, for decks that test bad input of the pile
# styles (a format string: fill in `inputs`).
EMPTY_BOX = """\
variable        inputs index {inputs}
include         ${{inputs}}/base.in
atom_modify     sort 0 0.0
boundary        f f f
region          box block -0.02 0.02 -0.02 0.02 0.0 0.2 units box
create_box      4 box
include         ${{inputs}}/materials_ne34.in
neighbor        0.002 bin
timestep        1e-5
"""


def run_error_cases(cases, tmp_path_factory, prepare):
    """Run the decks of `cases` ({name: (deck, pattern)}) that must stop with an
    ERROR containing `pattern`, a few at a time, each in its own folder made
    ready by `prepare(folder)`. Returns {name: RunResult, or the exception
    raised, which the test of that case re-raises}."""
    from concurrent.futures import ThreadPoolExecutor

    def one(workdir, deck, pattern):
        prepare(workdir)
        try:
            return harness.expect_error(deck, workdir, pattern, timeout=120)
        except Exception as exc:  # reported by the test of this case
            return exc

    with ThreadPoolExecutor(max_workers=8) as pool:
        futures = {name: pool.submit(one, tmp_path_factory.mktemp(name), deck, pattern)
                   for name, (deck, pattern) in cases.items()}
        return {name: f.result() for name, f in futures.items()}
