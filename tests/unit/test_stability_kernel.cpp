// SPDX-License-Identifier: GPL-2.0-or-later
// Stiffest-contact bound and blow-up signals (crush_stability_kernel.h)
// against independent answers: the numerical derivative of the Hertz force,
// the breakage-limit overlap of crush_breakage_kernel.h and direct sqrt tests.
#include <gtest/gtest.h>

#include <cmath>

#include "crush_breakage_kernel.h"
#include "crush_stability_kernel.h"

using namespace CrushKernels;

TEST(StabilityKernel, StiffnessAtPressureIsTheHertzTangent)
{
  // at the overlap where the mean pressure is p, dF/ddelta by central
  // differences of F = 4/3 E* sqrt(R*) delta^1.5
  for (double E_star : {1.125e10, 2.03e10, 1e21}) {
    const double R = 2e-3, p = 3.7e9;
    const double d = hertz_overlap_at_pressure(p, R, E_star);
    const double F = hertz_normal_force(d, R, E_star);
    const double a2 = R * d;  // contact radius squared
    EXPECT_NEAR(F / (kPi * a2) / p, 1.0, 1e-12);
    const double h = 1e-6 * d;
    const double k_num = (hertz_normal_force(d + h, R, E_star) - hertz_normal_force(d - h, R, E_star)) / (2 * h);
    EXPECT_NEAR(hertz_stiffness_at_pressure(p, R) / k_num, 1.0, 1e-8) << E_star;
  }
}

TEST(StabilityKernel, OverlapAtSigmaLimIsTheLimitOverlap)
{
  EXPECT_DOUBLE_EQ(hertz_overlap_at_pressure(2e9, 1e-3, 1.1e10), limit_overlap(2e9, 1e-3, 1.1e10));
}

TEST(StabilityKernel, WallAndEqualPartnerGiveTheSameOmega)
{
  // two-body relative motion: omega^2 = k / m*, m* = m m_q / (m + m_q)
  const double p = 4e9, r = 1e-3, rho = 2600, m = 4.0 / 3.0 * kPi * r * r * r * rho;
  const double w_wall = std::sqrt(hertz_stiffness_at_pressure(p, r) / m);
  const double w_pair = std::sqrt(hertz_stiffness_at_pressure(p, 0.5 * r) / (0.5 * m));
  EXPECT_NEAR(contact_omega_max(p, r, m) / w_wall, 1.0, 1e-14);
  EXPECT_NEAR(w_pair / w_wall, 1.0, 1e-14);
  // a larger partner of the same density gives less
  for (double x : {1.5, 2.0, 5.0}) {
    const double rq = x * r, mq = m * x * x * x, Rs = r * rq / (r + rq), ms = m * mq / (m + mq);
    EXPECT_LT(std::sqrt(hertz_stiffness_at_pressure(p, Rs) / ms), w_wall) << x;
  }
}

TEST(StabilityKernel, MovedTooFar)
{
  EXPECT_FALSE(moved_too_far(10.0 * 10.0, 1e-6, 1e-4, 0.1));   // 1e-5 m = 0.1 r: not beyond
  EXPECT_TRUE(moved_too_far(10.01 * 10.01, 1e-6, 1e-4, 0.1));
  EXPECT_FALSE(moved_too_far(0.0, 1.0, 1e-4, 0.1));
}

TEST(StabilityKernel, OverlapTooDeepMatchesTheSquareRootTest)
{
  const double ri = 1e-3, rj = 0.4e-3;
  for (double frac : {0.1, 0.5, 1.0, 2.0, 3.0})
    for (double dist = 0.0; dist < 1.6e-3; dist += 0.37e-4) {
      const bool direct = (ri + rj - dist) > frac * std::min(ri, rj);
      EXPECT_EQ(overlap_too_deep(dist * dist, ri, rj, frac), direct) << frac << " " << dist;
    }
}
