# SPDX-License-Identifier: GPL-2.0-or-later
"""Multi-grain scenes for the deck tests of `fix crush/particle`
(test_crush_parallel.py): deterministic packings written as LAMMPS data files,
a square STL platen, and the common deck header.

Everything here is plain text generation; no LIGGGHTS is run.  Packings are
made with a fixed numpy seed, so a scene is the same in every session.
"""

import math
from pathlib import Path

import numpy as np

from crushpost.materials import E_GRAIN, MU_GRAIN, NU_GRAIN, RHO_GRAIN, rayleigh_time  # noqa: F401

# docs/model.md §3 material (NE34 quartz, crushpost.materials): G = 9 GPa,
# nu = 0.2 -> E = 2 G (1 + nu) = 21.6 GPa. Type 2 is the wall material (steel).
E_WALL, NU_WALL = 200e9, 0.2
DENSITY = RHO_GRAIN
SEED_FIX = 15485863           # a prime > 10000

# Apollonian fragment radii (docs/model.md §2.6)
R1_RATIO = 1.0 / (1.0 + math.sqrt(2.0))      # 0.414214


def _small_ratio():
    # centre of a small fragment at distance u = r - r2 from the parent centre
    # along a cube diagonal, tangent to three large fragments (centres at
    # distance a = r - r1 on the axes): u^2 - 2 a u / sqrt3 + a^2 = (r1 + r2)^2
    # with r2 = r - u  ->  linear in u (r = 1).
    a, s = 1.0 - R1_RATIO, 1.0 + R1_RATIO
    u = (s * s - a * a) / (2.0 * s - 2.0 * a / math.sqrt(3.0))
    return 1.0 - u


R2_RATIO = _small_ratio()                    # 0.230093 (docs/model.md §2.6)
assert abs(R2_RATIO - 0.230093) < 5e-7


def sphere_mass(d, rho=DENSITY):
    d = np.asarray(d, dtype=float)
    return math.pi / 6.0 * d ** 3 * rho


def smallest_fragment_radius(d_comm):
    """Smallest radius a fragment can have with d_frag_min = 0: the small
    Apollonian fragment of a parent just at the comminution limit."""
    return R2_RATIO * 0.5 * d_comm


def write_plate_stl(path, xlo, xhi, ylo, yhi):
    """A square of two facets in the plane z = 0, normal +z."""
    text = f"""solid plate
facet normal 0 0 1
outer loop
vertex {xlo!r} {ylo!r} 0
vertex {xhi!r} {ylo!r} 0
vertex {xhi!r} {yhi!r} 0
endloop
endfacet
facet normal 0 0 1
outer loop
vertex {xlo!r} {ylo!r} 0
vertex {xhi!r} {yhi!r} 0
vertex {xlo!r} {yhi!r} 0
endloop
endfacet
endsolid plate
"""
    Path(path).write_text(text)


def column_packing(xs, ys, height, dmin, dmax, seed, gap=0.01, z0=0.0):
    """Columns of grains stacked along z at the lateral positions (xs x ys).

    Each column holds grains of diameters drawn log-uniformly from
    [dmin, dmax], each a fraction `gap` of its diameter above the one below,
    until the next grain would end above z0 + height.  Returns an (n, 4)
    array of x, y, z, d (row order = atom tag order).
    """
    rng = np.random.RandomState(seed)
    rows = []
    for x in xs:
        for y in ys:
            z = z0
            while True:
                d = math.exp(rng.uniform(math.log(dmin), math.log(dmax)))
                top = z + d * (1.0 + gap)
                if top > z0 + height:
                    break
                rows.append((x, y, z + d * (0.5 + gap), d))
                z = top
    return np.array(rows, dtype=float)


def write_data(path, grains, box, ntypes=2, vz=None):
    """LAMMPS data file for atom_style granular: id type diameter density x y z
    (type 1 for every grain).  `vz` (optional) gives every grain that z velocity."""
    (xlo, xhi), (ylo, yhi), (zlo, zhi) = box
    lines = ["LAMMPS data file: crush/particle test packing", "",
             f"{len(grains)} atoms", f"{ntypes} atom types", "",
             f"{xlo!r} {xhi!r} xlo xhi", f"{ylo!r} {yhi!r} ylo yhi",
             f"{zlo!r} {zhi!r} zlo zhi", "", "Atoms", ""]
    for k, (x, y, z, d) in enumerate(grains):
        lines.append(f"{k + 1} 1 {d!r} {DENSITY!r} {x!r} {y!r} {z!r}")
    if vz is not None:
        lines += ["", "Velocities", ""]
        for k in range(len(grains)):
            lines.append(f"{k + 1} 0 0 {vz!r} 0 0 0")
    Path(path).write_text("\n".join(lines) + "\n")


def preamble(boundary="f f f"):
    """The lines every granular test deck starts with: SI units, moduli above
    1e9 Pa (hard_particles), granular atoms with an atom map, newton off (fix
    crush/particle tests the contacts of owned grains), ghost velocities."""
    return f"""\
units           si
hard_particles  yes
atom_style      granular
atom_modify     map array
boundary        {boundary}
newton          off
communicate     single vel yes
"""


def header(boundary="f f f", processors="* 1 1", skin=1e-4):
    """Units, atom style, material tables (2 types: grain, wall), Hertz pair
    style with Mindlin tangential history, no rolling (`fix nve` only)."""
    return preamble(boundary) + f"""\
processors      {processors}
read_data       grains.data
neighbor        {skin!r} bin
neigh_modify    delay 0
thermo_modify   lost error
fix m1 all property/global youngsModulus peratomtype {E_GRAIN!r} {E_WALL!r}
fix m2 all property/global poissonsRatio peratomtype {NU_GRAIN!r} {NU_WALL!r}
fix m3 all property/global coefficientRestitution peratomtypepair 2 0.5 0.5 0.5 0.5
fix m4 all property/global coefficientFriction peratomtypepair 2 {MU_GRAIN:g} 0.5 0.5 0.5
pair_style      gran model hertz tangential history
pair_coeff      * *
"""


# ---------------------------------------------------------------------------
# one-dimensional compression by a descending mesh platen
# ---------------------------------------------------------------------------

# LIGGGHTS' STL reader (InputMeshTri::meshtrifile) prints to `screen` without
# checking it, so a deck with a mesh crashes under the harness' `-screen none`.
# A later `-screen` argument wins: send the screen output to /dev/null instead.
MESH_ARGS = ["-screen", "/dev/null"]


class Scene:
    """A compression scene written into a folder: grains.data, plate.stl and
    the deck text.  Attributes: grains ((n, 4) x y z d), box, dt, d_comm,
    r_bound (smallest radius that can occur), mass0, deck."""


def compression_scene(workdir, nx, ny, height, dmin, dmax, nsteps, speed=2.0,
                      sigma_lim0=1.5e8, m=10, d0=0.002, var=0.36, d_comm=4e-4,
                      packing_seed=12345, mirror=False, periodic=False,
                      processors="* 1 1", thermo=1000, dump_every=0,
                      alpha=0.05, dt_frac=0.18, extra="", lost="error"):
    """Columns of grains (see `column_packing`) on an nx x ny grid of pitch
    1.05 dmax, compressed from the top by a flat mesh platen moving down at
    `speed`, on a primitive bottom wall.  Side walls are primitive planes, or
    with `periodic` the box is periodic in x and y and the grid is shifted by
    0.1 pitch so the first row and column of grains straddle the boundaries.
    With `mirror` the columns at x < 0 are the mirror images of those at x > 0
    (nx even), so the scene is symmetric about the x = 0 plane where
    `processors * 1 1` splits it at 2 ranks.

    The time step is dt_frac (default 0.18) of the Rayleigh time of the
    smallest particle that can occur (docs/model.md §5).  The deck prints
    thermo step atoms f_top[3] f_crush[1..7] every `thermo` steps with full
    precision, writes the events to events.txt and, with dump_every > 0,
    `dump.*.txt` files (id type x y z radius mass f_crush[1] f_crush[2]).
    `extra` is appended to the fix crush/particle line (e.g. ' d_frag_min 2e-4').
    `lost` is the thermo_modify lost setting.  LIGGGHTS 3.8's lost check
    (Thermo::lost_check) reports lost atoms whenever the total count drops
    between two thermo outputs; every break adds atoms while d_frag_min <=
    0.414 d_comm, but above that a grain that goes entirely to fines lowers
    the count on purpose (use 'ignore' then: fix crush/particle's own count
    still stops a real loss, docs/liggghts-patches.md).
    """
    workdir = Path(workdir)
    workdir.mkdir(parents=True, exist_ok=True)
    pitch = 1.05 * dmax
    Lx, Ly = 0.5 * nx * pitch, 0.5 * ny * pitch
    shift = 0.1 * pitch if periodic else 0.0
    xs = -Lx + (np.arange(nx) + (0.0 if periodic else 0.5)) * pitch + shift
    ys = -Ly + (np.arange(ny) + (0.0 if periodic else 0.5)) * pitch + shift
    if mirror:
        assert nx % 2 == 0 and not periodic
        right = column_packing(xs[nx // 2:], ys, height, dmin, dmax, packing_seed)
        left = right.copy()
        left[:, 0] = -left[:, 0]
        grains = np.vstack([left, right])
    else:
        grains = column_packing(xs, ys, height, dmin, dmax, packing_seed)
    ztop = height + 1e-4
    box = ((-Lx, Lx), (-Ly, Ly), (-0.5e-3, ztop + 1e-3))
    write_data(workdir / "grains.data", grains, box)
    write_plate_stl(workdir / "plate.stl", -Lx, Lx, -Ly, Ly)

    r_bound = min(smallest_fragment_radius(d_comm), 0.5 * grains[:, 3].min())
    dt = dt_frac * rayleigh_time(r_bound)

    walls = ("fix wz all wall/gran model hertz tangential history primitive type 2 zplane 0.0\n")
    if not periodic:
        for name, plane, pos in (("wx0", "xplane", -Lx), ("wx1", "xplane", Lx),
                                 ("wy0", "yplane", -Ly), ("wy1", "yplane", Ly)):
            walls += (f"fix {name} all wall/gran model hertz tangential history "
                      f"primitive type 2 {plane} {pos!r}\n")
    dump = ""
    if dump_every:
        dump = (f"dump d all custom {dump_every} dump.*.txt id type x y z radius mass "
                f"f_crush[1] f_crush[2]\n"
                "dump_modify d sort id format "
                "\"%d %d %.17g %.17g %.17g %.17g %.17g %.17g %.17g\"\n")
    deck = header(boundary="p p f" if periodic else "f f f", processors=processors) + f"""\
timestep        {dt!r}
fix top all mesh/surface/stress file plate.stl type 2 move 0 0 {ztop!r}
fix walls all wall/gran model hertz tangential history mesh n_meshes 1 meshes top
{walls}fix damp all damp/local alpha {alpha!r}
fix mv all move/mesh mesh top linear 0. 0. {-speed!r}
fix integ all nve
fix crush all crush/particle sigma_lim0 {sigma_lim0!r} m {m!r} d0 {d0!r} scale 1 var {var!r} d_comm {d_comm!r} seed {SEED_FIX} events events.txt{extra}
thermo_style    custom step atoms f_top[3] f_crush[1] f_crush[2] f_crush[3] f_crush[4] f_crush[5] f_crush[6] f_crush[7]
thermo_modify   format float %.17g lost {lost} norm no
thermo          {thermo}
{dump}run             {nsteps}
"""
    scene = Scene()
    scene.grains = grains
    scene.box = np.array(box)
    scene.dt = dt
    scene.d_comm = d_comm
    scene.r_bound = r_bound
    scene.mass0 = float(sphere_mass(grains[:, 3]).sum())
    scene.deck = deck
    scene.nsteps = nsteps
    return scene


def read_events(path):
    """Events file of fix crush/particle as a dict of arrays: step, time, tag,
    d, x, y, z, F_n, F_lim, partner ('wall'/'particle'), generation."""
    cols = {k: [] for k in ("step", "time", "tag", "d", "x", "y", "z", "F_n", "F_lim",
                            "partner", "generation")}
    for line in Path(path).read_text().splitlines():
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        w = line.split()
        assert len(w) == 11, line
        for k, v in zip(cols, w):
            cols[k].append(v)
    out = {}
    for k, v in cols.items():
        if k == "partner":
            out[k] = np.array(v, dtype=object)
        elif k in ("step", "tag", "generation"):
            out[k] = np.array(v, dtype=float).astype(np.int64)
        else:
            out[k] = np.array(v, dtype=float)
    return out
