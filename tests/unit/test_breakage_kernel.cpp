// SPDX-License-Identifier: GPL-2.0-or-later
// Unit tests for crush_breakage_kernel.h (docs/model.md §2 and §5): Russell &
// Muir Wood limit force, Hertz contact, size effect, seeded strength scatter,
// Rayleigh time. Every expected value is derived independently of the kernel
// formula it checks (numerical root finding, closed-form statistics, values
// computed by hand), so a wrong kernel makes the test fail.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <cstdint>
#include <vector>

#include "crush_breakage_kernel.h"

using namespace CrushKernels;

namespace {

const double kPiRef = 3.14159265358979323846;

// Calibrated NE34 parameters (docs/model.md §3) and steel pile.
const double kG = 9e9, kNu = 0.2, kE = 2.0 * kG * (1.0 + kNu);  // 21.6 GPa
const double kEsteel = 2.0 * 85e9 * 1.2;                          // 204 GPa
const double kSigma0 = 1.9e9, kM = 10.0, kD0 = 2e-3, kVar = 0.36;

// Hertz contact radius for force F: a = (3 F R* / (4 E*))^(1/3).
double hertz_contact_radius(double F, double R, double E)
{
  return std::cbrt(3.0 * F * R / (4.0 * E));
}

// Independent solution of F = sigma pi a(F)^2 by bisection on ln F: the mean
// contact pressure F / (pi a^2) grows like F^(1/3), so the root is unique.
double limit_force_by_bisection(double sigma, double R, double E)
{
  double lo = std::log(1e-30), hi = std::log(1e30);
  for (int it = 0; it < 300; ++it) {
    const double mid = 0.5 * (lo + hi);
    const double F = std::exp(mid);
    const double a = hertz_contact_radius(F, R, E);
    if (F / (kPiRef * a * a) < sigma) lo = mid; else hi = mid;
  }
  return std::exp(0.5 * (lo + hi));
}

struct Case { double sigma, R, E; };

std::vector<Case> contact_cases()
{
  const double Epp = 1.0 / (2.0 * (1.0 - kNu * kNu) / kE);                 // grain-grain
  const double Epw = 1.0 / ((1.0 - kNu * kNu) / kE + (1.0 - kNu * kNu) / kEsteel);  // grain-steel
  return {
    {1.9e9, 0.105e-3 / 2.0, Epp},            // two d50 grains, real size
    {1.9e9 * 2.3, 0.105e-3, Epw},            // grain on the pile (wall)
    {3.1e8, 4.095e-3 * 0.5, Epp},            // N = 39 scene
    {1.0, 1.0, 1.0},                         // dimensionless
    {7.3e7, 2.2e-5, 3.7e10},
  };
}

double normal_cdf(double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); }
double normal_pdf(double x) { return std::exp(-0.5 * x * x) / std::sqrt(2.0 * kPiRef); }

}  // namespace

// ---------------------------------------------------------------------------
// Limit force and Hertz contact

TEST(BreakageKernel, LimitForceIsSigmaTimesHertzContactArea)
{
  for (const Case& c : contact_cases()) {
    const double F = limit_force(c.sigma, c.R, c.E);
    ASSERT_GT(F, 0.0);
    // Self-consistency: at F = F_lim, sigma_lim * pi * a(F_lim)^2 == F_lim.
    const double a = hertz_contact_radius(F, c.R, c.E);
    EXPECT_NEAR(c.sigma * kPiRef * a * a, F, 1e-12 * F);
    // Independent derivation: root of F = sigma pi a(F)^2 found numerically.
    const double Fb = limit_force_by_bisection(c.sigma, c.R, c.E);
    EXPECT_NEAR(F, Fb, 1e-10 * Fb);
    // Mean contact pressure below sigma_lim just under F_lim, above it just over.
    const double a_lo = hertz_contact_radius(0.999 * F, c.R, c.E);
    const double a_hi = hertz_contact_radius(1.001 * F, c.R, c.E);
    EXPECT_LT(0.999 * F / (kPiRef * a_lo * a_lo), c.sigma);
    EXPECT_GT(1.001 * F / (kPiRef * a_hi * a_hi), c.sigma);
  }
}

TEST(BreakageKernel, LimitForceScaling)
{
  // F_lim ~ sigma^3 R*^2 / E*^2.
  const double F = limit_force(2.0e9, 1e-4, 1e10);
  EXPECT_NEAR(limit_force(4.0e9, 1e-4, 1e10), 8.0 * F, 1e-12 * 8.0 * F);
  EXPECT_NEAR(limit_force(2.0e9, 3e-4, 1e10), 9.0 * F, 1e-12 * 9.0 * F);
  EXPECT_NEAR(limit_force(2.0e9, 1e-4, 2e10), 0.25 * F, 1e-12 * 0.25 * F);
  // Hand value: sigma = 1, R* = 1, E* = 1 -> pi^3 * 9/16.
  EXPECT_NEAR(limit_force(1.0, 1.0, 1.0), 31.006276680299820 * 0.5625, 1e-13);
}

TEST(BreakageKernel, HertzForceAtLimitOverlapEqualsLimitForce)
{
  for (const Case& c : contact_cases()) {
    const double d = limit_overlap(c.sigma, c.R, c.E);
    ASSERT_GT(d, 0.0);
    const double F = limit_force(c.sigma, c.R, c.E);
    EXPECT_NEAR(hertz_normal_force(d, c.R, c.E), F, 1e-12 * F);
    // Geometric check: Hertz a^2 = R* delta, so at the limit pi a^2 sigma == F.
    EXPECT_NEAR(kPiRef * c.R * d * c.sigma, F, 1e-12 * F);
  }
}

TEST(BreakageKernel, HertzNormalForce)
{
  // F = 4 E* a^3 / (3 R*) with a = sqrt(R* delta) (independent form).
  const double R = 2.5e-4, E = 1.1e10;
  for (double delta : {1e-9, 3.7e-7, 2e-6, 1e-5}) {
    const double a = std::sqrt(R * delta);
    const double ref = 4.0 * E * a * a * a / (3.0 * R);
    EXPECT_NEAR(hertz_normal_force(delta, R, E), ref, 1e-13 * ref);
  }
  EXPECT_EQ(hertz_normal_force(0.0, R, E), 0.0);
  EXPECT_EQ(hertz_normal_force(-1e-6, R, E), 0.0);
}

TEST(BreakageKernel, EffectiveRadius)
{
  EXPECT_NEAR(effective_radius(2.0, 3.0), 1.2, 1e-15);       // 1/(1/2 + 1/3)
  EXPECT_NEAR(effective_radius(3.0, 2.0), 1.2, 1e-15);
  EXPECT_NEAR(effective_radius(1e-4, 1e-4), 5e-5, 1e-20);    // equal spheres: r/2
  EXPECT_NEAR(effective_radius(1e-4, 3e-4), 7.5e-5, 1e-19);
  // Wall: 1/r_q = 0, R* = r_p.
  EXPECT_EQ(effective_radius(1.7e-4, 0.0), 1.7e-4);
  EXPECT_EQ(effective_radius(1.7e-4, -1.0), 1.7e-4);
  // Huge partner approaches the wall value.
  EXPECT_NEAR(effective_radius(1.0, 1e12), 1.0, 1e-11);
}

TEST(BreakageKernel, EffectiveModulus)
{
  // Identical materials: E* = E / (2 (1 - nu^2)).
  EXPECT_NEAR(effective_modulus(kE, kNu, kE, kNu), kE / (2.0 * (1.0 - kNu * kNu)), 1e-6);
  EXPECT_NEAR(effective_modulus(kE, kNu, kE, kNu), 11.25e9, 1e-3);  // 21.6e9 / 1.92
  // Grain on steel (wall uses its own material), hand value:
  // 1/E* = 0.96/21.6e9 + 0.96/204e9 -> E* = 21.6e9*204e9/(0.96*225.6e9).
  const double ref = 21.6e9 * 204e9 / (0.96 * (21.6e9 + 204e9));
  EXPECT_NEAR(effective_modulus(kE, kNu, kEsteel, kNu), ref, 1e-12 * ref);
  EXPECT_NEAR(effective_modulus(kEsteel, kNu, kE, kNu), ref, 1e-12 * ref);
  // Different Poisson ratios.
  const double ref2 = 1.0 / ((1.0 - 0.09) / 70e9 + (1.0 - 0.25) / 200e9);
  EXPECT_NEAR(effective_modulus(70e9, 0.3, 200e9, 0.5), ref2, 1e-12 * ref2);
  // Rigid partner: E* -> E/(1 - nu^2).
  EXPECT_NEAR(effective_modulus(1.0, 0.5, 1e300, 0.0), 1.0 / 0.75, 1e-14);
}

// ---------------------------------------------------------------------------
// Size effect

TEST(BreakageKernel, SizeEffectDoublingDiameter)
{
  // m = 10: factor 2^(-0.3) = 0.8122523963562356 (hand value).
  const double s1 = size_effect_strength(kSigma0, 1.0, 0.21e-3, 1.0, kD0, 10.0);
  const double s2 = size_effect_strength(kSigma0, 1.0, 0.42e-3, 1.0, kD0, 10.0);
  EXPECT_NEAR(s2 / s1, 0.8122523963562356, 1e-13);
  for (double m : {3.0, 5.0, 10.0, 20.0}) {
    for (double d : {1e-5, 2.1e-4, 8.19e-3}) {
      const double a = size_effect_strength(kSigma0, 1.3, d, 39.0, kD0, m);
      const double b = size_effect_strength(kSigma0, 1.3, 2.0 * d, 39.0, kD0, m);
      EXPECT_NEAR(b / a, std::exp(-3.0 * std::log(2.0) / m), 1e-13);
    }
  }
}

TEST(BreakageKernel, SizeEffectReferenceDiameterAndScaling)
{
  // At d = N d0 the size factor is 1: sigma = sigma_lim0 * f.
  for (double N : {1.0, 39.0}) {
    for (double f : {0.4, 1.0, 1.7}) {
      EXPECT_NEAR(size_effect_strength(kSigma0, f, N * kD0, N, kD0, kM), kSigma0 * f,
                  1e-15 * kSigma0);
    }
  }
  // Linear in f and in sigma_lim0.
  const double base = size_effect_strength(kSigma0, 1.0, 0.21e-3, 1.0, kD0, kM);
  EXPECT_NEAR(size_effect_strength(kSigma0, 0.6, 0.21e-3, 1.0, kD0, kM), 0.6 * base,
              1e-14 * base);
  EXPECT_NEAR(size_effect_strength(2.0 * kSigma0, 1.0, 0.21e-3, 1.0, kD0, kM), 2.0 * base,
              1e-14 * base);
  // Hand value, d50 = 0.21 mm, N = 1: (0.21/2)^(-0.3) = exp(-0.3 ln 0.105).
  EXPECT_NEAR(base / kSigma0, std::exp(-0.3 * std::log(0.105)), 1e-13);
  // Scene at N = 39 with d = 39 d50 has the same strength as d50 at N = 1.
  EXPECT_NEAR(size_effect_strength(kSigma0, 1.0, 39.0 * 0.21e-3, 39.0, kD0, kM), base,
              1e-12 * base);
  // Smaller is stronger.
  EXPECT_GT(size_effect_strength(kSigma0, 1.0, 0.1e-3, 1.0, kD0, kM), base);
}

// ---------------------------------------------------------------------------
// Random numbers and strength scatter

TEST(BreakageKernel, Uniform01RangeAndMoments)
{
  const int n = 100000;
  double sum = 0.0, sum2 = 0.0;
  double mn = 1.0, mx = 0.0;
  for (int i = 0; i < n; ++i) {
    const double u = uniform01(12345u, static_cast<uint64_t>(i + 1), STREAM_STRENGTH, 0);
    ASSERT_GT(u, 0.0);
    ASSERT_LT(u, 1.0);
    mn = std::min(mn, u);
    mx = std::max(mx, u);
    sum += u;
    sum2 += u * u;
  }
  const double mean = sum / n;
  EXPECT_NEAR(mean, 0.5, 0.005);
  EXPECT_NEAR(sum2 / n - mean * mean, 1.0 / 12.0, 0.002);
  EXPECT_LT(mn, 1e-3);
  EXPECT_GT(mx, 1.0 - 1e-3);
  // Counter direction too (one tag, many counters).
  sum = 0.0;
  for (int i = 0; i < n; ++i) sum += uniform01(7u, 99u, STREAM_ROTATION, static_cast<uint64_t>(i));
  EXPECT_NEAR(sum / n, 0.5, 0.005);
}

TEST(BreakageKernel, Uniform01NoCollisionsAcrossTags)
{
  // Every tag gets its own draw: 100,000 small tags plus tags with high bits
  // set (LIGGGHTS tags are 32-bit; fragments get new tags) give 300,000
  // distinct values (a 53-bit collision by chance has probability ~5e-6).
  std::vector<double> v;
  for (uint64_t t = 1; t <= 100000; ++t) {
    v.push_back(uniform01(4242u, t, STREAM_STRENGTH, 0));
    v.push_back(uniform01(4242u, t + (uint64_t(1) << 31), STREAM_STRENGTH, 0));
    v.push_back(uniform01(4242u, t + (uint64_t(1) << 20), STREAM_STRENGTH, 0));
  }
  std::sort(v.begin(), v.end());
  EXPECT_EQ(std::adjacent_find(v.begin(), v.end()) - v.begin(), static_cast<long>(v.size()));
}

TEST(BreakageKernel, StandardNormalMomentsAndCdf)
{
  const int n = 400000;
  std::vector<double> x(n);
  double sum = 0.0;
  for (int i = 0; i < n; ++i) {
    x[i] = standard_normal(2024u, static_cast<uint64_t>(i / 4 + 1), STREAM_STRENGTH,
                           static_cast<uint64_t>(i % 4));
    sum += x[i];
  }
  const double mean = sum / n;
  double m2 = 0.0, m3 = 0.0, m4 = 0.0;
  for (double v : x) {
    const double d = v - mean;
    m2 += d * d;
    m3 += d * d * d;
    m4 += d * d * d * d;
  }
  m2 /= n; m3 /= n; m4 /= n;
  EXPECT_NEAR(mean, 0.0, 0.01);
  EXPECT_NEAR(m2, 1.0, 0.01);
  EXPECT_NEAR(m3 / std::pow(m2, 1.5), 0.0, 0.03);  // skewness
  EXPECT_NEAR(m4 / (m2 * m2), 3.0, 0.06);          // kurtosis
  // Kolmogorov-Smirnov-like maximal deviation of the empirical CDF.
  std::sort(x.begin(), x.end());
  double dmax = 0.0;
  for (int i = 0; i < n; ++i) {
    const double Fi = normal_cdf(x[i]);
    dmax = std::max(dmax, std::max(std::fabs(Fi - double(i) / n), std::fabs(Fi - double(i + 1) / n)));
  }
  EXPECT_LT(dmax, 0.01);
}

TEST(BreakageKernel, StrengthFactorMatchesTruncatedNormal)
{
  // f ~ Normal(1, var) with non-positive draws redrawn = normal truncated at 0.
  // Exact moments: alpha = -1/var, lambda = phi(alpha) / (1 - Phi(alpha)),
  // mean = 1 + var lambda, sd = var sqrt(1 + alpha lambda - lambda^2).
  const double var = kVar;
  const double alpha = -1.0 / var;
  const double lambda = normal_pdf(alpha) / (1.0 - normal_cdf(alpha));
  const double mean_exact = 1.0 + var * lambda;
  const double sd_exact = var * std::sqrt(1.0 + alpha * lambda - lambda * lambda);
  // Sanity of the closed form: mean slightly above 1 (P(f <= 0) = 0.27 %).
  EXPECT_NEAR(normal_cdf(alpha), 0.0027366, 1e-6);
  EXPECT_NEAR(mean_exact, 1.00304007, 1e-7);
  EXPECT_NEAR(sd_exact, 0.35573963, 1e-7);

  const int n = 100000;
  double sum = 0.0, sum2 = 0.0, mn = 1e300;
  for (int tag = 1; tag <= n; ++tag) {
    const double f = strength_factor(31415u, static_cast<uint64_t>(tag), var);
    ASSERT_GT(f, 0.0);
    mn = std::min(mn, f);
    sum += f;
    sum2 += f * f;
  }
  const double mean = sum / n;
  const double sd = std::sqrt((sum2 / n - mean * mean) * n / (n - 1.0));
  EXPECT_NEAR(mean, mean_exact, 0.01 * mean_exact);
  EXPECT_NEAR(sd, sd_exact, 0.01 * sd_exact);
  EXPECT_NEAR(mean, 1.0, 0.01);
  // NOTE: the exact truncated sd is 1.18 % below var (0.35574 vs 0.36), so a
  // 1 % band around var cannot hold even for a perfect generator; the nominal
  // check uses 2 % and the tight check is the one against sd_exact above.
  EXPECT_NEAR(sd, var, 0.02 * var);
  // The lower tail is populated (P(f < 1 - 2.5 var) = 0.62 %, ~600 draws)
  // and no draw is at or below 0 (checked above).
  EXPECT_LT(mn, 1.0 - 2.5 * var);
}

TEST(BreakageKernel, StrengthFactorZeroVarianceIsExactlyOne)
{
  for (uint64_t tag = 1; tag < 1000; ++tag) {
    EXPECT_EQ(strength_factor(5u, tag, 0.0), 1.0);
  }
  EXPECT_EQ(strength_factor(5u, 17u, -0.1), 1.0);
}

TEST(BreakageKernel, StrengthDrawsArePureFunctionsOfSeedAndTag)
{
  int differ_seed = 0, differ_tag = 0;
  for (uint64_t tag = 1; tag <= 1000; ++tag) {
    const double a = strength_factor(11u, tag, kVar);
    // Same inputs, same output, independent of call order / interleaving.
    (void)strength_factor(11u, tag + 7, kVar);
    (void)uniform01(11u, tag, STREAM_ROTATION, 0);
    EXPECT_EQ(strength_factor(11u, tag, kVar), a);
    if (strength_factor(12u, tag, kVar) != a) ++differ_seed;
    if (strength_factor(11u, tag + 1, kVar) != a) ++differ_tag;
  }
  EXPECT_EQ(differ_seed, 1000);
  EXPECT_EQ(differ_tag, 1000);
  // Different streams of the same (seed, tag) are different numbers.
  EXPECT_NE(uniform01(11u, 5u, STREAM_STRENGTH, 0), uniform01(11u, 5u, STREAM_ROTATION, 0));
  // Same tag under two seeds: correlation of the draws is ~0.
  const int n = 20000;
  double sxy = 0.0, sx = 0.0, sy = 0.0, sxx = 0.0, syy = 0.0;
  for (int t = 1; t <= n; ++t) {
    const double x = strength_factor(1u, static_cast<uint64_t>(t), kVar);
    const double y = strength_factor(2u, static_cast<uint64_t>(t), kVar);
    sx += x; sy += y; sxy += x * y; sxx += x * x; syy += y * y;
  }
  const double cov = sxy / n - (sx / n) * (sy / n);
  const double corr = cov / std::sqrt((sxx / n - sx * sx / n / n) * (syy / n - sy * sy / n / n));
  EXPECT_LT(std::fabs(corr), 0.03);
}

TEST(BreakageKernel, SizeEffectExponentFromLogLogFit)
{
  // d log-uniform over one decade (0.1 .. 1 mm), scattered strength
  // (var 0.36). Least-squares slope of ln sigma vs ln d ~ -3/m, m = 10.
  //
  // Sample size: the residual scatter is sd(ln f) ~ 0.45 and sd(ln d) =
  // ln10/sqrt12 = 0.66, so the slope's standard error is ~0.68/sqrt(n):
  // 0.0048 for n = 20,000, i.e. a 2 % band (0.006) is only ~1.2 standard
  // errors and a correct kernel fails it for many seeds (it does for this
  // one: slope -0.2936; 43 of seeds 1..200 fall outside 2 %). With n = 200,000 the standard error is ~0.0015 and
  // the 2 % band is ~4 standard errors. The fit's own standard error is
  // checked as well.
  const double m = 10.0;
  for (int n : {20000, 200000}) {
    double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0, syy = 0.0;
    double sy0 = 0.0, sxy0 = 0.0;  // same fit without scatter (f removed)
    for (int i = 0; i < n; ++i) {
      const uint64_t tag = static_cast<uint64_t>(i + 1);
      const double u = uniform01(777u, tag, 9u, 0);  // own stream for the size
      const double d = 1e-4 * std::pow(10.0, u);
      const double f = strength_factor(777u, tag, kVar);
      const double s = size_effect_strength(kSigma0, f, d, 1.0, kD0, m);
      const double x = std::log(d), y = std::log(s), y0 = std::log(s / f);
      sx += x; sy += y; sxx += x * x; sxy += x * y; syy += y * y;
      sy0 += y0; sxy0 += x * y0;
    }
    const double Sxx = sxx - sx * sx / n, Sxy = sxy - sx * sy / n, Syy = syy - sy * sy / n;
    const double slope = Sxy / Sxx;
    const double se = std::sqrt((Syy - slope * Sxy) / (n - 2.0) / Sxx);
    // Without scatter the points lie exactly on a line of slope -3/m.
    EXPECT_NEAR((sxy0 - sx * sy0 / n) / Sxx, -3.0 / m, 1e-9);
    EXPECT_LT(std::fabs(slope + 3.0 / m), 4.0 * se) << "n = " << n << " slope " << slope;
    if (n == 20000) {
      EXPECT_NEAR(se, 0.68 / std::sqrt(double(n)), 0.15 * 0.68 / std::sqrt(double(n)));
    } else {
      EXPECT_NEAR(slope, -3.0 / m, 0.02 * 3.0 / m);
    }
  }
}

// ---------------------------------------------------------------------------
// Rayleigh time and moduli

TEST(BreakageKernel, RayleighTime)
{
  // Hand value: r = 0.1 mm, rho = 2600, G = 9 GPa, nu = 0.2:
  // pi 1e-4 sqrt(2600/9e9) / (0.1631*0.2 + 0.8766) = 1.8571471307569e-7 s.
  EXPECT_NEAR(rayleigh_time(1e-4, 2600.0, 9e9, 0.2), 1.8571471307569207e-07, 1e-19);
  // Linear in r.
  const double t = rayleigh_time(1e-4, 2600.0, 9e9, 0.2);
  for (double k : {0.01, 0.23009318787021937, 2.0, 39.0}) {
    EXPECT_NEAR(rayleigh_time(k * 1e-4, 2600.0, 9e9, 0.2), k * t, 1e-14 * k * t);
  }
  // sqrt(rho/G) scaling.
  EXPECT_NEAR(rayleigh_time(1e-4, 4.0 * 2600.0, 9e9, 0.2), 2.0 * t, 1e-14 * t);
  EXPECT_NEAR(rayleigh_time(1e-4, 2600.0, 4.0 * 9e9, 0.2), 0.5 * t, 1e-14 * t);
  // nu = 0: pi r sqrt(rho/G) / 0.8766.
  EXPECT_NEAR(rayleigh_time(1.0, 1.0, 1.0, 0.0), kPiRef / 0.8766, 1e-14);
}

TEST(BreakageKernel, ShearModulusFromYoung)
{
  EXPECT_NEAR(shear_modulus(21.6e9, 0.2), 9e9, 1e-3);   // NE34 grains
  EXPECT_NEAR(shear_modulus(204e9, 0.2), 85e9, 1e-2);   // steel pile
  for (double nu : {0.0, 0.15, 0.3, 0.49}) {
    const double G = 3.3e9;
    EXPECT_NEAR(shear_modulus(2.0 * G * (1.0 + nu), nu), G, 1e-15 * G * 10);
  }
  EXPECT_NEAR(shear_modulus(3.0, 0.5), 1.0, 1e-15);
}

// The multiply-only pair test must agree with the direct overlap test
// radsum - |dx| >= limit_overlap(sigma, R*, E*) except within rounding of the
// boundary, and must be exact on both sides of it.
TEST(BreakageKernel, PairLimitReachedMatchesOverlapTest)
{
  uint64_t state = 12345;
  auto uni = [&state](double lo, double hi) {
    state = splitmix64(state);
    return lo + (hi - lo) * ((state >> 11) * (1.0 / 9007199254740992.0));
  };
  int n_true = 0, n_false = 0;
  for (int k = 0; k < 200000; k++) {
    const double rp = uni(0.2e-3, 5e-3), rq = uni(0.2e-3, 5e-3);
    const double sigma = uni(1e6, 2e9), E = uni(5e9, 5e10);
    const double radsum = rp + rq;
    const double R = effective_radius(rp, rq);
    const double dlim = limit_overlap(sigma, R, E);
    // overlaps spread around the limit overlap, some beyond radsum
    const double delta = dlim * uni(0.0, 2.0);
    if (delta >= radsum) continue;
    const double dist = radsum - delta;
    const double rsq = dist * dist;
    const bool direct = (radsum - std::sqrt(rsq)) >= dlim;
    const bool fast = pair_limit_reached(rsq, radsum, rp * rq, sigma,
                                         limit_overlap_coefficient(E));
    if (std::fabs(delta - dlim) > 1e-9 * dlim) {
      EXPECT_EQ(direct, fast) << k;
    }
    (direct ? n_true : n_false)++;
  }
  EXPECT_GT(n_true, 10000);
  EXPECT_GT(n_false, 10000);
  // a limit overlap beyond the sum of radii can never be reached
  EXPECT_FALSE(pair_limit_reached(0.0, 1e-3, 0.25e-6, 2e9, limit_overlap_coefficient(1e-3)));
  // exact hand case: r = 1, 1 (R* = 1/2), sigma = 1, c = 0.04 -> dlim = 0.02
  EXPECT_TRUE(pair_limit_reached(1.97 * 1.97, 2.0, 1.0, 1.0, 0.04));
  EXPECT_FALSE(pair_limit_reached(1.99 * 1.99, 2.0, 1.0, 1.0, 0.04));
}

// The margin is the overlap still missing: adding it to the overlap reaches
// the limit overlap of docs/model.md §2.4 exactly.
TEST(BreakageKernel, PairLimitMarginReachesLimitOverlap)
{
  const double rp = 1.2e-3, rq = 0.7e-3, sigma = 3e8, E = 2.4e10;
  const double c = limit_overlap_coefficient(E);
  const double dlim = limit_overlap(sigma, effective_radius(rp, rq), E);
  for (double delta : {0.0, 0.3 * dlim, dlim, 1.7 * dlim}) {
    const double m = pair_limit_margin(delta, rp + rq, rp * rq, sigma, c);
    EXPECT_NEAR(delta + m, dlim, 1e-12 * dlim);
  }
}

// margin_holds must never claim a + b < B when it is not (it may be
// conservative), and must accept clearly safe cases.
TEST(BreakageKernel, MarginHoldsIsConservative)
{
  uint64_t state = 777;
  auto uni = [&state]() {
    state = splitmix64(state);
    return (state >> 11) * (1.0 / 9007199254740992.0);
  };
  int accepted = 0;
  for (int k = 0; k < 100000; k++) {
    const double a = uni(), b = uni(), B = 3.0 * uni() - 0.5;
    if (margin_holds(a * a, b * b, B)) {
      EXPECT_LT(a + b, B);
      accepted++;
    }
  }
  EXPECT_GT(accepted, 10000);
  EXPECT_TRUE(margin_holds(0.0, 0.01, 1.0));
  EXPECT_FALSE(margin_holds(0.0, 0.0, 0.0));
  EXPECT_FALSE(margin_holds(0.0, 0.0, -1.0));
}

TEST(BreakageKernel, SphereMass)
{
  // a 1 mm diameter quartz sphere: pi/6 (1e-3)^3 2650 kg
  EXPECT_NEAR(sphere_mass(0.5e-3, 2650.0), 3.14159265358979323846 / 6.0 * 1e-9 * 2650.0, 1e-22);
  EXPECT_DOUBLE_EQ(sphere_mass(2.0, 1.0) / sphere_mass(1.0, 1.0), 8.0);
}
