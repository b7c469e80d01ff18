/* Einav (2007) breakage index Br = B_t / B_p (SPEC section 2), computed
   exactly for a discrete grading. Stateless kernels with no LIGGGHTS
   dependency, unit-tested in tests/unit/test_breakage_index_kernel.cpp.

   For a set of particles the cumulative mass fraction finer than d, F(d), is
   a step function, so I = integral_{d_min}^{d_max} F(d) d(ln d) is a sum:
   each particle of mass m_p adds (m_p / M) ln(d_max / clamp(d_p, d_min, d_max)).
   Fines (mass lost in breakage below the resolved sizes) count as finer than
   every size in the range: they add (m_f / M) ln(d_max / d_min). M includes
   the fines. Then B_t = I - I_0 and B_p = I_u - I_0. */

#ifndef CRUSH_BREAKAGE_INDEX_KERNEL_H
#define CRUSH_BREAKAGE_INDEX_KERNEL_H

#include <cmath>

namespace CrushKernels {

// Unnormalised contribution m ln(d_max / clamp(d)) of one particle (or of the
// fines, with d <= d_min). FixCrushParticle sums it over its group.
inline double breakage_integral_term(double m, double d, double d_min, double d_max)
{
  const double dc = (d < d_min) ? d_min : ((d > d_max) ? d_max : d);
  return m * std::log(d_max / dc);
}

// Integral of the fractal limit grading F_u(d) = (d^k - d_min^k)/(d_max^k - d_min^k),
// k = 3 - omega, over d(ln d) on [d_min, d_max]: with L = ln(d_max/d_min) and
// x = k L it is L (1/x - 1/expm1(x)), written as a series near x = 0 (omega -> 3,
// the log-uniform limit L/2) where the closed form cancels.
inline double fractal_grading_integral(double d_min, double d_max, double omega)
{
  const double L = std::log(d_max / d_min);
  const double x = (3.0 - omega) * L;
  if (std::fabs(x) < 1e-3) return L * (0.5 - x / 12.0 + x * x * x / 720.0);
  return L * (1.0 / x - 1.0 / std::expm1(x));
}

// Br from the integrals of the current, initial and limit gradings.
inline double breakage_index(double I, double I0, double Iu)
{
  const double Bp = Iu - I0;
  return (Bp > 0.0) ? (I - I0) / Bp : 0.0;
}

}  // namespace CrushKernels

#endif
