# SPDX-License-Identifier: GPL-2.0-or-later
"""The oedometer scene (examples/oedometer, docs/model.md §4.2) end to end,
in a small cell: radius 3.5 d50, height 6 d50 (about 370 grains at N = 39),
a short preparation (15 radius-expansion chunks), loading to 5 MPa, unloading.
The driver examples/oedometer/run.py runs exactly as a user runs it, twice:
crushable NE34 grains on 1 MPI rank and unbreakable grains on 2 ranks.

a. The platen follows its command.  z_top in the thermo output moves at
   exactly the commanded speed (down while loading, up while unloading,
   continuous at the reversal; checked against the log's Time column), and
   the grains really touch a platen there: in every particle dump taken while
   sigma_v > 0.5 MPa the highest grain surface max(z + r) lies within
   [0, 0.08 d50] above z_top (the overlap with the platen: a platen moving at
   another speed would leave the grains' top elsewhere), and the lowest
   min(z - r) within 0.08 d50 below the fixed bottom platen at z = 0.
   sigma_v rises on loading (rank correlation with time > 0.9 once it stays
   above 50 kPa; the peak among the last loading samples, the last one
   >= sv_max) and
   falls on unloading (every sample below the peak, rank correlation with
   time < -0.9, ending below sv_end * sv_max).
b. The void ratio falls monotonically on loading, and it is what it claims
   to be: e = A z_top / (V_grains + V_fines) - 1 from the printed columns,
   and V_grains equals sum(4/3 pi r^3) of the particle dumps (to the dumps'
   6 printed digits).
c. Br is exactly zero without crushing (and no event, no fines, constant
   atom count); with crushing Br rises at every breakage and stays put (to
   round-off) between them, is > 0 at the end and
   larger at the peak stress than when sigma_v first passes 1 MPa, the atom
   count grows by exactly 13 per event, and the events file lists every
   event.
   Crushing begins where the calibration study found it for this cell
   (docs/studies/calibration.md, bench/calibration/results/oedsmall_crush_s*.json,
   six packing seeds): 1 % of the grains broken once sigma_v has reached
   0.3-5 MPa (study: 0.46-4.2 MPa), 1-4.5 % broken by 5 MPa (study:
   1.45-2.6 %).
d. Mass balance: V_grains + fines / rho is constant over loading and
   unloading to 1e-10 relative (the deck prints thermo floats with 15
   significant digits), while V_grains alone changes by far more.
e. Outputs: oedometer.h5 holds the path and PSD datasets, summary.json the
   advertised keys with values that agree with the path, and the PNGs exist.

Measured on 2 cores shared with other jobs: 40 s at a load average of about 4,
85 s at about 8 (25-45 s of CPU time); the 2-rank run slows down most when
other jobs compete for the cores.
"""

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import harness  # noqa: E402

from crushpost.materials import D50 as D50_1, RHO_GRAIN  # noqa: E402
from crushpost.oedometer import stress_path  # noqa: E402
from crushpost.prep import core_area, core_volumes  # noqa: E402

CTEST_TIMEOUT = 1900   # ctest's budget: the crushable and the unbreakable runs (RUN_TIMEOUT each)

RUN_PY = harness.REPO / "examples" / "oedometer" / "run.py"
RHO = RHO_GRAIN
N = 39.0
D50 = D50_1 * N
R_D50, H_D50 = 3.5, 6.0
R_CELL, H_CELL = R_D50 * D50, H_D50 * D50
A_CELL = math.pi * R_CELL ** 2
V_LOAD = 1.25          # m/s: neither the deck's nor run.py's default
# core porosity of the preparation: this cell's core (farther than d50 from
# the walls) is 2.5 d50 by 4 d50, all of it near a wall, where the packing
# cannot be made as dense as NE34's 0.385 (docs/preparation.md)
N_TARGET = 0.40
SV_MAX = 5e6
SV_END = 0.05          # the deck's default: unload until sv < SV_END * SV_MAX
DUMP_EVERY = 1000       # the prepared (dense) sample reaches 5 MPa within about 10,000 steps
OPTIONS = ["--N", str(N), "--R-d50", str(R_D50), "--H-d50", str(H_D50),
           "--n-target", str(N_TARGET), "--sv-max", str(SV_MAX), "--v-load", str(V_LOAD),
           "--thermo-every", "250", "--dump-every", str(DUMP_EVERY)]
RUN_TIMEOUT = 900

SUMMARY_KEYS = {"grains", "N", "n_particles_initial", "n_particles_final",
                "porosity_start_of_loading", "e_start", "e_min", "e_end",
                "sigma_v_max_MPa", "n_break_events", "Br_final", "fines_mass",
                "wall_time_s", "mpi_ranks", "plots"}
PATH_KEYS = {"Step", "Time", "Atoms", "z_top", "sv", "e_void", "e_core", "n_break",
             "fines", "Br", "phase"}
PSD_KEYS = {"sizes", "steps", "sv", "F"}


class Run:
    """One run of examples/oedometer/run.py and what it wrote."""

    def __init__(self, out, grains, nprocs):
        self.out = Path(out)
        self.grains = grains
        self.nprocs = nprocs
        cmd = [sys.executable, str(RUN_PY), "--out", str(self.out), "--np", str(nprocs),
               "--grains", grains, "--liggghts", str(harness.liggghts_bin())] + OPTIONS
        env = harness._child_env()
        proc = subprocess.run(cmd, env=env, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                              stderr=subprocess.STDOUT, universal_newlines=True,
                              errors="replace", timeout=RUN_TIMEOUT)
        log = self.out / "log.liggghts"
        self.log_text = log.read_text(errors="replace") if log.exists() else ""
        if proc.returncode != 0:
            raise harness.DeckError("run.py failed (%d)\n%s\n--- log tail ---\n%s" % (
                proc.returncode, proc.stdout[-3000:], "\n".join(self.log_text.splitlines()[-40:])))
        self.path = stress_path(str(log))
        self.load = self.path["phase"] == 0
        # V_grains is not kept in the path: take it from the same thermo blocks
        steps, vg = [], []
        for b in harness.parse_thermo(self.log_text):
            if "z_top" in b and "V_grains" in b:
                steps.append(b["Step"])
                vg.append(b["V_grains"])
        steps, vg = np.concatenate(steps), np.concatenate(vg)
        _, first = np.unique(steps, return_index=True)
        by_step = dict(zip(steps[first], vg[first]))
        self.V_grains = np.array([by_step[s] for s in self.path["Step"]])
        self.path["V_grains"] = self.V_grains
        with open(self.out / "summary.json") as f:
            self.summary = json.load(f)

    def dumps(self):
        return harness.read_dumps(self.out, "dump.grains.*.txt")

    def at_step(self, name, step):
        k = np.flatnonzero(self.path["Step"] == step)
        assert k.size == 1, "step %d not in the thermo output" % step
        return self.path[name][k[0]]


@pytest.fixture(scope="module")
def crushable(tmp_path_factory):
    return Run(tmp_path_factory.mktemp("oedo_crushable"), "crushable_ne34", 1)


@pytest.fixture(scope="module")
def unbreakable(tmp_path_factory):
    return Run(tmp_path_factory.mktemp("oedo_unbreakable"), "unbreakable", 2)


@pytest.fixture(params=["crushable", "unbreakable"])
def run(request):
    return request.getfixturevalue(request.param)


def stays_above(sv, level):
    """Index from which sv stays above level (the loose start can be dynamic)."""
    below = np.flatnonzero(sv <= level)
    return 0 if below.size == 0 else below[-1] + 1


# ---------------------------------------------------------------- a. platen

def test_platen_moves_at_the_commanded_speed(run):
    p = run.path
    t, z = p["Time"], p["z_top"]
    load, unload = run.load, ~run.load
    assert load.sum() > 20 and unload.sum() > 5, (load.sum(), unload.sum())
    assert np.all(np.diff(p["Step"]) > 0)
    # loading starts at the cell height and descends at -V_LOAD
    assert z[0] == pytest.approx(H_CELL, rel=1e-12)
    tl, zl = t[load], z[load]
    np.testing.assert_allclose(zl, H_CELL - V_LOAD * (tl - tl[0]), rtol=0, atol=1e-12)
    np.testing.assert_allclose(np.diff(zl) / np.diff(tl), -V_LOAD, rtol=1e-8)
    # unloading: rises at +V_LOAD from where loading stopped (the reversal
    # happens at the end of a chunk, i.e. at the last loading sample)
    tu, zu = t[unload], z[unload]
    np.testing.assert_allclose(zu, zl[-1] + V_LOAD * (tu - tl[-1]), rtol=0, atol=1e-12)
    np.testing.assert_allclose(np.diff(zu) / np.diff(tu), V_LOAD, rtol=1e-8)


def test_grains_touch_the_platen_where_it_is_commanded(run):
    checked = 0
    for fr in run.dumps():
        step = fr.timestep
        if step not in run.path["Step"] or run.at_step("sv", step) < 0.5e6:
            continue
        z, r = fr["z"], fr["radius"]
        z_top = run.at_step("z_top", step)
        above = np.max(z + r) - z_top      # overlap with the top platen
        below = np.min(z - r)              # overlap with the bottom platen (z = 0)
        # (dumps print 6 significant digits: 1e-6 m of slack for rounding)
        assert -1e-6 < above < 0.08 * D50, (step, above / D50)
        assert -0.08 * D50 < below < 1e-6, (step, below / D50)
        # radial: inside the frictionless cylinder, to an overlap
        assert np.max(np.hypot(fr["x"], fr["y"]) + r) < R_CELL + 0.08 * D50
        checked += 1
    assert checked >= 5, checked


def test_vertical_stress_rises_on_loading_and_falls_on_unloading(run):
    from scipy.stats import spearmanr
    sv = run.path["sv"]
    svl, svu = sv[run.load], sv[~run.load]
    k0 = stays_above(svl, 50e3)
    assert len(svl) - k0 > 10, "sigma_v never settled above 50 kPa"
    rho, _ = spearmanr(np.arange(len(svl) - k0), svl[k0:])
    assert rho > 0.9, rho
    # loading stops at the first chunk end past sv_max; a breakage can take a
    # little off the stress just before, so the peak is among the last samples
    assert svl[-1] >= SV_MAX, svl[-1]
    assert np.argmax(svl) >= len(svl) - max(3, (len(svl) - k0) // 10), (np.argmax(svl), len(svl))
    # unloading: the stress falls (the abrupt reversal of the platen makes
    # the first few samples bounce by ~10 % of sv_max, hence a rank test)
    assert svu.max() < svl[-1], (svu.max(), svl[-1])
    rho, _ = spearmanr(np.arange(len(svu)), svu)
    assert rho < -0.9, rho
    assert svu[-1] < SV_END * SV_MAX


# ---------------------------------------------------------------- b. void ratio

def test_void_ratio_falls_on_loading(run):
    p = run.path
    e = p["e_void"][run.load]
    k0 = stays_above(p["sv"][run.load], 50e3)
    de = np.diff(e[k0:])
    assert np.all(de <= 1e-12), de.max()
    assert e[k0] - e[-1] > 0.02, (e[k0], e[-1])
    # and rebounds (slightly) on unloading
    assert p["e_void"][-1] > e[-1]


def test_void_ratio_is_the_cell_volume_over_the_solid_volume(run):
    p = run.path
    solid = run.V_grains + p["fines"] / RHO
    np.testing.assert_allclose(p["e_void"], A_CELL * p["z_top"] / solid - 1.0, rtol=1e-12)
    checked = 0
    for fr in run.dumps():
        if fr.timestep not in p["Step"]:
            continue
        v_dump = np.sum(4.0 / 3.0 * math.pi * fr["radius"] ** 3)
        assert v_dump == pytest.approx(run.at_step("V_grains", fr.timestep), rel=2e-5)
        checked += 1
    assert checked >= 5, checked


def test_core_void_ratio_is_that_of_the_grains_inside_the_core(run):
    """e_core of the deck (inputs/core_cylinder.in with the platen as the
    core's top) against exact sphere/cylinder volumes of the dumped grains
    (crushpost.prep.core_volumes), fines spread by volume as the deck does;
    it starts at the preparation's core porosity and stays below e_void (the
    loose fringe at the walls is outside the core)."""
    p = run.path
    area_core = core_area(R_CELL, D50, 360)
    checked, worst = 0, 0.0
    for fr in run.dumps():
        step = fr.timestep
        if step not in p["Step"]:
            continue
        z_top, fines = run.at_step("z_top", step), run.at_step("fines", step)
        V_core, V_sample = area_core * (z_top - 2 * D50), A_CELL * z_top
        c = np.column_stack([fr["x"], fr["y"], fr["z"]])
        vcg = np.sum(core_volumes(c, fr["radius"], R_CELL, z_top, D50))
        e_exact = V_core / (vcg + fines / RHO * V_core / V_sample) - 1.0
        worst = max(worst, abs(run.at_step("e_core", step) - e_exact))
        checked += 1
    assert checked >= 5, checked
    # the block's cut of a sphere by the core's curved side is approximate
    # (inputs/core_cylinder.in), dumps carry 6 digits
    assert worst < 1e-3, worst
    n0 = run.summary["prep"]["porosity_core"]
    assert p["e_core"][0] == pytest.approx(n0 / (1 - n0), abs=1e-9)
    assert np.all(p["e_core"] < p["e_void"])
    assert run.summary["e_core_start"] == p["e_core"][0]

# ---------------------------------------------------------------- c. breakage index

def test_no_breakage_without_crushing(unbreakable):
    p = unbreakable.path
    assert np.all(p["Br"] == 0.0)
    assert np.all(p["n_break"] == 0.0) and np.all(p["fines"] == 0.0)
    assert np.all(p["Atoms"] == p["Atoms"][0])
    assert p["Atoms"][0] == unbreakable.summary["n_particles_initial"]
    np.testing.assert_allclose(unbreakable.V_grains, unbreakable.V_grains[0], rtol=1e-14)
    assert unbreakable.summary["Br_final"] == 0.0
    assert unbreakable.summary["n_break_events"] == 0


def test_breakage_grows_with_stress(crushable):
    p = crushable.path
    br, sv, nb = p["Br"], p["sv"], p["n_break"]
    assert np.all(np.diff(nb) >= 0.0)
    # Br only moves at a breakage (round-off aside: it is re-summed every output)
    dbr, dnb = np.diff(br), np.diff(nb)
    assert np.all(dbr >= -1e-12), "Br decreased"
    assert np.all(np.abs(dbr[dnb == 0]) <= 1e-12)
    assert np.all(dbr[dnb > 0] > 0.0)
    assert br[-1] > 0.0 and nb[-1] > 0
    load = crushable.load
    k1 = np.flatnonzero(load & (sv >= 1e6))[0]
    k_peak = np.flatnonzero(load)[-1]
    assert br[k_peak] > br[k1], (br[k1], br[k_peak])
    # no breakage on unloading below the peak (the strongest loading is over);
    # Br the same to round-off (its size bins are re-summed at every output,
    # in the particles' current order)
    assert nb[-1] == nb[k_peak]
    assert br[-1] == pytest.approx(br[k_peak], rel=0, abs=1e-12)
    # 14 fragments replace each parent (no fragment goes to fines here)
    np.testing.assert_array_equal(p["Atoms"] - p["Atoms"][0], 13 * nb)
    events = [l for l in (crushable.out / "breakage_events.txt").read_text().splitlines()
              if l.strip() and not l.startswith("#")]
    assert len(events) == int(nb[-1])


# crushing onset of this cell (bench/calibration/results/oedsmall_crush_s*.json:
# six packing seeds of the same options at 1 rank). 1 % of the grains have
# broken once sigma_v (largest so far) reaches 0.46-4.2 MPa, and 1.45-2.6 %
# of them by the end of loading at 5 MPa. The bands below widen those ranges
# a little (the 1.45-2.6 % are read from the study's thinned paths).
# Measured on seed 2024 with the grain strength changed: half sigma_lim0
# breaks 12 % of the grains by 5 MPa, four times sigma_lim0 only 0.6 %
# (1 % never reached): both fail; twice sigma_lim0 (1.1 %, onset at
# 3.6 MPa) is within the seed scatter of this small cell and passes.
ONSET_1PCT_BAND = (0.3e6, SV_MAX)
BROKEN_AT_SV_MAX_BAND = (0.010, 0.045)


def test_crushing_begins_in_the_range_of_the_study(crushable):
    from crushpost.oedometer import crushing_onset
    p = crushable.path
    n0 = int(p["Atoms"][0])
    onset, _ = crushing_onset(p, n0, 0.01)
    assert ONSET_1PCT_BAND[0] <= onset <= ONSET_1PCT_BAND[1], onset
    k_peak = np.flatnonzero(crushable.load)[-1]
    broken = p["n_break"][k_peak] / n0
    assert BROKEN_AT_SV_MAX_BAND[0] <= broken <= BROKEN_AT_SV_MAX_BAND[1], broken


# ---------------------------------------------------------------- d. mass balance

def test_solid_volume_is_conserved(run):
    p = run.path
    solid = run.V_grains + p["fines"] / RHO
    rel = np.abs(solid / solid[0] - 1.0)
    assert rel.max() < 1e-10, rel.max()


def test_mass_balance_check_sees_breakage(crushable):
    # the balance above is not trivial: the grains lost a measurable volume to fines
    vg = crushable.V_grains
    assert 1.0 - vg[-1] / vg[0] > 1e-3, 1.0 - vg[-1] / vg[0]


# ---------------------------------------------------------------- e. outputs

def test_hdf5_and_summary(run):
    h5py = pytest.importorskip("h5py")
    s = run.summary
    assert SUMMARY_KEYS <= set(s), SUMMARY_KEYS - set(s)
    with h5py.File(run.out / "oedometer.h5", "r") as h:
        assert PATH_KEYS <= set(h["path"]), PATH_KEYS - set(h["path"])
        assert PSD_KEYS <= set(h["psd"]), PSD_KEYS - set(h["psd"])
        n = len(h["path/Step"])
        for k in PATH_KEYS:
            assert h["path"][k].shape == (n,), k
        np.testing.assert_array_equal(h["path/sv"][()], run.path["sv"])
        np.testing.assert_array_equal(h["path/phase"][()], run.path["phase"])
        sizes, F = h["psd/sizes"][()], h["psd/F"][()]
        assert F.ndim == 2 and F.shape[1] == sizes.size and F.shape[0] == len(h["psd/steps"])
        assert F.shape[0] >= 3
        assert np.all(np.diff(sizes) > 0)
        assert np.all((F >= 0) & (F <= 1 + 1e-12))
        assert np.all(np.diff(F, axis=1) >= -1e-12), "grading not cumulative"
        assert np.all(np.diff(h["psd/sv"][()]) > 0), "PSD snapshots not ordered by stress"
        for k in ("grains", "N", "n_break_events", "Br_final", "e_start"):
            assert k in h.attrs, k
    p = run.path
    assert s["grains"] == run.grains and s["mpi_ranks"] == run.nprocs and s["N"] == N
    assert s["n_particles_final"] == int(p["Atoms"][-1])
    assert s["e_start"] == pytest.approx(p["e_void"][0], rel=1e-12)
    assert s["e_end"] == pytest.approx(p["e_void"][-1], rel=1e-12)
    assert s["e_min"] == pytest.approx(p["e_void"].min(), rel=1e-12)
    assert s["porosity_start_of_loading"] == pytest.approx(s["e_start"] / (1 + s["e_start"]))
    assert s["sigma_v_max_MPa"] == pytest.approx(p["sv"][run.load].max() / 1e6, rel=1e-12)
    assert s["sigma_v_max_MPa"] >= SV_MAX / 1e6
    assert s["n_break_events"] == int(p["n_break"][-1])
    assert s["Br_final"] == pytest.approx(p["Br"][-1], rel=1e-12, abs=0)
    assert s["wall_time_s"] > 0
    for png in ("e_log_sigma_v.png", "Br_sigma_v.png", "psd.png"):
        assert png in s["plots"]
        data = (run.out / png).read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 5000, png


def test_sample_starts_at_the_target_core_porosity(run):
    """The preparation (inputs/prepare_expand.in) reached the core porosity
    N_TARGET at 5 kPa and said so; summary.json reports it with the
    coordination number; the whole cell (walls included) is looser."""
    assert "EXPANDED porosity_core" in run.log_text
    prep = run.summary["prep"]
    assert abs(prep["porosity_core"] - N_TARGET) <= 0.005, prep
    assert abs(prep["p_static"] / 5e3 - 1) <= 0.1, prep
    assert prep["porosity_all"] > prep["porosity_core"]
    assert 1.0 < prep["coordination"] < 6.0
