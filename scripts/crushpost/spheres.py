"""Measurement spheres (SPEC section 4 item 6) as a LIGGGHTS deck block.

The stress in a sphere of volume V is sigma = (1/V) sum_c F^c (x) L^c over its
contacts. LIGGGHTS' `compute stress/atom pair` gives every grain half of the
branch-vector/force product of each of its contacts, so summing it over the
grains whose centres lie in the sphere counts contacts between two such grains
fully and contacts that cross the sphere's surface by half; this is the usual
weighting of measurement spheres. Signs: LIGGGHTS reports stress*volume with
compression negative; the block outputs compression positive.

`measurement_sphere_block` writes the regions, computes and a `fix ave/time`
that appends one line per output step to a text file: step, then for each
sphere the six components xx yy zz xy xz yz (Pa). `write_sphere_block` writes
it to a file a deck can `include`; `chamber_sphere_centres` places spheres at
radii r/R and depths below the sample top (SPEC 4.6); `read_sphere_series`
reads the output. Command line: ``python3 -m crushpost spheres --help``.
"""

import numpy as np

COMPONENTS = ("xx", "yy", "zz", "xy", "xz", "yz")


def measurement_sphere_block(centres, radius, every, filename, group="all", prefix="ms"):
    """Deck text for spheres of radius `radius` at `centres` (n, 3), output every `every` steps."""
    centres = np.atleast_2d(np.asarray(centres, dtype=float))
    vol = 4.0 / 3.0 * np.pi * radius ** 3
    lines = ["# measurement spheres (written by crushpost.spheres)",
             "compute %s_sa %s stress/atom pair" % (prefix, group)]
    values = []
    for k, c in enumerate(centres):
        name = "%s%d" % (prefix, k + 1)
        lines.append("region %s_reg sphere %.10g %.10g %.10g %.10g units box"
                     % (name, c[0], c[1], c[2], radius))
        lines.append("compute %s %s reduce/region %s_reg sum %s"
                     % (name, group, name, " ".join("c_%s_sa[%d]" % (prefix, j) for j in range(1, 7))))
        for j in range(1, 7):
            lines.append("variable %s_%s equal -c_%s[%d]/%.12g"
                         % (name, COMPONENTS[j - 1], name, j, vol))
            values.append("v_%s_%s" % (name, COMPONENTS[j - 1]))
    lines.append("fix %s_out all ave/time %d 1 %d %s file %s"
                 % (prefix, every, every, " ".join(values), filename))
    return "\n".join(lines) + "\n"


def write_sphere_block(path, centres, radius, every, filename, group="all", prefix="ms"):
    """Write :func:`measurement_sphere_block` to ``path`` (a file to ``include``); returns the text."""
    text = measurement_sphere_block(centres, radius, every, filename, group=group, prefix=prefix)
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
