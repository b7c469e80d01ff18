"""ASCII STL meshes for LIGGGHTS walls (fix mesh/surface): plates, and later
the chamber and pile. Normals follow the right-hand rule of each facet."""

import numpy as np


def _facet(f, a, b, c):
    n = np.cross(np.subtract(b, a), np.subtract(c, a))
    n = n / np.linalg.norm(n)
    f.write(" facet normal %.9g %.9g %.9g\n  outer loop\n" % tuple(n))
    for p in (a, b, c):
        f.write("   vertex %.12g %.12g %.12g\n" % tuple(p))
    f.write("  endloop\n endfacet\n")


def write_stl(path, triangles, name="mesh"):
    """Write triangles (iterable of three 3-vectors) as an ASCII STL solid."""
    with open(path, "w") as f:
        f.write("solid %s\n" % name)
        for a, b, c in triangles:
            _facet(f, a, b, c)
        f.write("endsolid %s\n" % name)


def plate_triangles(half_width, z=0.0):
    """Square plate |x|, |y| <= half_width in the plane z, normal +z (two facets)."""
    h = half_width
    p = [(-h, -h, z), (h, -h, z), (h, h, z), (-h, h, z)]
    return [(p[0], p[1], p[2]), (p[0], p[2], p[3])]


def write_plate_stl(path, half_width, z=0.0):
    write_stl(path, plate_triangles(half_width, z), "plate")
