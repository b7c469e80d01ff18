# SPDX-License-Identifier: GPL-2.0-or-later
"""crushpost fit-qc on a fix jack/pile series (virgin penetration only) and
the top-wall hole reported by crushpost pile."""

import json
import math

import numpy as np
import pytest

from crushpost.cli import main
from crushpost.trend import qc_trend

R = 0.018
A, B = 5e6, 60.0


def _jack_file(path):
    """A cyclic series: virgin pushes on a (1 - exp(-b h)); after each
    unload the re-push reloads linearly from zero to the deepest point."""
    rows, step, deepest = [], 0, 0.0
    area = math.pi * R ** 2

    def row(d, q, phase, cycle):
        nonlocal step
        step += 10
        rows.append((step, step * 1e-7, d, q * area, 0.0, q * area, phase, cycle, 0.0))

    for cycle, end in enumerate((0.01, 0.02, 0.03), 1):
        if deepest > 0:
            row(deepest - 0.001, 0.0, 1, cycle - 1)
            row(deepest - 0.001, 0.0, 2, cycle - 1)
            for h in np.linspace(deepest - 0.001, deepest, 11)[1:-1]:
                row(h, qc_trend(deepest, A, B) * (h - deepest + 0.001) / 0.001, 0, cycle)
        for h in np.linspace(deepest, end, 41)[1:]:
            row(h, qc_trend(h, A, B), 0, cycle)
        deepest = end
    with open(path, "w") as f:
        f.write("# fix jack/pile jack: mode cyclic, v 1 m/s, depth 0.03 m\n"
                "# forces on the pile from the grains, + up\n"
                "# z_ref 0.1 m: depth = z_ref - z of the cone apex; z_ref = keyword surface\n"
                "# step time depth F_cone F_shaft F_head phase cycle v_next\n")
        for r in rows:
            f.write("%d %.17g %.17g %.17g %.17g %.17g %d %d %.17g\n" % r)


def test_fit_qc_on_a_jack_series_fits_virgin_penetration(tmp_path, capsys):
    path = tmp_path / "jack.txt"
    _jack_file(path)
    assert main(["fit-qc", str(path), "--pile-radius", str(R)]) == 0
    fit = json.loads(capsys.readouterr().out)
    assert fit["points"] == "virgin penetration"
    assert fit["n_points"] == 120 and fit["n_excluded"] == 2 * 2 + 2 * 9
    assert fit["a"] == pytest.approx(A, rel=1e-8) and fit["b"] == pytest.approx(B, rel=1e-8)
    # the radius is required for a jack series
    assert main(["fit-qc", str(path)]) == 1
    assert "--pile-radius" in capsys.readouterr().err


def test_pile_reports_the_hole_and_its_gap(tmp_path, capsys):
    assert main(["pile", "--radius", "0.018", "--shaft-length", "0.1", "--N", "39",
                 "--out", str(tmp_path)]) == 0
    hole = json.loads(capsys.readouterr().out)["hole"]
    assert hole["radius"] == 0.018 and hole["segments"] == 48
    assert hole["gap_max"] == pytest.approx(0.018 * (1 - math.cos(math.pi / 24)), rel=1e-9)
    assert hole["gap_min"] == pytest.approx(0.0, abs=1e-15)
    assert hole["smallest_fragment"] == pytest.approx(1.0365e-3, rel=1e-4)
    assert hole["closed_to_fragments"] is True
    # real-size grains (N = 1) would pass the facets' gap: reported, not hidden
    assert main(["pile", "--radius", "0.018", "--shaft-length", "0.1", "--N", "1",
                 "--out", str(tmp_path)]) == 0
    assert json.loads(capsys.readouterr().out)["hole"]["closed_to_fragments"] is False
