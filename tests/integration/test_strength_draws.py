# SPDX-License-Identifier: GPL-2.0-or-later
"""Deck-level tests of the strength draws of `fix crush/particle` (docs/model.md §2.5):

    sigma_lim = sigma_lim0 * f * (d / (N d0)) ^ (-3/m),   f ~ Normal(1, var),

non-positive f redrawn, f a function of the seed and the atom's tag only.

c. 103,823 grains on a simple-cubic lattice (pitch 3 mm, no contacts, no
   walls), five diameters 0.2 to 2 mm (a decade) in blocks of tags, `run 0`,
   dumped with `id radius f_crush[1] f_crush[2]` at full precision.  From
   f = sigma_lim / (sigma_lim0 (d / (N d0))^(-3/m)):
   - f > 0 everywhere; the mean of f within 1 % of 1; the mean and standard
     deviation within 1 % of, and within 4 standard errors of, the exact
     moments of Normal(1, var) truncated to f > 0 (mean 1.00304, sd 0.35574:
     redrawing the non-positive draws lowers the sd by 1.2 % at var = 0.36, so
     the raw sample sd is *not* within 1 % of var by construction); the
     maximum-likelihood fit of a normal truncated at 0 gives back mean 1 and
     sd var within 1 %; a Kolmogorov-Smirnov test against that law;
   - the size-effect exponent from a least-squares fit of log sigma_lim
     against log d: within 2 % of -3/m for m = 10, N = 1 and m = 5, N = 39;
   - f itself does not depend on m, N or d0 (same seed: same f per tag);
   - var 0 gives f = 1 exactly (to round-off);
   - the per-atom sigma_lim values are bit-identical at 1 and 2 ranks (the
     lattice is split at x = 0.07 m), and a different seed gives other draws
     (uncorrelated with the first ones).
"""

import math
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy import optimize, stats

sys.path.insert(0, str(Path(__file__).resolve().parent))
import crush_multi as cm  # noqa: E402
import harness  # noqa: E402
from crushpost.materials import D0, E_GRAIN, MU_GRAIN, RHO_GRAIN, VAR  # noqa: E402
from crushpost.materials import SIGMA_LIM0 as SIGMA0  # noqa: E402

SEED = 15485863
SEED2 = 32452843                     # another prime > 10000
PITCH = 0.003
NSIDE = 47                           # 47^3 = 103823 grains
NATOMS = NSIDE ** 3
DIAMETERS = (0.0002, 0.0004, 0.0007, 0.0012, 0.002)     # 0.2 mm .. 2 mm
BLOCK = 20000                         # tags 1..20000 -> first diameter, ...


def _groups():
    lines = []
    for k, d in enumerate(DIAMETERS):
        lo = k * BLOCK + 1
        if k < len(DIAMETERS) - 1:
            lines.append(f"group g{k} id <> {lo} {lo + BLOCK - 1}")
        else:
            lines.append(f"group g{k} id >= {lo}")
        lines.append(f"set group g{k} diameter {d!r} density {RHO_GRAIN:g}")
    return "\n".join(lines)


DECK = cm.preamble() + f"""\
processors      * 1 1
region          box block 0 {NSIDE * PITCH - PITCH / 2!r} 0 {NSIDE * PITCH - PITCH / 2!r} 0 {NSIDE * PITCH - PITCH / 2!r} units box
create_box      1 box
lattice         sc {PITCH!r}
create_atoms    1 box
neighbor        1e-4 bin
neigh_modify    delay 0
fix m1 all property/global youngsModulus peratomtype {E_GRAIN!r}
fix m2 all property/global poissonsRatio peratomtype 0.2
fix m3 all property/global coefficientRestitution peratomtypepair 1 0.5
fix m4 all property/global coefficientFriction peratomtypepair 1 {MU_GRAIN:g}
pair_style      gran model hertz tangential history
pair_coeff      * *
{_groups()}
timestep        4e-9
fix integ all nve
fix crush all crush/particle sigma_lim0 {SIGMA0!r} m ${{m}} d0 {D0!r} scale ${{N}} var ${{var}} d_comm 1e-4 seed ${{seed}}
dump d all custom 1 strength.txt id radius f_crush[1] f_crush[2]
dump_modify d sort id format "%d %.17g %.17g %.17g"
thermo_style    custom step atoms f_crush[1] f_crush[2]
thermo_modify   lost error
run 0
"""

_RUNS = {}


def _draws(tmp_path_factory, m=10, N=1, var=VAR, seed=SEED, nprocs=1):
    """Run the deck once per parameter set; returns (ids, d, sigma, f, res)."""
    key = (m, N, var, seed, nprocs)
    if key not in _RUNS:
        workdir = tmp_path_factory.mktemp(f"draws_m{m}_N{N}_v{var}_s{seed}_np{nprocs}")
        res = harness.run_deck(DECK, workdir, nprocs=nprocs, timeout=300, check=True,
                               variables={"m": m, "N": N, "var": var, "seed": seed})
        (frame,) = harness.read_dump(res.path("strength.txt"))
        assert frame.natoms == NATOMS and len(frame) == NATOMS
        ids = frame["id"].astype(np.int64)
        np.testing.assert_array_equal(ids, np.arange(1, NATOMS + 1))
        d = 2.0 * frame["radius"]
        sigma = frame["f_crush[1]"]
        np.testing.assert_array_equal(frame["f_crush[2]"], 0.0)      # generation 0
        f = sigma / (SIGMA0 * (d / (N * D0)) ** (-3.0 / m))
        if nprocs == 2:
            assert "2 by 1 by 1 MPI processor grid" in res.log
        (blk,) = res.thermo
        assert blk["Atoms"][-1] == NATOMS and blk["crush[1]"][-1] == 0   # nothing broke
        _RUNS[key] = (ids, d, sigma, f, res)
    return _RUNS[key]


def _truncnorm(var):
    return stats.truncnorm(-1.0 / var, np.inf, loc=1.0, scale=var)


def test_sizes_as_built(tmp_path_factory):
    ids, d, _, _, _ = _draws(tmp_path_factory)
    expect = np.array(DIAMETERS)[np.minimum((ids - 1) // BLOCK, len(DIAMETERS) - 1)]
    np.testing.assert_allclose(d, expect, rtol=1e-15)
    assert d.max() / d.min() == pytest.approx(10.0)


def test_moments_of_strength_factor(tmp_path_factory):
    _, d, _, f, _ = _draws(tmp_path_factory)
    n = len(f)
    assert np.all(f > 0)
    mean, sd = f.mean(), f.std(ddof=1)
    tn = _truncnorm(VAR)
    assert mean == pytest.approx(1.0, rel=0.01)
    assert mean == pytest.approx(tn.mean(), rel=0.01)
    assert sd == pytest.approx(tn.std(), rel=0.01)
    # exact moments of the truncated normal (truncation: mean +0.3 %, sd -1.2 %)
    assert abs(mean - tn.mean()) < 4 * tn.std() / math.sqrt(n), (mean, tn.mean())
    # sd of the sample sd ~ sd * sqrt((kurtosis_excess + 2) / (4 n))
    k_ex = tn.stats(moments="k")
    se_sd = tn.std() * math.sqrt((float(k_ex) + 2.0) / (4.0 * n))
    assert abs(sd - tn.std()) < 4 * se_sd, (sd, tn.std())
    # the same for every size class (f does not depend on d)
    for dk in DIAMETERS:
        fk = f[d == dk]
        assert abs(fk.mean() - tn.mean()) < 4 * tn.std() / math.sqrt(len(fk)), dk


def _fit_truncated_normal(f):
    """Maximum-likelihood (mu, sd) of a normal truncated to f > 0."""
    def nll(p):
        mu, sd = p
        if sd <= 0:
            return np.inf
        return -(np.sum(stats.norm.logpdf(f, mu, sd)) - len(f) * stats.norm.logsf(0.0, mu, sd))
    res = optimize.minimize(nll, [f.mean(), f.std()], method="Nelder-Mead",
                            options={"xatol": 1e-7, "fatol": 1e-7})
    assert res.success, res
    return res.x


def test_distribution_is_truncated_normal(tmp_path_factory):
    _, _, _, f, _ = _draws(tmp_path_factory)
    ks = stats.kstest(f, _truncnorm(VAR).cdf)
    assert ks.pvalue > 1e-3, ks
    mu, sd = _fit_truncated_normal(f)
    assert mu == pytest.approx(1.0, rel=0.01)
    assert sd == pytest.approx(VAR, rel=0.01)


@pytest.mark.parametrize("m, N", [(10, 1), (5, 39)])
def test_size_effect_exponent(tmp_path_factory, m, N):
    _, d, sigma, f, _ = _draws(tmp_path_factory, m=m, N=N)
    slope, _ = np.polyfit(np.log(d), np.log(sigma), 1)
    assert slope == pytest.approx(-3.0 / m, rel=0.02), slope
    # the prefactor: at d = N d0 the median strength is sigma_lim0 times the
    # median of f (intercept of the fit through the class medians)
    med = np.array([np.median(sigma[d == dk]) for dk in DIAMETERS])
    s2, c2 = np.polyfit(np.log(np.array(DIAMETERS) / (N * D0)), np.log(med), 1)
    assert s2 == pytest.approx(-3.0 / m, rel=0.02)
    assert math.exp(c2) == pytest.approx(SIGMA0 * _truncnorm(VAR).median(), rel=0.02)


def test_factor_independent_of_size_law(tmp_path_factory):
    """Same seed and tags: the same f whatever m, N (the law only scales it)."""
    _, _, _, f10, _ = _draws(tmp_path_factory, m=10, N=1)
    _, _, _, f5, _ = _draws(tmp_path_factory, m=5, N=39)
    np.testing.assert_allclose(f5, f10, rtol=1e-13)


def test_no_scatter_with_var_zero(tmp_path_factory):
    _, d, sigma, f, _ = _draws(tmp_path_factory, var=0.0)
    np.testing.assert_allclose(f, 1.0, rtol=1e-14)
    np.testing.assert_allclose(sigma, SIGMA0 * (d / D0) ** -0.3, rtol=1e-14)


def test_draws_same_at_1_and_2_ranks(tmp_path_factory):
    _, _, s1, _, _ = _draws(tmp_path_factory, nprocs=1)
    _, _, s2, _, _ = _draws(tmp_path_factory, nprocs=2)
    np.testing.assert_array_equal(s1, s2)


def test_other_seed_other_draws(tmp_path_factory):
    _, _, s1, f1, _ = _draws(tmp_path_factory, seed=SEED)
    _, _, s2, f2, _ = _draws(tmp_path_factory, seed=SEED2)
    assert np.sum(s1 == s2) == 0
    assert abs(np.corrcoef(f1, f2)[0, 1]) < 0.02
    # and the second seed is just as good a sample of the same law
    tn = _truncnorm(VAR)
    assert abs(f2.mean() - tn.mean()) < 4 * tn.std() / math.sqrt(len(f2))
    assert f2.std(ddof=1) == pytest.approx(tn.std(), rel=0.01)
