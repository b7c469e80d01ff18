# SPDX-License-Identifier: GPL-2.0-or-later
"""Measurement-sphere deck block (crushpost.spheres) and `python3 -m crushpost spheres`."""

import json
import math

import numpy as np

from crushpost.cli import main
import pytest

from crushpost.spheres import (chamber_sphere_centres, check_chamber_spheres,
                               measurement_sphere_block, read_sphere_series, write_sphere_block)


def parse_block(text):
    regions, divisors, fix = {}, {}, None
    for line in text.splitlines():
        w = line.split()
        if not w or w[0].startswith("#"):
            continue
        if w[0] == "region":
            assert w[2] == "sphere" and w[-2:] == ["units", "box"]
            regions[w[1]] = [float(v) for v in w[3:7]]
        elif w[0] == "variable" and w[2] == "equal":
            # variable msK_cc equal c_msK[j]/VOLUME
            num, vol = w[3].split("/")
            assert num.startswith("c_ms")
            divisors[w[1]] = float(vol)
        elif w[0] == "fix":
            fix = w
    return regions, divisors, fix


def test_block_regions_volumes_and_output():
    centres = [[0.1, -0.2, 0.3], [1.0, 2.0, -3.0]]
    text = measurement_sphere_block(centres, 0.05, 250, "out.txt")
    regions, divisors, fix = parse_block(text)
    assert sorted(regions) == ["ms1_reg", "ms2_reg"]
    assert regions["ms1_reg"] == [0.1, -0.2, 0.3, 0.05]
    assert regions["ms2_reg"] == [1.0, 2.0, -3.0, 0.05]
    assert len(divisors) == 12
    for v in divisors.values():
        assert math.isclose(v, 4.0 / 3.0 * math.pi * 0.05 ** 3, rel_tol=1e-10)
    # fix ID group ave/time Nevery Nrepeat Nfreq values... file NAME
    assert fix[3:6] == ["ave/time", "250", "1"] and fix[6] == "250"
    assert fix[-2:] == ["file", "out.txt"]
    vals = fix[7:-2]
    assert vals[:6] == ["v_ms1_xx", "v_ms1_yy", "v_ms1_zz", "v_ms1_xy", "v_ms1_xz", "v_ms1_yz"]
    assert len(vals) == 12
    # V_p sigma_p of compute stress/grain (compression positive, walls
    # included), reduced inside each region
    assert "variable ms_Vp atom 4.0/3.0*PI*r*r*r" in text
    for j in range(1, 7):
        assert "variable ms_s%d atom c_sigma_p[%d]*v_ms_Vp" % (j, j) in text
    assert "compute ms2 all reduce/region ms2_reg sum v_ms_s1 v_ms_s2 v_ms_s3 v_ms_s4 v_ms_s5 v_ms_s6" in text
    assert "stress/atom" not in text
    other = measurement_sphere_block(centres, 0.05, 250, "out.txt", prefix="mt", stress="sg")
    assert "variable mt_s3 atom c_sg[3]*v_mt_Vp" in other


def test_chamber_grid():
    R, top = 0.018, 1.0
    c = chamber_sphere_centres([2, 3, 5, 8], [0.2, 0.5, 0.8], R, top, azimuth_deg=90.0)
    assert c.shape == (12, 3)
    np.testing.assert_allclose(np.hypot(c[:, 0], c[:, 1]), np.tile([2, 3, 5, 8], 3) * R)
    np.testing.assert_allclose(c[:, 0], 0.0, atol=1e-15)    # along +y
    assert np.all(c[:, 1] > 0)
    np.testing.assert_allclose(c[:, 2], np.repeat([0.8, 0.5, 0.2], 4))


def test_series_roundtrip(tmp_path):
    path = tmp_path / "s.txt"
    rows = []
    for step in (0, 500):
        vals = [step]
        for k in range(2):
            vals += [1.0 + k + step, 2.0, 3.0, 4.0 + k, 5.0, 6.0]
        rows.append(vals)
    path.write_text("# Time-averaged data\n# TimeStep ...\n" +
                    "\n".join(" ".join(str(v) for v in r) for r in rows) + "\n")
    steps, sig = read_sphere_series(path, 2)
    assert steps.tolist() == [0, 500]
    np.testing.assert_allclose(sig[1, 1], [[502.0, 5.0, 5.0], [5.0, 2.0, 6.0], [5.0, 6.0, 3.0]])
    np.testing.assert_allclose(sig, np.swapaxes(sig, 2, 3))


def test_cli_writes_the_block(tmp_path, capsys):
    out = tmp_path / "spheres.in"
    argv = ["spheres", "--radius", "0.018", "--centre", "0", "0", "0.5",
            "--r-over-R", "2", "8", "--depth", "0.2", "--pile-radius", "0.018",
            "--z-top", "1.0", "--every", "400", "--file", "sph.txt", "--out", str(out)]
    assert main(argv) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["n_spheres"] == 3
    expect = measurement_sphere_block([[0, 0, 0.5], [0.036, 0, 0.8], [0.144, 0, 0.8]],
                                      0.018, 400, "sph.txt")
    assert out.read_text() == expect
    again = tmp_path / "again.in"
    assert write_sphere_block(again, info["centres"], 0.018, 400, "sph.txt") == expect


def test_cli_errors(tmp_path, capsys):
    out = str(tmp_path / "x.in")
    assert main(["spheres", "--radius", "0.01", "--out", out]) == 1          # no sphere
    assert main(["spheres", "--radius", "0.01", "--r-over-R", "2", "--out", out]) == 1
    assert main(["spheres", "--radius", "-1", "--centre", "0", "0", "0", "--out", out]) == 1
    err = capsys.readouterr().err
    assert "no sphere" in err and "grid needs" in err and "positive" in err


def test_sphere_check_names_the_wall():
    R, H, Rp = 0.05, 0.07, 0.018
    ok = chamber_sphere_centres([2.0], [0.02, 0.04], Rp, H)       # r = 36 mm
    clearance = check_chamber_spheres(ok, 0.012, R, 0.0, H, R_pile=Rp)
    assert clearance == pytest.approx(min(R - 0.036 - 0.012, 0.036 - 0.012 - Rp, 0.02 - 0.012),
                                      abs=1e-12)
    # touching the shaft is allowed (the block counts the pile's contacts)
    assert check_chamber_spheres([[0.036, 0.0, 0.035]], 0.018, 0.06, 0.0, H, R_pile=Rp) == \
        pytest.approx(0.0, abs=1e-12)
    cases = [([[0.036, 0, 0.035]], 0.0145, "sphere 1 ", "lateral wall"),
             ([[0.036, 0, 0.035], [0.03, 0, 0.005]], 0.01, "sphere 2 ", "bottom"),
             ([[0.03, 0, 0.065]], 0.01, "sphere 1 ", "top wall"),
             ([[0.025, 0, 0.035]], 0.01, "sphere 1 ", "pile's path")]
    for centres, radius, which, wall in cases:
        with pytest.raises(ValueError) as e:
            check_chamber_spheres(centres, radius, R, 0.0, H, R_pile=Rp)
        assert which in str(e.value) and wall in str(e.value), str(e.value)
    # below the pile's final apex the path is free
    assert check_chamber_spheres([[0.0, 0.0, 0.015]], 0.01, R, 0.0, H, R_pile=Rp,
                                 z_tip_final=0.03) > 0
    # symmetry planes of sectors
    with pytest.raises(ValueError, match="symmetry plane y = 0"):
        check_chamber_spheres([[0.03, 0.005, 0.035]], 0.01, R, 0.0, H, sector=180)
    with pytest.raises(ValueError, match="symmetry plane x = 0"):
        check_chamber_spheres([[0.005, 0.03, 0.035]], 0.01, R, 0.0, H, sector=90)
    assert check_chamber_spheres([[-0.03, 0.02, 0.035]], 0.01, R, 0.0, H, sector=180) > 0
