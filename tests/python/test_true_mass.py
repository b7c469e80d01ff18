# SPDX-License-Identifier: GPL-2.0-or-later
"""True mass under density scaling (issue: "True mass everywhere").

The same grains give the same Br (crushpost br) and the same grading curves
(crushpost.oedometer.psd_snapshots) whether the dump's `mass` column is
scaled by fix crush/particle density_scale or not: the tools take the grains'
true mass from the true-mass column (v_mass_true) or from the radius, never
from `mass`. Synthetic data: one 0.2 mm grain of four broken into its 14
Apollonian fragments; density scaling with d_ref = 0.2 mm raises every
fragment's mass by (d_ref / d)^2 (5.8 and 18.9 times).
"""

import json

import numpy as np
import pytest

from crushpost.cli import main
from crushpost.dump import true_mass
from crushpost.materials import RHO_GRAIN
from crushpost.oedometer import psd_snapshots

RHO = RHO_GRAIN
R = 0.1e-3
R1, R2 = R / (1 + np.sqrt(2)), 0.230093 * R
D_REF = 2 * R


def _write(path, snaps, scaled, true_column=True):
    with open(path, "w") as fh:
        for step, radii in snaps:
            radii = np.asarray(radii)
            m_true = RHO * 4.0 / 3.0 * np.pi * radii ** 3
            m = m_true * np.where(2 * radii < D_REF, (D_REF / (2 * radii)) ** 2, 1.0) if scaled else m_true
            cols = "id type x y z radius mass" + (" v_mass_true" if true_column else "")
            fh.write("ITEM: TIMESTEP\n%d\nITEM: NUMBER OF ATOMS\n%d\n" % (step, len(radii)))
            fh.write("ITEM: BOX BOUNDS ff ff ff\n0 1\n0 1\n0 1\nITEM: ATOMS %s\n" % cols)
            for k, r in enumerate(radii):
                line = "%d 1 0.5 0.5 0.5 %.17g %.17g" % (k + 1, r, m[k])
                if true_column:
                    line += " %.17g" % m_true[k]
                fh.write(line + "\n")


SNAPS = [(0, [R] * 4), (500, [R] * 3 + [R1] * 6 + [R2] * 8)]


@pytest.mark.parametrize("true_column", [True, False])
def test_br_is_the_same_with_scaling_on_and_off(tmp_path, capsys, true_column):
    events = tmp_path / "events.txt"
    events.write_text("# step time parent_tag parent_diameter x y z F_n F_lim partner generation\n"
                      "500 1e-4 4 %.17g 0.5 0.5 0.5 1.0 0.9 particle 0\n" % (2 * R))
    out = {}
    for scaled in (False, True):
        path = tmp_path / ("dump_%d.txt" % scaled)
        _write(path, SNAPS, scaled, true_column)
        assert main(["br", str(path), "--json", "--density", str(RHO), "--events", str(events)]) == 0
        out[scaled] = json.loads(capsys.readouterr().out)
    assert out[True]["Br_einav"] == pytest.approx(out[False]["Br_einav"], rel=1e-12)
    assert out[True]["fines_mass"] == pytest.approx(out[False]["fines_mass"], rel=1e-12)
    # and it is the answer of the true masses: fines = 47.61 % of one grain
    m_grain = RHO * 4.0 / 3.0 * np.pi * R ** 3
    kept = (6 * R1 ** 3 + 8 * R2 ** 3) / R ** 3
    assert out[True]["fines_mass"] == pytest.approx(m_grain * (1 - kept), rel=1e-5)
    assert out[True]["Br_einav"] > 0


def test_psd_is_the_same_with_scaling_on_and_off(tmp_path):
    sizes = np.geomspace(0.01e-3, 0.3e-3, 30)
    curves = {}
    for scaled in (False, True):
        d = tmp_path / ("s%d" % scaled)
        d.mkdir()
        _write(d / "dump.grains.0.txt", SNAPS[:1], scaled)
        _write(d / "dump.grains.500.txt", SNAPS[1:], scaled)
        steps, curves[scaled] = psd_snapshots(str(d / "dump.grains.*.txt"), RHO, sizes)
        assert list(steps) == [0, 500]
    np.testing.assert_allclose(curves[True], curves[False], rtol=1e-12, atol=1e-15)
    # mass fraction finer than 0.1 mm after the break: the fragments over all
    # particles (no fines counted here), from true masses
    frag = 6 * R1 ** 3 + 8 * R2 ** 3
    k = np.searchsorted(sizes, 0.1e-3)
    assert curves[True][1][k] == pytest.approx(frag / (3 * R ** 3 + frag), rel=1e-9)


def test_true_mass_prefers_the_true_column_and_names_the_file():
    atoms = {"radius": np.array([1e-3]), "mass": np.array([99.0]), "v_mass_true": np.array([1.5])}
    assert true_mass(atoms, RHO)[0] == 1.5
    del atoms["v_mass_true"]
    assert true_mass(atoms, RHO)[0] == pytest.approx(RHO * 4 / 3 * np.pi * 1e-9, rel=1e-15)
    with pytest.raises(KeyError, match="some/file.txt"):
        true_mass({"mass": np.array([1.0])}, RHO, "some/file.txt")


def test_printed_reading_is_the_decks_default():
    """crushpost's name for the printed reading is the default of the deck block."""
    import re
    from pathlib import Path
    from crushpost.breakage import CRUSH_READING_PRINTED
    deck = (Path(__file__).resolve().parents[2] / "inputs" / "crushable_ne34.in").read_text()
    m = re.search(r'^variable crush_reading index "([^"]*)"', deck, re.M)
    assert m and m.group(1) == CRUSH_READING_PRINTED


def test_grain_models_are_the_deck_blocks_and_their_readings():
    """Every name of crushpost's GRAIN_MODELS is a block under inputs/; a
    named crushable model sets the reading GRAIN_MODELS gives it (string
    style, so that no -var can override it silently) and then includes
    crushable_ne34.in; unbreakable.in defines no fix crush."""
    import re
    from pathlib import Path
    from crushpost.breakage import CRUSH_READING_PRINTED, GRAIN_MODELS
    inputs = Path(__file__).resolve().parents[2] / "inputs"
    for name, reading in GRAIN_MODELS.items():
        deck = (inputs / (name + ".in")).read_text()
        code = "\n".join(line for line in deck.splitlines() if not line.startswith("#"))
        if reading is None:
            assert "crush/particle" not in code, name
        elif name != "crushable_ne34":
            m = re.search(r'^variable crush_reading string "([^"]*)"$', code, re.M)
            assert m and m.group(1) == reading, name
            assert reading != CRUSH_READING_PRINTED
            assert code.strip().endswith("include ${inputs}/crushable_ne34.in"), name


def test_grain_model_reading_rejects_what_a_deck_would_ignore_or_refuse():
    from crushpost.breakage import CRUSH_READING_PRINTED, grain_model_reading
    assert grain_model_reading("crushable_ne34") is None
    assert grain_model_reading("crushable_ne34", "pressure peak") == "pressure peak"
    assert grain_model_reading("crushable_ne34_peak", CRUSH_READING_PRINTED) is None
    assert grain_model_reading("unbreakable", "") is None
    with pytest.raises(ValueError, match="--grains crushable: not a grain model"):
        grain_model_reading("crushable")
    with pytest.raises(ValueError, match="sets its own reading"):
        grain_model_reading("crushable_ne34_peak", "scatter weibull")
    with pytest.raises(ValueError, match="unbreakable grains have no criterion"):
        grain_model_reading("unbreakable", "pressure peak")
    from crushpost.breakage import GRAIN_MODELS, effective_reading
    assert effective_reading("crushable_ne34") == CRUSH_READING_PRINTED
    assert effective_reading("crushable_ne34", "force sliding") == "force sliding"
    assert effective_reading("crushable_ne34_peak") == GRAIN_MODELS["crushable_ne34_peak"]
    assert effective_reading("unbreakable") is None


def test_utilisation_at_picks_the_snapshot_at_each_stress():
    from crushpost.oedometer import utilisation_at
    path = {"Step": np.array([0, 100, 200, 300, 400]), "phase": np.array([0, 0, 0, 0, 1]),
            "sv": np.array([0.5e6, 1e6, 10e6, 30e6, 1e6])}
    snaps = [(100, {"v_utilisation": np.array([0.0, 0.1, 0.2, 0.3])}),
             (200, {"v_utilisation": np.array([0.4, 0.5, 0.6])}),
             (300, {"v_utilisation": np.array([0.9, 0.2, 0.0, 0.7])}),
             (400, {"v_utilisation": np.array([1.0])})]        # unloading: never picked
    out = utilisation_at(snaps, path, [1e6, 10e6, 30e6, 50e6])
    assert out[1e6]["step"] == 100 and out[1e6]["n_contact"] == 3
    assert out[1e6]["median"] == pytest.approx(0.2)
    assert out[10e6]["max"] == pytest.approx(0.6) and out[10e6]["frac_above_0.5"] == pytest.approx(1 / 3)
    assert out[30e6]["step"] == 300 and out[30e6]["max"] == pytest.approx(0.9)
    assert out[50e6] is None                       # never reached
    assert utilisation_at([(100, {"radius": np.ones(2)})], path, [1e6])[1e6] is None
