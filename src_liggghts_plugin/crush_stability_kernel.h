// SPDX-License-Identifier: GPL-2.0-or-later
/* Time step over the stiffest contact and the cheap blow-up signals of
   fix check/stability (docs/stability.md, "Time step and blow-up
   detection"): stateless kernels with no LIGGGHTS dependency, unit-tested
   in tests/unit/test_stability_kernel.cpp. */

#ifndef CRUSH_STABILITY_KERNEL_H
#define CRUSH_STABILITY_KERNEL_H

#include <cmath>

namespace CrushKernels {

// Tangent stiffness dF/d(delta) = 2 E* sqrt(R* delta) of a Hertz contact
// whose mean pressure F / (pi a^2) is p. With a = sqrt(R* delta) and
// p = 4 E* a / (3 pi R*): k = 3/2 pi p R*. E* cancels: at a given contact
// pressure a steel (or rigid) partner is no stiffer than a grain, only R*
// counts. Units: Pa * m = N/m.
inline double hertz_stiffness_at_pressure(double p, double R_star)
{
  return 1.5 * 3.14159265358979323846 * p * R_star;
}

// Overlap of a Hertz contact at mean pressure p: delta = R* (3 pi p / (4 E*))^2
// (the breakage limit overlap when p = sigma_lim). Units: m.
inline double hertz_overlap_at_pressure(double p, double R_star, double E_star)
{
  const double g = 3.0 * 3.14159265358979323846 * p / (4.0 * E_star);
  return R_star * g * g;
}

// Angular frequency bound omega = sqrt(k / m*) of the stiffest contact a
// particle of radius r and mass m can have when no contact of it carries a
// mean pressure above p. The worst partner is a wall (R* = r, m* = m) or an
// equal particle (R* = r/2, m* = m/2): both give k / m* = 3/2 pi p r / m;
// any partner q with m_q / r_q >= m / r (larger grains of the same density,
// or particles under density scaling, whose m/r is the same below d_ref)
// gives less. Units: sqrt(Pa m / kg) = 1/s.
inline double contact_omega_max(double p, double r, double m)
{
  return std::sqrt(hertz_stiffness_at_pressure(p, r) / m);
}

// Signal (a) of fix check/stability: has particle moved more than
// `frac` of its radius in one step, |v| dt > frac r? Multiplications only.
inline bool moved_too_far(double v2, double dt, double r, double frac)
{
  const double s = frac * r;
  return v2 * dt * dt > s * s;
}

// Signal (b): does a pair overlap by more than `frac` of the smaller radius,
// radsum - sqrt(rsq) > frac min(r_i, r_j)? Same answer without the square
// root: with A = radsum - frac r_min, true iff A > 0 and rsq < A^2.
inline bool overlap_too_deep(double rsq, double r_i, double r_j, double frac)
{
  const double A = r_i + r_j - frac * (r_i < r_j ? r_i : r_j);
  return A > 0.0 && rsq < A * A;
}

}  // namespace CrushKernels

#endif
