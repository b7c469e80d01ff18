// SPDX-License-Identifier: GPL-2.0-or-later
// Unit tests for crush_breakage_index_kernel.h (docs/model.md §2.8, Einav 2007
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
#include "crush_breakage_kernel.h"
#include "crush_fragment_kernel.h"

using namespace CrushKernels;

namespace {

// docs/model.md §3: d_max = 0.27 mm, d_min = 0.01 mm (real size, N = 1).
const double kDmin = 0.01e-3, kDmax = 0.27e-3;

// Fractal limit grading F_u(d) = (d^k - d_min^k)/(d_max^k - d_min^k), k = 3 - omega
// (docs/model.md §2.8), written as expm1(k ln(d/d_min)) / expm1(k ln(d_max/d_min)),
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
    // Scaled by N = 39 (docs/model.md §2.8: d_max, d_min scale with N): integral over ln d unchanged.
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

// ---------------------------------------------------------------------------
// Binned integrals and the bound (fines_grading fractal | d_min)
// ---------------------------------------------------------------------------

namespace {

// Fractal fines of one break written out from the formula of docs/model.md §2.8: mass m spread
// over [d_min, d_f] with F(x) = (x^k - d_min^k) / (d_f^k - d_min^k), k = 3 - omega
// (log-uniform at omega = 3).
struct FractalPart { double m, d_f; };

struct Grading {
  std::vector<Grain> grains;       // particles (and fragments counted at their size)
  std::vector<FractalPart> fractal;
  double below = 0.0;              // mass finer than d_min
  double omega = 2.6;
  double mass() const
  {
    double M = below;
    for (const Grain& p : grains) M += p.m;
    for (const FractalPart& f : fractal) M += f.m;
    return M;
  }
  // mass fraction finer than d, straight from the definitions
  double F(double d) const
  {
    double s = below;
    for (const Grain& p : grains)
      if (p.d <= d) s += p.m;
    const double k = 3.0 - omega;
    for (const FractalPart& f : fractal) {
      if (d >= f.d_f || f.d_f <= kDmin) { s += f.m; continue; }
      if (d <= kDmin) continue;
      const double G = (k == 0.0) ? std::log(d / kDmin) / std::log(f.d_f / kDmin)
                                  : (std::pow(d, k) - std::pow(kDmin, k)) /
                                        (std::pow(f.d_f, k) - std::pow(kDmin, k));
      s += f.m * G;
    }
    return s / mass();
  }
};

// int F d(ln d) over [lo, hi] (in u = ln(d/d_min)) by 8-point Gauss-Legendre on
// every piece between the kinks and jumps of F (particle sizes, fractal tops),
// where F is smooth: exact to round-off.
double quadrature_bin(const Grading& g, double lo, double hi)
{
  static const double xg[8] = {-0.9602898564975363, -0.7966664774136267, -0.5255324099163290,
                               -0.1834346424956498, 0.1834346424956498, 0.5255324099163290,
                               0.7966664774136267, 0.9602898564975363};
  static const double wg[8] = {0.1012285362903763, 0.2223810344533745, 0.3137066458778873,
                               0.3626837833783620, 0.3626837833783620, 0.3137066458778873,
                               0.2223810344533745, 0.1012285362903763};
  std::vector<double> cuts = {lo, hi};
  for (const Grain& p : g.grains) {
    const double u = std::log(p.d / kDmin);
    if (u > lo && u < hi) cuts.push_back(u);
  }
  for (const FractalPart& f : g.fractal) {
    const double u = std::log(f.d_f / kDmin);
    if (u > lo && u < hi) cuts.push_back(u);
  }
  std::sort(cuts.begin(), cuts.end());
  double s = 0.0;
  for (size_t c = 0; c + 1 < cuts.size(); c++) {
    const double a = cuts[c], b = cuts[c + 1];
    for (int q = 0; q < 8; q++) {
      const double u = 0.5 * (a + b) + 0.5 * (b - a) * xg[q];
      s += 0.5 * (b - a) * wg[q] * g.F(kDmin * std::exp(u));
    }
  }
  return s;
}

// The kernel's normalised bin integrals of a Grading.
std::vector<double> kernel_bins(const Grading& g, const BrGrid& grid)
{
  std::vector<double> H(2 * grid.n + 1, 0.0), J(grid.n, 0.0);
  for (const Grain& p : g.grains) br_histogram_add(p.m, p.d, grid, &H[0]);
  br_histogram_integrals(&H[0], grid, &J[0]);
  for (const FractalPart& f : g.fractal) br_add_fractal(f.m, f.d_f, g.omega, grid, &J[0]);
  br_add_point(g.below, 0.5 * kDmin, grid, &J[0]);
  const double M = g.mass();
  for (double& v : J) v /= M;
  return J;
}

// A random breakage history: grains of a uniform sand broken one after another
// (a random breakable grain each time) into the 14 Apollonian fragments.
// fractal: fines convention; d_comm: grains finer never break; d_frag_min:
// fragments finer are not created. Returns the grading after every break.
struct History {
  BrGrid grid;
  std::vector<double> J0, U;
  std::vector<std::vector<double> > J;  // after each break
  std::vector<double> I_old;            // unbinned integral with all fines below d_min
};

History random_history(unsigned seed, bool fractal, double d_comm, double d_frag_min, int nbreaks,
                       double omega = 2.6)
{
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> U01(0.0, 1.0);
  History h;
  h.grid = br_grid(kDmin, kDmax);
  std::vector<Grain> grains;
  for (int p = 0; p < 60; p++) {
    const double d = 0.15e-3 * std::exp(std::log(0.27 / 0.15) * U01(rng));
    grains.push_back({d, 2600.0 * kPi / 6.0 * d * d * d});
  }
  const int n = h.grid.n;
  auto bins_of = [&](const std::vector<Grain>& gs, const std::vector<double>& Jf, double fines) {
    std::vector<double> H(2 * n + 1, 0.0), J(Jf);
    double M = fines;
    for (const Grain& p : gs) { br_histogram_add(p.m, p.d, h.grid, &H[0]); M += p.m; }
    br_histogram_integrals(&H[0], h.grid, &J[0]);
    for (double& v : J) v /= M;
    return J;
  };
  std::vector<double> Jf(n, 0.0);
  double fines = 0.0;
  h.J0 = bins_of(grains, Jf, 0.0);
  h.U.assign(n, 0.0);
  br_limit_bins(omega, h.grid, &h.U[0]);
  const double r1 = large_fragment_ratio(), r2 = small_fragment_ratio();
  for (int k = 0; k < nbreaks; k++) {
    std::vector<int> breakable;
    for (size_t p = 0; p < grains.size(); p++)
      if (grains[p].d >= d_comm) breakable.push_back((int)p);
    if (breakable.empty()) break;
    const int p = breakable[(size_t)(U01(rng) * breakable.size()) % breakable.size()];
    const Grain parent = grains[p];
    grains.erase(grains.begin() + p);
    const double r = 0.5 * parent.d, rho = parent.m / (kPi / 6.0 * parent.d * parent.d * parent.d);
    const double m1 = 4.0 * kPi / 3.0 * (r1 * r) * (r1 * r) * (r1 * r) * rho;
    const double m2 = 4.0 * kPi / 3.0 * (r2 * r) * (r2 * r) * (r2 * r) * rho;
    const bool keep1 = 2.0 * (r1 * r) >= d_frag_min, keep2 = 2.0 * (r2 * r) >= d_frag_min;
    double kept = 0.0;
    if (keep1) for (int f = 0; f < 6; f++) { grains.push_back({2.0 * r1 * r, m1}); kept += m1; }
    if (keep2) for (int f = 0; f < 8; f++) { grains.push_back({2.0 * r2 * r, m2}); kept += m2; }
    fines += parent.m - kept;
    br_add_break_fines(fractal, parent.d, parent.m, r1, r2, m1, m2, keep1, keep2, omega, h.grid, &Jf[0]);
    h.J.push_back(bins_of(grains, Jf, fines));
    double I = fines * std::log(kDmax / kDmin), M = fines;
    for (const Grain& g : grains) { I += breakage_integral_term(g.m, g.d, kDmin, kDmax); M += g.m; }
    h.I_old.push_back(I / M);
  }
  return h;
}

double sum(const std::vector<double>& v)
{
  double s = 0.0;
  for (double x : v) s += x;
  return s;
}

}  // namespace

TEST(BreakageIndexBins, PsiSeriesMatchesClosedForm)
{
  // the two branches of br_psi meet at |z| = 0.5; psi(0) = 1/2
  for (double z : {0.4999999, -0.4999999, 0.3, -0.2, 1e-3}) {
    const double closed = (std::expm1(z) - z) / (z * z);
    EXPECT_NEAR(br_psi(z), closed, 1e-12 * closed) << z;  // closed form loses ~1e-13 at 1e-3
  }
  EXPECT_EQ(br_psi(0.0), 0.5);
  EXPECT_NEAR(br_psi(0.5), (std::expm1(0.5) - 0.5) / 0.25, 1e-15);
}

TEST(BreakageIndexBins, BinIntegralsMatchQuadrature)
{
  // particles on both sides of the range and on bin edges, fines below d_min,
  // fractal fines with tops inside a bin, on an edge, at d_max, below d_min
  const BrGrid grid = br_grid(kDmin, kDmax);
  for (double omega : {2.6, 3.0, 2.0, 2.999999}) {
    Grading g;
    g.omega = omega;
    std::mt19937_64 rng(42u);
    std::uniform_real_distribution<double> U01(0.0, 1.0);
    for (int p = 0; p < 300; p++) {
      const double d = std::exp(std::log(kDmin / 3.0) + std::log(9.0 * kDmax / kDmin) * U01(rng));
      g.grains.push_back({d, (0.1 + U01(rng)) * 1e-9});
    }
    g.grains.push_back({kDmin * std::exp(17 * grid.h), 1e-9});  // on a bin edge
    g.grains.push_back({kDmin, 2e-9});
    g.grains.push_back({kDmax, 2e-9});
    g.below = 3e-9;
    g.fractal = {{4e-9, 0.23 * 0.21e-3}, {2e-9, kDmin * std::exp(40 * grid.h)},
                 {1e-9, kDmax}, {1e-9, 0.5 * kDmin}, {5e-9, 2.0 * kDmin}};
    const std::vector<double> J = kernel_bins(g, grid);
    double total = 0.0;
    for (int b = 0; b < grid.n; b++) {
      const double q = quadrature_bin(g, b * grid.h, (b + 1) * grid.h);
      EXPECT_NEAR(J[b], q, 1e-13) << "omega " << omega << " bin " << b;
      total += q;
    }
    // the bins add up to the whole integral
    EXPECT_NEAR(sum(J), total, 1e-12);
  }
}

TEST(BreakageIndexBins, LimitBinsAreTheLimitGradingIntegral)
{
  const BrGrid grid = br_grid(kDmin, kDmax);
  for (double omega : {2.6, 3.0, 2.0}) {
    std::vector<double> U(grid.n);
    br_limit_bins(omega, grid, &U[0]);
    Grading g;
    g.omega = omega;
    g.fractal = {{1.0, kDmax}};
    for (int b = 0; b < grid.n; b += 9)
      EXPECT_NEAR(U[b], quadrature_bin(g, b * grid.h, (b + 1) * grid.h), 1e-14) << omega << " " << b;
    EXPECT_NEAR(sum(U), fractal_grading_integral(kDmin, kDmax, omega), 1e-13);
  }
  // omega -> 3 is continuous (series branch): bins at 3 - 1e-12 and at 3 agree
  std::vector<double> a(grid.n), b(grid.n);
  br_limit_bins(3.0, grid, &a[0]);
  br_limit_bins(3.0 - 1e-12, grid, &b[0]);
  for (int k = 0; k < grid.n; k++) EXPECT_NEAR(a[k], b[k], 1e-13);  // d U_b / d omega ~ 0.01
  // log-uniform bins: int over bin b of u / L du = h^2 (b + 1/2) / L
  for (int k = 0; k < grid.n; k += 13) EXPECT_NEAR(a[k], grid.h * grid.h * (k + 0.5) / grid.L, 1e-15);
}

TEST(BreakageIndexBins, UnclippedSumIsTheOldFormulaWithFinesBelowDmin)
{
  // legacy convention: sum of the bins = the unbinned step-grading integral
  // with all fines finer than d_min, for any history
  for (unsigned seed : {1u, 2u, 3u}) {
    const History h = random_history(seed, false, 0.0, 0.0, 80);
    for (size_t k = 0; k < h.J.size(); k++) EXPECT_NEAR(sum(h.J[k]), h.I_old[k], 1e-13) << k;
  }
}

TEST(BreakageIndexBins, ZeroForInitialOneForLimit)
{
  const History h = random_history(7u, true, 0.0, 0.0, 1);
  EXPECT_EQ(bounded_breakage_index(&h.J0[0], &h.J0[0], &h.U[0], h.grid.n), 0.0);
  EXPECT_EQ(bounded_breakage_index(&h.U[0], &h.J0[0], &h.U[0], h.grid.n), 1.0);
  // the limit grading sampled by 20000 grains (mass dF_u at each ln-d cell centre)
  const BrGrid grid = h.grid;
  Grading g;
  const int K = 20000;
  for (int i = 0; i < K; i++) {
    const double a = kDmin * std::exp(i * grid.L / K), b = kDmin * std::exp((i + 1) * grid.L / K);
    g.grains.push_back({std::sqrt(a * b), fractal_grading(b, kDmin, kDmax, 2.6) -
                                              fractal_grading(a, kDmin, kDmax, 2.6)});
  }
  const std::vector<double> J = kernel_bins(g, grid);
  EXPECT_NEAR(bounded_breakage_index(&J[0], &h.J0[0], &h.U[0], grid.n), 1.0, 1e-4);
  // an initial grading above the limit one in every bin: no potential, Br = 0
  EXPECT_EQ(bounded_breakage_index(&h.U[0], &h.U[0], &h.J0[0], grid.n), 0.0);
}

TEST(BreakageIndexBins, BoundedForRandomHistories)
{
  // both conventions, with and without a comminution limit and d_frag_min;
  // grains broken until none can break or 400 breaks. Br in [0, 1], never
  // decreasing (breakage only moves mass to finer sizes), equal to the
  // unclipped ratio while every bin is within its bounds.
  const double Iu = fractal_grading_integral(kDmin, kDmax, 2.6);
  bool old_passed_one = false, some_clipped = false;
  int n_hist = 0;
  for (unsigned seed = 11; seed < 17; seed++)
    for (int fractal = 0; fractal < 2; fractal++)
      for (double d_comm : {0.0, 0.55 * 0.21e-3})
        for (double d_frag_min : {0.0, 0.03e-3}) {
          if (d_comm == 0.0 && d_frag_min == 0.0) continue;  // would never end
          const History h = random_history(seed, fractal == 1, d_comm, d_frag_min, 400);
          n_hist++;
          const double I0 = sum(h.J0);
          double prev = 0.0;
          for (size_t k = 0; k < h.J.size(); k++) {
            const double Br = bounded_breakage_index(&h.J[k][0], &h.J0[0], &h.U[0], h.grid.n);
            ASSERT_GE(Br, 0.0);
            ASSERT_LE(Br, 1.0);
            ASSERT_GE(Br, prev - 1e-14);
            prev = Br;
            bool inside = true;
            for (int b = 0; b < h.grid.n; b++)
              inside = inside && h.J[k][b] >= h.J0[b] && h.J[k][b] <= h.U[b] && h.J0[b] <= h.U[b];
            const double einav = breakage_index(sum(h.J[k]), I0, Iu);
            if (inside) EXPECT_NEAR(Br, einav, 1e-12);
            else some_clipped = true;
            if (breakage_index(h.I_old[k], I0, Iu) > 1.0) old_passed_one = true;
          }
        }
  EXPECT_EQ(n_hist, 6 * 2 * 3);
  // the histories reach the bound, and the former index (unclipped, fines
  // below d_min) passed 1 in some of them: the case this bound is for
  EXPECT_TRUE(some_clipped);
  EXPECT_TRUE(old_passed_one);
}

TEST(BreakageIndexBins, FractalFinesGrowBrLessThanFinesBelowDmin)
{
  // same history, two conventions: the fractal fines are coarser than d_min,
  // so the integral (and Br) grows less
  const History a = random_history(5u, true, 0.55 * 0.21e-3, 0.0, 30);
  const History b = random_history(5u, false, 0.55 * 0.21e-3, 0.0, 30);
  ASSERT_EQ(a.J.size(), b.J.size());
  for (size_t k = 0; k < a.J.size(); k++) EXPECT_LT(sum(a.J[k]), sum(b.J[k]));
}
