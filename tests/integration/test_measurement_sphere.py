# SPDX-License-Identifier: GPL-2.0-or-later
"""Measurement spheres (docs/model.md §4.6, issue 5 item 7): in a homogeneous,
isotropically compressed packing a sphere reads the boundary stress within 10 %,
at 2 MPI ranks.

The packing is made by radius expansion (inputs/grow_to_stress.in) in a cube of
six frictionless mesh plates. What the test compares (docs/measurement_spheres.md
has the numbers behind each choice):

* Boundary stress from the contact forces on the plates (compute
  wall/gran/local on the output steps), not from the plates' mesh/surface/stress
  thermo values: the first thermo row of a run (its setup step) reports those
  about 1.5 times the contact forces.
* Bookkeeping check, independent of the spheres: the whole-sample Love average
  (1/V_box) sum over all contacts, grain-grain with centre-to-centre branch
  vectors and grain-wall with centre-to-contact-point ones, equals the plate
  stress (exact in static equilibrium; 3 % allows the residual out-of-balance
  forces, measured within 1 %).
* The grains within about two diameters of a plate carry less stress than the
  core (wall effect: looser, layered packing; measured 40 % less in the first
  0.7 d, 17 % less in the next 0.7 d) and that fringe is a large part of a
  sample 14 grains wide, so the core carries 17-19 % more than the mean plate
  stress (two seeds). The boundary stress the sphere must read is the one
  the core transmits to the plates: the force on the central patch of each
  plate (contact points farther than 0.15 L, about two diameters, from the
  other plates) over the patch area. The sphere (radius 0.35 L) stays the
  same distance from the plates. Mean stress within 10 %, components 15 %.
* Both are averaged over the same output steps of one window.
"""

import os

import numpy as np
import pytest

from harness import REPO, run_deck

from crushpost.materials import RHO_GRAIN  # noqa: E402
from crushpost.meshes import axis_plate_triangles, write_stl  # noqa: E402
from crushpost.packing import D50_NE34, ne34_diameters, rsa_box, write_lammps_data  # noqa: E402
from crushpost.spheres import measurement_sphere_block, read_sphere_series  # noqa: E402
from crushpost.stress import sphere_stress  # noqa: E402

CTEST_TIMEOUT = 1000   # ctest's budget: the one sphere run (timeout 900 s)

N = 39
D50 = D50_NE34 * N
L = 12 * D50         # cube side
S_PREP = 100e3       # isotropic stress reached by the expansion
CORE = 0.35 * L      # half-width of the plates' central patches = sphere radius
EVERY = 500          # output interval of spheres and contact dumps (steps)

DECK = """
variable inputs index {inputs}
include ${{inputs}}/base.in
boundary f f f
read_data grains.data
include ${{inputs}}/materials_ne34.in
neighbor 0.001 bin
neigh_modify delay 0
timestep 1.5e-7
{plates}
fix walls all wall/gran model hertz tangential history mesh n_meshes 6 meshes xm xp ym yp zm zp
include ${{inputs}}/integrate.in
# contact lists for the checks and the per-particle stress the spheres sum
# (LIGGGHTS wants them before the first run; they are evaluated only on the
# output steps below)
include ${{inputs}}/contacts_local.in
variable vol_atom atom mass/${{rho_grain}}
compute  V_grains all reduce sum v_vol_atom
variable A equal {area}
variable V_container equal {volume}
variable sx equal (f_xp[1]-f_xm[1])/(2*v_A)
variable sy equal (f_yp[2]-f_ym[2])/(2*v_A)
variable sz equal (f_zp[3]-f_zm[3])/(2*v_A)
variable p_mean equal (v_sx+v_sy+v_sz)/3
variable n_target index 0.0
variable s_prep index {s_prep}
variable grow_rate index 1e-3
variable n_expand_max index 30
thermo 2000
include ${{inputs}}/grow_to_stress.in
{spheres}
dump pairs all local {every} pairs.*.txt c_pgl[1] c_pgl[2] c_pgl[3] c_pgl[4] c_pgl[5] c_pgl[6] c_pgl[16] c_pgl[17] c_pgl[18]
dump walls all local {every} walls.*.txt c_wgl[1] c_wgl[2] c_wgl[3] c_wgl[4] c_wgl[5] c_wgl[6] c_wgl[16] c_wgl[17] c_wgl[18]
thermo_style custom step atoms v_sx v_sy v_sz v_porosity
thermo_modify lost error
thermo {every}
run 4000
"""


def build(workdir):
    rng = np.random.default_rng(7)
    d = ne34_diameters(4000, N, rng=rng)
    n = int(np.searchsorted(np.cumsum(np.pi / 6 * d ** 3), 0.6 * L ** 3))
    d = d[:n] * 0.75
    pos = rsa_box(d, [-L / 2] * 3, [L / 2] * 3, rng=rng)
    B = 0.7 * L
    write_lammps_data(os.path.join(workdir, "grains.data"), pos, d, RHO_GRAIN,
                      (-B, B, -B, B, -B, B), ntypes=4)
    plates = []
    for axis, name in enumerate("xyz"):
        for sign, tag in ((-1, "m"), (1, "p")):
            mid = name + tag
            write_stl(os.path.join(workdir, mid + ".stl"),
                      axis_plate_triangles(0.65 * L, axis, sign * L / 2), mid)
            plates.append("fix %s all mesh/surface/stress file %s.stl type 3" % (mid, mid))
    return "\n".join(plates), n


def read_local(path, ncol):
    """Rows of a LIGGGHTS `dump local` file (one snapshot)."""
    with open(path) as fh:
        lines = fh.read().splitlines()
    k = next(i for i, s in enumerate(lines) if s.startswith("ITEM: ENTRIES"))
    rows = [list(map(float, s.split())) for s in lines[k + 1:] if s.strip()]
    return np.array(rows, dtype=float).reshape(-1, ncol)


def plate_stresses(walls, half_width):
    """Normal stress of each axis (compression positive) from the wall contacts
    whose contact point lies within |u|, |v| < half_width on the plates:
    mean force of the two plates over the patch area (2 half_width)^2."""
    cp, f = walls[:, 0:3], walls[:, 6:9]
    out = np.empty(3)
    for k in range(3):
        u, v = [(1, 2), (2, 0), (0, 1)][k]
        on = np.abs(np.abs(cp[:, k]) - L / 2) < 1e-3 * L
        patch = on & (np.abs(cp[:, u]) < half_width) & (np.abs(cp[:, v]) < half_width)
        # force on the grains points away from the plate: +x on xm, -x on xp
        out[k] = -np.sum(np.sign(cp[patch, k]) * f[patch, k]) / 2.0 / (2.0 * half_width) ** 2
    return out


def boundary_tensor(walls):
    """(1/V_box) sum over the plate contacts of F (x) x_c (contact point x_c,
    force on the grain), compression positive: the mean stress the plates
    impose, off-diagonal terms included (force moments on the plates)."""
    return sphere_stress(walls[:, 0:3], walls[:, 6:9], L ** 3)


def love_whole_sample(pairs, walls):
    """(1/V_box) sum over every contact of F (x) L, compression positive."""
    xi, xj, f = pairs[:, 0:3], pairs[:, 3:6], pairs[:, 6:9]
    cp, xw, fw = walls[:, 0:3], walls[:, 3:6], walls[:, 6:9]
    branches = np.concatenate([xj - xi, cp - xw])
    forces = np.concatenate([f, fw])
    return sphere_stress(branches, forces, L ** 3)


@pytest.mark.parametrize("nprocs", [2])
def test_sphere_reads_boundary_stress(tmp_path, nprocs):
    plates, n = build(tmp_path)
    block = measurement_sphere_block([[0.0, 0.0, 0.0]], CORE, EVERY, "spheres.txt")
    deck = DECK.format(inputs=REPO / "inputs", plates=plates, area=L * L, volume=L ** 3,
                       s_prep=S_PREP, spheres=block, every=EVERY)
    res = run_deck(deck, tmp_path, nprocs=nprocs, timeout=900, check=True)
    steps, sigma = read_sphere_series(tmp_path / "spheres.txt", 1)
    assert len(steps) == 9
    full, core, love, bnd = [], [], [], []
    for s in steps:
        walls = read_local(tmp_path / ("walls.%d.txt" % s), 9)
        pairs = read_local(tmp_path / ("pairs.%d.txt" % s), 9)
        full.append(plate_stresses(walls, L / 2))
        core.append(plate_stresses(walls, CORE))
        love.append(love_whole_sample(pairs, walls))
        bnd.append(boundary_tensor(walls))
    full, core = np.mean(full, 0), np.mean(core, 0)
    love, bnd = np.mean(love, 0), np.mean(bnd, 0)
    s = sigma[:, 0].mean(axis=0)

    # the packing carries a real isotropic stress
    assert full.min() > 5e3, full
    # the contact forces on the plates are what the plates' own force output
    # says during the run (its setup row, the first, is left out: see above)
    th = res.thermo[-1]
    mesh = np.array([th["sx"][1:], th["sy"][1:], th["sz"][1:]]).mean(axis=1)
    assert np.allclose(mesh, np.mean([plate_stresses(read_local(
        tmp_path / ("walls.%d.txt" % st), 9), L / 2) for st in steps[1:]], 0), rtol=1e-3), mesh
    # bookkeeping: the whole-sample Love average is the plate stress, every
    # component (they differ by sum_p x_p (x) F_p, zero when each grain's
    # contact forces balance)
    assert np.allclose(np.diag(bnd), full, rtol=1e-4)  # dump local writes 6 digits
    assert np.abs(love - bnd).max() < 0.03 * full.mean(), (love, bnd)

    # the sphere reads the stress the core carries to the plates: mean within 10 %
    p_sphere, p_core = np.trace(s) / 3.0, core.mean()
    assert abs(p_sphere - p_core) / p_core < 0.10, (s, core, full)
    # each normal component within 15 % (measured 5 % here; 11 % with another
    # seed of the same sample). Single components of one small sample are
    # noisier than the mean: (1) its core carries a shear stress of 0.13-0.17 p
    # (sigma_xy below; the frictionless plates take it as force moments), so
    # the stress is anisotropic at the 10 % level and the sphere (a volume
    # average) and the patches (areas on the plates) see that field in
    # different places; (2) a patch holds only some 100 contacts per plate:
    # changing its half-width from 0.35 L to 0.30 L moves single components by
    # up to 11 %, the mean by 2-7 %.
    for k in range(3):
        assert abs(s[k, k] - core[k]) / core[k] < 0.15, (k, s, core)
    shear = max(abs(s[0, 1]), abs(s[0, 2]), abs(s[1, 2]))
    assert shear < 0.2 * p_core
    # the stress the whole plates carry is below the core's (wall fringe): the
    # reason the comparison is made with the core patches
    assert full.mean() < core.mean()
