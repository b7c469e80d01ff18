# SPDX-License-Identifier: GPL-2.0-or-later
"""The calibrated constants of the package, in one place: Fontainebleau NE34
(docs/model.md §3), the steel of the pile and platens, and the Rayleigh
time (docs/model.md §5).

This module is the Python home of these values; the deck home is
``inputs/materials_ne34.in`` (elastic constants, density, friction) with
``inputs/crushable_ne34.in`` (the crushing parameters of ``fix
crush/particle``) and ``inputs/integrate.in`` (local damping). ``DECK``
says, for each value, where the deck side has it;
tests/python/test_materials.py checks that the two sides agree, and
tests/python/test_constants_lint.py that no other tracked file writes out a
copy of the distinctive ones (``LINTED``).

Everything here is a plain float (or int) with the exact value a driver or
test wrote before, so a value computed from them is the same float.
Sizes are at real size (``N = 1``) in m; multiply by ``N`` for a scaled run.
"""

import math

__all__ = [
    "G_GRAIN", "NU_GRAIN", "E_GRAIN", "MU_GRAIN", "RHO_GRAIN",
    "G_STEEL", "NU_STEEL", "E_STEEL", "MU_PILE", "E_RIGID",
    "SIGMA_LIM0", "M_SIZE", "D0", "VAR", "D50", "CU", "E_MAX", "E_MIN",
    "D_COMM_RATIO", "D_MAX_BR", "D_MIN_BR", "OMEGA", "D_LOC",
    "DECK", "LINTED", "rayleigh_time",
]

# --------------------------------------------------------------------------
# The grain: Fontainebleau NE34 quartz (docs/model.md §3)
# --------------------------------------------------------------------------
#: grain shear modulus [Pa]; inputs/materials_ne34.in ``G_grain``
G_GRAIN = 9e9
#: grain Poisson ratio; inputs/materials_ne34.in ``nu_grain``
NU_GRAIN = 0.2
#: grain Young's modulus E = 2 G (1 + nu) = 21.6 GPa [Pa]; inputs/materials_ne34.in
#: ``E_grain`` (an equal-style variable of the same expression)
E_GRAIN = 2.0 * G_GRAIN * (1.0 + NU_GRAIN)
#: grain-grain friction coefficient; inputs/materials_ne34.in ``mu_grain``
MU_GRAIN = 0.275
#: grain density [kg/m3]; inputs/materials_ne34.in ``rho_grain``
RHO_GRAIN = 2600.0

# --------------------------------------------------------------------------
# Steel (pile, platens) and the other wall materials
# --------------------------------------------------------------------------
#: steel shear modulus [Pa]; inputs/materials_ne34.in ``G_steel``
G_STEEL = 85e9
#: steel Poisson ratio; inputs/materials_ne34.in ``nu_steel``
NU_STEEL = 0.2
#: steel Young's modulus E = 2 G (1 + nu) = 204 GPa [Pa]; inputs/materials_ne34.in
#: ``E_steel`` (an equal-style variable of the same expression)
E_STEEL = 2.0 * G_STEEL * (1.0 + NU_STEEL)
#: pile-sand interface friction tan(delta); inputs/materials_ne34.in ``mu_pile``
MU_PILE = 0.5
#: Young's modulus of the rigid symmetry planes (type 4) [Pa];
#: inputs/materials_ne34.in ``E_rigid``
E_RIGID = 1e21

# --------------------------------------------------------------------------
# Crushing (docs/model.md §2, §3): fix crush/particle of inputs/crushable_ne34.in
# --------------------------------------------------------------------------
#: reference strength sigma_lim0 [Pa]; inputs/crushable_ne34.in, keyword
#: ``sigma_lim0`` of ``fix crush``
SIGMA_LIM0 = 1.9e9
#: size-effect modulus m; inputs/crushable_ne34.in, keyword ``m`` of ``fix crush``
M_SIZE = 10.0
#: reference diameter d0 at N = 1 [m]; inputs/crushable_ne34.in, keyword ``d0``
#: of ``fix crush``
D0 = 2e-3
#: the scatter: standard deviation of the strength factor f ~ Normal(1, VAR)
#: (the fix's keyword is called ``var``); inputs/crushable_ne34.in, keyword
#: ``var`` of ``fix crush``
VAR = 0.36
#: median grain size d50 at N = 1 [m]; inputs/crushable_ne34.in ``d50``
#: (equal-style ``0.21e-3*${N}``)
D50 = 0.21e-3
#: coefficient of uniformity d60/d10 (about; the grading of crushpost.packing);
#: no deck value
CU = 1.47
#: index void ratios (about; the target porosity of docs/studies/calibration.md);
#: no deck value
E_MAX, E_MIN = 0.87, 0.53
#: comminution limit d_comm over d50; inputs/crushable_ne34.in ``d_comm_ratio``
D_COMM_RATIO = 0.55
#: largest and smallest diameter of the limit grading at N = 1 [m];
#: inputs/crushable_ne34.in ``d_max_Br``, ``d_min_Br`` (equal-style, times ``${N}``)
D_MAX_BR = 0.27e-3
D_MIN_BR = 0.01e-3
#: fractal dimension w of the limit grading; inputs/crushable_ne34.in, keyword
#: ``omega`` of ``fix crush``
OMEGA = 2.6
#: local damping D_loc; inputs/integrate.in ``D_loc``
D_LOC = 0.05

#: Where the deck side has each value: name here -> (block under inputs/, how
#: the block holds it, its name there). "index": ``variable NAME index VALUE``;
#: "equal": ``variable NAME equal EXPR`` (EXPR with ``*${N}`` for sizes, or
#: the E = 2 G (1 + nu) expression); "fix crush": the keyword of the ``fix
#: crush all crush/particle`` command. tests/python/test_materials.py reads
#: them all.
DECK = {
    "G_GRAIN": ("materials_ne34.in", "index", "G_grain"),
    "NU_GRAIN": ("materials_ne34.in", "index", "nu_grain"),
    "E_GRAIN": ("materials_ne34.in", "equal", "E_grain"),
    "MU_GRAIN": ("materials_ne34.in", "index", "mu_grain"),
    "RHO_GRAIN": ("materials_ne34.in", "index", "rho_grain"),
    "G_STEEL": ("materials_ne34.in", "index", "G_steel"),
    "NU_STEEL": ("materials_ne34.in", "index", "nu_steel"),
    "E_STEEL": ("materials_ne34.in", "equal", "E_steel"),
    "MU_PILE": ("materials_ne34.in", "index", "mu_pile"),
    "E_RIGID": ("materials_ne34.in", "index", "E_rigid"),
    "SIGMA_LIM0": ("crushable_ne34.in", "fix crush", "sigma_lim0"),
    "M_SIZE": ("crushable_ne34.in", "fix crush", "m"),
    "D0": ("crushable_ne34.in", "fix crush", "d0"),
    "VAR": ("crushable_ne34.in", "fix crush", "var"),
    "OMEGA": ("crushable_ne34.in", "fix crush", "omega"),
    "D50": ("crushable_ne34.in", "equal", "d50"),
    "D_COMM_RATIO": ("crushable_ne34.in", "index", "d_comm_ratio"),
    "D_MAX_BR": ("crushable_ne34.in", "equal", "d_max_Br"),
    "D_MIN_BR": ("crushable_ne34.in", "equal", "d_min_Br"),
    "D_LOC": ("integrate.in", "index", "D_loc"),
}

#: The values distinctive enough that no other tracked source file may write
#: them out (tests/python/test_constants_lint.py): any numeric literal equal
#: to one of them as a float (2600, 2600.0, 2.6e3 alike) is a copy. The other
#: values (0.2, 0.5, 10, 2e-3, 0.36, 0.55, ...) are common numbers and are not
#: linted. d50 is: the decks that need it before the grain block write it
#: out on a line tagged 'lint: calibrated-ok'.
LINTED = ("G_GRAIN", "E_GRAIN", "MU_GRAIN", "RHO_GRAIN", "G_STEEL", "E_STEEL", "SIGMA_LIM0", "D50")


def rayleigh_time(r, rho=RHO_GRAIN, G=G_GRAIN, nu=NU_GRAIN):
    """Rayleigh time of a sphere of radius ``r`` [m] (docs/model.md §5) [s]:
    T_R = pi r sqrt(rho / G) / (0.1631 nu + 0.8766), by default of the NE34
    grain (density ``rho`` [kg/m3], shear modulus ``G`` [Pa], Poisson ratio
    ``nu``)."""
    return math.pi * r * math.sqrt(rho / G) / (0.1631 * nu + 0.8766)
