# SPDX-License-Identifier: GPL-2.0-or-later
"""Density scaling of fine particles, `fix crush/particle ... density_scale
D_REF` (issue "Error against run time", item 1).

A particle finer than D_REF, an initial grain or a fragment, gets its mass
raised by (D_REF/d)^2, so that its Rayleigh time equals that of a D_REF
particle; the fix's mass balance, fines and Br stay in true mass. Checked
against answers computed here (crush_multi's sphere masses and Rayleigh
time):

a. a periodic compression with dozens of breaks and D_REF = 1 mm (grains
   0.6-1.2 mm, fragments down to 0.06 mm): particle mass + fines == the
   initial TRUE mass at every thermo output (1e-12), atom counts and tags as
   without scaling (test_crush_parallel's checks);
b. every particle in the first and last dump has mass rho V (D_REF/d)^2
   below D_REF and rho V above (1e-12): a scaled fragment has the Rayleigh
   time of a D_REF particle;
c. the log says scaling is on and how many grains it scaled, and the time
   step check uses the scaled mass (its T_R is that of D_REF);
d. a static packing (no gravity, platen held, damped to rest, then every
   velocity set to zero) has exactly the same contact forces, per grain and
   on the platen, with scaling switched on: at fixed positions a contact's
   force depends on the overlap, the radii and the relative velocity; mass
   enters only through the viscous damping of the Hertz contact, which is
   proportional to the relative velocity, zero here. The forces are compared
   to the last bit (the same contacts summed in the same order), not to a
   tolerance.
"""

import math
import re
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import crush_multi as cm  # noqa: E402
import harness  # noqa: E402
import test_crush_parallel as tcp  # noqa: E402  (mass/tag checks of the compressions)

D_REF = 1.0e-3
SCENE = dict(nx=4, ny=4, height=0.006, dmin=6e-4, dmax=1.2e-3, nsteps=24000, periodic=True,
             thermo=500, dump_every=24000, extra=f" density_scale {D_REF!r}")

_RUNS = {}


def _run(tmp_path_factory, nprocs):
    if nprocs not in _RUNS:
        workdir = tmp_path_factory.mktemp(f"density_scale_np{nprocs}")
        scene = cm.compression_scene(workdir, **SCENE)
        res = harness.run_deck(scene.deck, workdir, nprocs=nprocs, timeout=300,
                               extra_args=cm.MESH_ARGS, check=True)
        res.scene = scene
        res.events = cm.read_events(workdir / "events.txt")
        (res.blk,) = res.thermo
        _RUNS[nprocs] = res
    return _RUNS[nprocs]


def _scaled_mass(d, rho=cm.DENSITY):
    m = rho * math.pi / 6.0 * d ** 3
    return np.where(d < D_REF, m * (D_REF / d) ** 2, m)


@pytest.mark.parametrize("nprocs", [1, 2])
def test_true_mass_balance_with_scaling(tmp_path_factory, nprocs):
    res = _run(tmp_path_factory, nprocs)
    assert res.blk["crush[1]"][-1] >= 10, "too few breaks to test"
    tcp._check_counters(res)            # mass + fines == true initial mass, 1e-12


@pytest.mark.parametrize("nprocs", [1, 2])
def test_scaled_masses_give_the_reference_rayleigh_time(tmp_path_factory, nprocs):
    res = _run(tmp_path_factory, nprocs)
    for step in (0, SCENE["nsteps"]):
        (frame,) = harness.read_dump(res.path(f"dump.{step}.txt"))
        d = 2.0 * frame["radius"]
        np.testing.assert_allclose(frame["mass"], _scaled_mass(d), rtol=1e-12)
        fine = d < D_REF
        assert fine.any() and (~fine).any()
        rho_eff = frame["mass"][fine] / (math.pi / 6.0 * d[fine] ** 3)
        # T_R = pi r sqrt(rho / G) / (0.1631 nu + 0.8766): same G and nu, so
        # equal Rayleigh times mean equal r sqrt(rho)
        T_R = np.array([cm.rayleigh_time(0.5 * di, rho=ri) for di, ri in zip(d[fine], rho_eff)])
        np.testing.assert_allclose(T_R, cm.rayleigh_time(0.5 * D_REF), rtol=1e-12)
    gen = frame["f_crush[2]"]
    assert (gen[d < D_REF] >= 1).sum() > 100       # fragments among them


def test_log_reports_scaling_and_the_time_step_check(tmp_path_factory):
    res = _run(tmp_path_factory, 1)
    n_fine = int((res.scene.grains[:, 3] < D_REF).sum())
    m = re.search(r"density scaling on: particles finer than d = (\S+) .*?; (\d+) particles "
                  r"scaled now", res.log)
    assert m, res.summary()
    assert float(m.group(1)) == pytest.approx(D_REF) and int(m.group(2)) == n_fine
    # the smallest fragment that can occur is finer than D_REF: its scaled
    # Rayleigh time is that of a D_REF particle
    m = re.search(r"smallest radius that can occur (\S+), its Rayleigh time T_R (\S+),", res.log)
    assert m and float(m.group(1)) < 0.5 * D_REF
    assert float(m.group(2)) == pytest.approx(cm.rayleigh_time(0.5 * D_REF), rel=1e-5)


def _local_entries(path):
    """The rows of a `dump local` file (one frame) as a 2-D float array."""
    text = Path(path).read_text().split("ITEM: ENTRIES", 1)[1]
    return np.array([[float(w) for w in line.split()] for line in text.splitlines()[1:]
                     if line.strip()])


def test_static_packing_keeps_its_forces_exactly(tmp_path):
    """Unbreakable grains compressed (35 grain-grain contacts carry the
    platen's 4 kN), platen held, damped to rest, every velocity set to zero;
    then the forces of that state without and with scaling (run 0: computed
    at the same positions, not integrated). Every grain-grain contact force
    (compute pair/gran/local) must be the same to the
    last bit. (A first run 0 re-sorts the atoms, which LIGGGHTS does at the
    set-up of every run, and so changes the order of the platen's sum in the
    14th digit; the unscaled forces are those of a second one.) With the
    residual velocities of the damped packing left in, the contacts' viscous
    damping, which goes with the square root of the effective mass, makes
    contact forces differ in the 14th digit: the test fails."""
    # d_comm 2 mm: no fragment can occur, so the time step follows the grains
    scene = cm.compression_scene(tmp_path, nx=3, ny=3, height=0.005, dmin=6e-4, dmax=1.2e-3,
                                 nsteps=20000, speed=1.0, sigma_lim0=1e13, d_comm=2e-3,
                                 thermo=1000, alpha=0.3)
    crush_line = next(line for line in scene.deck.splitlines()
                      if line.startswith("fix crush all crush/particle"))
    # the compute must exist before the first run
    deck = scene.deck.replace("fix integ all nve\n",
                              "fix integ all nve\ncompute pgl all pair/gran/local id force\n")
    assert deck != scene.deck
    cols = " ".join("c_pgl[%d]" % k for k in range(1, 7))
    fmt = "modify format \"" + " ".join(["%.17g"] * 6) + "\""
    deck += f"""\
unfix mv
run 30000
velocity all set 0 0 0
run 0
run 0
write_dump all local contacts_unscaled.txt {cols} {fmt}
write_dump all custom masses_unscaled.txt id mass modify sort id format "%d %.17g"
{crush_line} density_scale {D_REF!r}
run 0
write_dump all local contacts_scaled.txt {cols} {fmt}
write_dump all custom masses_scaled.txt id mass modify sort id format "%d %.17g"
"""
    res = harness.run_deck(deck, tmp_path, nprocs=1, timeout=300, extra_args=cm.MESH_ARGS,
                           check=True)
    assert "particles scaled now" in res.log
    assert res.thermo[-1]["crush[1]"][-1] == 0                  # nothing broke
    # every grain-grain contact: ids, periodic flag, force vector, to the last bit
    # (the platen's force is not compared: a `run 0` prints a mesh's force at
    # the set-up row, where stock LIGGGHTS adds the set-up forces to the
    # previous total, docs/liggghts-patches.md)
    c0 = _local_entries(res.path("contacts_unscaled.txt"))
    c1 = _local_entries(res.path("contacts_scaled.txt"))
    assert c0.shape == c1.shape and c0.shape[0] >= 20, (c0.shape, c1.shape)
    # the packing carries load: the grain contacts' normal forces add up to kN
    assert np.abs(c0[:, -3:]).sum() > 1000.0, res.summary()
    np.testing.assert_array_equal(c1, c0)
    # while the masses did change: contacts of scaled grains carry load
    (m0,) = harness.read_dump(res.path("masses_unscaled.txt"))
    (m1,) = harness.read_dump(res.path("masses_scaled.txt"))
    scaled_ids = set(m1["id"][m1["mass"] > m0["mass"] * 1.01].astype(int))
    loaded = np.abs(c0[:, 3:6]).max(axis=1) > 1.0
    touches = [int(i) in scaled_ids or int(j) in scaled_ids for i, j in c0[loaded, :2]]
    assert sum(touches) >= 10, sum(touches)
