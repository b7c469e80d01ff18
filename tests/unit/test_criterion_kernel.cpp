// SPDX-License-Identifier: GPL-2.0-or-later
// Criterion readings (crush_criterion_kernel.h) against the Hertz formulas of
// crush_breakage_kernel.h: each factor makes the reading's pressure or force
// equal to sigma_lim at F_lim k.
#include <gtest/gtest.h>

#include <cmath>

#include "crush_breakage_kernel.h"
#include "crush_criterion_kernel.h"

using namespace CrushKernels;

namespace {
// Hertz contact radius at force F: a^3 = 3 F R* / (4 E*)
double contact_radius(double F, double R, double E) { return std::cbrt(3.0 * F * R / (4.0 * E)); }
}  // namespace

TEST(Criterion, PrintedReadingIsOne)
{
  EXPECT_EQ(pressure_limit_factor(PRESSURE_MEAN), 1.0);
  EXPECT_EQ(force_limit_factor(FORCE_NORMAL, 0.5), 1.0);
  EXPECT_EQ(limit_overlap_factor(1.0), 1.0);
  EXPECT_EQ(size_law_scale(SIZE_PRINTED, 39.0), 39.0);
}

TEST(Criterion, PeakPressureReachesSigmaAtItsLimit)
{
  const double sigma = 2.4e9, R = 2e-4, E = 1.2e10;
  const double F = limit_force(sigma, R, E) * pressure_limit_factor(PRESSURE_PEAK);
  const double a = contact_radius(F, R, E);
  EXPECT_NEAR(1.5 * F / (kPi * a * a) / sigma, 1.0, 1e-13);
  EXPECT_NEAR(1.0 / pressure_limit_factor(PRESSURE_PEAK), 3.375, 1e-14);
}

TEST(Criterion, SlidingForceReachesTheLimit)
{
  const double mu = 0.275, Fn = 100.0;
  const double k = force_limit_factor(FORCE_SLIDING, mu);
  // a sliding contact at F_n = F_lim k carries F_lim in total
  const double Ft = mu * Fn;
  EXPECT_NEAR(std::sqrt(Fn * Fn + Ft * Ft) * k / Fn, 1.0, 1e-15);
  EXPECT_NEAR(k, 0.96420, 1e-5);
}

TEST(Criterion, OverlapFactorFollowsHertz)
{
  const double sigma = 1.1e9, R = 3e-4, E = 2e10;
  for (double k : {8.0 / 27.0, 0.9, 1.0 / 27.0}) {
    const double d1 = limit_overlap(sigma, R, E) * limit_overlap_factor(k);
    EXPECT_NEAR(hertz_normal_force(d1, R, E) / (k * limit_force(sigma, R, E)), 1.0, 1e-12) << k;
  }
}

TEST(Criterion, SizeTermWithoutNWeakensTwentySevenFold)
{
  const double d = 39 * 0.21e-3, s0 = 1.9e9, d0 = 2e-3, m = 10, N = 39;
  const double printed = size_effect_strength(s0, 1.0, d, size_law_scale(SIZE_PRINTED, N), d0, m);
  const double no_N = size_effect_strength(s0, 1.0, d, size_law_scale(SIZE_NO_N, N), d0, m);
  EXPECT_NEAR(printed / no_N, std::pow(39.0, 0.3), 1e-12);
  const double F_ratio = std::pow(printed / no_N, 3.0);   // F_lim ~ sigma^3
  EXPECT_NEAR(F_ratio, std::pow(39.0, 0.9), 1e-9);
  EXPECT_NEAR(F_ratio, 27.0, 0.1 * 27.0);
}
