// SPDX-License-Identifier: GPL-2.0-or-later
#include <gtest/gtest.h>

#include <cmath>

#include "crush_tangential_kernel.h"

using namespace CrushKernels;

namespace {

// Displacement-based rule of LIGGGHTS' `tangential history` (the answer the
// incremental rule must differ from): u += v dt, F = -k_t(now) u, capped.
struct HistoryContact {
  double u = 0.0;
  double force(double v, double kt, double dt, double limit)
  {
    u += v * dt;
    double f = -kt * u;
    if (std::fabs(f) > limit) {
      f = (f > 0 ? limit : -limit);
      u = -f / kt;
    }
    return f;
  }
};

const double n_z[3] = { 0.0, 0.0, 1.0 };

}  // namespace

TEST(TangentialIncremental, ConstantNormalForceLoadsLinearlyThenSlides)
{
  // k_t = 2e6 N/m, v = 1e-3 m/s along x, dt = 1e-6 s, mu F_n = 0.5 N:
  // F_t = -k_t v t (2e-3 N a step) until |F_t| = 0.5 N after 250 steps.
  const double kt = 2e6, dt = 1e-6, limit = 0.5;
  const double v[3] = { 1e-3, 0.0, 0.0 };
  double ft[3] = { 0.0, 0.0, 0.0 };
  for (int step = 1; step <= 200; step++) {
    EXPECT_FALSE(tangential_force_step(ft, n_z, v, kt, dt, limit));
    EXPECT_NEAR(ft[0], -kt * 1e-3 * step * dt, 1e-12);
  }
  bool slid = false;
  for (int step = 201; step <= 400; step++)
    slid = tangential_force_step(ft, n_z, v, kt, dt, limit) || slid;
  EXPECT_TRUE(slid);
  EXPECT_NEAR(ft[0], -limit, 1e-12);
  EXPECT_DOUBLE_EQ(ft[1], 0.0);
  EXPECT_DOUBLE_EQ(ft[2], 0.0);
}

TEST(TangentialIncremental, ReversalAfterSlipUnloadsFromTheLimit)
{
  // After sliding at -limit, reversing the motion lowers |F_t| by k_t du
  // from the limit (the slip is forgotten), and the force reaches +limit
  // after 2 limit / k_t of reverse travel.
  const double kt = 1e6, dt = 1e-6, limit = 0.3;
  const double fwd[3] = { 1e-3, 0.0, 0.0 }, back[3] = { -1e-3, 0.0, 0.0 };  // 1e-3 N a step
  double ft[3] = { 0.0, 0.0, 0.0 };
  for (int s = 0; s < 1000; s++) tangential_force_step(ft, n_z, fwd, kt, dt, limit);
  EXPECT_NEAR(ft[0], -limit, 1e-12);
  for (int s = 0; s < 100; s++) tangential_force_step(ft, n_z, back, kt, dt, limit);
  EXPECT_NEAR(ft[0], -limit + kt * 1e-3 * 100 * dt, 1e-12);
  for (int s = 0; s < 1000; s++) tangential_force_step(ft, n_z, back, kt, dt, limit);
  EXPECT_NEAR(ft[0], limit, 1e-12);
}

TEST(TangentialIncremental, FallingNormalForceKeepsTheForceWhereHistoryScalesIt)
{
  // Load to 60 % of the limit at k_t1, then hold the tangential position
  // (v = 0) while the normal overlap falls so that k_t drops to k_t2 and the
  // limit stays above the force: incremental keeps F_t, history gives
  // F_t k_t2 / k_t1.
  const double kt1 = 4e6, kt2 = 1e6, dt = 1e-6;
  const double limit1 = 1.0, limit2 = 0.7;
  const double v[3] = { 0.0, 1e-3, 0.0 }, rest[3] = { 0.0, 0.0, 0.0 };
  double ft[3] = { 0.0, 0.0, 0.0 };
  HistoryContact hist;
  double f_hist = 0.0;
  for (int s = 0; s < 150; s++) {
    tangential_force_step(ft, n_z, v, kt1, dt, limit1);
    f_hist = hist.force(v[1], kt1, dt, limit1);
  }
  const double f_loaded = -kt1 * 1e-3 * 150 * dt;  // -0.6 N
  EXPECT_NEAR(ft[1], f_loaded, 1e-12);
  EXPECT_NEAR(f_hist, f_loaded, 1e-12);

  EXPECT_FALSE(tangential_force_step(ft, n_z, rest, kt2, dt, limit2));
  f_hist = hist.force(0.0, kt2, dt, limit2);
  EXPECT_NEAR(ft[1], f_loaded, 1e-12);                // kept
  EXPECT_NEAR(f_hist, f_loaded * kt2 / kt1, 1e-12);   // scaled: -0.15 N

  // The limit then falls below the kept force: it slides at the limit.
  EXPECT_TRUE(tangential_force_step(ft, n_z, rest, kt2, dt, 0.4));
  EXPECT_NEAR(ft[1], -0.4, 1e-12);
}

TEST(TangentialIncremental, TurningContactPlaneKeepsTheMagnitude)
{
  // A force (3, 4, 0) N in the plane of n = z; the normal turns by 30 deg
  // about x: the force is brought into the new plane at the same length.
  double ft[3] = { 3.0, 4.0, 0.0 };
  const double a = M_PI / 6.0;
  const double n[3] = { 0.0, -std::sin(a), std::cos(a) };
  tangential_force_rotate(ft, n);
  EXPECT_NEAR(norm3(ft), 5.0, 1e-12);
  EXPECT_NEAR(ft[0] * n[0] + ft[1] * n[1] + ft[2] * n[2], 0.0, 1e-12);
  // its x part (along the axis of the turn) is unchanged up to the rescale
  // of the projected part: direction in the new plane as a rigid turn gives.
  EXPECT_NEAR(ft[0], 3.0 * 5.0 / std::sqrt(9.0 + 16.0 * std::cos(a) * std::cos(a)), 1e-12);
  // A force already in the plane is left alone; a zero force stays zero.
  double g[3] = { 1.0, 2.0, 0.0 };
  tangential_force_rotate(g, n_z);
  EXPECT_DOUBLE_EQ(g[0], 1.0);
  EXPECT_DOUBLE_EQ(g[1], 2.0);
  double z[3] = { 0.0, 0.0, 0.0 };
  tangential_force_rotate(z, n);
  EXPECT_DOUBLE_EQ(norm3(z), 0.0);
}

TEST(TangentialIncremental, ZeroLimitGivesZeroForce)
{
  // F_n = 0 (a grazing contact): no tangential force can be carried.
  double ft[3] = { 0.2, -0.1, 0.0 };
  const double v[3] = { 1.0, 1.0, 0.0 };
  EXPECT_TRUE(tangential_force_step(ft, n_z, v, 1e6, 1e-6, 0.0));
  EXPECT_DOUBLE_EQ(norm3(ft), 0.0);
}
