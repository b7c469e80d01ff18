// SPDX-License-Identifier: GPL-2.0-or-later
/* Density scaling of fine particles (fix crush/particle keyword
   density_scale D_REF): a stateless kernel with no LIGGGHTS dependency,
   unit-tested in tests/unit/test_density_scale_kernel.cpp.

   The Rayleigh time T_R = pi r sqrt(rho / G) / (0.1631 nu + 0.8766) limits
   the time step; it falls with the radius, so the smallest fragments set
   the step. Raising the density of a particle finer than D_REF by
   (D_REF / d)^2 gives it the Rayleigh time of a D_REF particle, so the step
   can follow D_REF instead of the finest fragment. Only the inertia
   changes: contact forces depend on radii and overlaps, not on mass. */

#ifndef CRUSH_DENSITY_SCALE_KERNEL_H
#define CRUSH_DENSITY_SCALE_KERNEL_H

namespace CrushKernels {

// Factor on the mass of a particle of diameter d: (d_ref / d)^2 below d_ref,
// 1 at or above it, and 1 when scaling is off (d_ref <= 0).
// Called by FixCrushParticle::setup_pre_exchange (every particle at the
// start of a run), FixCrushParticle::break_particles (every fragment) and
// FixCrushParticle::check_timestep.
inline double density_scale_factor(double d, double d_ref)
{
  if (!(d_ref > 0.0) || !(d < d_ref)) return 1.0;
  const double s = d_ref / d;
  return s * s;
}

// Velocity factor of the fragments of one break under density scaling.
// Fragments are inscribed in the parent and take its velocity times this
// factor, sum_true / sum_scaled (sums over the fragments kept: true and
// scaled masses). Their momentum is then sum_true v, that of the same
// fragments without scaling (the fines carry the rest off, as without
// scaling), and never more than the parent's scaled momentum; their scaled
// kinetic energy (sum_true v)^2 / (2 sum_scaled) is at most that of the
// unscaled fragments, sum_true v^2 / 2 (sum_scaled >= sum_true). With
// scaling off (or no fragment scaled) the factor is exactly 1: fragments take
// the parent's velocity. Called by FixCrushParticle::break_particles and
// FixCrushParticle::energy_of_breaks.
inline double fragment_velocity_factor(double sum_true, double sum_scaled)
{
  if (!(sum_scaled > 0.0) || sum_scaled == sum_true) return 1.0;
  return sum_true / sum_scaled;
}

}  // namespace CrushKernels

#endif
