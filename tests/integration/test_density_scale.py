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
d. a static packing (no gravity, platen held, damped to rest) keeps its
   platen force when scaling is switched on: contact forces do not depend on
   mass.
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


def test_static_packing_keeps_its_stress(tmp_path):
    """Unbreakable grains compressed, platen held, damped to rest; then the
    same state runs on without and with scaling. The platen force must not
    move when the masses change: a packing at rest has no inertial forces."""
    # d_comm 2 mm: no fragment can occur, so the time step follows the grains
    scene = cm.compression_scene(tmp_path, nx=3, ny=3, height=0.005, dmin=6e-4, dmax=1.2e-3,
                                 nsteps=5000, speed=1.0, sigma_lim0=1e13, d_comm=2e-3,
                                 thermo=1000, alpha=0.3)
    crush_line = next(line for line in scene.deck.splitlines()
                      if line.startswith("fix crush all crush/particle"))
    deck = scene.deck + f"""\
unfix mv
run 30000
variable fz equal f_top[3]
variable fz0 equal ${{fz}}
run 3000
print "PLATEN unscaled ${{fz0}} ${{fz}}"
{crush_line} density_scale {D_REF!r}
run 3000
print "PLATEN scaled ${{fz}}"
"""
    res = harness.run_deck(deck, tmp_path, nprocs=1, timeout=300, extra_args=cm.MESH_ARGS,
                           check=True)
    a, b = map(float, re.search(r"PLATEN unscaled (\S+) (\S+)", res.log).groups())
    (c,) = map(float, re.search(r"PLATEN scaled (\S+)", res.log).groups())
    assert abs(a) > 1.0, res.summary()               # the packing carries load
    assert "particles scaled now" in res.log
    assert abs(b - a) <= 1e-4 * abs(a), (a, b)       # at rest
    assert abs(c - b) <= 1e-4 * abs(a), (a, b, c)    # scaling changes no contact force
