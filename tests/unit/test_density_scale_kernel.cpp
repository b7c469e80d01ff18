// SPDX-License-Identifier: GPL-2.0-or-later
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

// Fragments of one break, all scaled (d_ref above the parent): the factor
// gives them the momentum of their true mass at the parent's velocity, and a
// kinetic energy below that of the unscaled fragments (hand computation:
// the 6 + 8 Apollonian fragments of a 1 mm parent, d_ref = 2 mm).
TEST(DensityScale, FragmentVelocityKeepsTrueMomentum)
{
  const double r = 0.5e-3, rho = 2600.0, d_ref = 2e-3, v = 3.0;
  const double r1 = r / (1.0 + std::sqrt(2.0)), r2 = 0.230093 * r;
  const double m1 = 4.0 / 3.0 * kPi * r1 * r1 * r1 * rho, m2 = 4.0 / 3.0 * kPi * r2 * r2 * r2 * rho;
  const double s1 = (d_ref / (2 * r1)) * (d_ref / (2 * r1)), s2 = (d_ref / (2 * r2)) * (d_ref / (2 * r2));
  const double sum_true = 6 * m1 + 8 * m2, sum_scaled = 6 * m1 * s1 + 8 * m2 * s2;
  const double k = fragment_velocity_factor(sum_true, sum_scaled);
  EXPECT_NEAR(sum_scaled * k * v, sum_true * v, 1e-15 * sum_true * v);  // momentum
  const double ke = 0.5 * sum_scaled * (k * v) * (k * v);
  EXPECT_LT(ke, 0.5 * sum_true * v * v);
  EXPECT_NEAR(ke, 0.5 * sum_true * v * v * sum_true / sum_scaled, 1e-12 * ke);
  EXPECT_LT(k, 0.2);
  // scaling off, or nothing scaled: the parent's velocity exactly
  EXPECT_EQ(fragment_velocity_factor(sum_true, sum_true), 1.0);
  EXPECT_EQ(fragment_velocity_factor(0.0, 0.0), 1.0);
}
