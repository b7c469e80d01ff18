// SPDX-License-Identifier: GPL-2.0-or-later
/* Local (non-viscous) damping of PFC, docs/model.md §2.3.
   Stateless kernels, no LIGGGHTS dependency; unit-tested in tests/unit. */

#ifndef CRUSH_DAMPING_KERNEL_H
#define CRUSH_DAMPING_KERNEL_H

namespace CrushKernels {

// Sign with sign(0) = 0: a component at rest is not damped.
inline double sign_or_zero(double v)
{
  return (v > 0.0) ? 1.0 : ((v < 0.0) ? -1.0 : 0.0);
}

// One force component after local damping, F - alpha |F| sign(v).
// Called by FixDampLocal::post_force for each translational component.
inline double local_damping_force(double f, double v, double alpha)
{
  return f - alpha * (f < 0.0 ? -f : f) * sign_or_zero(v);
}

// Exact kinetic-energy ratio between successive velocity peaks, one full
// cycle apart, of a linear oscillator under local damping: the outward
// quarter swings against stiffness k(1+alpha), the return one with k(1-alpha).
// Used by tests as the analytic answer.
inline double local_damping_energy_ratio_per_cycle(double alpha)
{
  const double r = (1.0 - alpha) / (1.0 + alpha);
  return r * r;
}

}  // namespace CrushKernels

#endif
