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

}  // namespace CrushKernels

#endif
