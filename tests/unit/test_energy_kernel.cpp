// SPDX-License-Identifier: GPL-2.0-or-later
// Unit tests for crush_energy_kernel.h: the elastic energy of a Hertz contact
// is checked against the numerical integral of the Hertz force (the force
// kernel of crush_breakage_kernel.h is independent of the energy formula),
// the effective shear modulus against G_i and nu_i by hand, and the history
// spring against F_t^2 / (2 k_t).

#include <gtest/gtest.h>

#include <cmath>

#include "crush_breakage_kernel.h"
#include "crush_energy_kernel.h"

using namespace CrushKernels;

namespace {

const double kG = 9e9, kNu = 0.2, kE = 2.0 * kG * (1.0 + kNu);  // NE34 grain
const double kEsteel = 2.0 * 85e9 * 1.2;                          // steel

// Work of the Hertz force from 0 to delta by Simpson's rule in u = sqrt(delta)
// (the integrand 2 u F(u^2) is smooth in u).
double hertz_work(double delta, double R, double E)
{
  const int n = 2000;
  const double U = std::sqrt(delta), h = U / n;
  double s = 0.0;
  for (int k = 0; k <= n; k++) {
    const double u = k * h;
    const double w = (k == 0 || k == n) ? 1.0 : (k % 2 ? 4.0 : 2.0);
    s += w * 2.0 * u * hertz_normal_force(u * u, R, E);
  }
  return s * h / 3.0;
}

}  // namespace

TEST(EnergyKernel, HertzEnergyIsWorkOfHertzForce)
{
  const double R = effective_radius(0.5 * 0.21e-3 * 39, 0.4 * 0.21e-3 * 39);
  const double Es = effective_modulus(kE, kNu, kE, kNu);
  for (double rel : {1e-6, 1e-4, 1e-2}) {
    const double delta = rel * R;
    EXPECT_NEAR(hertz_normal_energy(delta, R, Es), hertz_work(delta, R, Es),
                1e-9 * hertz_work(delta, R, Es));
    // U = 2/5 F delta
    EXPECT_NEAR(hertz_normal_energy(delta, R, Es), 0.4 * hertz_normal_force(delta, R, Es) * delta,
                1e-12 * hertz_normal_energy(delta, R, Es));
  }
  EXPECT_EQ(hertz_normal_energy(0.0, R, Es), 0.0);
  EXPECT_EQ(hertz_normal_energy(-1e-6, R, Es), 0.0);
}

TEST(EnergyKernel, EffectiveShearModulusByHand)
{
  // equal grains: 1/G* = 2 (2 - nu)/G, so G* = G / (2 (2 - nu)) = 9e9 / 3.6
  EXPECT_NEAR(effective_shear_modulus(kE, kNu, kE, kNu), 9e9 / 3.6, 1e-6 * 9e9);
  // grain and steel: (2 - 0.2)/9e9 + (2 - 0.2)/85e9
  const double ref = 1.0 / (1.8 / 9e9 + 1.8 / 85e9);
  EXPECT_NEAR(effective_shear_modulus(kE, kNu, kEsteel, kNu), ref, 1e-9 * ref);
}

TEST(EnergyKernel, SpringEnergyIsFtSquaredOver2kt)
{
  const double R = 2e-3, delta = 3e-6;
  const double Gs = effective_shear_modulus(kE, kNu, kE, kNu);
  const double kt = tangential_stiffness(delta, R, Gs);
  EXPECT_NEAR(kt, 8.0 * Gs * std::sqrt(R * delta), 1e-12 * kt);
  const double s[3] = {1e-7, -2e-7, 0.5e-7};
  const double s2 = s[0] * s[0] + s[1] * s[1] + s[2] * s[2];
  const double Ft2 = kt * kt * s2;
  EXPECT_NEAR(tangential_spring_energy(kt, s2), Ft2 / (2.0 * kt), 1e-12 * Ft2 / kt);
  // a contact without overlap stores nothing, whatever the history holds
  EXPECT_EQ(contact_elastic_energy(0.0, R, 1e10, Gs, s2), 0.0);
  const double Es = effective_modulus(kE, kNu, kE, kNu);
  EXPECT_NEAR(contact_elastic_energy(delta, R, Es, Gs, s2),
              hertz_work(delta, R, Es) + Ft2 / (2.0 * kt), 1e-9 * hertz_work(delta, R, Es));
}

TEST(EnergyKernel, KineticEnergy)
{
  const double v[3] = {3.0, -4.0, 12.0};  // |v| = 13
  EXPECT_DOUBLE_EQ(kinetic_energy(2.0, v), 169.0);
}
