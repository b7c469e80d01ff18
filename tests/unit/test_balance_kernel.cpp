// SPDX-License-Identifier: GPL-2.0-or-later
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <vector>

#include "crush_balance_kernel.h"

using namespace CrushKernels;

namespace {

// counts of each part for points at fractional positions f
std::vector<double> part_counts(const std::vector<double> &f, const std::vector<double> &splits)
{
  std::vector<double> n(splits.size() - 1, 0.0);
  for (size_t i = 0; i < f.size(); i++) n[balance_part(f[i], splits)] += 1.0;
  return n;
}

std::vector<double> histogram(const std::vector<double> &f, int nbins)
{
  std::vector<double> h(nbins, 0.0);
  for (size_t i = 0; i < f.size(); i++) h[balance_bin(f[i], nbins)] += 1.0;
  return h;
}

// deterministic pseudo-random numbers in [0, 1) (no dependence on the C library)
struct Lcg {
  unsigned long long s;
  explicit Lcg(unsigned long long seed) : s(seed) {}
  double next()
  {
    s = s * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(s >> 11) / 9007199254740992.0;
  }
};

}  // namespace

TEST(BalanceKernel, BinClampsToTheEnds)
{
  EXPECT_EQ(balance_bin(-0.1, 10), 0);
  EXPECT_EQ(balance_bin(0.0, 10), 0);
  EXPECT_EQ(balance_bin(0.05, 10), 0);
  EXPECT_EQ(balance_bin(0.15, 10), 1);
  EXPECT_EQ(balance_bin(1.0, 10), 9);
  EXPECT_EQ(balance_bin(1.3, 10), 9);
  EXPECT_EQ(balance_bin(std::nan(""), 10), 0);
}

TEST(BalanceKernel, PartFollowsLiggghtsOwnershipRule)
{
  const std::vector<double> s = {0.0, 0.2, 0.7, 1.0};
  EXPECT_EQ(balance_part(-0.5, s), 0);
  EXPECT_EQ(balance_part(0.0, s), 0);
  EXPECT_EQ(balance_part(0.1999, s), 0);
  EXPECT_EQ(balance_part(0.2, s), 1);  // lower face belongs to the part
  EXPECT_EQ(balance_part(0.6999, s), 1);
  EXPECT_EQ(balance_part(0.7, s), 2);
  EXPECT_EQ(balance_part(1.0, s), 2);
  EXPECT_EQ(balance_part(2.0, s), 2);
}

TEST(BalanceKernel, UniformCountsGiveUniformCuts)
{
  const std::vector<double> h(100, 7.0);
  const std::vector<double> s = balance_cuts(h, 4, 0.0);
  ASSERT_EQ(s.size(), 5u);
  for (int k = 0; k <= 4; k++) EXPECT_NEAR(s[k], 0.25 * k, 1e-14);
}

TEST(BalanceKernel, LinearDensityGivesSquareRootQuantiles)
{
  // density proportional to f on [0,1]: cumulative f^2, so the cut of the
  // k-th of P parts is sqrt(k/P). With bin counts equal to the exact
  // integral over each bin, linear interpolation within a bin is exact
  // up to the curvature inside that bin (< 1/nbins^2).
  const int nbins = 1000, parts = 4;
  std::vector<double> h(nbins);
  for (int j = 0; j < nbins; j++) {
    const double a = static_cast<double>(j) / nbins, b = static_cast<double>(j + 1) / nbins;
    h[j] = b * b - a * a;
  }
  const std::vector<double> s = balance_cuts(h, parts, 0.0);
  for (int k = 1; k < parts; k++) EXPECT_NEAR(s[k], std::sqrt(static_cast<double>(k) / parts), 1e-6);
  EXPECT_EQ(s[0], 0.0);
  EXPECT_EQ(s[parts], 1.0);
}

TEST(BalanceKernel, EmptyGapPutsTheCutInItsMiddle)
{
  // half the grains in bin 1, half in bin 8: the cut between 2 parts lies
  // anywhere in the empty bins 2..7, and is put at their middle (0.5)
  std::vector<double> h(10, 0.0);
  h[1] = 50.0;
  h[8] = 50.0;
  const std::vector<double> s = balance_cuts(h, 2, 0.0);
  EXPECT_NEAR(s[1], 0.5, 1e-14);
  // asymmetric gap: bins 3..4 empty between grains in 0..2 and 5..9
  std::vector<double> g(10, 0.0);
  for (int j = 0; j < 3; j++) g[j] = 10.0;
  for (int j = 5; j < 10; j++) g[j] = 6.0;
  EXPECT_NEAR(balance_cuts(g, 2, 0.0)[1], 0.4, 1e-14);
}

TEST(BalanceKernel, PointsBalanceWithinOneBinOfGrains)
{
  // strongly non-uniform grains (density ~ f^3), 8 parts: every part holds
  // N/8 up to the grains of one bin (the interpolation within a bin)
  Lcg rng(10007);
  std::vector<double> f;
  for (int i = 0; i < 40000; i++) f.push_back(std::pow(rng.next(), 0.25));
  const int nbins = 2000, parts = 8;
  const std::vector<double> h = histogram(f, nbins);
  double hmax = 0.0;
  for (int j = 0; j < nbins; j++) hmax = std::max(hmax, h[j]);
  const std::vector<double> n = part_counts(f, balance_cuts(h, parts, 0.0));
  for (int k = 0; k < parts; k++) EXPECT_NEAR(n[k], 5000.0, hmax);
  EXPECT_LT(balance_imbalance(n), 1.0 + hmax / 5000.0);
  // the uniform cuts would be far off
  std::vector<double> u(parts + 1);
  for (int k = 0; k <= parts; k++) u[k] = static_cast<double>(k) / parts;
  EXPECT_GT(balance_imbalance(part_counts(f, u)), 3.0);
}

TEST(BalanceKernel, MinimumWidthKeepsEveryPartNonEmpty)
{
  // every grain in one bin: quantiles all inside that bin; with a minimum
  // width each part is at least that wide and the cuts stay in (0, 1)
  std::vector<double> h(100, 0.0);
  h[99] = 1000.0;
  const double w = 0.05;
  const std::vector<double> s = balance_cuts(h, 4, w);
  for (int k = 0; k < 4; k++) EXPECT_GE(s[k + 1] - s[k], w - 1e-14);
  EXPECT_EQ(s[0], 0.0);
  EXPECT_EQ(s[4], 1.0);
}

TEST(BalanceKernel, NoGrainsOrOnePartGiveUniformCuts)
{
  const std::vector<double> s = balance_cuts(std::vector<double>(10, 0.0), 3, 0.0);
  EXPECT_NEAR(s[1], 1.0 / 3.0, 1e-15);
  EXPECT_NEAR(s[2], 2.0 / 3.0, 1e-15);
  const std::vector<double> one = balance_cuts(std::vector<double>(10, 1.0), 1, 0.0);
  ASSERT_EQ(one.size(), 2u);
  EXPECT_EQ(one[0], 0.0);
  EXPECT_EQ(one[1], 1.0);
}

TEST(BalanceKernel, StepsMoveEachPointAtMostOneRankAndReachTheTarget)
{
  // random old and new cuts for 2..9 parts: each step moves every point of
  // a fine grid by at most one grid index, the cuts stay strictly
  // increasing, and the target is reached within parts - 1 steps
  Lcg rng(10009);
  for (int trial = 0; trial < 2000; trial++) {
    const int parts = 2 + trial % 8;
    std::vector<double> a(parts + 1), b(parts + 1);
    a[0] = b[0] = 0.0;
    for (int k = 1; k <= parts; k++) {
      a[k] = a[k - 1] + 0.01 + rng.next();
      b[k] = b[k - 1] + 0.01 + rng.next();
    }
    for (int k = 1; k <= parts; k++) {
      a[k] /= a[parts];
      b[k] /= b[parts];
    }
    a[parts] = b[parts] = 1.0;
    std::vector<double> cur = a;
    int steps = 0;
    while (cur != b && steps < parts + 2) {
      const std::vector<double> next = balance_step(cur, b);
      for (int k = 0; k < parts; k++) ASSERT_LT(next[k], next[k + 1]);
      for (int i = 0; i <= 1000; i++) {
        const double f = i / 1000.0;
        ASSERT_LE(std::abs(balance_part(f, next) - balance_part(f, cur)), 1);
      }
      cur = next;
      steps++;
    }
    EXPECT_TRUE(cur == b) << "parts " << parts;
    EXPECT_LE(steps, parts - 1);
  }
}

TEST(BalanceKernel, ImbalanceIsMaxOverMean)
{
  EXPECT_DOUBLE_EQ(balance_imbalance({10.0, 10.0, 10.0, 10.0}), 1.0);
  EXPECT_DOUBLE_EQ(balance_imbalance({0.0, 10.0, 20.0, 10.0}), 2.0);
  EXPECT_DOUBLE_EQ(balance_imbalance({0.0, 0.0}), 1.0);
  EXPECT_DOUBLE_EQ(balance_imbalance({}), 1.0);
}
