// SPDX-License-Identifier: GPL-2.0-or-later
/* Einav (2007) breakage index Br = B_t / B_p (docs/model.md §2.8) for a discrete
   grading plus unresolved fines, bounded to [0, 1]. Stateless kernels with no
   LIGGGHTS dependency, unit-tested in tests/unit/test_breakage_index_kernel.cpp;
   scripts/crushpost/breakage.py implements the same definition in numpy.

   Sizes enter through u = ln(d / d_min), so [d_min, d_max] is u in [0, L],
   L = ln(d_max / d_min). F(u) is the mass fraction finer than d, M the total
   mass (particles + fines). The integral I = int_0^L F du is split into
   kBrBins equal bins of width h = L / kBrBins: J_b = int_bin F du.

   Every part of the grading adds to J_b through its own cumulative
   distribution G (G = fraction of that part finer than u):
   m int_bin G du = m [P(u_hi) - P(u_lo)], P(u) = int_0^u G ds.
   * a particle (or fragment) of size u_p: G is a step at u_p, P(u) = max(0, u - u_p);
     particles finer than d_min count at d_min (u_p = 0), coarser than d_max
     never count (P = 0 on [0, L]);
   * fines spread like the limit grading between d_min and d_f ("fractal"):
     G(u) = expm1(k u) / expm1(k U), k = 3 - omega, U = ln(d_f / d_min), and
     G = 1 above U; omega = 3 (k = 0) is the log-uniform limit G = u / U;
   * fines below d_min ("d_min", the legacy convention): a particle at u_p = 0.
   For the particles present at one step the bins are filled from two sums per
   bin (the mass per bin and the in-bin term m (u_hi - u_p)), see
   br_histogram_add and br_histogram_integrals.

   Bound: breakage only moves mass to finer sizes, so F >= F0 throughout; the
   limit grading is F_u. In each bin the current integral is clipped to
   [J0_b, max(U_b, J0_b)] and Br = sum(clipped - J0_b) / sum(max(U_b, J0_b) - J0_b):
   exactly 0 for the initial grading, exactly 1 for the limit grading, within
   [0, 1] for any grading, and equal to the unclipped Einav ratio
   (I - I0) / (Iu - I0) whenever J0_b <= J_b <= U_b in every bin. */

#ifndef CRUSH_BREAKAGE_INDEX_KERNEL_H
#define CRUSH_BREAKAGE_INDEX_KERNEL_H

#include <cmath>

namespace CrushKernels {

// Number of log-uniform size bins of [d_min, d_max] for the bound (128 bins:
// 0.026 in ln d for the calibration range d_max/d_min = 27, finer than any
// sieve series).
const int kBrBins = 128;

// Unnormalised contribution m ln(d_max / clamp(d)) of one particle (or of the
// fines, with d <= d_min) to the unbinned integral I (legacy, unclipped sum).
inline double breakage_integral_term(double m, double d, double d_min, double d_max)
{
  const double dc = (d < d_min) ? d_min : ((d > d_max) ? d_max : d);
  return m * std::log(d_max / dc);
}

// expm1(z) / z, 1 at z = 0.
inline double br_expm1_ratio(double z)
{
  return (z == 0.0) ? 1.0 : std::expm1(z) / z;
}

// (e^z - 1 - z) / z^2, 1/2 at z = 0; a series where the closed form cancels.
inline double br_psi(double z)
{
  if (std::fabs(z) < 0.5) {
    double term = 0.5, sum = 0.5;  // z^n / (n + 2)!
    for (int n = 1; n < 24; n++) {
      term *= z / (n + 2);
      sum += term;
    }
    return sum;
  }
  return (std::expm1(z) - z) / (z * z);
}

// Integral of the fractal limit grading F_u over d(ln d) on [d_min, d_max]:
// with L = ln(d_max/d_min) and x = (3 - omega) L it is L (1/x - 1/expm1(x)),
// = L psi(x) / expm1_ratio(x), L/2 at omega = 3 (log-uniform).
inline double fractal_grading_integral(double d_min, double d_max, double omega)
{
  const double L = std::log(d_max / d_min);
  const double x = (3.0 - omega) * L;
  return L * br_psi(x) / br_expm1_ratio(x);
}

// Br from the integrals of the current, initial and limit gradings, unclipped.
inline double breakage_index(double I, double I0, double Iu)
{
  const double Bp = Iu - I0;
  return (Bp > 0.0) ? (I - I0) / Bp : 0.0;
}

// Log-uniform bins of [d_min, d_max].
struct BrGrid {
  double d_min, d_max, L, h;
  int n;
};

inline BrGrid br_grid(double d_min, double d_max, int n = kBrBins)
{
  BrGrid g;
  g.d_min = d_min;
  g.d_max = d_max;
  g.L = std::log(d_max / d_min);
  g.n = n;
  g.h = g.L / n;
  return g;
}

// P(u) = int_0^u G ds of the fractal distribution on [0, U] (G = 1 beyond U):
// int_0^u expm1(k s) ds / expm1(k U) = u^2 psi(k u) / (U expm1_ratio(k U)).
inline double br_fractal_P(double u, double U, double k)
{
  if (u <= 0.0) return 0.0;
  if (u >= U) return U * br_psi(k * U) / br_expm1_ratio(k * U) + (u - U);
  return u * u * br_psi(k * u) / (U * br_expm1_ratio(k * U));
}

// Add mass m spread over [d_min, d_f] with the limit grading's shape (fractal
// dimension omega) to the unnormalised bin integrals J[0..n-1]. d_f <= d_min
// puts the mass below d_min (contributes m h to every bin).
inline void br_add_fractal(double m, double d_f, double omega, const BrGrid &g, double *J)
{
  const double U = std::log(d_f / g.d_min);
  if (!(U > 0.0)) {
    for (int b = 0; b < g.n; b++) J[b] += m * g.h;
    return;
  }
  const double k = 3.0 - omega;
  double P_lo = 0.0;
  for (int b = 0; b < g.n; b++) {
    const double P_hi = br_fractal_P((b + 1) * g.h, U, k);
    J[b] += m * (P_hi - P_lo);
    P_lo = P_hi;
  }
}

// Add a point mass m at diameter d (clamped to [d_min, d_max] as above) to J.
inline void br_add_point(double m, double d, const BrGrid &g, double *J)
{
  if (d >= g.d_max) return;
  const double u = (d <= g.d_min) ? 0.0 : std::log(d / g.d_min);
  for (int b = 0; b < g.n; b++) {
    const double lo = b * g.h, hi = (b + 1) * g.h;
    const double len = hi - ((u > lo) ? u : lo);
    if (len > 0.0) J[b] += m * ((len < g.h) ? len : g.h);
  }
}

// Analytic bin integrals of the limit grading F_u (unit mass): U_b.
inline void br_limit_bins(double omega, const BrGrid &g, double *U)
{
  for (int b = 0; b < g.n; b++) U[b] = 0.0;
  br_add_fractal(1.0, g.d_max, omega, g, U);
}

// Histogram of particles for one evaluation, 2n + 1 values:
// H[0] mass at or below d_min, H[1 + b] mass in bin b, H[1 + n + b] the in-bin
// term sum m (u_hi - u_p). Particles coarser than d_max add nothing (they only
// count in the total mass). Ranks fill their own and sum the arrays.
inline void br_histogram_add(double m, double d, const BrGrid &g, double *H)
{
  if (d >= g.d_max) return;
  if (d <= g.d_min) { H[0] += m; return; }
  const double u = std::log(d / g.d_min);
  int b = (int)(u / g.h);
  if (b >= g.n) b = g.n - 1;  // round-off at d_max
  double t = (b + 1) * g.h - u;
  t = (t < 0.0) ? 0.0 : ((t > g.h) ? g.h : t);
  H[1 + b] += m;
  H[1 + g.n + b] += m * t;
}

// Unnormalised bin integrals of a histogram: J_b = (mass finer than the bin's
// lower edge) h + in-bin term. Adds to J.
inline void br_histogram_integrals(const double *H, const BrGrid &g, double *J)
{
  double below = H[0];
  for (int b = 0; b < g.n; b++) {
    J[b] += below * g.h + H[1 + g.n + b];
    below += H[1 + b];
  }
}

// Bounded Br from the normalised bin integrals of the current (J), initial
// (J0) and limit (U) gradings; 0 when the initial grading is at or above the
// limit grading in every bin.
inline double bounded_breakage_index(const double *J, const double *J0, const double *U, int n)
{
  double num = 0.0, den = 0.0;
  for (int b = 0; b < n; b++) {
    const double top = (U[b] > J0[b]) ? U[b] : J0[b];
    double v = (J[b] > J0[b]) ? J[b] : J0[b];
    if (v > top) v = top;
    num += v - J0[b];
    den += top - J0[b];
  }
  return (den > 0.0) ? num / den : 0.0;
}

// Fines of one break of a parent of diameter d and mass m_parent that keeps
// `kept` of its 14 Apollonian fragments (6 of ratio r1, then 8 of ratio r2,
// diameters r1 d and r2 d; kept_large / kept_small say which groups exist)
// added to J. m_frag1, m_frag2: masses of one large, one small fragment.
// fractal: the volume the 14 fragments do not fill spreads over
// [d_min, r2 d] like the limit grading (the Apollonian packing continued below
// its smallest resolved sphere is self-similar); fragments not created (finer
// than d_frag_min) count at their own size. Otherwise (legacy "d_min"
// convention) all of it is finer than d_min.
inline void br_add_break_fines(bool fractal, double d, double m_parent, double r1, double r2,
                               double m_frag1, double m_frag2, bool kept_large, bool kept_small,
                               double omega, const BrGrid &g, double *J)
{
  const double lost = m_parent - 6.0 * m_frag1 - 8.0 * m_frag2;
  double dropped = 0.0;
  if (!kept_large) dropped += 6.0 * m_frag1;
  if (!kept_small) dropped += 8.0 * m_frag2;
  if (!fractal) {
    br_add_point(lost + dropped, g.d_min, g, J);
    return;
  }
  br_add_fractal(lost, r2 * d, omega, g, J);
  if (!kept_large) br_add_point(6.0 * m_frag1, r1 * d, g, J);
  if (!kept_small) br_add_point(8.0 * m_frag2, r2 * d, g, J);
}

}  // namespace CrushKernels

#endif
