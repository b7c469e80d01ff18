# SPDX-License-Identifier: GPL-2.0-or-later
"""Bad input to `fix crush/particle` gets a clear error naming the keyword,
and the time-step check of docs/model.md §5 (dt_check warn|error, dt_frac).

The time-step answers are computed here from docs/model.md §5:
T_R = pi r sqrt(rho/G) / (0.1631 nu + 0.8766) for the smallest particle that
can ever exist: the smallest fragment (r2 = 0.230093 r) of the smallest
breakable particle, a breakable particle being as small as d_comm
(r = r2 d_comm / 2), unless a particle that can never break is smaller, or
fragments finer than d_frag_min go to fines (r >= d_frag_min / 2).
"""

import re
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import crush_decks as cd  # noqa: E402

REQUIRED = [("sigma_lim0", "%g" % cd.SIGMA0), ("m", "10"), ("d0", "0.002"), ("scale", "1"),
            ("var", "0.36"), ("d_comm", "5e-4"), ("seed", str(cd.SEED))]
D_GRAIN = 1.0e-3


def args(drop=None, replace=None, extra=""):
    """Keyword list of the fix, without `drop`, with `replace` = {key: value}."""
    out = []
    for k, v in REQUIRED:
        if k == drop:
            continue
        out += [k, (replace or {}).get(k, v)]
    return " ".join(out) + (" " + extra if extra else "")


def deck(crush_args, dt=1e-9, atom_style="granular", newton="off", tangential="history",
         small=None, nsteps=0):
    """One 1 mm grain on a primitive wall (and optionally a second, `small`
    diameter grain far away); the fix; `run nsteps`."""
    if atom_style == "granular":
        setup = cd.header("-0.01 0.01 -0.01 0.01 -0.001 0.01",
                          [(cd.E_GRAIN, cd.NU_GRAIN, "grain"), (cd.E_STEEL, cd.NU_STEEL, "wall")],
                          newton=newton)
        setup = setup.replace("tangential history", "tangential " + tangential)
        setup += f"""\
timestep {dt!r}
create_atoms 1 single -0.002 0 0.0005 units box
set atom 1 diameter {D_GRAIN!r} density {cd.DENSITY!r}
"""
        if small:
            setup += (f"create_atoms 1 single 0.002 0 0.005 units box\n"
                      f"set atom 2 diameter {small!r} density {cd.DENSITY!r}\n")
        setup += ("fix bottom all wall/gran model hertz tangential history primitive "
                  "type 2 zplane 0.0\nfix integ all nve\n")
    else:
        setup = f"""\
units si
atom_style {atom_style}
atom_modify map array
boundary f f f
newton {newton}
region box block -0.01 0.01 -0.01 0.01 -0.01 0.01 units box
create_box 1 box
mass 1 1.0e-6
create_atoms 1 single 0 0 0 units box
timestep {dt!r}
thermo_modify lost error
"""
    return setup + f"fix crush all crush/particle {crush_args}\nrun {nsteps}\n"


def check_error(tmp_path, text, pattern, nprocs=1):
    res = cd.expect_error(text, tmp_path, pattern, nprocs=nprocs)
    # the message is an ERROR line of the fix and names what is wrong
    assert any(pattern in e for e in res.errors), res.errors
    return res


# ---------------------------------------------------------------------------
# the reference deck itself runs
# ---------------------------------------------------------------------------

def test_reference_deck_runs(tmp_path):
    res = cd.run(deck(args(), nsteps=10), tmp_path)
    assert res.ok and not res.errors


# ---------------------------------------------------------------------------
# required keywords
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("key", [k for k, _ in REQUIRED])
def test_missing_required_keyword(tmp_path, key):
    check_error(tmp_path, deck(args(drop=key)), f"missing required keyword '{key}'")


def test_missing_keyword_two_ranks(tmp_path):
    check_error(tmp_path, deck(args(drop="seed")), "missing required keyword 'seed'", nprocs=2)


@pytest.mark.parametrize("key,value,rule", [
    ("sigma_lim0", "0", "> 0"),
    ("m", "-1", "> 0"),
    ("d0", "0", "> 0"),
    ("scale", "0", "> 0"),
    ("d_comm", "0", "> 0"),
    ("var", "-0.1", ">= 0"),
])
def test_non_positive_values(tmp_path, key, value, rule):
    res = check_error(tmp_path, deck(args(replace={key: value})), f"keyword '{key}' must be {rule}")
    assert any(value in e for e in res.errors), res.errors     # the offending value is quoted


def test_var_zero_is_allowed(tmp_path):
    res = cd.run(deck(args(replace={"var": "0"})), tmp_path)
    assert res.ok


@pytest.mark.parametrize("seed", ["15485864",      # even
                                  "9973",          # prime but <= 10000
                                  "15485863.5"])   # not an integer
def test_seed_must_be_prime_above_10000(tmp_path, seed):
    check_error(tmp_path, deck(args(replace={"seed": seed})),
                "keyword 'seed' must be a prime number > 10000")


def test_seed_prime_accepted(tmp_path):
    res = cd.run(deck(args(replace={"seed": "10007"})), tmp_path)   # smallest prime > 10000
    assert res.ok


# ---------------------------------------------------------------------------
# syntax
# ---------------------------------------------------------------------------

def test_unknown_keyword(tmp_path):
    check_error(tmp_path, deck(args(extra="sigma_lim 1e9")), "unknown keyword 'sigma_lim'")


@pytest.mark.parametrize("key", ["seed", "events", "dt_check"])
def test_missing_value(tmp_path, key):
    # the keyword is the last word of the fix command
    if key == "seed":
        text = deck(args(drop="seed") + " seed")
    else:
        text = deck(args(extra=key))
    check_error(tmp_path, text, f"keyword '{key}' needs a value")


@pytest.mark.parametrize("key,value", [("m", "ten"), ("d0", "2mm"), ("var", "")])
def test_non_numeric_value(tmp_path, key, value):
    if value == "":
        value = "d_comm"          # a keyword where the value should be
        text = deck(args(drop="var", extra=f"var {value} 5e-4"))
        check_error(tmp_path, text, f"value '{value}' of keyword 'var' is not a number")
        return
    check_error(tmp_path, deck(args(replace={key: value})),
                f"value '{value}' of keyword '{key}' is not a number")


def test_dt_check_bad_value(tmp_path):
    res = check_error(tmp_path, deck(args(extra="dt_check maybe")), "keyword 'dt_check'")
    assert any("'warn' or 'error'" in e and "maybe" in e for e in res.errors), res.errors


@pytest.mark.parametrize("key", ["margin_skip", "events_append"])
def test_yes_no_bad_value(tmp_path, key):
    res = check_error(tmp_path, deck(args(extra=f"{key} maybe")), f"keyword '{key}'")
    assert any("'yes' or 'no'" in e and "maybe" in e for e in res.errors), res.errors


@pytest.mark.parametrize("value", ["0", "3.5"])
def test_omega_out_of_range(tmp_path, value):
    check_error(tmp_path, deck(args(extra=f"br omega {value}")), "keyword 'omega' must be in (0, 3]")


def test_omega_three_allowed(tmp_path):
    assert cd.run(deck(args(extra="br omega 3")), tmp_path).ok


@pytest.mark.parametrize("value", ["0", "1.5"])
def test_dt_frac_out_of_range(tmp_path, value):
    check_error(tmp_path, deck(args(extra=f"dt_frac {value}")), "keyword 'dt_frac' must be in (0, 1]")


def test_d_frag_min_negative(tmp_path):
    check_error(tmp_path, deck(args(extra="d_frag_min -1e-5")), "keyword 'd_frag_min' must be >= 0")


@pytest.mark.parametrize("extra", ["br d_max 1e-5 d_min 1e-5",
                                   "d_max 1e-6"])       # below the default d_min = 0.01 mm * N
def test_d_max_not_above_d_min(tmp_path, extra):
    check_error(tmp_path, deck(args(extra=extra)), "'d_max' must be larger than 'd_min'")


def test_d_min_positive(tmp_path):
    check_error(tmp_path, deck(args(extra="d_min 0")), "keyword 'd_min' must be > 0")


def test_events_file_cannot_be_opened(tmp_path):
    # error->one of LIGGGHTS writes to the screen only (not to the log file),
    # so the screen goes to stdout here
    res = cd.expect_error(deck(args(extra="events no_such_dir/events.txt")), tmp_path,
                          "cannot open file 'no_such_dir/events.txt' given to keyword 'events'",
                          screen="/dev/stdout")
    assert res.errors


# ---------------------------------------------------------------------------
# set-up the fix cannot work with
# ---------------------------------------------------------------------------

def test_atom_style_without_radius(tmp_path):
    res = check_error(tmp_path, deck(args(), atom_style="atomic"), "fix crush/particle needs per-atom radius")
    assert any("atom_style granular" in e for e in res.errors), res.errors


@pytest.mark.parametrize("nprocs", [1, 2])
def test_newton_on(tmp_path, nprocs):
    # tangential no_history: pair gran with history would refuse newton on first
    res = check_error(tmp_path, deck(args(), newton="on", tangential="no_history"),
                      "crush/particle requires 'newton off'", nprocs)
    assert any("newton" in e for e in res.errors)


# ---------------------------------------------------------------------------
# time step check (docs/model.md §5)
# ---------------------------------------------------------------------------

def smallest_radius(d_comm, grains=(D_GRAIN,), d_frag_min=0.0):
    """Smallest particle radius that can ever occur in the deck."""
    radii = []
    for d in grains:
        if d >= d_comm:     # breakable: down to fragments of a particle at d_comm
            radii.append(max(cd.R2_RATIO * 0.5 * d_comm, 0.5 * d_frag_min))
        radii.append(0.5 * d)
    return min(radii)


def dt_limit(r_min, dt_frac=0.2):
    return dt_frac * cd.rayleigh_time(r_min)


def _dt_line(res):
    m = re.search(r"smallest radius that can occur (\S+), its Rayleigh time T_R (\S+), "
                  r"dt/T_R = (\S+)", res.all_text)
    assert m, res.summary()
    return float(m.group(1)), float(m.group(2)), float(m.group(3))


def _dt_warnings(res):
    # the Rayleigh check's warning (the stiffest-contact one, "dt_omega", is
    # tested in test_stability.py)
    return [w for w in res.warnings if "crush/particle" in w and "dt_frac * T_R" in w]


@pytest.mark.parametrize("case", [
    # d_comm 0.5 mm: fragments of a 0.5 mm particle, r = r2 * 0.25 mm
    dict(d_comm=5e-4, grains=(D_GRAIN,), extra="", small=None),
    # the same with dt_frac 0.1
    dict(d_comm=5e-4, grains=(D_GRAIN,), extra="", small=None, dt_frac=0.1),
    # a 0.1 mm grain below d_comm: it never breaks but is the smallest
    dict(d_comm=5e-4, grains=(D_GRAIN, 1e-4), extra="", small=1e-4),
    # fragments finer than d_frag_min go to fines
    dict(d_comm=5e-4, grains=(D_GRAIN,), extra="d_frag_min 1.5e-4", small=None, dfm=1.5e-4),
    # d_comm above every grain: nothing can break, the grain itself counts
    dict(d_comm=2e-3, grains=(D_GRAIN,), extra="", small=None),
], ids=["d_comm", "dt_frac", "unbreakable_small", "d_frag_min", "nothing_breaks"])
def test_dt_check_threshold(tmp_path, case):
    """The limit dt_frac * T_R(smallest radius that can occur), from Python:
    0.99 of it runs silently, 1.01 of it warns (same check as dt_check error)."""
    dt_frac = case.get("dt_frac", 0.2)
    r_min = smallest_radius(case["d_comm"], case["grains"], case.get("dfm", 0.0))
    limit = dt_limit(r_min, dt_frac)
    extra = case["extra"] + (f" dt_frac {dt_frac}" if "dt_frac" in case else "")
    base = args(replace={"d_comm": repr(case["d_comm"])}, extra=extra)
    ok = cd.run(deck(base, dt=0.99 * limit, small=case["small"]), tmp_path / "ok")
    r, T_R, ratio = _dt_line(ok)
    assert r == pytest.approx(r_min, rel=1e-5)
    assert T_R == pytest.approx(cd.rayleigh_time(r_min), rel=1e-5)
    assert ratio == pytest.approx(0.99 * dt_frac, rel=1e-5)
    assert not _dt_warnings(ok)
    warn = cd.run(deck(base, dt=1.01 * limit, small=case["small"]), tmp_path / "warn")
    assert len(_dt_warnings(warn)) == 1, warn.warnings
    assert _dt_line(warn)[2] == pytest.approx(1.01 * dt_frac, rel=1e-5)


@pytest.mark.parametrize("nprocs", [1, 2])
def test_dt_check_error(tmp_path, nprocs):
    limit = dt_limit(smallest_radius(5e-4))
    res = check_error(tmp_path, deck(args(extra="dt_check error"), dt=2 * limit),
                      "fix crush/particle: time step", nprocs)
    err = [e for e in res.errors if "time step" in e][0]
    assert "exceeds dt_frac * T_R" in err and "reduce the time step" in err


@pytest.mark.parametrize("explicit", [True, False])
@pytest.mark.parametrize("nprocs", [1, 2])
def test_dt_check_warn(tmp_path, nprocs, explicit):
    """Default (or `dt_check warn`): the run goes on, with one warning that
    gives the time step, the limit and the radius."""
    r_min = smallest_radius(5e-4)
    limit = dt_limit(r_min)
    dt = 2 * limit
    extra = "dt_check warn" if explicit else ""
    res = cd.run(deck(args(extra=extra), dt=dt, nsteps=5), tmp_path, nprocs=nprocs)
    assert res.ok and not res.errors
    warns = _dt_warnings(res)
    log_warns = [ln for ln in res.log.splitlines() if ln.startswith("WARNING") and "dt_frac * T_R" in ln]
    assert len(warns) == 1 and len(log_warns) == 1, warns      # once, not once per rank
    w = warns[0]
    assert "exceeds dt_frac * T_R" in w and "reduce the time step" in w
    nums = [float(x) for x in re.findall(r"[-+]?\d+\.?\d*(?:e[-+]?\d+)?", w.split("(/")[0])]
    assert any(x == pytest.approx(dt, rel=1e-5) for x in nums), w
    assert any(x == pytest.approx(cd.rayleigh_time(r_min), rel=1e-5) for x in nums), w
    assert any(x == pytest.approx(r_min, rel=1e-5) for x in nums), w
