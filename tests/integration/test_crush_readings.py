# SPDX-License-Identifier: GPL-2.0-or-later
"""Deck tests of the criterion readings, the per-atom outputs and the fragment
velocities under density scaling of `fix crush/particle` / `compute crush/atom`.

Independent answers, computed here in Python:

a. Readings (docs/fix_crush_particle.md "Criterion readings"): one grain
   pressed between two platens (the "stack" scene of
   test_crush_single_grain.py) breaks at the F_lim of the reading:
   - pressure peak: 3 F / (2 pi a^2) >= sigma_lim, F_lim (2/3)^3;
   - force sliding: F_n sqrt(1 + mu^2) >= F_lim, mu of the grain-steel pair;
   - size_law no_N: sigma_lim of the scaled diameter with N = 1;
   - pressure peak with force sliding: the product of the two factors.
   The event's F_lim equals the Python value (1e-6) and the press is slow
   (a step adds less than 1e-3 to the force), so F_n at the break is within
   1e-3 above it, and the force on the
   platen within 1 %.
b. Utilisation: one grain held (not integrated) between two steel planes
   with overlaps that carry half of its limit force; compute crush/atom gives
   0.5 (printed reading) and 0.5 * 27/8 (peak pressure), to 1e-9; its other
   columns are the strength, the generation and the true mass. Under density
   scaling the true mass stays the sphere's mass while `mass` is scaled.
   The named grain models inputs/crushable_ne34.in, crushable_ne34_peak.in
   and crushable_ne34_peak_weibull.in on the same held grain: F_n over the
   F_lim of the grain's own drawn strength, the peak models' 27/8 times
   the printed one's at their own strengths (the Weibull model draws
   another); a crush_reading given with the peak model stops the run.
c. Atom-style variables of inputs/crushable_ne34.in: v_sigma_lim and
   v_generation are per particle (the fix's per-atom values, differing
   between grains), not the fix's global vector; the same in a dump, a VTK
   file and an HDF5 snapshot, after a break (fragments: generation 1,
   strength redrawn for their size).
d. Density scaling: the 14 fragments of a break move with the parent's
   velocity times sum(m_true) / sum(m_scaled) of the fragments, so their
   momentum is that of their true mass at the parent's velocity and their
   kinetic energy is below the parent's.
"""

import math
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import crush_decks as cd  # noqa: E402
import harness  # noqa: E402
import test_crush_single_grain as sg  # noqa: E402

PEAK = 8.0 / 27.0
SLIDING_STEEL = 1.0 / math.sqrt(1.0 + cd.FRICTION_GW ** 2)


class ReadingStack(sg.Stack):
    """The stack scene with the F_lim of a reading: factor k on every
    F_lim (grain-wall contacts only here) and, for size_law no_N, the
    strength of the scaled diameter with N = 1."""

    def __init__(self, name, d, k=1.0, no_N=False, **kw):
        self.k = k
        self.no_N = no_N
        super().__init__(name, d, **kw)

    def limits(self):
        if self.no_N:
            self.sigma = cd.strength(self.d, 1)
        return sorted((F * self.k, g, kind) for F, g, kind in super().limits())


READINGS = {
    "peak": (ReadingStack("peak", [1.0e-3], k=PEAK, speed=0.02, crush_extra="pressure peak"), "top"),
    "sliding": (ReadingStack("sliding", [1.0e-3], k=SLIDING_STEEL, speed=0.02, top=sg.T_STEEL, bottom=sg.T_STEEL,
                             crush_extra="force sliding"), None),
    "peak_sliding": (ReadingStack("peak_sliding", [1.0e-3], k=PEAK * SLIDING_STEEL, speed=0.02, top=sg.T_STEEL,
                                  bottom=sg.T_STEEL, crush_extra="pressure peak force sliding"), None),
    "no_N": (ReadingStack("no_N", [39 * cd.D50], N=39, no_N=True, speed=0.005, half=0.02,
                          crush_extra="size_law no_N"), "top"),
}


@pytest.mark.parametrize("name", sorted(READINGS))
def test_reading_breaks_at_its_limit(tmp_path_factory, name):
    case, kind = READINGS[name]
    res, events, frames = sg._run(tmp_path_factory, case, 1)
    assert len(events) == 1, events
    ev = events[0]
    F_lim, g, first_kind = case.limits()[0]
    assert ev.F_lim == pytest.approx(F_lim, rel=1e-6)
    assert 1.0 <= ev.F_n / F_lim < 1.001, (ev.F_n, F_lim)
    if kind is not None:                  # different walls: the critical one is known
        assert ev.partner == "wall" and first_kind == kind
    blk, row = sg._window(res)
    assert abs(blk["f_top[3]"][row[ev.step - 1]]) == pytest.approx(F_lim, rel=0.01)
    # the printed limit is not what broke it (the test can tell readings apart)
    printed = sg.Stack("printed", list(case.d), N=case.N).limits()[0][0]
    assert abs(F_lim / printed - 1.0) > 0.03


def test_readings_factors():
    """The factors the docs quote, from the formulas."""
    sigma, Rs, Es = 2.0e9, 3e-4, 2e10
    F = cd.limit_force(sigma, Rs, Es) * PEAK
    a = (3 * F * Rs / (4 * Es)) ** (1 / 3)
    assert 1.5 * F / (math.pi * a * a) == pytest.approx(sigma, rel=1e-12)   # peak pressure
    assert 1.0 / PEAK == pytest.approx(3.375, rel=1e-15)
    # size term at the scaled diameter without N: F_lim / 27 at N = 39, m = 10
    d = 39 * cd.D50
    ratio = (cd.limit_force(cd.strength(d, 1), Rs, Es) / cd.limit_force(cd.strength(d, 39), Rs, Es))
    assert ratio == pytest.approx(39 ** -0.9, rel=1e-12)
    assert 1 / ratio == pytest.approx(27.0, rel=0.03)


# ---------------------------------------------------------------------------
# b. utilisation
# ---------------------------------------------------------------------------

D_HELD = 1.0e-3
D_SMALL = 0.5e-3     # a second grain beside it, touching nothing


def _held_deck(fraction, extra, N=1, grain_block=None):
    """One grain held between two steel planes with the overlap of `fraction`
    of its mean-strength limit force, a second grain touching nothing; fix
    crush/particle as crush_fix(extra) writes it, or, with `grain_block`, as
    that block of inputs/ defines it (its own calibrated values and scatter)."""
    r = D_HELD / 2
    sigma = float(cd.strength(D_HELD, N))
    es = cd.effective_modulus(cd.E_GRAIN, cd.NU_GRAIN, cd.E_STEEL, cd.NU_STEEL)
    delta = cd.hertz_overlap(fraction * cd.limit_force(sigma, r, es), r, es)
    text = cd.header("-0.003 0.003 -0.003 0.003 -0.001 0.003", [sg.GRAIN, sg.STEEL])
    text += f"""\
timestep 1e-9
create_atoms 1 single 0 0 {r - delta!r} units box
create_atoms 1 single 0.0015 0 {0.5 * D_SMALL + 1e-5!r} units box
set atom 1 diameter {D_HELD!r} density {cd.DENSITY!r}
set atom 2 diameter {D_SMALL!r} density {cd.DENSITY!r}
fix bottom all wall/gran model hertz tangential history primitive type 2 zplane 0.0
fix top all wall/gran model hertz tangential history primitive type 2 zplane {D_HELD - 2 * delta!r}
"""
    if grain_block is None:
        text += cd.crush_fix(scale=N, var=0.0, d_comm=1e-4, extra=extra)
    else:
        text += (f"variable inputs index {harness.REPO / 'inputs'}\nvariable N index {N}\n"
                 f"variable seed index {cd.SEED}\nvariable crush_events index events.txt\n"
                 f"{extra or ''}include ${{inputs}}/{grain_block}.in\n")
    text += """\
compute ca all crush/atom crush
dump d all custom 1 held.txt id mass c_ca[1] c_ca[2] c_ca[3] c_ca[4]
dump_modify d format "%d %.17g %.17g %.17g %.17g %.17g" sort id
thermo_style custom step atoms
thermo_modify lost error
run 0
"""
    return text


@pytest.mark.parametrize("extra, expect_factor", [("", 1.0), ("pressure peak", 1.0 / PEAK),
                                                  ("density_scale 0.002", 1.0)])
def test_utilisation_of_a_grain_at_half_its_limit(tmp_path, extra, expect_factor):
    res = cd.run(_held_deck(0.5, extra), tmp_path)
    (frame,) = harness.read_dump(res.path("held.txt"))
    held, free = 0, 1                   # sorted by id: 1 held, 2 free (no contact)
    assert frame["c_ca[4]"][held] == pytest.approx(0.5 * expect_factor, rel=1e-9)
    assert frame["c_ca[4]"][free] == 0.0
    d = np.array([D_HELD, D_SMALL])
    np.testing.assert_allclose(frame["c_ca[1]"], cd.strength(d, 1), rtol=1e-12)
    np.testing.assert_array_equal(frame["c_ca[2]"], 0.0)
    m_true = cd.sphere_mass(d / 2)
    np.testing.assert_allclose(frame["c_ca[3]"], m_true, rtol=1e-12)
    if "density_scale" in extra:        # scaled by (2 mm / d)^2
        np.testing.assert_allclose(frame["mass"], (2e-3 / d) ** 2 * m_true, rtol=1e-12)
    else:
        np.testing.assert_allclose(frame["mass"], m_true, rtol=1e-12)


def test_named_grain_models_read_the_criterion_they_name(tmp_path):
    """inputs/crushable_ne34.in, crushable_ne34_peak.in and
    crushable_ne34_peak_weibull.in on the same held grain (same seed: the
    same strength drawn by the same law): utilisation F_n / F_lim of the
    grain's own strength, the peak model's 3.375 times the printed one's;
    the Weibull model's strength is another draw."""
    u, sigma = {}, {}
    for model, k in (("crushable_ne34", 1.0), ("crushable_ne34_peak", PEAK),
                      ("crushable_ne34_peak_weibull", PEAK)):
        res = cd.run(_held_deck(0.01, None, grain_block=model), tmp_path / model)
        (frame,) = harness.read_dump(res.path("held.txt"))
        sigma_own = frame["c_ca[1]"][0]
        es = cd.effective_modulus(cd.E_GRAIN, cd.NU_GRAIN, cd.E_STEEL, cd.NU_STEEL)
        r = D_HELD / 2
        F_n = 0.01 * cd.limit_force(float(cd.strength(D_HELD, 1)), r, es)
        assert frame["c_ca[4]"][0] == pytest.approx(F_n / (k * cd.limit_force(sigma_own, r, es)),
                                                    rel=1e-9)
        u[model] = frame["c_ca[4]"][0]
        sigma[model] = sigma_own
    assert u["crushable_ne34_peak"] / u["crushable_ne34"] == pytest.approx(1.0 / PEAK, rel=1e-12)
    # the same seed and law draw the same strength; the Weibull law another
    assert sigma["crushable_ne34_peak"] == sigma["crushable_ne34"]
    assert sigma["crushable_ne34_peak_weibull"] != pytest.approx(sigma["crushable_ne34"], rel=1e-6)


def test_named_grain_model_refuses_a_reading_of_its_own(tmp_path):
    # the block sets crush_reading itself; a user's -var (an index variable)
    # stops the run instead of being obeyed or ignored silently
    deck = _held_deck(0.01, 'variable crush_reading index "scatter weibull"\n',
                      grain_block="crushable_ne34_peak")
    cd.expect_error(deck, tmp_path, "Cannot redefine variable as a different style")


# ---------------------------------------------------------------------------
# c. the decks' atom variables, in a dump, a VTK file and a snapshot
# ---------------------------------------------------------------------------

def test_deck_variables_are_per_particle(tmp_path):
    """Four 2 mm grains, var 0.36: four different strengths; one is pressed
    by a platen until it breaks. The decks' v_sigma_lim, v_generation,
    v_mass_true equal the fix's per-atom array in a text dump, a VTK dump and
    an HDF5 snapshot after the break."""
    vtk = pytest.importorskip("vtk")
    from vtk.util.numpy_support import vtk_to_numpy
    inputs = harness.REPO / "inputs"
    d = 2.0e-3
    case = sg.Stack("vars", [d], N=1, top=sg.T_STEEL, bottom=sg.T_STEEL, speed=0.2, half=0.01)
    box = "-0.01 0.01 -0.01 0.01 -0.001 %r" % (case.z_top0 + 0.001)
    text = cd.header(box, [sg.GRAIN, sg.STEEL, sg.OTHER])
    text += f"timestep {case.dt!r}\n"
    text += f"create_atoms 1 single 0 0 {case.r[0]!r} units box\n"
    for x in (-0.006, 0.004, 0.007):    # beside the platen: never loaded
        text += f"create_atoms 1 single {x!r} 0.005 {case.r[0]!r} units box\n"
    text += f"set atom * diameter {d!r} density {cd.DENSITY!r}\n"
    text += f"""\
fix top all mesh/surface/stress file plate.stl type 2 move 0 0 {case.z_top0!r}
fix walls all wall/gran model hertz tangential history mesh n_meshes 1 meshes top
fix bottom all wall/gran model hertz tangential history primitive type 2 zplane 0.0
fix mv all move/mesh mesh top linear 0. 0. {-case.speed!r}
fix integ all nve
variable N index 1
variable seed index {cd.SEED}
variable crush_events index events.txt
variable d_comm_ratio index 2.0
include {inputs}/crushable_ne34.in
thermo_style custom step atoms f_crush[1]
thermo_modify lost error
thermo 100
run {case.step_pred + 200}
dump t all custom 1 vars.txt id f_crush[1] f_crush[2] v_sigma_lim v_generation v_mass_true c_crush_atom[3] mass
dump_modify t format "%d %.17g %.17g %.17g %.17g %.17g %.17g %.17g" sort id
dump v all custom/vtk 1 vars_*.vtk id radius v_sigma_lim v_generation v_mass_true v_utilisation
variable one equal step<{case.step_pred + 201}
fix snap all snapshot/hdf5 file snap trigger v_one values v_sigma_lim v_generation v_mass_true
run 2
"""
    # d_comm_ratio 2 with N = 1: d_comm = 0.42 mm < 2 mm (grains break, and
    # fragments of 0.83 mm and 0.46 mm may break too)
    res = cd.run(text, tmp_path, files={"plate.stl": lambda p: cd.write_plate_stl(p, half=0.004)})
    events = cd.read_events(res.path("events.txt"))
    assert len(events) >= 1
    frames = harness.read_dump(res.path("vars.txt"))
    f = frames[-1]
    assert len(f) >= 4 + 13
    np.testing.assert_array_equal(f["v_sigma_lim"], f["f_crush[1]"])
    np.testing.assert_array_equal(f["v_generation"], f["f_crush[2]"])
    np.testing.assert_allclose(f["v_mass_true"], cd.sphere_mass(np.cbrt(f["mass"] / cd.sphere_mass(1.0))),
                               rtol=1e-12)
    assert len(set(f["v_sigma_lim"][:4])) >= 3         # the scatter, per grain
    frag = f["id"] > 4
    assert np.all(f["v_generation"][frag] >= 1) and np.all(f["v_generation"][~frag] == 0)
    # fragments' strengths are those of their size (redrawn, per tag)
    r_frag = np.cbrt(f["mass"][frag] / cd.sphere_mass(1.0))
    f_draw = f["v_sigma_lim"][frag] / cd.strength(2 * r_frag, 1)
    assert np.all(f_draw > 0) and len(set(np.round(f_draw, 12))) > 5
    # the VTK file of the last step
    vfiles = sorted(Path(res.path(".")).glob("vars_[0-9]*.vtk"), key=lambda p: int(p.stem.split("_")[1]))
    reader = vtk.vtkPolyDataReader() if "POLYDATA" in vfiles[-1].read_text(errors="ignore")[:300] \
        else vtk.vtkUnstructuredGridReader()
    reader.SetFileName(str(vfiles[-1]))
    reader.ReadAllScalarsOn()
    reader.ReadAllVectorsOn()
    reader.Update()
    pd = reader.GetOutput().GetPointData()
    ids = vtk_to_numpy(pd.GetArray("id")).astype(int)
    order = np.argsort(ids)
    by_id = {int(i): k for k, i in enumerate(f["id"].astype(int))}
    rows = [by_id[int(i)] for i in ids[order]]
    np.testing.assert_allclose(vtk_to_numpy(pd.GetArray("sigma_lim"))[order], f["v_sigma_lim"][rows], rtol=1e-6)
    np.testing.assert_array_equal(vtk_to_numpy(pd.GetArray("generation"))[order], f["v_generation"][rows])
    # the HDF5 snapshot (written at the step the trigger leaves 1 -> 0)
    snaps = sorted(Path(res.path(".")).glob("snap_*.h5"))
    assert snaps, "no snapshot written"
    from crushpost.snapshot import read_snapshot
    snap = read_snapshot(str(snaps[-1]))["particles"]
    srow = [by_id[int(i)] for i in snap["id"]]
    np.testing.assert_array_equal(np.ravel(snap["values"]["v_sigma_lim"]), f["v_sigma_lim"][srow])
    np.testing.assert_array_equal(np.ravel(snap["values"]["v_generation"]), f["v_generation"][srow])


# ---------------------------------------------------------------------------
# d. fragment velocities under density scaling
# ---------------------------------------------------------------------------

D_REF = 1.0e-3      # every fragment of the 1 mm grain is scaled


def test_fragments_keep_true_momentum_under_density_scaling(tmp_path_factory):
    case = sg.Stack("scaled", [1.0e-3], N=1, top=sg.T_STEEL, bottom=sg.T_OTHER,
                    crush_extra=f"density_scale {D_REF!r}")
    res, events, frames = sg._run(tmp_path_factory, case, 1)
    assert len(events) == 1, events
    ev = events[0]
    before, after = frames[ev.step - 1], frames[ev.step]
    _, vp_all = sg._pre_exchange_state(before, case.dt)
    vp = vp_all[0]
    assert np.linalg.norm(vp) > 1e-5                       # the parent moves
    frag = after["id"] > 1
    r = after["radius"][frag]
    m_true = cd.sphere_mass(r)
    m_scaled = m_true * (D_REF / (2 * r)) ** 2
    np.testing.assert_allclose(after["mass"][frag], m_scaled, rtol=1e-12)
    factor = m_true.sum() / m_scaled.sum()
    assert factor < 0.2                                    # a strong test: far from 1
    vf = np.column_stack([after["vx"], after["vy"], after["vz"]])[frag] \
        - 0.5 * case.dt * np.column_stack([after["fx"], after["fy"], after["fz"]])[frag] / m_scaled[:, None]
    np.testing.assert_allclose(vf, np.tile(factor * vp, (14, 1)), rtol=0, atol=1e-9 * np.linalg.norm(vp))
    # momentum: that of the true fragment mass at the parent's velocity
    np.testing.assert_allclose((m_scaled[:, None] * vf).sum(axis=0), m_true.sum() * vp,
                               rtol=0, atol=1e-9 * m_true.sum() * np.linalg.norm(vp))
    # kinetic energy: below that of the unscaled fragments, and of the parent
    ke_frag = 0.5 * np.sum(m_scaled * np.sum(vf ** 2, axis=1))
    ke_parent = 0.5 * cd.sphere_mass(case.r[0]) * vp @ vp
    assert ke_frag <= 0.5 * m_true.sum() * (vp @ vp) * (1 + 1e-9)
    assert ke_frag < ke_parent
