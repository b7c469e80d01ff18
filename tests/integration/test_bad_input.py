# SPDX-License-Identifier: GPL-2.0-or-later
"""Malformed command lines for every style of the plugin (issue 12, item 5).

Each style parses its keywords with the shared parser (crush_args.h). Every
line below is one of its good lines with one fault: a missing value, a word
for a number, a negative or zero value where it is not allowed, NaN, inf,
a number beyond the largest double (1e999) or an integer setting beyond an
int, an unknown keyword or a repeated keyword. Each must stop LIGGGHTS with
an ERROR line from that style naming the keyword (read from the log file);
a crash (no ERROR line), a hang (the short timeout) or a run that goes on
fails the case. The good lines themselves are accepted (so a fault is what
stops each deck). Decks are a few lines that end at the style's command;
run at 1 rank, two at a time, plus one case at 2 ranks.
"""

import os
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import harness  # noqa: E402
from crushpost.materials import SIGMA_LIM0  # noqa: E402
from crushpost.meshes import cylinder_triangles, write_stl  # noqa: E402

TIMEOUT = 30          # s per deck: each fails (or runs) at once; more means a hang
WORKERS = 2

PRELUDE = """\
units           si
atom_style      granular
atom_modify     map array
boundary        f f f
newton          off
region          box block -0.05 0.05 -0.05 0.05 -0.05 0.05 units box
create_box      3 box
"""

# the servo looks its mesh up when it is defined
MESH = "fix side all mesh/surface/stress file side.stl type 1\n"

# style -> (command, good keyword/value pairs, lines the deck needs before it)
STYLES = {
    "fix crush/particle": ("fix bad all crush/particle",
                           [("sigma_lim0", "%g" % SIGMA_LIM0), ("m", "10"), ("d0", "0.002"),
                            ("scale", "1"), ("var", "0.36"), ("d_comm", "5e-4"),
                            ("seed", "15485863")], ""),
    "fix damp/local": ("fix bad all damp/local", [("alpha", "0.05")], ""),
    "fix servo/radial": ("fix bad all servo/radial",
                         [("mesh", "side"), ("target", "1e5"), ("gain", "1e-6"),
                          ("height", "0.04")], MESH),
    "fix jack/pile": ("fix bad all jack/pile",
                      [("cone", "cone"), ("shaft", "shaft"), ("mode", "cyclic"), ("v", "0.5"),
                       ("stroke", "0.004"), ("v_unload", "0.05"), ("pause", "1e-4"),
                       ("depth", "0.01")], ""),
    "fix snapshot/hdf5": ("fix bad all snapshot/hdf5", [("file", "snap"), ("trigger", "v_t")],
                          "variable t equal step\n"),
    "compute stress/grain": ("compute bad all stress/grain",
                             [("pair_local", "pgl"), ("wall_local", "none")], ""),
}


def args_of(style, replace=None, drop=(), extra=""):
    """The good keyword list of `style` with {key: value} replaced, keys dropped
    and `extra` appended."""
    words = []
    for k, v in STYLES[style][1]:
        if k in drop:
            continue
        words += [k, (replace or {}).get(k, v)]
    return " ".join(words + ([extra] if extra else []))


def deck(style, args):
    command, _, before = STYLES[style]
    return PRELUDE + before + "%s %s\n" % (command, args)


# what the ERROR line must say, by kind of fault
def non_finite(key, value):
    return ["keyword '%s'" % key, "must be", "got %s" % value]


def not_a_number(key, value):
    return ["value '%s' of keyword '%s' is not a number; allowed: " % (value, key)]


def out_of_range(key, value):
    return ["keyword '%s'" % key, "must be", "got %s" % value]


def missing_value(key):
    return ["keyword '%s' needs a value" % key]


def unknown(key):
    return ["unknown keyword '%s'; expected " % key]


def repeated(key):
    return ["keyword '%s' is given twice" % key]


def case(style, name, args, expected):
    return pytest.param(style, args, expected, id="%s-%s" % (style.split()[1], name))


def numeric_cases(style, key, values):
    """One case per bad value of a number-valued keyword."""
    out = []
    for v in values:
        if v in ("nan", "inf", "1e999"):
            exp = non_finite(key, v)
        elif v[0].isalpha():
            exp = not_a_number(key, v)
        else:
            exp = out_of_range(key, v)
        out.append(case(style, "%s_%s" % (key, v), args_of(style, replace={key: v}), exp))
    return out


def optional_cases(style, key, values):
    """Bad values of an optional keyword, appended to the good line."""
    out = []
    for v in values:
        exp = non_finite(key, v) if v in ("nan", "inf", "1e999") else (
            not_a_number(key, v) if v[0].isalpha() else out_of_range(key, v))
        out.append(case(style, "%s_%s" % (key, v), args_of(style, extra="%s %s" % (key, v)), exp))
    return out


CRUSH, DAMP, SERVO = "fix crush/particle", "fix damp/local", "fix servo/radial"
JACK, SNAP, STRESS = "fix jack/pile", "fix snapshot/hdf5", "compute stress/grain"

CASES = (
    # --- fix crush/particle: strength, modulus, reference size, scatter and
    # comminution limit took inf and 1e999 before the shared parser
    numeric_cases(CRUSH, "sigma_lim0", ["inf", "1e999", "strong"])
    + numeric_cases(CRUSH, "m", ["inf", "1e999", "-10"])
    + numeric_cases(CRUSH, "d0", ["inf", "1e999", "-0.002"])
    + numeric_cases(CRUSH, "var", ["inf", "1e999", "nan"])
    + numeric_cases(CRUSH, "d_comm", ["inf", "1e999", "0"])
    + numeric_cases(CRUSH, "scale", ["nan", "1e999"])
    + numeric_cases(CRUSH, "seed", ["inf", "1e999"])
    + optional_cases(CRUSH, "d_max", ["inf", "1e999"])
    + optional_cases(CRUSH, "d_min", ["nan"])
    + optional_cases(CRUSH, "omega", ["inf"])
    + optional_cases(CRUSH, "d_frag_min", ["inf"])
    + optional_cases(CRUSH, "dt_frac", ["nan"])
    + optional_cases(CRUSH, "density_scale", ["-1e-3", "inf", "fine"])
    # criterion readings: a word outside the list, f_min outside [0, 1)
    + [case(CRUSH, "pressure_max", args_of(CRUSH, extra="pressure max"),
            ["keyword 'pressure' must be 'mean' or 'peak', got 'max'"]),
       case(CRUSH, "force_total", args_of(CRUSH, extra="force total"),
            ["keyword 'force' must be 'normal' or 'sliding', got 'total'"]),
       case(CRUSH, "scatter_lognormal", args_of(CRUSH, extra="scatter lognormal"),
            ["keyword 'scatter' must be 'normal', 'truncated' or 'weibull', got 'lognormal'"]),
       case(CRUSH, "f_min_without_truncated", args_of(CRUSH, extra="f_min 0.5"),
            ["keyword 'f_min' belongs to 'scatter truncated'"]),
       case(CRUSH, "truncated_without_f_min", args_of(CRUSH, extra="scatter truncated"),
            ["'scatter truncated' needs keyword 'f_min'"])]
    + optional_cases(CRUSH, "f_min", ["1.5", "-0.1", "nan"])
    + [case(CRUSH, "missing_value", args_of(CRUSH, extra="dt_frac"), missing_value("dt_frac")),
       case(CRUSH, "unknown", args_of(CRUSH, extra="colour red"), unknown("colour")),
       case(CRUSH, "repeated", args_of(CRUSH, extra="m 12"), repeated("m"))]
    # --- fix damp/local (alpha 0 is allowed: no zero case)
    + numeric_cases(DAMP, "alpha", ["fast", "-0.1", "nan", "inf", "1e999"])
    + [case(DAMP, "missing_value", "alpha", missing_value("alpha")),
       case(DAMP, "unknown", args_of(DAMP, extra="colour red"), unknown("colour")),
       case(DAMP, "repeated", args_of(DAMP, extra="alpha 0.1"), repeated("alpha"))]
    # --- fix servo/radial
    + numeric_cases(SERVO, "target", ["high", "inf"])
    + numeric_cases(SERVO, "gain", ["-1", "1e999"])
    + numeric_cases(SERVO, "height", ["inf", "1e999"])
    + optional_cases(SERVO, "vmax", ["0", "nan"])
    + optional_cases(SERVO, "sector", ["inf"])
    + [case(SERVO, "axis_1e999", args_of(SERVO, extra="axis 1e999 0"),
            non_finite("axis", "1e999")),
       case(SERVO, "axis_nan", args_of(SERVO, extra="axis 0 nan"), non_finite("axis", "nan")),
       case(SERVO, "missing_value", args_of(SERVO, extra="vmax"), missing_value("vmax")),
       case(SERVO, "unknown", args_of(SERVO, extra="colour red"), unknown("colour")),
       case(SERVO, "repeated", args_of(SERVO, extra="target 2e5"), repeated("target"))]
    # --- fix jack/pile
    + numeric_cases(JACK, "v", ["fast", "inf"])
    + numeric_cases(JACK, "depth", ["0", "1e999"])
    + numeric_cases(JACK, "stroke", ["nan"])
    + numeric_cases(JACK, "v_unload", ["inf"])
    + numeric_cases(JACK, "pause", ["-1", "1e999"])
    + optional_cases(JACK, "zero_tol", ["inf"])
    + optional_cases(JACK, "pause_servo", ["nan"])
    + optional_cases(JACK, "surface", ["1e999"])
    + optional_cases(JACK, "sector", ["inf"])
    + optional_cases(JACK, "every", ["1e999", "1e12", "nan"])
    + [case(JACK, "missing_value", args_of(JACK, extra="every"), missing_value("every")),
       case(JACK, "unknown", args_of(JACK, extra="colour red"), unknown("colour")),
       case(JACK, "repeated", args_of(JACK, extra="v 0.4"), repeated("v"))]
    # --- fix snapshot/hdf5
    + optional_cases(SNAP, "leaving", ["push", "nan", "inf", "1e999"])
    + [case(SNAP, "leaving_second_inf", args_of(SNAP, extra="leaving 0 inf"),
            non_finite("leaving", "inf")),
       case(SNAP, "missing_value", args_of(SNAP, extra="contacts"), missing_value("contacts")),
       case(SNAP, "unknown", args_of(SNAP, extra="colour red"), unknown("colour")),
       case(SNAP, "repeated", args_of(SNAP, extra="trigger v_t"), repeated("trigger")),
       case(SNAP, "repeated_list", args_of(SNAP, extra="values v_t values v_u"),
            repeated("values"))]
    # --- compute stress/grain
    + [case(STRESS, "missing_value", args_of(STRESS, drop=("pair_local",), extra="pair_local"),
            missing_value("pair_local")),
       case(STRESS, "unknown", args_of(STRESS, extra="colour red"), unknown("colour")),
       case(STRESS, "repeated", args_of(STRESS, extra="pair_local pgl"), repeated("pair_local"))]
)


def _prepare(workdir):
    write_stl(str(workdir / "side.stl"), cylinder_triangles(0.03, -0.04, 0.04, 12), "side")


def _run(workdir, text, nprocs=1):
    """harness.run_deck; at 1 rank the binary is started without mpirun (an
    MPI singleton): mpirun waits about 2 s after a rank exits with an error,
    which would triple the time of this file."""
    _prepare(workdir)
    # -screen: LIGGGHTS' mesh code writes to the screen unchecked (crush_decks.py)
    flags = ["-log", harness.LOG_NAME, "-echo", "none", "-screen", "screen.txt"]
    try:
        if nprocs > 1:
            return harness.run_deck(text, workdir, nprocs=nprocs, timeout=TIMEOUT,
                                    extra_args=flags[-2:])
        (workdir / harness.DECK_NAME).write_text(text)
        cmd = [str(harness.liggghts_bin()), "-in", harness.DECK_NAME] + flags
        proc = subprocess.run(cmd, cwd=str(workdir), env=dict(os.environ, OMP_NUM_THREADS="1"),
                              stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE, timeout=TIMEOUT, universal_newlines=True,
                              errors="replace")
        log = workdir / harness.LOG_NAME
        return harness.RunResult(cmd, workdir, proc.returncode, proc.stdout, proc.stderr,
                                 log.read_text(errors="replace") if log.exists() else "")
    except Exception as exc:  # a hang (timeout): reported by the case
        return exc


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """Every deck of this file, run once, two at a time."""
    jobs = {}
    for p in CASES:
        style, args, _ = p.values
        jobs[p.id] = deck(style, args)
    for style in STYLES:
        jobs["good-" + style] = deck(style, args_of(style))
    with ThreadPoolExecutor(max_workers=WORKERS) as pool:
        futures = {name: pool.submit(_run, tmp_path_factory.mktemp("bad"), text)
                   for name, text in jobs.items()}
        return {name: f.result() for name, f in futures.items()}


@pytest.mark.parametrize("style", sorted(STYLES))
def test_good_line_is_accepted(runs, style):
    res = runs["good-" + style]
    if isinstance(res, Exception):
        raise res
    assert res.ok and not res.errors, res.summary()


@pytest.mark.parametrize("style, args, expected", CASES)
def test_bad_line_is_an_error_naming_the_keyword(runs, request, style, args, expected):
    res = runs[request.node.callspec.id]
    if isinstance(res, Exception):
        raise res
    assert not res.ok, "accepted: %s %s\n%s" % (STYLES[style][0], args, res.summary())
    mine = [e for e in res.errors if e.startswith("ERROR: %s: " % style)]
    assert mine, "no ERROR line from %s (a crash?)\n%s" % (style, res.summary())
    assert any(all(part in e for part in expected) for e in mine), (expected, mine)


def test_two_ranks(tmp_path):
    """Every rank parses the line and stops together: no hang at 2 ranks."""
    res = _run(tmp_path, deck(SERVO, args_of(SERVO, extra="gain 2e-6")), nprocs=2)
    if isinstance(res, Exception):
        raise res
    assert not res.ok
    assert any(repeated("gain")[0] in e for e in res.errors), res.summary()
