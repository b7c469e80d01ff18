// SPDX-License-Identifier: GPL-2.0-or-later
// Strength scatter laws (crush_strength_kernel.h): moments of large samples
// against the laws' exact moments, the truncation bound, and the printed law
// kept draw for draw.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "crush_breakage_kernel.h"
#include "crush_strength_kernel.h"

using namespace CrushKernels;

namespace {
const uint64_t kSeed = 15485863;
void moments(const std::vector<double> &f, double *mean, double *sd)
{
  double s = 0, s2 = 0;
  for (double x : f) { s += x; s2 += x * x; }
  *mean = s / f.size();
  *sd = std::sqrt(s2 / f.size() - *mean * *mean);
}
}  // namespace

TEST(Strength, NormalLawIsThePrintedDraw)
{
  for (uint64_t tag = 1; tag < 2000; ++tag)
    EXPECT_EQ(strength_factor_law(SCATTER_NORMAL, kSeed, tag, 0.36, 0.0, 0.0),
              strength_factor(kSeed, tag, 0.36));
}

TEST(Strength, VarZeroIsOneForEveryLaw)
{
  for (int law : {SCATTER_NORMAL, SCATTER_TRUNCATED, SCATTER_WEIBULL})
    EXPECT_EQ(strength_factor_law(law, kSeed, 7, 0.0, 0.5, 3.0), 1.0);
}

TEST(Strength, WeibullShapeGivesTheCoefficientOfVariation)
{
  for (double cv : {0.1, 0.36, 0.5, 1.0}) {
    const double k = weibull_shape_for_cov(cv);
    EXPECT_NEAR(weibull_cov(k), cv, 1e-10) << cv;
  }
  // exponential law: shape 1, cv 1
  EXPECT_NEAR(weibull_shape_for_cov(1.0), 1.0, 1e-9);
}

TEST(Strength, WeibullSampleHasMeanOneAndTheCv)
{
  const double cv = 0.36, k = weibull_shape_for_cov(cv);
  std::vector<double> f;
  for (uint64_t tag = 1; tag <= 200000; ++tag) f.push_back(strength_factor_law(SCATTER_WEIBULL, kSeed, tag, cv, 0, k));
  double mean, sd;
  moments(f, &mean, &sd);
  // standard errors: cv / sqrt(n) = 8e-4 for the mean; 4 of them
  EXPECT_NEAR(mean, 1.0, 4 * cv / std::sqrt(200000.0));
  EXPECT_NEAR(sd, cv, 0.01 * cv);
  for (double x : f) EXPECT_GT(x, 0.0);
}

TEST(Strength, TruncatedLawStaysAboveItsBound)
{
  const double var = 0.36, f_min = 0.5;
  std::vector<double> f;
  for (uint64_t tag = 1; tag <= 100000; ++tag) {
    const double x = strength_factor_law(SCATTER_TRUNCATED, kSeed, tag, var, f_min, 0);
    ASSERT_GT(x, f_min);
    f.push_back(x);
  }
  // exact mean of Normal(1, var) truncated below at f_min:
  // 1 + var phi(a) / (1 - Phi(a)), a = (f_min - 1) / var
  const double a = (f_min - 1.0) / var;
  const double phi = std::exp(-0.5 * a * a) / std::sqrt(2.0 * kPi);
  const double Phi = 0.5 * std::erfc(-a / std::sqrt(2.0));
  const double mean_exact = 1.0 + var * phi / (1.0 - Phi);
  double mean, sd;
  moments(f, &mean, &sd);
  EXPECT_NEAR(mean, mean_exact, 4 * var / std::sqrt(100000.0));
  EXPECT_GT(mean, 1.0);
  // the draws above the bound are those of the printed law, tag by tag
  for (uint64_t tag = 1; tag <= 2000; ++tag) {
    const double p = strength_factor(kSeed, tag, var);
    if (p > f_min) EXPECT_EQ(strength_factor_law(SCATTER_TRUNCATED, kSeed, tag, var, f_min, 0), p);
  }
}
