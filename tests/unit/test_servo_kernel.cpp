// SPDX-License-Identifier: GPL-2.0-or-later
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "crush_servo_kernel.h"

using namespace CrushKernels;

namespace {

const double kPi = 3.14159265358979323846;

// One triangle of a synthetic wall.
struct Tri {
  double p[3][3];
};

// Cylinder of n_seg vertical strips (two triangles each) on a circle of
// radius R about (x0, y0), from z_lo to z_hi, like crushpost.meshes.
// cylinder_triangles. flip reverses every triangle's node order (normals
// pointing the other way).
std::vector<Tri> cylinder(double R, double z_lo, double z_hi, int n_seg, double x0, double y0,
                          bool flip = false)
{
  std::vector<Tri> out;
  for (int k = 0; k < n_seg; k++) {
    const double a0 = 2.0 * kPi * k / n_seg, a1 = 2.0 * kPi * (k + 1) / n_seg;
    const double b0[3] = {x0 + R * std::cos(a0), y0 + R * std::sin(a0), z_lo};
    const double b1[3] = {x0 + R * std::cos(a1), y0 + R * std::sin(a1), z_lo};
    const double t0[3] = {b0[0], b0[1], z_hi};
    const double t1[3] = {b1[0], b1[1], z_hi};
    const double *tri[2][3] = {{b0, t1, b1}, {b0, t0, t1}};
    for (int t = 0; t < 2; t++) {
      Tri T;
      for (int j = 0; j < 3; j++)
        for (int c = 0; c < 3; c++) T.p[j][c] = tri[t][flip ? 2 - j : j][c];
      out.push_back(T);
    }
  }
  return out;
}

}  // namespace

TEST(ServoKernel, RadialUnitVectorsInEveryQuadrant)
{
  double e[2];
  ASSERT_TRUE(radial_unit_vector(3.0, 0.0, 0.0, 0.0, e));
  EXPECT_DOUBLE_EQ(e[0], 1.0);
  EXPECT_DOUBLE_EQ(e[1], 0.0);
  ASSERT_TRUE(radial_unit_vector(1.0, 1.0, 2.0, 2.0, e));  // off-origin axis, third quadrant
  EXPECT_NEAR(e[0], -std::sqrt(0.5), 1e-15);
  EXPECT_NEAR(e[1], -std::sqrt(0.5), 1e-15);
  ASSERT_TRUE(radial_unit_vector(-0.3, 0.4, 0.0, 0.0, e));
  EXPECT_NEAR(e[0], -0.6, 1e-15);
  EXPECT_NEAR(e[1], 0.8, 1e-15);
  ASSERT_TRUE(radial_unit_vector(0.0, -2.0, 0.0, 0.0, e));
  EXPECT_DOUBLE_EQ(e[0], 0.0);
  EXPECT_DOUBLE_EQ(e[1], -1.0);
  EXPECT_DOUBLE_EQ(radial_distance(1.0, 1.0, 4.0, 5.0), 5.0);
}

TEST(ServoKernel, NoRadialDirectionOnTheAxis)
{
  double e[2] = {7.0, 7.0};
  EXPECT_FALSE(radial_unit_vector(1.5, -2.0, 1.5, -2.0, e));
  EXPECT_EQ(e[0], 0.0);
  EXPECT_EQ(e[1], 0.0);
}

TEST(ServoKernel, VelocityExpandsWhenStressAboveTargetAndContractsBelow)
{
  const double K = 1e-7, target = 76e3, vmax = 0.5;
  // packing pushes harder than the target: wall moves out
  EXPECT_GT(servo_radial_velocity(80e3, target, K, vmax), 0.0);
  EXPECT_NEAR(servo_radial_velocity(80e3, target, K, vmax), 4e-4, 1e-15);
  // softer: wall moves in
  EXPECT_LT(servo_radial_velocity(70e3, target, K, vmax), 0.0);
  EXPECT_NEAR(servo_radial_velocity(70e3, target, K, vmax), -6e-4, 1e-15);
  EXPECT_EQ(servo_radial_velocity(target, target, K, vmax), 0.0);
}

TEST(ServoKernel, VelocityIsCappedByVmax)
{
  EXPECT_DOUBLE_EQ(servo_radial_velocity(1e9, 76e3, 1e-6, 0.2), 0.2);
  EXPECT_DOUBLE_EQ(servo_radial_velocity(0.0, 76e3, 1e-3, 0.2), -0.2);
  // default vmax = gain * target: a wall with no contact moves in at exactly vmax
  const double K = 2e-6, target = 5e4;
  EXPECT_DOUBLE_EQ(servo_radial_velocity(0.0, target, K, K * target), -K * target);
}

TEST(ServoKernel, ScaleFactorTakesRadiusToRPlusVdt)
{
  const double R = 0.216, v = -0.05, dt = 1e-6;
  const double f = radial_scale_factor(R, v, dt);
  EXPECT_NEAR(f * R, R + v * dt, 1e-18);
  EXPECT_DOUBLE_EQ(radial_scale_factor(R, 0.0, dt), 1.0);
  EXPECT_GT(radial_scale_factor(R, 0.1, dt), 1.0);
  EXPECT_LT(radial_scale_factor(R, -0.1, dt), 1.0);
}

TEST(ServoKernel, ScalingAboutAxisPointMovesNodesRadiallyByVdt)
{
  // move(-p), scale(f), move(p) on a node of the wall: its distance from the
  // axis goes from R to R + v dt, its angle stays, z stretches about z_mid
  const double x0 = 0.01, y0 = -0.02, zmid = 0.5, R = 0.2, v = 0.3, dt = 1e-3;
  const double f = radial_scale_factor(R, v, dt);
  const double a = 0.7;
  const double node[3] = {x0 + R * std::cos(a), y0 + R * std::sin(a), 0.9};
  const double c[3] = {x0, y0, zmid};
  double moved[3];
  for (int k = 0; k < 3; k++) moved[k] = (node[k] - c[k]) * f + c[k];
  for (int k = 0; k < 3; k++) EXPECT_NEAR(moved[k], scale_about(node[k], c[k], f), 1e-15);
  EXPECT_NEAR(radial_distance(moved[0], moved[1], x0, y0), R + v * dt, 1e-15);
  EXPECT_NEAR(std::atan2(moved[1] - y0, moved[0] - x0), a, 1e-14);
  EXPECT_NEAR(moved[2] - zmid, f * (node[2] - zmid), 1e-15);
}

TEST(ServoKernel, TriangleGeometryOutwardNormalAndArea)
{
  // facet in the plane x = 1, from y = -1 to 1 and z = 0 to 2: area 2, normal +x
  const double p0[3] = {1.0, -1.0, 0.0}, p1[3] = {1.0, 1.0, 0.0}, p2[3] = {1.0, 1.0, 2.0};
  double n[3], c[3];
  EXPECT_DOUBLE_EQ(wall_triangle_geometry(p0, p1, p2, 0.0, 0.0, n, c), 2.0);
  EXPECT_NEAR(n[0], 1.0, 1e-15);
  EXPECT_NEAR(n[1], 0.0, 1e-15);
  EXPECT_NEAR(n[2], 0.0, 1e-15);
  EXPECT_NEAR(c[0], 1.0, 1e-15);
  EXPECT_NEAR(c[1], 1.0 / 3.0, 1e-15);
  EXPECT_NEAR(c[2], 2.0 / 3.0, 1e-15);
  // reversed node order: same outward normal
  EXPECT_DOUBLE_EQ(wall_triangle_geometry(p2, p1, p0, 0.0, 0.0, n, c), 2.0);
  EXPECT_NEAR(n[0], 1.0, 1e-15);
  // axis on the other side of the facet: the normal flips to point away from it
  wall_triangle_geometry(p0, p1, p2, 3.0, 0.0, n, c);
  EXPECT_NEAR(n[0], -1.0, 1e-15);
  // degenerate
  EXPECT_EQ(wall_triangle_geometry(p0, p0, p2, 0.0, 0.0, n, c), 0.0);
  EXPECT_EQ(n[0], 0.0);
}

TEST(ServoKernel, PerimeterOfStripCylinderFromAreas)
{
  const double R = 0.216, zl = -0.05, zh = 1.05;
  for (int n_seg : {12, 48, 96}) {
    std::vector<Tri> wall = cylinder(R, zl, zh, n_seg, 0.0, 0.0);
    double area = 0.0, nz_max = 0.0;
    for (const Tri &t : wall) {
      double n[3], c[3];
      area += wall_triangle_geometry(t.p[0], t.p[1], t.p[2], 0.0, 0.0, n, c);
      nz_max = std::fmax(nz_max, std::fabs(n[2]));
    }
    EXPECT_LT(nz_max, 1e-14);
    const double P = wall_perimeter(area, zh - zl);
    EXPECT_NEAR(P, polygon_perimeter(n_seg, R), 1e-12);
    EXPECT_LT(P, 2.0 * kPi * R);
  }
  EXPECT_NEAR(polygon_perimeter(100000, 1.0), 2.0 * kPi, 1e-8);
}

// Uniform pressure p on every facet of a synthetic cylinder (force = p * area
// along the facet's outward normal, plus wall friction along z and along the
// facet's chord): the measured radial stress over the whole wall is p, at
// any axis position and facet orientation.
TEST(ServoKernel, RadialStressOfUniformPressureOnSyntheticCylinder)
{
  const double p = 76e3, R = 0.05, zl = 0.0, zh = 0.12;
  for (int flip = 0; flip < 2; flip++) {
    for (double x0 : {0.0, 0.3}) {
      const double y0 = -0.1;
      std::vector<Tri> wall = cylinder(R, zl, zh, 48, x0, y0, flip != 0);
      double F_r = 0.0, F_r_centroid = 0.0, area = 0.0;
      for (const Tri &t : wall) {
        double n[3], c[3];
        const double A = wall_triangle_geometry(t.p[0], t.p[1], t.p[2], x0, y0, n, c);
        // chord direction of the facet (horizontal, in its plane)
        const double chord[3] = {-n[1], n[0], 0.0};
        double f[3];
        for (int k = 0; k < 3; k++) f[k] = p * A * n[k] + 0.3 * p * A * chord[k];
        f[2] += 0.2 * p * A;  // vertical friction
        F_r += element_radial_force(f, n);
        F_r_centroid += element_radial_force_centroid(f, c, x0, y0);
        area += A;
      }
      const double P = wall_perimeter(area, zh - zl);
      EXPECT_NEAR(radial_stress(F_r, P, zh - zl), p, 1e-9 * p);
      // the centroid projection picks up a little of the chord friction and
      // the facet tilt: close, not exact
      EXPECT_NEAR(radial_stress(F_r_centroid, P, zh - zl), p, 0.01 * p);
      // with 2 pi R instead of the polygon perimeter: 0.3 % off for 48 facets
      const double circle = F_r / (2.0 * kPi * R * (zh - zl));
      EXPECT_NEAR(circle / p, polygon_perimeter(48, R) / (2.0 * kPi * R), 1e-12);
    }
  }
}

// Grains touching only the band 0 < z < H of a taller wall: the stress over
// that band is F_r / (P H).
TEST(ServoKernel, RadialStressOverSampleBandOfTallerWall)
{
  const double p = 150e3, R = 0.1, H = 0.2, wall_lo = -0.05, wall_hi = 0.3;
  std::vector<Tri> wall = cylinder(R, wall_lo, wall_hi, 24, 0.0, 0.0);
  double area = 0.0, F_r = 0.0;
  for (const Tri &t : wall) {
    double n[3], c[3];
    const double A = wall_triangle_geometry(t.p[0], t.p[1], t.p[2], 0.0, 0.0, n, c);
    area += A;
    // the part of the facet's area inside 0 < z < H carries pressure p:
    // each triangle spans the full wall height, its width is linear in z
    const double frac = H / (wall_hi - wall_lo);
    double f[3];
    for (int k = 0; k < 3; k++) f[k] = p * A * frac * n[k];
    F_r += element_radial_force(f, n);
  }
  const double P = wall_perimeter(area, wall_hi - wall_lo);
  EXPECT_NEAR(radial_stress(F_r, P, H), p, 1e-9 * p);
}

TEST(ServoKernel, NodeVelocityIsRadialAtRateVr)
{
  const double x0 = 1.0, y0 = 2.0, R = 0.3, vr = -0.04;
  const double node[3] = {x0 + R * std::cos(2.0), y0 + R * std::sin(2.0), 5.0};
  double v[3];
  radial_node_velocity(node, x0, y0, vr, R, v);
  EXPECT_NEAR(std::sqrt(v[0] * v[0] + v[1] * v[1]), std::fabs(vr), 1e-15);
  EXPECT_NEAR(v[0], vr * std::cos(2.0), 1e-15);
  EXPECT_NEAR(v[1], vr * std::sin(2.0), 1e-15);
  EXPECT_EQ(v[2], 0.0);
}

TEST(ServoKernel, TriangleSurfaceGeometryInLiggghtsConventions)
{
  // right triangle in the xy plane: edges 2, sqrt(5), 1
  const double a[3] = {0.0, 0.0, 0.0}, b[3] = {2.0, 0.0, 0.0}, c[3] = {0.0, 1.0, 0.0};
  const double *const p[3] = {a, b, c};
  TriangleGeometry g;
  ASSERT_TRUE(triangle_surface_geometry(p, g));
  EXPECT_DOUBLE_EQ(g.edge_len[0], 2.0);
  EXPECT_DOUBLE_EQ(g.edge_len[1], std::sqrt(5.0));
  EXPECT_DOUBLE_EQ(g.edge_len[2], 1.0);
  EXPECT_DOUBLE_EQ(g.edge_vec[0][0], 1.0);
  EXPECT_NEAR(g.edge_vec[1][0], -2.0 / std::sqrt(5.0), 1e-15);
  EXPECT_NEAR(g.edge_vec[1][1], 1.0 / std::sqrt(5.0), 1e-15);
  EXPECT_DOUBLE_EQ(g.edge_vec[2][1], -1.0);
  // normal by the right-hand rule of the node order
  EXPECT_NEAR(g.surf_norm[2], 1.0, 1e-15);
  // edge normals in the plane, pointing out of the triangle
  EXPECT_NEAR(g.edge_norm[0][1], -1.0, 1e-15);
  EXPECT_NEAR(g.edge_norm[2][0], -1.0, 1e-15);
  EXPECT_NEAR(g.edge_norm[1][0], 1.0 / std::sqrt(5.0), 1e-15);
  EXPECT_NEAR(g.edge_norm[1][1], 2.0 / std::sqrt(5.0), 1e-15);
  EXPECT_NEAR(g.area, 1.0, 1e-15);
  EXPECT_EQ(g.obtuse, -1);
  // obtuse at node 2
  const double d[3] = {0.0, 0.0, 0.0}, e[3] = {3.0, 0.0, 0.0}, f[3] = {1.0, 0.5, 0.0};
  const double *const q[3] = {d, e, f};
  ASSERT_TRUE(triangle_surface_geometry(q, g));
  EXPECT_EQ(g.obtuse, 2);
  // degenerate
  const double *const r[3] = {d, d, f};
  EXPECT_FALSE(triangle_surface_geometry(r, g));
}

TEST(ServoKernel, XyScalingOfAStripKeepsHeightAndNormalTurnsTheDiagonal)
{
  // one facet of a strip (inward node order) on a circle of radius R
  const double R = 0.2, zl = -0.1, zh = 1.1, f = 1.05;
  const double a0 = 0.3, a1 = 0.3 + 2.0 * kPi / 24;
  double b0[3] = {R * std::cos(a0), R * std::sin(a0), zl};
  double t1[3] = {R * std::cos(a1), R * std::sin(a1), zh};
  double b1[3] = {R * std::cos(a1), R * std::sin(a1), zl};
  TriangleGeometry g0, g1;
  {
    const double *const p[3] = {b0, t1, b1};
    ASSERT_TRUE(triangle_surface_geometry(p, g0));
  }
  scale_node_xy(b0, 0.0, 0.0, f);
  scale_node_xy(t1, 0.0, 0.0, f);
  scale_node_xy(b1, 0.0, 0.0, f);
  EXPECT_NEAR(radial_distance(t1[0], t1[1], 0.0, 0.0), f * R, 1e-15);
  EXPECT_EQ(t1[2], zh);
  const double *const p[3] = {b0, t1, b1};
  ASSERT_TRUE(triangle_surface_geometry(p, g1));
  for (int k = 0; k < 3; k++) {
    EXPECT_NEAR(g1.surf_norm[k], g0.surf_norm[k], 1e-14);   // still the same vertical plane
    EXPECT_NEAR(g1.edge_vec[1][k], g0.edge_vec[1][k], 1e-14);  // vertical edge t1 -> b1
  }
  EXPECT_NEAR(g1.edge_len[1], g0.edge_len[1], 1e-14);
  EXPECT_NEAR(g1.edge_len[2], f * g0.edge_len[2], 1e-14);    // horizontal chord
  EXPECT_NEAR(g1.area, f * g0.area, 1e-14);                   // chord x height / 2
  // the slanted edge b0 -> t1 turns: that is why the fix recomputes it
  EXPECT_GT(std::fabs(g1.edge_vec[0][2] - g0.edge_vec[0][2]), 1e-6);
}

// A chamber sector: uniform pressure p on the facets of the strips that lie in
// the sector (azimuth 0..theta of a fine strip cylinder, as the grains of a
// sector bounded by symmetry planes load it), none on the margin strips: the
// stress over the sector's arc theta R equals p to the polygon's deviation
// from the circle (sin(x)/x for strips of angle 2x), for a quarter and a half.
TEST(ServoKernel, SectorArcLengthGivesThePressureOnTheLoadedStrips)
{
  EXPECT_NEAR(sector_arc_length(360.0, 0.2), 2.0 * kPi * 0.2, 1e-15);
  EXPECT_NEAR(sector_arc_length(90.0, 0.2), 0.5 * kPi * 0.2, 1e-15);
  const double p = 76e3, R = 0.05, H = 0.1;
  const int n_seg = 48;                      // 7.5 degree strips
  for (double theta : {90.0, 180.0}) {
    std::vector<Tri> wall = cylinder(R, 0.0, H, n_seg, 0.0, 0.0);
    double F_r = 0.0;
    for (const Tri &t : wall) {
      double n[3], c[3];
      const double A = wall_triangle_geometry(t.p[0], t.p[1], t.p[2], 0.0, 0.0, n, c);
      double az = std::atan2(c[1], c[0]) * 180.0 / kPi;
      if (az < 0.0) az += 360.0;
      if (az > theta) continue;              // outside the sector: no grains
      double f[3];
      for (int k = 0; k < 3; k++) f[k] = p * A * n[k];
      F_r += element_radial_force(f, n);
    }
    const double half = kPi / n_seg;          // half the strip angle
    const double expected = p * std::sin(half) / half;
    EXPECT_NEAR(radial_stress(F_r, sector_arc_length(theta, R), H), expected, 1e-9 * p);
    // and over the whole mesh perimeter it would be theta/360 of that
    EXPECT_NEAR(radial_stress(F_r, polygon_perimeter(n_seg, R), H) / p, theta / 360.0, 1e-9);
  }
}
