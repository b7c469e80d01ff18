# SPDX-License-Identifier: GPL-2.0-or-later
"""ASCII STL meshes for LIGGGHTS walls (fix mesh/surface): plates, cylinder
walls, and the cone-ended pile (cone tip and shaft as separate meshes).
Normals follow the right-hand rule of each facet."""

import math
import os

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


def plate_triangles(half_width, z=0.0, lo=None):
    """Square plate |x|, |y| <= half_width in the plane z, normal +z (two facets).
    ``lo`` = (x_lo, y_lo): the plate spans x_lo <= x <= half_width,
    y_lo <= y <= half_width instead (the bottom of a chamber sector)."""
    h = half_width
    xl, yl = (-h, -h) if lo is None else lo
    p = [(xl, yl, z), (h, yl, z), (h, h, z), (xl, h, z)]
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


def _arc_segments(n_seg, phi0, phi1):
    """Start and end angles (radians) of the n_seg equal segments of the arc
    from azimuth phi0 to phi1 (degrees)."""
    span = math.radians(phi1 - phi0)
    return [(math.radians(phi0) + span * k / n_seg, math.radians(phi0) + span * (k + 1) / n_seg)
            for k in range(n_seg)]


def cylinder_triangles(radius, z_lo, z_hi, n_seg, center=(0.0, 0.0), inward=True,
                       phi0=0.0, phi1=360.0):
    """Lateral surface of a cylinder with its axis along z through ``center``:
    ``n_seg`` vertical strips (two facets each) between z_lo and z_hi, nodes on
    the circle of ``radius`` (an inscribed polygon; its perimeter is
    2 n_seg radius sin(pi / n_seg)). No caps. Facet normals point to the axis
    when ``inward`` (a chamber wall), away from it otherwise. For fix
    servo/radial, which needs exactly this shape. ``phi0``, ``phi1`` (degrees,
    default the full circle): an arc of the cylinder from azimuth phi0 to phi1
    (``n_seg`` strips over the arc), the side wall of a chamber sector."""
    x0, y0 = center
    tris = []
    for a0, a1 in _arc_segments(n_seg, phi0, phi1):
        b0 = (x0 + radius * math.cos(a0), y0 + radius * math.sin(a0), z_lo)
        b1 = (x0 + radius * math.cos(a1), y0 + radius * math.sin(a1), z_lo)
        t0 = (b0[0], b0[1], z_hi)
        t1 = (b1[0], b1[1], z_hi)
        if inward:
            tris += [(b0, t1, b1), (b0, t0, t1)]
        else:
            tris += [(b0, b1, t1), (b0, t1, t0)]
    return tris


# --------------------------------------------------------------------------
# pile: cone tip and cylindrical shaft (docs/model.md §4.5)
# --------------------------------------------------------------------------
#
# The pile axis is the z axis. The cone's apex points down, at z = tip_z; its
# base (radius R) is at z = tip_z + cone_height(R). The shaft is the lateral
# surface of a cylinder of radius R from the cone base up to
# z = tip_z + cone_height(R) + shaft_length. Both are open surfaces (no base
# disc, no top cap): grains only ever touch the outside. Their boundary rings
# share the same n_seg vertices at angles 2 pi k / n_seg, so cone + shaft is
# one watertight surface apart from the open top. Every facet normal points
# out of the pile (right-hand rule of the vertex order). The polygons are
# inscribed: vertices lie exactly at radius R.

PILE_APEX_ANGLE_DEG = 60.0


def cone_height(radius, apex_angle_deg=PILE_APEX_ANGLE_DEG):
    """Height of a cone of base radius ``radius`` and full apex angle
    ``apex_angle_deg`` (60 degrees: R / tan 30 deg = sqrt(3) R)."""
    if not radius > 0:
        raise ValueError("cone radius must be > 0, got %r" % (radius,))
    if not 0.0 < apex_angle_deg < 180.0:
        raise ValueError("apex angle must be in (0, 180) degrees, got %r" % (apex_angle_deg,))
    return radius / math.tan(math.radians(0.5 * apex_angle_deg))


def _ring(radius, z, n_seg):
    phi = 2.0 * np.pi * np.arange(n_seg) / n_seg
    return np.column_stack([radius * np.cos(phi), radius * np.sin(phi), np.full(n_seg, float(z))])


def _check_segments(n_seg):
    if int(n_seg) != n_seg or n_seg < 3:
        raise ValueError("n_seg (segments around the axis) must be an integer >= 3, got %r"
                         % (n_seg,))
    return int(n_seg)


def cone_tip_triangles(radius, tip_z=0.0, n_seg=24, apex_angle_deg=PILE_APEX_ANGLE_DEG):
    """Lateral surface of the cone tip: ``n_seg`` facets from the apex
    (0, 0, tip_z) to the base ring of radius ``radius``; normals outward
    (away from the axis and down)."""
    n_seg = _check_segments(n_seg)
    h = cone_height(radius, apex_angle_deg)
    apex = (0.0, 0.0, float(tip_z))
    ring = _ring(radius, tip_z + h, n_seg)
    # (apex, P_{k+1}, P_k): (P_{k+1} - A) x (P_k - A) points outward
    return [(apex, tuple(ring[(k + 1) % n_seg]), tuple(ring[k])) for k in range(n_seg)]


def default_shaft_rings(radius, length):
    """Axial divisions of the shaft used when none are given: facets no
    taller than the pile diameter."""
    return max(1, int(math.ceil(length / (2.0 * radius) - 1e-9)))


def shaft_triangles(radius, length, z_bottom, n_seg=24, n_rings=None):
    """Lateral surface of the cylinder radius ``radius``, z in
    [z_bottom, z_bottom + length], as ``n_rings`` bands of ``n_seg`` quads
    (two facets each); normals point away from the axis."""
    n_seg = _check_segments(n_seg)
    if not radius > 0:
        raise ValueError("shaft radius must be > 0, got %r" % (radius,))
    if not length > 0:
        raise ValueError("shaft length must be > 0, got %r" % (length,))
    if n_rings is None:
        n_rings = default_shaft_rings(radius, length)
    if int(n_rings) != n_rings or n_rings < 1:
        raise ValueError("n_rings must be an integer >= 1, got %r" % (n_rings,))
    n_rings = int(n_rings)
    zs = [z_bottom + length * j / n_rings for j in range(n_rings)] + [z_bottom + length]
    tris = []
    for j in range(n_rings):
        lo = _ring(radius, zs[j], n_seg)
        hi = _ring(radius, zs[j + 1], n_seg)
        for k in range(n_seg):
            k1 = (k + 1) % n_seg
            a, b, c, d = tuple(lo[k]), tuple(lo[k1]), tuple(hi[k1]), tuple(hi[k])
            tris.append((a, b, c))
            tris.append((a, c, d))
    return tris


def write_pile_stl(out_dir, radius, shaft_length, tip_z=0.0, n_seg=24, n_rings=None,
                   cone_name="cone.stl", shaft_name="shaft.stl",
                   apex_angle_deg=PILE_APEX_ANGLE_DEG):
    """Write the cone tip and the shaft as two ASCII STL files in ``out_dir``.

    Returns a dict: paths (cone, shaft), radius, tip_z, cone_height, z_base
    (cone base = shaft bottom), z_top (shaft top), n_seg, n_rings and the
    facet counts.
    """
    h = cone_height(radius, apex_angle_deg)
    z_base = tip_z + h
    if n_rings is None:
        n_rings = default_shaft_rings(radius, shaft_length)
    cone = cone_tip_triangles(radius, tip_z, n_seg, apex_angle_deg)
    shaft = shaft_triangles(radius, shaft_length, z_base, n_seg, n_rings)
    os.makedirs(out_dir, exist_ok=True)
    cone_path = os.path.join(out_dir, cone_name)
    shaft_path = os.path.join(out_dir, shaft_name)
    write_stl(cone_path, cone, "cone")
    write_stl(shaft_path, shaft, "shaft")
    return {"cone": cone_path, "shaft": shaft_path, "radius": float(radius),
            "tip_z": float(tip_z), "apex_angle_deg": float(apex_angle_deg),
            "cone_height": h, "z_base": z_base, "z_top": z_base + shaft_length,
            "shaft_length": float(shaft_length), "n_seg": int(n_seg), "n_rings": int(n_rings),
            "cone_facets": len(cone), "shaft_facets": len(shaft)}


def read_stl(path):
    """Facets of an ASCII STL file: (normals (n, 3), vertices (n, 3, 3))."""
    normals, verts, cur = [], [], []
    with open(path) as f:
        for line in f:
            w = line.split()
            if not w:
                continue
            if w[0] == "facet":
                normals.append([float(x) for x in w[2:5]])
                cur = []
            elif w[0] == "vertex":
                cur.append([float(x) for x in w[1:4]])
            elif w[0] == "endfacet":
                if len(cur) != 3:
                    raise ValueError("%s: facet with %d vertices" % (path, len(cur)))
                verts.append(cur)
    return (np.array(normals, dtype=float).reshape(-1, 3),
            np.array(verts, dtype=float).reshape(-1, 3, 3))


def annulus_triangles(r_in, r_out, z, n_seg, center=(0.0, 0.0), phi0=0.0, phi1=360.0):
    """Flat ring r_in <= r <= r_out in the plane z (normal +z), n_seg sectors:
    a platen with a hole for the pile (calibration chamber top wall).
    ``phi0``, ``phi1`` (degrees): only the part from azimuth phi0 to phi1
    (the top wall of a chamber sector)."""
    x0, y0 = center
    tris = []
    for a0, a1 in _arc_segments(n_seg, phi0, phi1):
        i0 = (x0 + r_in * math.cos(a0), y0 + r_in * math.sin(a0), z)
        i1 = (x0 + r_in * math.cos(a1), y0 + r_in * math.sin(a1), z)
        o0 = (x0 + r_out * math.cos(a0), y0 + r_out * math.sin(a0), z)
        o1 = (x0 + r_out * math.cos(a1), y0 + r_out * math.sin(a1), z)
        tris += [(i0, o0, o1), (i0, o1, i1)]
    return tris
