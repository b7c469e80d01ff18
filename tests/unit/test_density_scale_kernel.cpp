// Density scaling of fine particles (crush_density_scale_kernel.h) against the
// Rayleigh time of crush_breakage_kernel.h: a scaled particle finer than
// d_ref has the Rayleigh time of a d_ref particle.
#include <gtest/gtest.h>

#include "crush_breakage_kernel.h"
#include "crush_density_scale_kernel.h"

using namespace CrushKernels;

TEST(DensityScale, OffAndAboveReferenceIsOne)
{
  EXPECT_EQ(density_scale_factor(1e-3, 0.0), 1.0);
  EXPECT_EQ(density_scale_factor(1e-3, -1.0), 1.0);
  EXPECT_EQ(density_scale_factor(2e-3, 2e-3), 1.0);
  EXPECT_EQ(density_scale_factor(5e-3, 2e-3), 1.0);
}

TEST(DensityScale, FinerParticleGetsTheReferenceRayleighTime)
{
  const double rho = 2650.0, E = 21.6e9, nu = 0.2, G = shear_modulus(E, nu);
  const double d_ref = 4.5e-3;
  const double T_ref = rayleigh_time(0.5 * d_ref, rho, G, nu);
  for (double d : {4.4e-3, 2.0e-3, 1.04e-3, 1e-4, 1e-6}) {
    const double f = density_scale_factor(d, d_ref);
    EXPECT_GT(f, 1.0);
    EXPECT_NEAR(rayleigh_time(0.5 * d, rho * f, G, nu) / T_ref, 1.0, 1e-14) << "d = " << d;
  }
}

TEST(DensityScale, FactorIsTheSquaredSizeRatio)
{
  EXPECT_DOUBLE_EQ(density_scale_factor(1e-3, 4e-3), 16.0);
  EXPECT_DOUBLE_EQ(density_scale_factor(3e-3, 4.5e-3), 2.25);
}
