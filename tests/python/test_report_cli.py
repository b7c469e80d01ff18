# SPDX-License-Identifier: GPL-2.0-or-later
"""``python3 -m crushpost report`` on a synthetic run folder laid out as
examples/cpt_demo/run.py leaves it (issue 10 items 3, 4 and 8): every
figure and fields.h5 group is made, known inputs come back (the q_c trend,
the states and their kinds, the reference column), and missing, truncated
or corrupt inputs give one line naming the file, never a traceback, while
the parts that do not need them are still made."""

import json
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

h5py = pytest.importorskip("h5py")

from crushpost import study  # noqa: E402
from crushpost.cli import main  # noqa: E402
from crushpost.snapshot import write_snapshot  # noqa: E402
from crushpost.trend import qc_trend  # noqa: E402
from conftest import write_events_file  # noqa: E402

R = 0.018
R_CH, H_CH = 0.06, 0.1
Z_REF = 0.095
A_QC, B_QC = 4e6, 150.0
N_SCALE = 39.0
# snapshot steps: the fix writes one at the step where the phase leaves push
# (the first unload row, or the last row: done) or pause (the next push's first row)
STEPS = {"prep": 1000, "push1": 3100, "pause1": 3600, "push2": 6100}


def _snapshot(path, step, x, radius, ids, trigger_old, rng):
    n = len(ids)
    # contacts: each grain with its next neighbour in id order, forces that
    # squeeze them together (compression), plus a few wall contacts
    i = np.arange(n - 1)
    pid = np.column_stack([ids[i], ids[i + 1]])
    cp = 0.5 * (x[i] + x[i + 1])
    f = -(x[i + 1] - x[i]) * 1e4 * rng.uniform(0.5, 1.5, (n - 1, 1))   # on id[:, 0]
    write_snapshot(path, {
        "step": step, "time": step * 1e-7, "dt": 1e-7, "trigger": "f_jack[6]",
        "trigger_old": float(trigger_old), "trigger_new": 1.0, "snapshot": 1,
        "particles": {"id": ids, "type": np.ones(n, dtype=np.int32), "x": x,
                      "v": np.zeros((n, 3)), "radius": radius},
        "contacts": {
            "pp": {"id": pid, "contact_point": cp, "force": f, "force_normal": f,
                   "overlap": np.full(n - 1, 1e-5)},
            "pw": {"id": ids[:5], "mesh": np.zeros(5, dtype=np.int32),
                   "triangle": np.zeros(5, dtype=np.int64),
                   "contact_point": x[:5] - [0, 0, 0.001],
                   "force": np.tile([0.0, 0.0, 2.0], (5, 1)),
                   "force_normal": np.tile([0.0, 0.0, 2.0], (5, 1)),
                   "overlap": np.full(5, 1e-5), "meshes": ["side", "bottom"],
                   "wall_fix": "walls"}}})


def make_run(out, snapshots=True):
    """A chamber run folder: summary.json, jack.txt (push to 10 mm, unload,
    pause, push to 20 mm), breakage_events.txt, log.liggghts, spheres.in/.txt
    and snapshots at the prepared state and at every push and pause end."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(1)
    area = math.pi * R * R
    rows = []

    def row(step, d, q, ph, cyc):
        rows.append("%d %.10g %.17g %.17g 0 %.17g %d %d 0" % (step, step * 1e-7, d, q * area,
                                                            q * area, ph, cyc))
    for k, h in enumerate(np.linspace(0.0, 0.01, 21)[1:]):
        row(1000 + 100 * (k + 1), h, qc_trend(h, A_QC, B_QC), 0, 1)
    row(3100, 0.0099, 0.0, 1, 1)
    row(3300, 0.0099, 0.0, 2, 1)
    row(3600, 0.0099, 0.0, 0, 2)
    for k, h in enumerate(np.linspace(0.01, 0.02, 21)[1:]):
        row(3600 + 120 * (k + 1), h, qc_trend(h, A_QC, B_QC), 0, 2)
    row(6100, 0.02, qc_trend(0.02, A_QC, B_QC), 3, 2)
    (out / "jack.txt").write_text(
        "# fix jack/pile jack: mode cyclic, v 1 m/s, depth 0.02 m, stroke 0.01 m\n"
        "# forces ...\n# z_ref %.17g m: depth = z_ref - z of the cone apex\n"
        "# step time depth F_cone F_shaft F_head phase cycle v_next\n" % Z_REF
        + "\n".join(rows) + "\n")
    summary = {"R_pile_m": R, "N": N_SCALE, "R_chamber_m": R_CH, "H_chamber_m": H_CH,
               "sector_deg": 360, "mode": "cyclic", "grains": "crushable_ne34", "mpi_ranks": 2}
    (out / "summary.json").write_text(json.dumps(summary))
    # grains: 1500 in the chamber, d about 6 mm
    n = 1500
    rho = (R_CH - 0.004) * np.sqrt(rng.uniform(0, 1, n))
    phi = rng.uniform(0, 2 * np.pi, n)
    x = np.column_stack([rho * np.cos(phi), rho * np.sin(phi), rng.uniform(0.003, Z_REF - 0.003, n)])
    x = x[np.argsort(x[:, 2])]
    radius = rng.uniform(0.0025, 0.0032, n)
    ids = np.arange(1, n + 1, dtype=np.int64)
    ev = ["# fix crush/particle crush: one line per breakage event",
          "# step time parent_tag parent_diameter x y z F_n F_lim partner generation"]
    snaps = out / "snapshots"
    if snapshots:
        snaps.mkdir()
        _snapshot(snaps / ("prep_%d.h5" % STEPS["prep"]), STEPS["prep"], x, radius, ids, 0, rng)
    for name, old in (("push1", 0), ("pause1", 2), ("push2", 0)):
        # grains near the tip move out; two grains break into new ids
        x = x + [0.0, 0.0, 0.0]
        x[:, :2] *= (1.0 + 0.002 * np.exp(-np.hypot(x[:, 0], x[:, 1]) / R))[:, None]
        broken = rng.choice(np.arange(n), 2, replace=False)
        for b in broken:
            ev.append("%d %.6g %d %.10g %.10g %.10g %.10g 5.0 1.0 particle 0"
                      % (STEPS[name] - 10, STEPS[name] * 1e-7, ids[b], 2 * radius[b],
                         x[b, 0], x[b, 1], x[b, 2]))
        new_ids = ids.max() + 1 + np.arange(2)
        ids = ids.copy()
        ids[broken] = new_ids
        radius = radius.copy()
        radius[broken] *= 0.414
        order = np.argsort(ids)
        ids, x, radius = ids[order], x[order], radius[order]
        if snapshots:
            _snapshot(snaps / ("jack_%d.h5" % STEPS[name]), STEPS[name], x, radius, ids, old, rng)
    (out / "breakage_events.txt").write_text("\n".join(ev) + "\n")
    # the log: one thermo block of the jacking
    lines = ["LIGGGHTS (Version LIGGGHTS-PUBLIC 3.8.0)",
             "Step Time Atoms f_jack[2] qc f_jack[4] f_jack[6] sv n_break fines Br M_grains"]
    for k, st in enumerate((1000, 3000, 6000)):
        lines.append("%d %g %d 0 0 0 0 0 %d %g 0.001 %.15g" % (st, st * 1e-7, n + 13 * 2 * k,
                                                               2 * k, 1e-4 * k, 1.0 - 1e-4 * k))
    lines.append("Loop time of 1 on 2 procs for 5000 steps with 1500 atoms")
    (out / "log.liggghts").write_text("\n".join(lines) + "\n")
    # two measurement spheres at r = 2 R
    (out / "spheres.in").write_text(
        "region ms1_reg sphere 0.036 0 0.07 0.01 units box\n"
        "region ms2_reg sphere 0.036 0 0.05 0.01 units box\n")
    srows = ["# Time-averaged data for fix ms_out", "# TimeStep v_ms1_xx ..."]
    for st in range(1200, 6001, 400):
        a = 1e5 * (1 + st / 6000.0)
        srows.append("%d %g %g %g 0 %g 0 %g %g %g 0 0 0" % (st, a, a, 2 * a, 0.1 * a, a, a, a))
    (out / "spheres.txt").write_text("\n".join(srows) + "\n")
    return out


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    return make_run(tmp_path_factory.mktemp("run") / "demo")


@pytest.fixture(scope="module")
def report(run, tmp_path_factory):
    out = tmp_path_factory.mktemp("report")
    ref = out.parent / "ref.json"
    ref.write_text(json.dumps({"qc_steady_MPa": {"value": 5.0, "source": "paper X, Fig. 3",
                                                 "unit": "MPa"},
                               "unknown_thing": {"value": 1.0, "source": "elsewhere"}}))
    rc = main(["report", str(run), "--out", str(out), "--reference", str(ref), "--quiet"])
    return out, rc


FIGURES = ["qc_depth.png", "initial_state.png", "stress_push1.png",
           "stress_pause1.png", "stress_push2.png", "radial_profiles.png",
           "stress_history.png", "rotation.png", "br_bands.png", "psd.png",
           "radial_increments.png", "breakage_density.png", "spheres_q_over_p.png"]


def test_every_figure_and_the_report(report):
    out, rc = report
    assert rc == 0
    for name in FIGURES:
        assert (out / name).stat().st_size > 1000, name
    html = (out / "report.html").read_text()
    for name in FIGURES:
        assert 'src="%s"' % name in html


def test_fields_h5_holds_the_numbers(report, run):
    out, _ = report
    with h5py.File(out / "fields.h5", "r") as f:
        kinds = [k.decode() for k in f["states/kind"][()]]
        assert kinds == ["initial", "push_end", "pause_end", "push_end"]
        assert f["states/step"][()].tolist() == [1000, 3100, 3600, 6100]
        # depth from jack.txt at the snapshot's step; cycle from the row before it
        assert np.allclose(f["states/depth"][()], [0.0, 0.0099, 0.0099, 0.02])
        assert f["states/cycle"][()].tolist() == [0, 1, 1, 2]
        # q_c that normalises: the end of the last push (the pause keeps push 1's)
        qn = f["states/qc_norm"][()]
        assert np.isnan(qn[0])
        assert qn[1:] == pytest.approx([qc_trend(0.01, A_QC, B_QC)] * 2 + [qc_trend(0.02, A_QC, B_QC)])
        n_r, n_z = f["rings/r_edges"].size - 1, f["rings/z_edges"].size - 1
        assert (n_r, n_z) == (3, 4)      # 60 mm in R = 18 mm rings (remainder joins); 95 mm / 25 mm
        for name in ("sigma_r", "sigma_theta", "sigma_z", "tau_rz", "p", "q", "sigma_1",
                     "sigma_2", "sigma_3", "psi", "rotation", "porosity", "n_grains", "low_count"):
            assert f["rings/" + name].shape == (4, n_r, n_z), name
        assert np.all(f["rings/rotation"][0] == 0.0)
        assert f["rings/n_grains"][0].sum() == 1500
        # the layers go down from the sand surface
        assert f["rings/z_edges"][-1] == pytest.approx(Z_REF)
        assert f["rings/h_over_R"][1] == pytest.approx((f["rings/z_mid"][()] - (Z_REF - 0.0099)) / R)
        # the history line r/R = 3 lies beyond the last ring centre (r/R = 2.67): its column
        hist = f["histories/r_over_R_3"]
        ks = hist["state"][()]
        assert ks.tolist() == [1, 2, 3]
        want = f["rings/sigma_z"][()][ks, 2, :] / f["states/qc_norm"][()][ks][:, None]
        assert np.allclose(hist["sigma_z"][()], want, rtol=1e-12)
        assert f["qc"].attrs["a"] == pytest.approx(A_QC, rel=1e-6)
        assert f["qc"].attrs["b"] == pytest.approx(B_QC, rel=1e-6)
        assert f["breakage/events/h_over_R"].shape == (6,)
        assert f["breakage/density/count"][()].sum() == 6
        assert f["breakage/bands/Br"].shape[0] == 4
        assert np.all(f["breakage/bands/Br"][0][np.isfinite(f["breakage/bands/Br"][0])] == 0.0)
        assert f["psd/F"].shape == (4, f["psd/sizes"].size)
        inc = f["increments"]
        assert sorted(inc.keys()) == ["00", "01", "02"]
        assert [inc[k].attrs["n_matched"] for k in ("00", "01", "02")] == [1498] * 3
        assert f["spheres/q_over_p"].shape == (13, 2)
        # sphere 1: sigma = diag(a, a, 2a) + tau_xz 0.1 a: q/p' = sqrt(1 + 3 0.01) / (4/3)
        assert f["spheres/q_over_p"][0, 0] == pytest.approx(math.sqrt(1.03) * 0.75, rel=1e-9)
        head = dict(f["headline"].attrs)
        assert head["qc_steady_MPa"] == pytest.approx(A_QC / 1e6, rel=1e-6)
        assert head["lost_atoms"] == 0 and head["n_break_events"] == 4
        # one 25 mm band holds the 40 points of virgin penetration (the
        # re-push's first row, below the deepest point, and the done row are out)
        virgin = np.concatenate([np.linspace(0.0, 0.01, 21)[1:], np.linspace(0.01, 0.02, 21)[1:]])
        assert f["qc/band_count"][()].tolist() == [40]
        assert f["qc/band_mean"][0] == pytest.approx(np.mean(qc_trend(virgin, A_QC, B_QC)),
                                                     rel=1e-12)
        assert "qc_last3_bands_MPa" not in head       # fewer than three bands
        assert head["n_break_events_first_step"] == 0  # the events come at steps 3090, ...


def test_reference_column(report):
    out, _ = report
    html = (out / "report.html").read_text()
    row = [r for r in html.split("<tr>") if r.startswith("<td>qc_steady_MPa</td>")][0]
    assert "paper X, Fig. 3" in row
    assert "%+.1f %%" % (100.0 * (A_QC / 1e6 - 5.0) / 5.0) in row      # -20.0 %
    assert "<td>unknown_thing</td><td>not in this report</td>" in html


def test_reference_csv(run, tmp_path):
    ref = tmp_path / "ref.csv"
    ref.write_text("# measured\nname,value,unit,source\nqc_steady_MPa,8,MPa,lab test 3\n")
    assert main(["report", str(run), "--out", str(tmp_path / "o"), "--reference", str(ref),
                 "--quiet"]) == 0
    assert "lab test 3" in (tmp_path / "o" / "report.html").read_text()


# ---------------------------------------------------------------------------
# bad input (item 8)
# ---------------------------------------------------------------------------

def _run_cli(argv):
    env = dict(os.environ)
    return subprocess.run([sys.executable, "-m", "crushpost", "report"] + argv,
                          capture_output=True, text=True, env=env, timeout=300)


def _corrupt(run, how):
    if how == "truncated jack.txt":
        p = run / "jack.txt"
        text = p.read_text()
        p.write_text(text[:len(text) // 2 + 7])          # cut inside a row
        return p, "not a fix jack/pile time series (the number of columns changed from 9 to "
    if how == "empty jack.txt":
        (run / "jack.txt").write_text("")
        return run / "jack.txt", "empty file"
    if how == "truncated snapshot":
        p = run / "snapshots" / ("jack_%d.h5" % STEPS["pause1"])
        data = p.read_bytes()
        p.write_bytes(data[:len(data) // 3])
        return p, "truncated"
    if how == "binary events":
        p = run / "breakage_events.txt"
        p.write_bytes(b"\x89PNG\r\n\x1a\n" + bytes(range(256)))
        return p, "not a text file"
    if how == "bad events row":
        p = run / "breakage_events.txt"
        p.write_text(p.read_text() + "1 2 3\n")
        return p, "expected 11 columns, got 3"
    if how == "spheres.txt columns":
        p = run / "spheres.txt"
        p.write_text("1000 1 2 3\n")
        return p, "not the output of 2 measurement spheres"
    if how == "summary.json":
        p = run / "summary.json"
        p.write_text("{not json")
        return p, "not a JSON summary"
    raise ValueError(how)


CASES = ["truncated jack.txt", "empty jack.txt", "truncated snapshot", "binary events",
         "bad events row", "spheres.txt columns", "summary.json"]
# what each bad input must leave intact
STILL_MADE = {"truncated jack.txt": ["initial_state.png", "psd.png", "br_bands.png"],
              "empty jack.txt": ["initial_state.png", "radial_increments.png"],
              "truncated snapshot": ["qc_depth.png", "stress_push2.png", "rotation.png"],
              "binary events": ["qc_depth.png", "stress_push1.png"],
              "bad events row": ["qc_depth.png", "rotation.png"],
              "spheres.txt columns": ["qc_depth.png", "breakage_density.png"],
              "summary.json": ["qc_depth.png"]}


@pytest.mark.parametrize("how", CASES)
def test_bad_input_is_one_line_naming_the_file(tmp_path, how):
    run = make_run(tmp_path / "run")
    path, words = _corrupt(run, how)
    argv = [str(run), "--out", str(tmp_path / "out"), "--quiet"]
    if how == "summary.json":
        argv += ["--pile-radius", str(R), "--N", str(N_SCALE)]
    res = _run_cli(argv)
    assert res.returncode == 1
    assert "Traceback" not in res.stderr
    errors = [ln for ln in res.stderr.splitlines() if "error:" in ln]
    assert len(errors) == 1, res.stderr
    assert errors[0].startswith("crushpost report: error: %s: " % path), errors[0]
    assert words in errors[0], errors[0]
    if how == "truncated jack.txt":
        assert errors[0].endswith("truncated while it was being written, or edited by hand?)")
        assert "usecols" not in errors[0]          # numpy's advice is not the user's
    for line in res.stderr.splitlines():
        assert line.startswith("crushpost report: "), line
    for name in STILL_MADE[how]:
        assert (tmp_path / "out" / name).exists(), (name, res.stderr)
    # the report says what was wrong
    assert str(path) in (tmp_path / "out" / "report.html").read_text()


def test_run_without_snapshots_gets_the_rest(tmp_path):
    run = make_run(tmp_path / "run", snapshots=False)
    res = _run_cli([str(run), "--out", str(tmp_path / "out")])
    assert res.returncode == 0, res.stderr
    assert "Traceback" not in res.stderr
    assert "no snapshots" in res.stderr
    made = sorted(os.listdir(tmp_path / "out"))
    assert made == ["breakage_density.png", "fields.h5", "qc_depth.png", "report.html",
                    "spheres_q_over_p.png"]


def test_band_means_over_the_ring_height(tmp_path):
    # bands of 5.1 mm (no point on an edge): four to 20 mm; the headline is
    # the mean over every virgin point of the last three, h >= 5.1 mm
    run = make_run(tmp_path / "run", snapshots=False)
    assert main(["report", str(run), "--out", str(tmp_path / "out"), "--ring-height", "0.0051",
                 "--quiet"]) == 0
    virgin = np.concatenate([np.linspace(0.0, 0.01, 21)[1:], np.linspace(0.01, 0.02, 21)[1:]])
    q = qc_trend(virgin, A_QC, B_QC)
    with h5py.File(tmp_path / "out" / "fields.h5", "r") as f:
        assert f["qc/band_bottom"][()] == pytest.approx(0.0051 * np.arange(1, 5))
        assert f["qc/band_count"][()].tolist() == [10, 10, 10, 10]
        assert f["qc/band_mean"][0] == pytest.approx(np.mean(q[virgin < 0.0051]), rel=1e-12)
        assert f["headline"].attrs["qc_last3_bands_MPa"] == pytest.approx(
            np.mean(q[virgin > 0.0051]) / 1e6, rel=1e-12)
    assert "qc_last3_bands_MPa" in (tmp_path / "out" / "report.html").read_text()


def test_breaks_at_the_first_step_of_jacking_are_counted_apart(tmp_path):
    # the log's jacking block starts at step 1000: events at step 1001 are
    # the breaks of crushing's switch-on; those one step later are not
    run = make_run(tmp_path / "run", snapshots=False)
    with open(run / "breakage_events.txt", "a") as f:
        for step in (1001, 1001, 1001, 1002):
            f.write("%d 1e-4 7 0.006 0.03 0.0 0.05 5.0 1.0 particle 0\n" % step)
    assert main(["report", str(run), "--out", str(tmp_path / "out"), "--quiet"]) == 0
    with h5py.File(tmp_path / "out" / "fields.h5", "r") as f:
        assert f["headline"].attrs["n_break_events_first_step"] == 3


def test_an_empty_event_log_counts_zero_in_every_zone(tmp_path):
    # crushable grains that never broke: the zones are measured (0), not
    # missing; the in-zone fraction is undefined and the map is skipped
    run = make_run(tmp_path / "run", snapshots=False)
    write_events_file(run / "breakage_events.txt", [])
    assert main(["report", str(run), "--out", str(tmp_path / "out"), "--quiet"]) == 0
    with h5py.File(tmp_path / "out" / "fields.h5", "r") as f:
        head = f["headline"].attrs
        for k in ("switch_on", "entry", "penetration", "in_zone", "along_shaft",
                  "beyond_5R_below", "elsewhere"):
            assert head["events_" + k] == 0, k
        assert math.isnan(head["fraction_in_zone"])
    assert not (tmp_path / "out" / "breakage_density.png").exists()


def _head_and_qc_attrs(out):
    with h5py.File(out / "fields.h5", "r") as f:
        return dict(f["headline"].attrs), dict(f["qc"].attrs)


def _committed_rel_sd(grains):
    # the study's pooled run-to-run spread of steady q_c, as run.py --table wrote it
    with open(study.STUDY_TABLE) as f:
        return json.load(f)["chamber_spread"]["models"][grains]["rel_std"]["qc_steady_MPa"]


def test_qc_run_to_run_scatter_next_to_the_fit_error(report):
    # the synthetic q_c lies on the trend: the fit's standard error is
    # round-off, so the study's run-to-run scatter (3.6 % crushable) dominates
    out, _ = report
    head, qa = _head_and_qc_attrs(out)
    rel = _committed_rel_sd("crushable_ne34")
    assert head["qc_run_scatter_MPa"] == pytest.approx(rel * head["qc_steady_MPa"], rel=1e-12)
    assert head["qc_steady_err_MPa"] < 1e-3 * head["qc_run_scatter_MPa"]
    assert qa["uncertainty_dominated_by"] == "run-to-run scatter"
    assert qa["run_scatter_rel"] == rel
    row = [r for r in (out / "report.html").read_text().split("<tr>")
           if r.startswith("<td>qc_steady_MPa</td>")][0]
    assert "(fit s.e.)" in row and "(run to run)" in row
    note = [r for r in (out / "report.html").read_text().split("<tr>")
            if r.startswith("<td>qc_run_scatter_MPa</td>")][0]
    assert "%.1f %%" % (100 * rel) in note and "run-to-run scatter dominates" in note


def test_a_noisy_fit_error_dominates_the_scatter(tmp_path):
    # unbreakable grains (4.2 %) and q_c with 30 % noise on 40 points: the
    # fit's standard error, about 0.3 MPa, exceeds 4.2 % of 4 MPa
    run = make_run(tmp_path / "run", snapshots=False)
    s = json.loads((run / "summary.json").read_text())
    s["grains"] = "unbreakable"
    (run / "summary.json").write_text(json.dumps(s))
    lines = (run / "jack.txt").read_text().splitlines(True)
    rng = np.random.default_rng(5)
    noisy = []
    for line in lines:
        w = line.split()
        if not line.startswith("#") and w[6] == "0" and float(w[3]) > 0:
            w[3] = "%.17g" % (float(w[3]) * (1 + 0.3 * rng.standard_normal()))
            line = " ".join(w) + "\n"
        noisy.append(line)
    (run / "jack.txt").write_text("".join(noisy))
    assert main(["report", str(run), "--out", str(tmp_path / "out"), "--quiet"]) == 0
    head, qa = _head_and_qc_attrs(tmp_path / "out")
    rel = _committed_rel_sd("unbreakable")
    assert head["qc_run_scatter_MPa"] == pytest.approx(rel * head["qc_steady_MPa"], rel=1e-12)
    assert head["qc_steady_err_MPa"] > head["qc_run_scatter_MPa"]
    assert qa["uncertainty_dominated_by"] == "fit standard error"


def test_no_scatter_without_a_grain_model(tmp_path):
    run = make_run(tmp_path / "run", snapshots=False)
    s = json.loads((run / "summary.json").read_text())
    del s["grains"]
    (run / "summary.json").write_text(json.dumps(s))
    res = _run_cli([str(run), "--out", str(tmp_path / "out")])
    assert res.returncode == 0, res.stderr
    assert "q_c run-to-run scatter skipped" in res.stderr
    head, _ = _head_and_qc_attrs(tmp_path / "out")
    assert "qc_run_scatter_MPa" not in head and "qc_steady_MPa" in head


@pytest.mark.parametrize("argv, words", [
    (["{tmp}/nowhere"], "{tmp}/nowhere: no such run folder"),
    (["{run}", "--reference", "{tmp}/missing.json"], "{tmp}/missing.json: no such file"),
    (["{run}", "--reference", "{tmp}/bad.csv"], "{tmp}/bad.csv: not a reference file"),
    (["{run}", "--ring-height", "-1"], "--ring-height must be > 0"),
])
def test_bad_arguments(tmp_path, argv, words):
    run = make_run(tmp_path / "run", snapshots=False)
    (tmp_path / "bad.csv").write_text("name,value,source\nqc,abc,x\n")
    fill = {"tmp": str(tmp_path), "run": str(run)}
    res = _run_cli([a.format(**fill) for a in argv] + ["--out", str(tmp_path / "o")])
    assert res.returncode == 1
    assert res.stderr.strip() == "crushpost report: error: " + words.format(**fill) or \
        res.stderr.strip().startswith("crushpost report: error: " + words.format(**fill)), res.stderr
    assert len(res.stderr.strip().splitlines()) == 1


def test_no_pile_radius(tmp_path):
    run = make_run(tmp_path / "run", snapshots=False)
    (run / "summary.json").unlink()
    res = _run_cli([str(run), "--out", str(tmp_path / "o")])
    assert res.returncode == 1
    assert res.stderr.strip().splitlines()[-1] == (
        "crushpost report: error: %s: no R_pile_m; give the pile radius with --pile-radius R (m)"
        % (run / "summary.json"))
