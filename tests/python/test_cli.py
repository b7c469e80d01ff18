# SPDX-License-Identifier: GPL-2.0-or-later
"""Command line through main() in-process, and once through python3 -m crushpost."""

import json
import os
import subprocess
import sys

import numpy as np
import pytest

from crushpost.cli import main
from crushpost.materials import D_MAX_BR, D_MIN_BR, RHO_GRAIN



def write_dump(path, snaps):
    with open(path, "w") as fh:
        for step, radii in snaps:
            fh.write("ITEM: TIMESTEP\n%d\nITEM: NUMBER OF ATOMS\n%d\n" % (step, len(radii)))
            fh.write("ITEM: BOX BOUNDS ff ff ff\n0 1\n0 1\n0 1\n")
            fh.write("ITEM: ATOMS id type x y z radius\n")
            for k, r in enumerate(radii):
                fh.write("%d 1 0.5 0.5 0.5 %.17g\n" % (k + 1, r))


def test_br_one_parent_crushed(tmp_path, capsys):
    # 4 grains of d = 0.2 mm; one breaks into the 14 Apollonian fragments,
    # the missing 47.61 % of its mass is fines.
    r = 0.1e-3
    r1, r2 = r / (1 + np.sqrt(2)), 0.230093 * r
    now = [r] * 3 + [r1] * 6 + [r2] * 8
    path = tmp_path / "dump.crush"
    write_dump(path, [(0, [r] * 4), (500, now)])
    events = tmp_path / "events.txt"
    events.write_text("# step time parent_tag parent_diameter x y z F_n F_lim partner generation\n"
                      "500 1e-4 4 %.17g 0.5 0.5 0.5 1.0 0.9 particle 0\n" % (2 * r))
    d_min, d_max, d = D_MIN_BR, D_MAX_BR, 2 * r
    vp, v1, v2 = r ** 3, r1 ** 3, r2 ** 3  # masses in units of rho pi/6 * 8
    fines = vp - 6 * v1 - 8 * v2
    L = np.log(d_max / d_min)
    k = 0.4
    iu = 1 / k - d_min ** k * L / (d_max ** k - d_min ** k)
    i0 = np.log(d_max / d)
    resolved = (3 * vp * np.log(d_max / d) + 6 * v1 * np.log(d_max / (2 * r1))
                + 8 * v2 * np.log(d_max / (2 * r2)))
    # fines at d_min (former convention): int F d(ln d) gains fines * L
    i_dmin = (resolved + fines * L) / (4 * vp)
    # fractal fines over [d_min, d_f = 2 r2]: with G = (x^k - d_min^k)/(d_f^k - d_min^k),
    # int_{d_min}^{d_max} G d(ln x) = L - U + (1/k - U d_min^k / (d_f^k - d_min^k)), U = ln(d_f/d_min)
    d_f = 2 * r2
    U = np.log(d_f / d_min)
    i_fr = (resolved + fines * (L - U + 1 / k - U * d_min ** k / (d_f ** k - d_min ** k))) / (4 * vp)

    # default: fractal fines, sizes from the event log
    assert main(["br", str(path), "--events", str(events), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["fines_grading"] == "fractal"
    assert out["Br_einav"] == pytest.approx((i_fr - i0) / (iu - i0), rel=1e-6)  # r2 to 6 digits
    assert 0 < out["Br"] <= out["Br_einav"]
    assert out["fines_mass"] == pytest.approx(RHO_GRAIN * np.pi / 6 * 8 * fines, rel=1e-5)
    assert out["timestep"] == 500 and out["initial_timestep"] == 0
    # the former convention, fines inferred from the mass deficit
    assert main(["br", str(path), "--fines-grading", "d_min", "--json"]) == 0
    old = json.loads(capsys.readouterr().out)
    assert old["Br_einav"] == pytest.approx((i_dmin - i0) / (iu - i0), rel=1e-10)
    assert old["fines_mass"] == pytest.approx(RHO_GRAIN * np.pi / 6 * 8 * fines, rel=1e-9)
    assert 0 < out["Br"] < old["Br"] <= old["Br_einav"]
    # fractal without the event log: the fines have no size, an error
    assert main(["br", str(path)]) == 1
    assert "--events" in capsys.readouterr().err
    # Plain output is the number alone; the initial grading may be another file.
    init = tmp_path / "dump.init"
    write_dump(init, [(0, [r] * 4)])
    assert main(["br", str(path), "--initial", str(init), "--events", str(events)]) == 0
    assert float(capsys.readouterr().out) == pytest.approx(out["Br"], rel=1e-9)
    # Scaling by N scales d_min, d_max: with grains also scaled by N, Br is unchanged.
    big = tmp_path / "dump.big"
    write_dump(big, [(0, [39 * r] * 4), (500, [39 * x for x in now])])
    events.write_text("500 1e-4 4 %.17g 0.5 0.5 0.5 1.0 0.9 particle 0\n" % (39 * 2 * r))
    assert main(["br", str(big), "--N", "39", "--events", str(events)]) == 0
    assert float(capsys.readouterr().out) == pytest.approx(out["Br"], rel=1e-8)


def test_br_missing_file_is_an_error(tmp_path, capsys):
    assert main(["br", str(tmp_path / "nope")]) == 1
    assert "error" in capsys.readouterr().err


def test_fit_qc(tmp_path, capsys):
    rng = np.random.default_rng(0)
    h = np.linspace(0, 1, 300)
    q = 9e6 * (1 - np.exp(-5 * h)) + rng.normal(0, 1e5, h.size)
    path = tmp_path / "qc.txt"
    np.savetxt(path, np.column_stack([h, q]), header="h q_c")
    assert main(["fit-qc", str(path)]) == 0
    fit = json.loads(capsys.readouterr().out)
    assert fit["a"] == pytest.approx(9e6, rel=0.02)
    assert fit["b"] == pytest.approx(5.0, rel=0.05)
    assert fit["a_err"] > 0 and fit["b_err"] > 0
    # band means over the default 0.025 (in h units): 40 bands of 1 m, each
    # the mean of the trend over its band (analytic integral) within the noise
    assert fit["band_width"] == 0.025 and len(fit["band_mean"]) == 40
    lo, hi = np.array(fit["band_bottom"]) - 0.025, np.array(fit["band_bottom"])
    exact = 9e6 * (1 - (np.exp(-5 * lo) - np.exp(-5 * hi)) / (5 * (hi - lo)))
    assert np.allclose(fit["band_mean"], exact, rtol=0, atol=1.5e5)
    assert sum(fit["band_count"]) == 300
    last3 = np.dot(fit["band_mean"][-3:], fit["band_count"][-3:]) / sum(fit["band_count"][-3:])
    assert fit["mean_last3_bands"] == pytest.approx(last3, rel=1e-12)
    assert main(["fit-qc", str(path), "--band-width", "0.5"]) == 0
    fit = json.loads(capsys.readouterr().out)
    assert fit["band_bottom"] == [0.5, 1.0] and "mean_last3_bands" not in fit


def test_thermo_summary(tmp_path, capsys):
    log = tmp_path / "log.liggghts"
    log.write_text("Step Atoms c_qc\n0 5 1.0\n10 5 3.0\nLoop time of 1\n"
                   "Step Atoms c_qc\n10 5 3.0\n20 6 2.0\nLoop time of 1\n")
    assert main(["thermo", str(log)]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0] == "# run 0: 2 rows" and "# run 1: 2 rows" in lines
    assert main(["thermo", "--concat", str(log)]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0] == "# all runs: 3 rows"
    qc = [ln.split() for ln in lines if ln.startswith("c_qc")][0]
    assert [float(v) for v in qc[1:]] == [3, 1.0, 2.0, 1.0, 3.0]
    log.write_text("no thermo here\n")
    assert main(["thermo", str(log)]) == 1


def test_python_dash_m(tmp_path):
    path = tmp_path / "qc.txt"
    h = np.linspace(0, 1, 50)
    np.savetxt(path, np.column_stack([h, 2.0 * (1 - np.exp(-3 * h))]))
    env = dict(os.environ)
    res = subprocess.run([sys.executable, "-m", "crushpost", "fit-qc", str(path)],
                         capture_output=True, text=True, env=env, timeout=60)
    assert res.returncode == 0, res.stderr
    fit = json.loads(res.stdout)
    assert fit["a"] == pytest.approx(2.0, rel=1e-6) and fit["b"] == pytest.approx(3.0, rel=1e-6)
