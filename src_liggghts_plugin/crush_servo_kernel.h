// SPDX-License-Identifier: GPL-2.0-or-later
/* Radial servo of a cylindrical mesh wall (fix servo/radial, docs/model.md
   §4.4): radial directions, the wall's radial stress from per-element
   forces, the servo velocity and the radial scale factor.
   Stateless kernels, no LIGGGHTS dependency; unit-tested in tests/unit. */

#ifndef CRUSH_SERVO_KERNEL_H
#define CRUSH_SERVO_KERNEL_H

#include <cmath>

namespace CrushKernels {

// Outward radial unit vector (e[0], e[1]) at (x, y) for a cylinder whose axis
// is parallel to z through (x0, y0). Returns false (and e = 0) on the axis.
inline bool radial_unit_vector(double x, double y, double x0, double y0, double e[2])
{
  const double dx = x - x0, dy = y - y0;
  const double r = std::sqrt(dx * dx + dy * dy);
  if (!(r > 0.0)) {
    e[0] = e[1] = 0.0;
    return false;
  }
  e[0] = dx / r;
  e[1] = dy / r;
  return true;
}

// Distance of (x, y) from the axis through (x0, y0).
inline double radial_distance(double x, double y, double x0, double y0)
{
  const double dx = x - x0, dy = y - y0;
  return std::sqrt(dx * dx + dy * dy);
}

// Radial wall velocity of the servo: proportional to the stress error, positive
// (outward, the wall expands) when the measured stress exceeds the target,
// clipped to [-vmax, vmax].
inline double servo_radial_velocity(double sigma_r, double target, double gain, double vmax)
{
  const double v = gain * (sigma_r - target);
  if (v > vmax) return vmax;
  if (v < -vmax) return -vmax;
  return v;
}

// Factor that takes the radius R to R + v_r dt.
inline double radial_scale_factor(double R, double v_r, double dt)
{
  return (R + v_r * dt) / R;
}

// A coordinate after scaling by `factor` about the centre c.
inline double scale_about(double x, double c, double factor)
{
  return c + factor * (x - c);
}

// Geometry of one triangle of the wall: area, unit normal oriented away from
// the axis (n_out[2] is its z component: 0 for a vertical facet), centroid.
// Returns the area (0 for a degenerate triangle, with n_out = 0).
inline double wall_triangle_geometry(const double *p0, const double *p1, const double *p2,
                                     double x0, double y0, double n_out[3], double centroid[3])
{
  for (int k = 0; k < 3; k++) centroid[k] = (p0[k] + p1[k] + p2[k]) / 3.0;
  const double a[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
  const double b[3] = {p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]};
  double n[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  if (!(len > 0.0)) {
    n_out[0] = n_out[1] = n_out[2] = 0.0;
    return 0.0;
  }
  double sgn = 1.0;
  if (n[0] * (centroid[0] - x0) + n[1] * (centroid[1] - y0) < 0.0) sgn = -1.0;
  for (int k = 0; k < 3; k++) n_out[k] = sgn * n[k] / len;
  return 0.5 * len;
}

// Outward normal force of one element: the force the grains put on it
// (LIGGGHTS element property 'f' of fix mesh/surface/stress) projected on
// the element's outward normal. Positive when the grains push the wall out.
inline double element_radial_force(const double *f, const double n_out[3])
{
  return f[0] * n_out[0] + f[1] * n_out[1] + f[2] * n_out[2];
}

// Same projection on the radial unit vector at the element's centroid (the
// alternative definition; equal to element_radial_force for a facet whose
// centroid lies on its mid-line, close to it for fine facets).
inline double element_radial_force_centroid(const double *f, const double centroid[3],
                                            double x0, double y0)
{
  double e[2];
  if (!radial_unit_vector(centroid[0], centroid[1], x0, y0, e)) return 0.0;
  return f[0] * e[0] + f[1] * e[1];
}

// Perimeter of a wall of vertical facets: its total area over its height.
// For n strips on a circle of radius R this is 2 n R sin(pi / n), the
// perimeter of the inscribed polygon (2 pi R as n grows).
inline double wall_perimeter(double area_total, double wall_height)
{
  return area_total / wall_height;
}

// Loaded perimeter of the lateral wall of a chamber sector of sector_deg
// degrees (0 < sector_deg <= 360) bounded by symmetry planes through the
// axis: the arc of the circle of radius R that the sector's grains touch.
inline double sector_arc_length(double sector_deg, double R)
{
  const double pi = 3.14159265358979323846;
  return sector_deg * (pi / 180.0) * R;
}

// Perimeter of the regular polygon of n sides inscribed in a circle of radius R.
inline double polygon_perimeter(int n, double R)
{
  const double pi = 3.14159265358979323846;
  return 2.0 * n * R * std::sin(pi / n);
}

// Mean radial stress on the band of wall in contact with a sample of height
// H: total outward normal force over (perimeter * H). For a circle this is
// F_r / (2 pi R H).
inline double radial_stress(double F_r, double perimeter, double H)
{
  return F_r / (perimeter * H);
}

// A node after scaling the x and y coordinates by `factor` about the axis
// through (x0, y0); z is unchanged (the wall keeps its height).
inline void scale_node_xy(double *node, double x0, double y0, double factor)
{
  node[0] = scale_about(node[0], x0, factor);
  node[1] = scale_about(node[1], y0, factor);
}

// Derived geometry of a mesh triangle with nodes p[0..2], in the conventions
// of LIGGGHTS' SurfaceMesh/TriMesh (element properties edgeLen, edgeVec,
// edgeNorm, surfaceNorm, area, obtuseAngleIndex):
//   edge_vec[i]  = unit vector from node i to node i+1, edge_len[i] its length
//   surf_norm    = unit(edge_vec[0] x edge_vec[1])
//   edge_norm[i] = unit(edge_vec[i] x surf_norm) (in-plane, normal to edge i)
//   area         = |edge_vec[0] x edge_vec[1]| edge_len[0] edge_len[1] / 2
//   obtuse       = the index i of the last node (in order 0, 1, 2) whose
//                  edge_vec[i] . edge_vec[i-1] > 0, else -1 (as the stock
//                  code leaves it after its loop over the nodes)
// fix servo/radial recomputes these after moving the nodes, since a scaling
// in x and y only turns the slanted edges. Returns false for a degenerate
// triangle (then only edge_vec/edge_len are set).
struct TriangleGeometry {
  double edge_len[3];
  double edge_vec[3][3];
  double edge_norm[3][3];
  double surf_norm[3];
  double area;
  int obtuse;
};

inline void cross3(const double *a, const double *b, double *c)
{
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}

inline double norm3(const double *a)
{
  return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
}

inline bool triangle_surface_geometry(const double *const p[3], TriangleGeometry &g)
{
  for (int i = 0; i < 3; i++) {
    const double *a = p[i], *b = p[(i + 1) % 3];
    for (int k = 0; k < 3; k++) g.edge_vec[i][k] = b[k] - a[k];
    g.edge_len[i] = norm3(g.edge_vec[i]);
    if (!(g.edge_len[i] > 0.0)) return false;
    for (int k = 0; k < 3; k++) g.edge_vec[i][k] /= g.edge_len[i];
  }
  double c[3];
  cross3(g.edge_vec[0], g.edge_vec[1], c);
  const double cn = norm3(c);
  if (!(cn > 1e-15)) return false;
  for (int k = 0; k < 3; k++) g.surf_norm[k] = c[k] / cn;
  for (int i = 0; i < 3; i++) {
    double e[3];
    cross3(g.edge_vec[i], g.surf_norm, e);
    const double en = norm3(e);
    for (int k = 0; k < 3; k++) g.edge_norm[i][k] = e[k] / en;
  }
  g.area = 0.5 * cn * g.edge_len[0] * g.edge_len[1];
  g.obtuse = -1;
  for (int i = 0; i < 3; i++) {
    const double *e = g.edge_vec[i], *f = g.edge_vec[(i + 2) % 3];
    g.obtuse = (e[0] * f[0] + e[1] * f[1] + e[2] * f[2] > 0.0) ? i : -1;
  }
  return true;
}

// Velocity of a wall node under radial expansion at rate v_r of a wall of
// radius R (nodes at distance R from the axis move at exactly v_r, outward):
// v = (v_r / R) (x - x0, y - y0, 0), the velocity field of the x-y scaling.
inline void radial_node_velocity(const double *node, double x0, double y0, double v_r, double R,
                                 double v[3])
{
  const double rate = v_r / R;
  v[0] = rate * (node[0] - x0);
  v[1] = rate * (node[1] - y0);
  v[2] = 0.0;
}

}  // namespace CrushKernels

#endif
