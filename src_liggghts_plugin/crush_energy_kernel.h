// SPDX-License-Identifier: GPL-2.0-or-later
/* Energy accounting of breaks (docs/fix_crush_particle.md, keyword energy;
   docs/stability.md): elastic energy stored in a Hertz-Mindlin contact as
   LIGGGHTS 3.8 models it (`pair_style gran model hertz tangential history`),
   and kinetic energy. Stateless kernels with no LIGGGHTS dependency,
   unit-tested in tests/unit/test_energy_kernel.cpp. */

#ifndef CRUSH_ENERGY_KERNEL_H
#define CRUSH_ENERGY_KERNEL_H

#include <cmath>

namespace CrushKernels {

// Hertz normal elastic energy at overlap delta: the work of
// F = 4/3 E* sqrt(R*) delta^(3/2) from 0 to delta,
// U_n = 8/15 E* sqrt(R*) delta^(5/2) = 2/5 F delta. Zero without overlap.
inline double hertz_normal_energy(double delta, double R_star, double E_star)
{
  return (delta > 0.0) ? 8.0 / 15.0 * E_star * std::sqrt(R_star * delta) * delta * delta : 0.0;
}

// Effective shear modulus of LIGGGHTS' hertz model (global_properties.cpp,
// Geff): 1/G* = 2 (2 - nu_p)(1 + nu_p)/E_p + 2 (2 - nu_q)(1 + nu_q)/E_q,
// i.e. (2 - nu_p)/G_p + (2 - nu_q)/G_q.
inline double effective_shear_modulus(double E_p, double nu_p, double E_q, double nu_q)
{
  return 1.0 / (2.0 * (2.0 - nu_p) * (1.0 + nu_p) / E_p + 2.0 * (2.0 - nu_q) * (1.0 + nu_q) / E_q);
}

// Tangential stiffness of the history spring: k_t = 8 G* sqrt(R* delta)
// (normal_model_hertz.h). The spring force is -k_t s for the stored
// tangential displacement s, which LIGGGHTS caps so that k_t |s| <= mu F_n.
inline double tangential_stiffness(double delta, double R_star, double G_star)
{
  return (delta > 0.0) ? 8.0 * G_star * std::sqrt(R_star * delta) : 0.0;
}

// Energy of the history spring, 1/2 k_t |s|^2 = |F_t|^2 / (2 k_t), from the
// squared stored displacement s2 = |s|^2.
inline double tangential_spring_energy(double k_t, double s2)
{
  return 0.5 * k_t * s2;
}

// Elastic energy of one contact: normal Hertz plus the tangential spring.
inline double contact_elastic_energy(double delta, double R_star, double E_star, double G_star, double s2)
{
  if (!(delta > 0.0)) return 0.0;
  return hertz_normal_energy(delta, R_star, E_star) +
         tangential_spring_energy(tangential_stiffness(delta, R_star, G_star), s2);
}

// Translational kinetic energy 1/2 m |v|^2.
inline double kinetic_energy(double m, const double v[3])
{
  return 0.5 * m * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

}  // namespace CrushKernels

#endif
