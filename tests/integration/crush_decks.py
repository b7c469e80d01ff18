# SPDX-License-Identifier: GPL-2.0-or-later
"""Deck builders and independent analytic answers for the deck-level tests of
`fix crush/particle` (docs/model.md §2 and §5).

Everything the tests compare against is computed here in Python from the
formulas of docs/model.md §2, without using the plugin's C++ kernels:

    1/E*   = (1 - nu_p^2)/E_p + (1 - nu_q^2)/E_q      (a wall: its own E, nu)
    1/R*   = 1/r_p + 1/r_q                            (a wall: R* = r_p)
    sigma  = sigma_lim0 f (d / (N d0))^(-3/m)
    F_lim  = (pi sigma)^3 (3 R* / (4 E*))^2
    F_n    = 4/3 E* sqrt(R*) delta^(3/2)               (Hertz, elastic part)
    T_R    = pi r sqrt(rho/G) / (0.1631 nu + 0.8766)
    fragments: 6 of r1 = r/(1+sqrt2) at r - r1 on 3 orthogonal axes, 8 of r2
    at r - r2 on the cube diagonals, r2 solved here from the tangency
    conditions (not copied from the 0.230093 of docs/model.md §2.6; the test checks both).

Note on running: LIGGGHTS 3.8 core code (input_mesh_tri.cpp, fix_mesh.cpp)
writes to `screen` without checking for NULL, so any deck with a
`fix mesh/surface` segfaults under the harness's `-screen none`.  `run`
below appends `-screen screen.txt` (the later flag wins).
"""

import math
import sys
from pathlib import Path

import numpy as np
from scipy.optimize import brentq

sys.path.insert(0, str(Path(__file__).resolve().parent))
import harness  # noqa: E402
from crushpost import materials  # noqa: E402
from crushpost.materials import rayleigh_time  # noqa: E402,F401  (cd.rayleigh_time of the deck tests)

# --------------------------------------------------------------------------
# docs/model.md §3 material (NE34 quartz, crushpost.materials) and the steel
# of the pile / platens
# --------------------------------------------------------------------------
G_GRAIN = materials.G_GRAIN
NU_GRAIN = materials.NU_GRAIN
E_GRAIN = 2.0 * G_GRAIN * (1.0 + NU_GRAIN)        # 21.6 GPa
E_STEEL = 200.0e9                                  # these tests' steel (materials.E_STEEL: 204 GPa)
NU_STEEL = materials.NU_STEEL
DENSITY = materials.RHO_GRAIN
SIGMA0 = materials.SIGMA_LIM0
M_WEIBULL = materials.M_SIZE
D0 = materials.D0
D50 = materials.D50                                # median grain size at N = 1 [m]
SEED = 15485863                                    # a prime > 10000
FRICTION_GG = materials.MU_GRAIN
FRICTION_GW = materials.MU_PILE



# --------------------------------------------------------------------------
# analytic model (docs/model.md §2.1, §2.4)
# --------------------------------------------------------------------------

def effective_modulus(E_p, nu_p, E_q, nu_q):
    return 1.0 / ((1.0 - nu_p ** 2) / E_p + (1.0 - nu_q ** 2) / E_q)


def effective_radius(r_p, r_q=None):
    """R* of a particle-particle contact, or of a wall contact (r_q None)."""
    if r_q is None:
        return r_p
    return 1.0 / (1.0 / r_p + 1.0 / r_q)


def strength(d, N=1.0, f=1.0, sigma0=SIGMA0, m=M_WEIBULL, d0=D0):
    return sigma0 * f * (d / (N * d0)) ** (-3.0 / m)


def limit_force(sigma, R_star, E_star):
    return (math.pi * sigma) ** 3 * (3.0 * R_star / (4.0 * E_star)) ** 2


def hertz_force(delta, R_star, E_star):
    delta = np.maximum(np.asarray(delta, dtype=float), 0.0)
    return 4.0 / 3.0 * E_star * np.sqrt(R_star) * delta ** 1.5


def hertz_overlap(F, R_star, E_star):
    """Overlap at which the Hertz force is F (inverse of hertz_force)."""
    return (3.0 * F / (4.0 * E_star * math.sqrt(R_star))) ** (2.0 / 3.0)


def sphere_mass(r, rho=DENSITY):
    return 4.0 / 3.0 * math.pi * np.asarray(r, dtype=float) ** 3 * rho


R1_RATIO = 1.0 / (1.0 + math.sqrt(2.0))


def _small_ratio():
    """r2/r from tangency: the small sphere at (r - r2)/sqrt3 (1, 1, 1) touches
    the large one at (r - r1, 0, 0) (distance r1 + r2), r = 1."""
    r1 = R1_RATIO
    a = np.array([1.0 - r1, 0.0, 0.0])

    def gap(r2):
        c = (1.0 - r2) / math.sqrt(3.0) * np.ones(3)
        return np.linalg.norm(c - a) - (r1 + r2)

    return brentq(gap, 1e-3, 0.5, xtol=1e-15, rtol=1e-15)


R2_RATIO = _small_ratio()
KEPT_VOLUME_FRACTION = 6.0 * R1_RATIO ** 3 + 8.0 * R2_RATIO ** 3


# --------------------------------------------------------------------------
# files
# --------------------------------------------------------------------------

def write_plate_stl(path, half=0.02, z=0.0):
    """A square plate (two facets) of side 2*half in the plane z, normal +z."""
    h = repr(float(half))
    zz = repr(float(z))
    text = f"""solid plate
facet normal 0 0 1
outer loop
vertex -{h} -{h} {zz}
vertex {h} -{h} {zz}
vertex {h} {h} {zz}
endloop
endfacet
facet normal 0 0 1
outer loop
vertex -{h} -{h} {zz}
vertex {h} {h} {zz}
vertex -{h} {h} {zz}
endloop
endfacet
endsolid plate
"""
    Path(path).write_text(text)


class Event:
    __slots__ = ("step", "time", "tag", "diameter", "x", "F_n", "F_lim", "partner",
                 "generation")

    def __repr__(self):
        return ("Event(step=%d, tag=%d, d=%.6g, F_n=%.8g, F_lim=%.8g, %s, gen %d)"
                % (self.step, self.tag, self.diameter, self.F_n, self.F_lim,
                   self.partner, self.generation))


def read_events(path):
    """Lines `step time parent_tag parent_diameter x y z F_n F_lim partner generation`."""
    events = []
    for line in Path(path).read_text().splitlines():
        s = line.strip()
        if not s or s.startswith("#"):
            continue
        w = s.split()
        assert len(w) == 11, "bad event line: %r" % line
        e = Event()
        e.step = int(w[0])
        e.time = float(w[1])
        e.tag = int(w[2])
        e.diameter = float(w[3])
        e.x = np.array([float(w[4]), float(w[5]), float(w[6])])
        e.F_n = float(w[7])
        e.F_lim = float(w[8])
        e.partner = w[9]
        e.generation = int(w[10])
        events.append(e)
    return events


# --------------------------------------------------------------------------
# deck pieces
# --------------------------------------------------------------------------

def header(box, materials, restitution=1.0, processors=None, newton="off",
           atom_style="granular", skin=0.0005):
    """Granular SI set-up with one atom type per entry of `materials`
    (list of (E, nu, kind) with kind 'grain' or 'wall'), Hertz contacts."""
    n = len(materials)
    E = " ".join(repr(float(m[0])) for m in materials)
    nu = " ".join(repr(float(m[1])) for m in materials)
    e = " ".join([repr(float(restitution))] * (n * n))
    mu = []
    for a in materials:
        for b in materials:
            mu.append(FRICTION_GG if a[2] == b[2] == "grain" else FRICTION_GW)
    mu = " ".join(repr(v) for v in mu)
    proc = f"processors {processors}\n" if processors else ""
    return f"""\
units si
hard_particles yes
atom_style {atom_style}
atom_modify map array
boundary f f f
newton {newton}
communicate single vel yes
{proc}region box block {box} units box
create_box {n} box
neighbor {skin!r} bin
neigh_modify delay 0
thermo_modify lost error
fix m1 all property/global youngsModulus peratomtype {E}
fix m2 all property/global poissonsRatio peratomtype {nu}
fix m3 all property/global coefficientRestitution peratomtypepair {n} {e}
fix m4 all property/global coefficientFriction peratomtypepair {n} {mu}
pair_style gran model hertz tangential history
pair_coeff * *
"""


def crush_fix(sigma0=SIGMA0, m=M_WEIBULL, d0=D0, scale=1, var=0.0, d_comm=1e-4,
              seed=SEED, extra="", fix_id="crush", group="all", events="events.txt"):
    ev = f" events {events}" if events else ""
    return (f"fix {fix_id} {group} crush/particle sigma_lim0 {sigma0!r} m {m!r} d0 {d0!r} "
            f"scale {scale} var {var!r} d_comm {d_comm!r} seed {seed}{ev} {extra}\n")


DUMP_COLUMNS = ("id type radius mass x y z vx vy vz fx fy fz f_crush[1] f_crush[2]")
DUMP_FORMAT = "%d %d" + " %.17g" * 13


def dump_lines(every, name="dump.txt", group="all"):
    return (f"dump d {group} custom {every} {name} {DUMP_COLUMNS}\n"
            f'dump_modify d format "{DUMP_FORMAT}" sort id\n')


def run(deck, workdir, nprocs=1, timeout=240, check=True, files=None, screen="screen.txt",
        lost_ok=False):
    """harness.run_deck with `-screen screen.txt` (mesh code needs a screen)
    and extra files (name -> callable(path)) written to the workdir first.
    screen="/dev/stdout" puts the screen output into RunResult.stdout;
    lost_ok as in harness.run_deck."""
    workdir = Path(workdir)
    workdir.mkdir(parents=True, exist_ok=True)
    for name, writer in (files or {}).items():
        writer(workdir / name)
    return harness.run_deck(deck, workdir, nprocs=nprocs, timeout=timeout, check=check,
                            extra_args=["-screen", screen], lost_ok=lost_ok)


def expect_error(deck, workdir, pattern, nprocs=1, timeout=120, files=None, screen="screen.txt",
                 lost_ok=False):
    """harness.expect_error, with the extra files, screen flag and lost_ok of `run`."""
    res = run(deck, workdir, nprocs=nprocs, timeout=timeout, check=False, files=files,
              screen=screen, lost_ok=lost_ok)
    if res.returncode == 0:
        raise harness.DeckError("deck was expected to fail (pattern %r) but ran successfully\n%s"
                                % (pattern, res.summary()))
    if not res.errors:
        raise harness.DeckError("deck failed without an ERROR line (expected %r)\n%s"
                                % (pattern, res.summary()))
    if pattern not in res.all_text:
        raise harness.DeckError("error text does not contain %r; errors were:\n  %s\n%s"
                                % (pattern, "\n  ".join(res.errors), res.summary()))
    return res
