// SPDX-License-Identifier: GPL-2.0-or-later
#include <gtest/gtest.h>

#include "crush_damping_kernel.h"

using namespace CrushKernels;

TEST(LocalDamping, OpposesMotionByFractionOfForceMagnitude)
{
  // Force along the velocity is reduced, force against it is increased.
  EXPECT_DOUBLE_EQ(local_damping_force(10.0, 1.0, 0.05), 9.5);
  EXPECT_DOUBLE_EQ(local_damping_force(-10.0, 1.0, 0.05), -10.5);
  EXPECT_DOUBLE_EQ(local_damping_force(10.0, -2.0, 0.05), 10.5);
  EXPECT_DOUBLE_EQ(local_damping_force(-10.0, -2.0, 0.05), -9.5);
}

TEST(LocalDamping, NoDampingAtRestOrWithoutForceOrAlpha)
{
  EXPECT_DOUBLE_EQ(local_damping_force(3.0, 0.0, 0.7), 3.0);
  EXPECT_DOUBLE_EQ(local_damping_force(0.0, 5.0, 0.7), 0.0);
  EXPECT_DOUBLE_EQ(local_damping_force(-4.0, 5.0, 0.0), -4.0);
}

TEST(LocalDamping, EnergyRatioPerCycle)
{
  EXPECT_DOUBLE_EQ(local_damping_energy_ratio_per_cycle(0.0), 1.0);
  // small alpha: loss per cycle ~ 4 alpha
  const double a = 1e-4;
  EXPECT_NEAR(1.0 - local_damping_energy_ratio_per_cycle(a), 4.0 * a, 1e-7);
  EXPECT_NEAR(local_damping_energy_ratio_per_cycle(0.5), 1.0 / 9.0, 1e-15);
}
