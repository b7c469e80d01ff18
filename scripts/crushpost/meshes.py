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


def rectangle_triangles(axis, coord, center, half_u, half_v, normal_sign=1):
    """Rectangle in the plane x[axis] = coord (two facets).

    The other two axes, in cyclic order after ``axis`` (u = axis+1, v = axis+2
    mod 3), span ``center[u] +- half_u`` and ``center[v] +- half_v``; ``center``
    is a 3-vector whose ``axis`` component is ignored. The facet normals point
    along ``normal_sign`` times the ``axis`` direction.
    """
    u, v = (axis + 1) % 3, (axis + 2) % 3

    def point(su, sv):
        p = [0.0, 0.0, 0.0]
        p[axis] = coord
        p[u] = center[u] + su * half_u
        p[v] = center[v] + sv * half_v
        return tuple(p)

    a, b, c, d = point(-1, -1), point(1, -1), point(1, 1), point(-1, 1)
    if normal_sign >= 0:          # u x v = +axis for cyclic (axis, u, v)
        return [(a, b, c), (a, c, d)]
    return [(a, c, b), (a, d, c)]


def write_rectangle_stl(path, axis, coord, center, half_u, half_v, normal_sign=1, name="plate"):
    """One rectangular plate (see :func:`rectangle_triangles`) as an ASCII STL file."""
    write_stl(path, rectangle_triangles(axis, coord, center, half_u, half_v, normal_sign), name)
