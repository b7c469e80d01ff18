// SPDX-License-Identifier: GPL-2.0-or-later
/* Strength scatter laws (fix crush/particle keywords scatter and f_min):
   the factor f_p of sigma_lim = sigma_lim0 f_p (d / (N d0))^(-3/m), drawn
   once per particle from the seed and the particle's tag (so draws do not
   depend on the number of MPI ranks). Stateless kernels with no LIGGGHTS
   dependency, unit-tested in tests/unit/test_strength_kernel.cpp.

   normal:    Normal(1, var), draws f <= 0 redrawn (the printed law);
   truncated: Normal(1, var), draws f <= f_min redrawn: no grain weaker than
              f_min (the mean rises above 1 as the bound rises);
   weibull:   Weibull with mean 1 and coefficient of variation var (the law
              of grain-crushing tests, e.g. McDowell & Bolton 1998), with a
              tail towards 0 that is thinner than the normal's for a given
              var only below f ~ 0.2 (docs/fix_crush_particle.md). */

#ifndef CRUSH_STRENGTH_KERNEL_H
#define CRUSH_STRENGTH_KERNEL_H

#include <cmath>
#include <cstdint>

#include "crush_breakage_kernel.h"

namespace CrushKernels {

enum ScatterLaw { SCATTER_NORMAL = 0, SCATTER_TRUNCATED = 1, SCATTER_WEIBULL = 2 };

// Normal(1, var) redrawn until f > f_min (f_min = 0: the printed law,
// CrushKernels::strength_factor). f_min must be < 1 + a few var for the loop
// to end quickly; the fix allows f_min in [0, 1). With var = 0 it is 1.
// Called by FixCrushParticle::assign_strength.
inline double strength_factor_truncated(uint64_t seed, uint64_t tag, double var, double f_min)
{
  if (var <= 0.0) return 1.0;
  for (uint64_t k = 0;; ++k) {
    const double f = 1.0 + var * standard_normal(seed, tag, STREAM_STRENGTH, k);
    if (f > f_min) return f;
  }
}

// Coefficient of variation of a Weibull law of shape k:
// sqrt(Gamma(1 + 2/k) / Gamma(1 + 1/k)^2 - 1), decreasing in k.
inline double weibull_cov(double k)
{
  const double g1 = std::tgamma(1.0 + 1.0 / k);
  return std::sqrt(std::tgamma(1.0 + 2.0 / k) / (g1 * g1) - 1.0);
}

// Shape k of the Weibull law with coefficient of variation cv (bisection on
// log k over [0.2, 200], i.e. cv from about 15 down to 0.0066; to 1e-12
// relative). Called by FixCrushParticle::parse_args once.
inline double weibull_shape_for_cov(double cv)
{
  double lo = std::log(0.2), hi = std::log(200.0);
  for (int it = 0; it < 200 && hi - lo > 1e-13; ++it) {
    const double mid = 0.5 * (lo + hi);
    if (weibull_cov(std::exp(mid)) > cv) lo = mid;
    else hi = mid;
  }
  return std::exp(0.5 * (lo + hi));
}

// Weibull factor of shape k and mean 1: f = lambda (-ln u)^(1/k) with
// lambda = 1 / Gamma(1 + 1/k), u uniform in (0, 1) (inverse transform).
// Called by FixCrushParticle::assign_strength.
inline double strength_factor_weibull(uint64_t seed, uint64_t tag, double k)
{
  const double u = uniform01(seed, tag, STREAM_STRENGTH, 0);
  const double lambda = 1.0 / std::tgamma(1.0 + 1.0 / k);
  return lambda * std::pow(-std::log(u), 1.0 / k);
}

// The factor of a law (var = 0: 1 for every law). weibull_k is the shape
// for var (weibull_shape_for_cov), f_min the bound of `truncated`.
inline double strength_factor_law(int law, uint64_t seed, uint64_t tag, double var, double f_min,
                                  double weibull_k)
{
  if (var <= 0.0) return 1.0;
  if (law == SCATTER_WEIBULL) return strength_factor_weibull(seed, tag, weibull_k);
  return strength_factor_truncated(seed, tag, var, law == SCATTER_TRUNCATED ? f_min : 0.0);
}

}  // namespace CrushKernels

#endif
