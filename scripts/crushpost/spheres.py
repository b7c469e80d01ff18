# SPDX-License-Identifier: GPL-2.0-or-later
"""Measurement spheres (docs/model.md §4.6) as a LIGGGHTS deck block.

The stress in a sphere of volume V is sigma = (1/V) sum_c F^c (x) L^c over its
contacts. The block sums V_p sigma_p over the grains whose centres lie in the
sphere, with sigma_p the per-particle stress of `compute stress/grain`
(sigma_p = -(1/V_p) sum_c s^c (x) F^c over every contact of p, walls, symmetry
planes, cone and shaft included; docs/compute_stress_grain.md). In that sum a
contact between two grains of the sphere contributes s_p F - s_q F = its
branch vector (x) F in full; a contact across the sphere's surface the part
from the inside grain's centre to the contact point (half the branch vector
between equal grains); a wall or pile contact the vector from the centre to
the contact point. So a sphere that touches the pile shaft or a wall counts
those contacts too. The sphere's volume V must lie inside the sample:
:func:`check_chamber_spheres` says whether a set of spheres does, and which
wall a sphere crosses. Output is compression positive (stress/grain's sign).

`measurement_sphere_block` writes the regions, computes and a `fix ave/time`
that appends one line per output step to a text file: step, then for each
sphere the six components xx yy zz xy xz yz (Pa; the symmetric part).
`write_sphere_block` writes it to a file a deck can `include` (after the
block that defines the stress compute, inputs/contacts_local.in);
`chamber_sphere_centres` places spheres at radii r/R and depths below the
sample top (docs/model.md §4.6); `read_sphere_series` reads the output. Command line:
``crushpost spheres --help``.
"""

import numpy as np

COMPONENTS = ("xx", "yy", "zz", "xy", "xz", "yz")


def measurement_sphere_block(centres, radius, every, filename, group="all", prefix="ms",
                             stress="sigma_p"):
    """Deck text for spheres of radius `radius` at `centres` (n, 3), output every
    `every` steps, from the per-atom compute `stress` (compute stress/grain,
    defined by inputs/contacts_local.in as ``sigma_p``)."""
    centres = np.atleast_2d(np.asarray(centres, dtype=float))
    vol = 4.0 / 3.0 * np.pi * radius ** 3
    lines = ["# measurement spheres (written by crushpost.spheres): (1/V) sum of V_p sigma_p",
             "# over the grains whose centres are in each sphere; needs compute %s" % stress,
             "variable %s_Vp atom 4.0/3.0*PI*r*r*r" % prefix]
    for j in range(1, 7):
        lines.append("variable %s_s%d atom c_%s[%d]*v_%s_Vp" % (prefix, j, stress, j, prefix))
    values = []
    for k, c in enumerate(centres):
        name = "%s%d" % (prefix, k + 1)
        lines.append("region %s_reg sphere %.10g %.10g %.10g %.10g units box"
                     % (name, c[0], c[1], c[2], radius))
        lines.append("compute %s %s reduce/region %s_reg sum %s"
                     % (name, group, name, " ".join("v_%s_s%d" % (prefix, j) for j in range(1, 7))))
        for j in range(1, 7):
            lines.append("variable %s_%s equal c_%s[%d]/%.12g"
                         % (name, COMPONENTS[j - 1], name, j, vol))
            values.append("v_%s_%s" % (name, COMPONENTS[j - 1]))
    lines.append("fix %s_out all ave/time %d 1 %d %s file %s"
                 % (prefix, every, every, " ".join(values), filename))
    return "\n".join(lines) + "\n"


def write_sphere_block(path, centres, radius, every, filename, group="all", prefix="ms",
                       stress="sigma_p"):
    """Write :func:`measurement_sphere_block` to ``path`` (a file to ``include``); returns the text."""
    text = measurement_sphere_block(centres, radius, every, filename, group=group, prefix=prefix,
                                    stress=stress)
    with open(path, "w") as fh:
        fh.write(text)
    return text


def chamber_sphere_centres(r_over_R, depths, pile_radius, z_top, axis_xy=(0.0, 0.0), azimuth_deg=0.0):
    """Centres (n, 3) of spheres at every radius r = r_over_R * pile_radius from
    the pile axis (along the azimuth ``azimuth_deg`` from +x) and every depth
    below ``z_top`` (the sample top), radii varying fastest."""
    phi = np.radians(azimuth_deg)
    out = []
    for depth in np.atleast_1d(np.asarray(depths, dtype=float)):
        for q in np.atleast_1d(np.asarray(r_over_R, dtype=float)):
            r = q * pile_radius
            out.append((axis_xy[0] + r * np.cos(phi), axis_xy[1] + r * np.sin(phi), z_top - depth))
    return np.array(out, dtype=float).reshape(-1, 3)


def check_chamber_spheres(centres, radius, R_side, z_bottom, z_top, R_pile=0.0, sector=360,
                          z_tip_final=None, axis_xy=(0.0, 0.0)):
    """Check that measurement spheres lie inside the sample of a chamber.

    A sphere's stress is (1/V) times the sum over its grains, so its whole
    volume V must be sand: inside the lateral wall (radius ``R_side``), above
    the bottom ``z_bottom``, below the top wall ``z_top``, on the sector's
    side of its symmetry planes (sector 180: y >= 0; 90: x, y >= 0), and out
    of the pile's path (radius ``R_pile`` about the axis, down to
    ``z_tip_final``, the lowest apex; None: all the way down). Touching is
    allowed: the block counts wall and pile contacts (stress/grain). Pass the
    positions the walls can have while the spheres report (e.g. the lowest
    top wall, the smallest lateral radius).

    Raises ValueError naming the first sphere (1-based, as in the block's
    IDs), its centre and the wall it crosses; returns the smallest clearance
    (m) of the spheres to any of them.
    """
    c = np.atleast_2d(np.asarray(centres, dtype=float)).reshape(-1, 3)
    if not radius > 0:
        raise ValueError("sphere radius must be > 0, got %r" % (radius,))
    if sector not in (360, 180, 90):
        raise ValueError("sector must be 360, 180 or 90 degrees, got %r" % (sector,))
    x, y, z = c[:, 0] - axis_xy[0], c[:, 1] - axis_xy[1], c[:, 2]
    rho = np.hypot(x, y)
    # spheres wholly below the pile's final apex are never reached by it
    below = np.zeros(len(c), dtype=bool) if z_tip_final is None else z + radius <= z_tip_final
    walls = [("the lateral wall (r = %.6g m)" % R_side, R_side - rho - radius),
             ("the bottom (z = %.6g m)" % z_bottom, z - radius - z_bottom),
             ("the top wall (z = %.6g m)" % z_top, z_top - z - radius)]
    if R_pile > 0:
        walls.append(("the pile's path (r = %.6g m)" % R_pile,
                      np.where(below, np.inf, rho - radius - R_pile)))
    if sector in (180, 90):
        walls.append(("the symmetry plane y = 0", y - radius))
    if sector == 90:
        walls.append(("the symmetry plane x = 0", x - radius))
    tol = 1e-12 * max(1.0, float(np.max(np.abs(c))), radius)
    clearance = np.inf
    for k in range(len(c)):
        for name, gap in walls:
            if gap[k] < -tol:
                raise ValueError("measurement sphere %d (centre %.6g %.6g %.6g m, radius %.6g m) "
                                 "crosses %s by %.3g m" % (k + 1, c[k, 0], c[k, 1], c[k, 2],
                                                          radius, name, -gap[k]))
            clearance = min(clearance, float(gap[k]))
    return clearance


def read_sphere_series(path, n_spheres):
    """Steps (m,) and stresses (m, n_spheres, 3, 3) from a measurement-sphere file."""
    data = np.loadtxt(path, comments="#", ndmin=2)
    steps = data[:, 0].astype(np.int64)
    comp = data[:, 1:].reshape(len(steps), n_spheres, 6)
    sigma = np.empty((len(steps), n_spheres, 3, 3))
    idx = {"xx": (0, 0), "yy": (1, 1), "zz": (2, 2), "xy": (0, 1), "xz": (0, 2), "yz": (1, 2)}
    for k, name in enumerate(COMPONENTS):
        i, j = idx[name]
        sigma[:, :, i, j] = comp[:, :, k]
        sigma[:, :, j, i] = comp[:, :, k]
    return steps, sigma
