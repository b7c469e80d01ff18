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


def axis_plate_triangles(half_width, axis, offset=0.0):
    """Square plate of half-width h in the plane x_axis = offset (axis 0, 1, 2),
    centred on the axis, normal along +axis."""
    h = half_width
    corners = [(-h, -h), (h, -h), (h, h), (-h, h)]
    u, v = [(1, 2), (2, 0), (0, 1)][axis]  # in-plane axes, (u, v, axis) right-handed
    pts = []
    for a, b in corners:
        p = [0.0, 0.0, 0.0]
        p[axis], p[u], p[v] = offset, a, b
        pts.append(tuple(p))
    return [(pts[0], pts[1], pts[2]), (pts[0], pts[2], pts[3])]


def cylinder_triangles(radius, z_lo, z_hi, n_seg, center=(0.0, 0.0), inward=True):
    """Lateral surface of a cylinder with its axis along z through ``center``:
    ``n_seg`` vertical strips (two facets each) between z_lo and z_hi, nodes on
    the circle of ``radius`` (an inscribed polygon; its perimeter is
    2 n_seg radius sin(pi / n_seg)). No caps. Facet normals point to the axis
    when ``inward`` (a chamber wall), away from it otherwise. For fix
    servo/radial, which needs exactly this shape."""
    import math
    x0, y0 = center
    tris = []
    for k in range(n_seg):
        a0 = 2.0 * math.pi * k / n_seg
        a1 = 2.0 * math.pi * (k + 1) / n_seg
        b0 = (x0 + radius * math.cos(a0), y0 + radius * math.sin(a0), z_lo)
        b1 = (x0 + radius * math.cos(a1), y0 + radius * math.sin(a1), z_lo)
        t0 = (b0[0], b0[1], z_hi)
        t1 = (b1[0], b1[1], z_hi)
        if inward:
            tris += [(b0, t1, b1), (b0, t0, t1)]
        else:
            tris += [(b0, b1, t1), (b0, t1, t0)]
    return tris
