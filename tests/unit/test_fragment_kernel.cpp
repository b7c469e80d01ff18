// SPDX-License-Identifier: GPL-2.0-or-later
// Unit tests for crush_fragment_kernel.h (docs/model.md §2.6): 14-sphere
// Apollonian fragmentation and the seeded random rotation of its frame.
// Geometry is checked from the returned radii and centres (tangency, no
// overlap, containment, volume, centre of mass), not from the ratio formulas.

#include <gtest/gtest.h>

#include <cmath>
#include <initializer_list>
#include <cstdint>
#include <vector>

#include "crush_fragment_kernel.h"

using namespace CrushKernels;

namespace {

double norm3(const double v[3]) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

double dist3(const double a[3], const double b[3])
{
  const double d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
  return norm3(d);
}

double det3(const double R[3][3])
{
  return R[0][0] * (R[1][1] * R[2][2] - R[1][2] * R[2][1]) -
         R[0][1] * (R[1][0] * R[2][2] - R[1][2] * R[2][0]) +
         R[0][2] * (R[1][0] * R[2][1] - R[1][1] * R[2][0]);
}

void expect_rotation(const double R[3][3], double tol)
{
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      double rrt = 0.0;  // (R R^T)_ij
      double rtr = 0.0;  // (R^T R)_ij
      for (int k = 0; k < 3; ++k) {
        rrt += R[i][k] * R[j][k];
        rtr += R[k][i] * R[k][j];
      }
      EXPECT_NEAR(rrt, i == j ? 1.0 : 0.0, tol);
      EXPECT_NEAR(rtr, i == j ? 1.0 : 0.0, tol);
    }
  }
  EXPECT_NEAR(det3(R), 1.0, tol);
}

// Checks the full set of geometric properties of a fragment set of a parent of
// radius r centred at the origin. Tolerances are relative to r.
void check_fragment_geometry(double r, const double radius[kFragments],
                             const double offset[kFragments][3])
{
  const double tol = 1e-12 * r;
  // Inside the parent and tangent to it.
  for (int k = 0; k < kFragments; ++k) {
    EXPECT_GT(radius[k], 0.0);
    EXPECT_NEAR(norm3(offset[k]) + radius[k], r, tol) << "fragment " << k;
  }
  // Pairwise: no overlap; count tangencies.
  int large_large = 0, small_small = 0;
  std::vector<int> small_touch_large(8, 0), large_touch_large(6, 0), large_touch_small(6, 0);
  for (int i = 0; i < kFragments; ++i) {
    for (int j = i + 1; j < kFragments; ++j) {
      const double gap = dist3(offset[i], offset[j]) - (radius[i] + radius[j]);
      EXPECT_GE(gap, -tol) << "fragments " << i << " and " << j << " overlap";
      const bool tangent = std::fabs(gap) <= tol;
      // Non-tangent pairs are clearly separated (no near-miss ambiguity).
      if (!tangent) {
        EXPECT_GT(gap, 1e-3 * r);
        continue;
      }
      if (i < 6 && j < 6) { ++large_large; ++large_touch_large[i]; ++large_touch_large[j]; }
      else if (i < 6 && j >= 6) { ++small_touch_large[j - 6]; ++large_touch_small[i]; }
      else ++small_small;
    }
  }
  for (int s = 0; s < 8; ++s) EXPECT_EQ(small_touch_large[s], 3) << "small fragment " << s;
  for (int l = 0; l < 6; ++l) {
    EXPECT_EQ(large_touch_large[l], 4) << "large fragment " << l;
    EXPECT_EQ(large_touch_small[l], 4) << "large fragment " << l;
  }
  EXPECT_EQ(large_large, 12);  // octahedron edges
  EXPECT_EQ(small_small, 0);
}

}  // namespace

TEST(FragmentKernel, RadiusRatios)
{
  EXPECT_NEAR(large_fragment_ratio(), 0.414214, 1e-6);
  EXPECT_NEAR(small_fragment_ratio(), 0.230093, 1e-6);
  // Large ratio: neighbours at sqrt2 (r - r1) touch: sqrt2 (1 - r1) = 2 r1.
  const double r1 = large_fragment_ratio();
  EXPECT_NEAR(std::sqrt(2.0) * (1.0 - r1), 2.0 * r1, 1e-15);
  EXPECT_EQ(kFragments, 14);
}

TEST(FragmentKernel, SmallRatioByIndependentBisection)
{
  // Solve |c_small - c_large| = r1 + r2 for r2 by bisection (r = 1).
  const double r1 = 1.0 / (1.0 + std::sqrt(2.0));
  auto g = [r1](double r2) {
    const double c = (1.0 - r2) / std::sqrt(3.0);
    const double dx = c - (1.0 - r1);
    return std::sqrt(dx * dx + 2.0 * c * c) - (r1 + r2);
  };
  double lo = 0.1, hi = 0.4;
  ASSERT_LT(g(lo) * g(hi), 0.0);
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    if (g(lo) * g(mid) <= 0.0) hi = mid; else lo = mid;
  }
  EXPECT_NEAR(small_fragment_ratio(), 0.5 * (lo + hi), 1e-14);
}

TEST(FragmentKernel, FragmentsInsideTangentAndNonOverlapping)
{
  for (double r : {1.0, 0.37, 1.05e-4, 4.095e-3}) {
    double radius[kFragments], offset[kFragments][3];
    apollonian_fragments(r, radius, offset);
    // 6 large then 8 small, with the documented sizes.
    for (int k = 0; k < 6; ++k) EXPECT_NEAR(radius[k], 0.414214 * r, 1e-6 * r);
    for (int k = 6; k < 14; ++k) EXPECT_NEAR(radius[k], 0.230093 * r, 1e-6 * r);
    check_fragment_geometry(r, radius, offset);
  }
}

TEST(FragmentKernel, LargeFragmentsOnAxesSmallOnDiagonals)
{
  const double r = 2.0;
  double radius[kFragments], offset[kFragments][3];
  apollonian_fragments(r, radius, offset);
  // Large: +x,-x,+y,-y,+z,-z at distance r - r1.
  for (int k = 0; k < 6; ++k) {
    const int axis = k / 2;
    const double sgn = (k % 2 == 0) ? 1.0 : -1.0;
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(offset[k][i], i == axis ? sgn * (r - radius[k]) : 0.0, 1e-15);
    }
  }
  // Small: all 8 sign combinations, equal |components|.
  int seen = 0;
  for (int k = 6; k < 14; ++k) {
    const double c = std::fabs(offset[k][0]);
    EXPECT_NEAR(std::fabs(offset[k][1]), c, 1e-15);
    EXPECT_NEAR(std::fabs(offset[k][2]), c, 1e-15);
    const int code = (offset[k][0] > 0) + 2 * (offset[k][1] > 0) + 4 * (offset[k][2] > 0);
    seen |= 1 << code;
  }
  EXPECT_EQ(seen, 0xFF);
}

TEST(FragmentKernel, VolumeFraction)
{
  for (double r : {1.0, 3.3e-4}) {
    double radius[kFragments], offset[kFragments][3];
    apollonian_fragments(r, radius, offset);
    double v = 0.0;
    for (int k = 0; k < kFragments; ++k) v += std::pow(radius[k] / r, 3);
    EXPECT_NEAR(v, 0.5239, 5e-5);                         // docs/model.md §2.6: 52.39 %
    EXPECT_NEAR(fragment_volume_fraction(), v, 1e-12);
  }
  EXPECT_NEAR(fragment_volume_fraction(), 0.523861230454921, 1e-12);  // hand value
}

TEST(FragmentKernel, CentreOfMassAtParentCentre)
{
  const double r = 0.7;
  double radius[kFragments], offset[kFragments][3];
  apollonian_fragments(r, radius, offset);
  double m = 0.0, cm[3] = {0.0, 0.0, 0.0};
  for (int k = 0; k < kFragments; ++k) {
    const double mk = radius[k] * radius[k] * radius[k];
    m += mk;
    for (int i = 0; i < 3; ++i) cm[i] += mk * offset[k][i];
  }
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(cm[i] / m, 0.0, 1e-15 * r);
}

TEST(FragmentKernel, RandomRotationIsProperOrthonormal)
{
  // Edge values and many pseudo-random inputs.
  const double edges[][3] = {{0.0, 0.0, 0.0}, {1.0, 1.0, 1.0}, {0.5, 0.25, 0.75},
                             {1e-12, 0.999999, 0.5}, {0.999999, 1e-9, 1e-9}};
  for (const auto& u : edges) {
    double R[3][3];
    random_rotation(u[0], u[1], u[2], R);
    expect_rotation(R, 1e-14);
  }
  for (uint64_t t = 1; t <= 2000; ++t) {
    double R[3][3];
    random_rotation(uniform01(3u, t, 7u, 0), uniform01(3u, t, 7u, 1), uniform01(3u, t, 7u, 2), R);
    expect_rotation(R, 1e-13);
  }
  // u = (0, 0, 0) or u1 = 1, u3 = 0 is the identity (w = 1 or quaternion (1,0,0,0)).
  double I[3][3];
  random_rotation(1.0, 0.3, 0.0, I);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(I[i][j], i == j ? 1.0 : 0.0, 1e-15);
}

TEST(FragmentKernel, RotatedFragmentsKeepAllTangencies)
{
  const double r = 1.3e-3;
  double radius[kFragments], offset[kFragments][3];
  apollonian_fragments(r, radius, offset);
  for (uint64_t tag = 1; tag <= 200; ++tag) {
    double R[3][3], rot[kFragments][3];
    event_rotation(42u, tag, R);
    for (int k = 0; k < kFragments; ++k) rotate(R, offset[k], rot[k]);
    check_fragment_geometry(r, radius, rot);
    // Centre of mass stays at the parent centre.
    double cm[3] = {0.0, 0.0, 0.0}, m = 0.0;
    for (int k = 0; k < kFragments; ++k) {
      const double mk = radius[k] * radius[k] * radius[k];
      m += mk;
      for (int i = 0; i < 3; ++i) cm[i] += mk * rot[k][i];
    }
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(cm[i] / m, 0.0, 1e-15 * r);
  }
}

TEST(FragmentKernel, RotateIsMatrixVectorProduct)
{
  const double R[3][3] = {{0.0, -1.0, 0.0}, {1.0, 0.0, 0.0}, {0.0, 0.0, 1.0}};  // 90 deg about z
  const double v[3] = {1.0, 2.0, 3.0};
  double out[3];
  rotate(R, v, out);
  EXPECT_DOUBLE_EQ(out[0], -2.0);
  EXPECT_DOUBLE_EQ(out[1], 1.0);
  EXPECT_DOUBLE_EQ(out[2], 3.0);
}

TEST(FragmentKernel, EventRotationIsPureFunctionOfSeedAndTag)
{
  int differ_seed = 0, differ_tag = 0;
  for (uint64_t tag = 1; tag <= 500; ++tag) {
    double A[3][3], B[3][3], C[3][3], D[3][3];
    event_rotation(9u, tag, A);
    event_rotation(9u, tag + 1000, C);  // interleaved unrelated call
    (void)strength_factor(9u, tag, 0.36);
    event_rotation(9u, tag, B);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) EXPECT_EQ(A[i][j], B[i][j]);
    event_rotation(10u, tag, D);
    bool ds = false, dt = false;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        ds = ds || (D[i][j] != A[i][j]);
        dt = dt || (C[i][j] != A[i][j]);
      }
    differ_seed += ds;
    differ_tag += dt;
  }
  EXPECT_EQ(differ_seed, 500);
  EXPECT_EQ(differ_tag, 500);
}

TEST(FragmentKernel, EventRotationsAreUniform)
{
  // Rotated x axis (first column of R) over 20,000 events: uniform on the
  // sphere has mean 0 and <x_i^2> = 1/3. Also check the rotated z axis and the
  // mean of the matrix (Haar measure: E[R] = 0).
  const int n = 20000;
  double mx[3] = {0, 0, 0}, mx2[3] = {0, 0, 0}, mz[3] = {0, 0, 0}, mz2[3] = {0, 0, 0};
  double mR[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
  double trace_sum = 0.0;
  for (int t = 1; t <= n; ++t) {
    double R[3][3];
    event_rotation(2718u, static_cast<uint64_t>(t), R);
    const double ex[3] = {1.0, 0.0, 0.0}, ez[3] = {0.0, 0.0, 1.0};
    double x[3], z[3];
    rotate(R, ex, x);
    rotate(R, ez, z);
    for (int i = 0; i < 3; ++i) {
      mx[i] += x[i]; mx2[i] += x[i] * x[i];
      mz[i] += z[i]; mz2[i] += z[i] * z[i];
      for (int j = 0; j < 3; ++j) mR[i][j] += R[i][j];
    }
    trace_sum += R[0][0] + R[1][1] + R[2][2];
  }
  double mean_x[3], mean_z[3];
  for (int i = 0; i < 3; ++i) {
    mean_x[i] = mx[i] / n;
    mean_z[i] = mz[i] / n;
    EXPECT_NEAR(mx2[i] / n, 1.0 / 3.0, 0.01) << "component " << i;
    EXPECT_NEAR(mz2[i] / n, 1.0 / 3.0, 0.01) << "component " << i;
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(mR[i][j] / n, 0.0, 0.02);
  }
  EXPECT_LT(norm3(mean_x), 0.02);
  EXPECT_LT(norm3(mean_z), 0.02);
  // Haar measure on SO(3): E[trace R] = 0 (angle density (1 - cos)/pi).
  EXPECT_NEAR(trace_sum / n, 0.0, 0.03);
}
