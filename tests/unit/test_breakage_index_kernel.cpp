// Unit tests for crush_breakage_index_kernel.h (SPEC section 2, Einav 2007
// breakage index). The closed forms are checked against direct numerical
// quadrature over ln d of the grading curves they integrate.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <random>
#include <utility>
#include <vector>

#include "crush_breakage_index_kernel.h"

using namespace CrushKernels;

namespace {

// SPEC section 3: d_max = 0.27 mm, d_min = 0.01 mm (real size, N = 1).
const double kDmin = 0.01e-3, kDmax = 0.27e-3;

// Fractal limit grading F_u(d) = (d^k - d_min^k)/(d_max^k - d_min^k), k = 3 - omega
// (SPEC section 2), written as expm1(k ln(d/d_min)) / expm1(k ln(d_max/d_min)),
// which is exact algebra and stays accurate for small |k|; log-uniform at k = 0.
double fractal_grading(double d, double d_min, double d_max, double omega)
{
  const double k = 3.0 - omega;
  const double l = std::log(d / d_min), L = std::log(d_max / d_min);
  if (k == 0.0) return l / L;
  return std::expm1(k * l) / std::expm1(k * L);
}

// Trapezoid rule in x = ln d with n points.
double trapezoid_fractal(double d_min, double d_max, double omega, int n)
{
  const double x0 = std::log(d_min), x1 = std::log(d_max);
  const double h = (x1 - x0) / (n - 1);
  double s = 0.0;
  for (int i = 0; i < n; ++i) {
    const double x = (i == n - 1) ? x1 : x0 + i * h;
    const double w = (i == 0 || i == n - 1) ? 0.5 : 1.0;
    s += w * fractal_grading(std::exp(x), d_min, d_max, omega);
  }
  return s * h;
}

struct Grain { double d, m; };

// Midpoint quadrature over ln d on [d_min, d_max] of the step function
// F(d) = (fines + sum of m_p with d_p < d) / M, M = all grains + fines.
// Error bound: each jump of height w is off by at most w h / 2 -> total <= h/2.
double quadrature_step_grading(std::vector<Grain> g, double fines, double d_min, double d_max,
                               int n, double* h_out)
{
  std::sort(g.begin(), g.end(), [](const Grain& a, const Grain& b) { return a.d < b.d; });
  double M = fines;
  for (const Grain& p : g) M += p.m;
  const double x0 = std::log(d_min), x1 = std::log(d_max);
  const double h = (x1 - x0) / n;
  size_t j = 0;
  double finer = fines;
  double s = 0.0;
  for (int i = 0; i < n; ++i) {
    const double d = std::exp(x0 + (i + 0.5) * h);
    while (j < g.size() && g[j].d < d) finer += g[j++].m;
    s += finer / M;
  }
  if (h_out) *h_out = h;
  return s * h;
}

// The kernel's normalised sum: (sum of terms + fines term) / M.
double kernel_grading_integral(const std::vector<Grain>& g, double fines, double d_min, double d_max)
{
  double I = 0.0, M = fines;
  for (const Grain& p : g) {
    I += breakage_integral_term(p.m, p.d, d_min, d_max);
    M += p.m;
  }
  // Fines are finer than d_min: passed with any d <= d_min.
  I += breakage_integral_term(fines, 0.5 * d_min, d_min, d_max);
  return I / M;
}

}  // namespace

TEST(BreakageIndexKernel, FractalGradingIntegralMatchesQuadrature)
{
  const int n = 100000;
  for (double omega : {2.6, 3.0, 2.0}) {
    const double q = trapezoid_fractal(kDmin, kDmax, omega, n);
    EXPECT_NEAR(fractal_grading_integral(kDmin, kDmax, omega), q, 1e-8) << "omega " << omega;
    // Scaled by N = 39 (SPEC: d_max, d_min scale with N): integral over ln d unchanged.
    const double q39 = trapezoid_fractal(39.0 * kDmin, 39.0 * kDmax, omega, n);
    EXPECT_NEAR(fractal_grading_integral(39.0 * kDmin, 39.0 * kDmax, omega), q39, 1e-8);
    EXPECT_NEAR(q39, q, 1e-8);
  }
  // Log-uniform limit (omega = 3): exactly L / 2.
  EXPECT_NEAR(fractal_grading_integral(kDmin, kDmax, 3.0), 0.5 * std::log(27.0), 1e-14);
  // omega = 2.6 gives a grading with more coarse mass than log-uniform:
  // F_u below the log-uniform line, so the integral is below L/2.
  EXPECT_LT(fractal_grading_integral(kDmin, kDmax, 2.6), 0.5 * std::log(27.0));
  EXPECT_GT(fractal_grading_integral(kDmin, kDmax, 2.6), 0.0);
}

TEST(BreakageIndexKernel, FractalGradingIntegralNearLogUniformLimit)
{
  // omega close to 3 (k = 3 - omega small but above the kernel's 1e-12 switch
  // to the log-uniform branch). The integral is smooth in k:
  // I = L (1/x - 1/(e^x - 1)) = L (1/2 - x/12 + x^3/720 - ...), x = k L,
  // so it must stay within O(k) of L/2 and match quadrature. The closed form
  // ((b - a)/k - a L)/(b - a) cancels catastrophically for small k (relative
  // error ~ 1e-16 / k^2): this test fails on that.
  const int n = 100000;
  const double L = std::log(kDmax / kDmin);
  for (double k : {1e-4, -1e-5, 1e-6, 1e-8, -1e-9, 1e-10}) {
    const double omega = 3.0 - k;
    const double q = trapezoid_fractal(kDmin, kDmax, omega, n);
    const double x = k * L;
    const double series = L * (0.5 - x / 12.0 + x * x * x / 720.0);
    EXPECT_NEAR(q, series, 1e-8) << "k = " << k;  // quadrature itself is sound
    EXPECT_NEAR(fractal_grading_integral(kDmin, kDmax, omega), q, 1e-7) << "k = " << k;
  }
}

TEST(BreakageIndexKernel, BreakageIndexEndpoints)
{
  const double Iu = fractal_grading_integral(kDmin, kDmax, 2.6);
  const double I0 = 0.37;
  EXPECT_EQ(breakage_index(I0, I0, Iu), 0.0);
  EXPECT_DOUBLE_EQ(breakage_index(Iu, I0, Iu), 1.0);
  EXPECT_NEAR(breakage_index(I0 + 0.25 * (Iu - I0), I0, Iu), 0.25, 1e-14);
  // Degenerate potential (initial grading already at or beyond the limit): 0.
  EXPECT_EQ(breakage_index(0.5, Iu, Iu), 0.0);
  EXPECT_EQ(breakage_index(0.5, Iu + 0.1, Iu), 0.0);
}

TEST(BreakageIndexKernel, IntegralTermSingleGrains)
{
  const double L = std::log(kDmax / kDmin);
  // A grain of size d_p is finer than d for d in (d_p, d_max]: m ln(d_max/d_p).
  EXPECT_NEAR(breakage_integral_term(2.0, 0.1e-3, kDmin, kDmax), 2.0 * std::log(2.7), 1e-14);
  // Coarser than d_max: never finer, 0. Finer than d_min: always finer, m L.
  EXPECT_EQ(breakage_integral_term(3.0, 0.5e-3, kDmin, kDmax), 0.0);
  EXPECT_EQ(breakage_integral_term(3.0, kDmax, kDmin, kDmax), 0.0);
  EXPECT_NEAR(breakage_integral_term(3.0, 1e-6, kDmin, kDmax), 3.0 * L, 1e-14);
  EXPECT_NEAR(breakage_integral_term(3.0, 0.0, kDmin, kDmax), 3.0 * L, 1e-14);
  EXPECT_NEAR(breakage_integral_term(3.0, kDmin, kDmin, kDmax), 3.0 * L, 1e-14);
  EXPECT_EQ(breakage_integral_term(0.0, 1e-4, kDmin, kDmax), 0.0);
}

TEST(BreakageIndexKernel, DiscreteGradingSumMatchesStepFunctionQuadrature)
{
  std::mt19937_64 rng(20240611u);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  for (int trial = 0; trial < 3; ++trial) {
    std::vector<Grain> g;
    // Sizes log-uniform over [d_min/4, 4 d_max]: some below d_min, some above d_max.
    const double lo = std::log(kDmin / 4.0), hi = std::log(4.0 * kDmax);
    for (int p = 0; p < 2000; ++p) {
      const double d = std::exp(lo + (hi - lo) * U(rng));
      g.push_back({d, 2600.0 * d * d * d * (0.2 + U(rng))});
    }
    // Grains exactly at the range ends.
    g.push_back({kDmin, 1e-9});
    g.push_back({kDmax, 1e-9});
    double M = 0.0;
    for (const Grain& p : g) M += p.m;
    const double fines = (trial == 0) ? 0.0 : (trial == 1 ? 0.1 * M : 0.6 * M);

    double h = 0.0;
    const double q = quadrature_step_grading(g, fines, kDmin, kDmax, 2000000, &h);
    const double I = kernel_grading_integral(g, fines, kDmin, kDmax);
    EXPECT_NEAR(I, q, h) << "trial " << trial;
    EXPECT_GT(I, 0.0);
    EXPECT_LT(I, std::log(kDmax / kDmin));
  }
}

TEST(BreakageIndexKernel, AllFinesAndAllCoarse)
{
  const double L = std::log(kDmax / kDmin);
  std::vector<Grain> coarse = {{kDmax, 1.0}, {2.0 * kDmax, 3.0}};
  EXPECT_EQ(kernel_grading_integral(coarse, 0.0, kDmin, kDmax), 0.0);
  // Only fines: F = 1 everywhere, I = L.
  EXPECT_NEAR(kernel_grading_integral({}, 5.0, kDmin, kDmax), L, 1e-14);
  // Coarse grains plus the same mass of fines: I = L/2 (F = 1/2 throughout).
  EXPECT_NEAR(kernel_grading_integral({{kDmax, 4.0}}, 4.0, kDmin, kDmax), 0.5 * L, 1e-14);
}

TEST(BreakageIndexKernel, GradingOnFractalLimitGivesBrOne)
{
  // Initial grading: uniform sand between 0.15 and 0.27 mm (log-uniform).
  const int K = 20000;
  std::vector<Grain> g0, gu;
  {
    const double a = std::log(0.15e-3), b = std::log(kDmax);
    for (int i = 0; i < K; ++i) g0.push_back({std::exp(a + (i + 0.5) * (b - a) / K), 1.0 / K});
  }
  // Limit grading discretised: mass dF_u in each ln-d bin, placed at its centre.
  {
    const double a = std::log(kDmin), b = std::log(kDmax);
    for (int i = 0; i < K; ++i) {
      const double dl = std::exp(a + i * (b - a) / K), dh = std::exp(a + (i + 1) * (b - a) / K);
      gu.push_back({std::exp(a + (i + 0.5) * (b - a) / K),
                    fractal_grading(dh, kDmin, kDmax, 2.6) - fractal_grading(dl, kDmin, kDmax, 2.6)});
    }
  }
  const double I0 = kernel_grading_integral(g0, 0.0, kDmin, kDmax);
  const double Iu = fractal_grading_integral(kDmin, kDmax, 2.6);
  // Initial grading integral by hand: log-uniform on [0.15, 0.27] mm -> 0.5 ln(1.8).
  EXPECT_NEAR(I0, 0.5 * std::log(0.27 / 0.15), 1e-8);
  EXPECT_NEAR(breakage_index(I0, I0, Iu), 0.0, 1e-15);
  EXPECT_NEAR(breakage_index(kernel_grading_integral(gu, 0.0, kDmin, kDmax), I0, Iu), 1.0, 1e-6);
  // Mixture 30 % limit grading + 70 % initial: Br = 0.3 (B_t is linear in F).
  std::vector<Grain> mix;
  for (const Grain& p : g0) mix.push_back({p.d, 0.7 * p.m});
  for (const Grain& p : gu) mix.push_back({p.d, 0.3 * p.m});
  EXPECT_NEAR(breakage_index(kernel_grading_integral(mix, 0.0, kDmin, kDmax), I0, Iu), 0.3, 1e-6);
}
