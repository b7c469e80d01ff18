// SPDX-License-Identifier: GPL-2.0-or-later
/* Readings of the breakage criterion (fix crush/particle keywords pressure,
   force, size_law): stateless kernels with no LIGGGHTS dependency,
   unit-tested in tests/unit/test_criterion_kernel.cpp. The printed
   criterion (docs/model.md §2.4) is
       F_n >= F_lim = (pi sigma_lim)^3 (3 R* / (4 E*))^2,
   the force at which the MEAN Hertz pressure F_n / (pi a^2) reaches
   sigma_lim. Each reading below changes F_lim by a factor k that depends on
   the reading only (and on the friction of the contact's materials), so the
   fix applies it as one factor per pair of material types: F_lim k, and a
   limit overlap times k^(2/3) (Hertz: delta ~ F^(2/3)). Where each reading
   comes from and what it does: docs/fix_crush_particle.md "Criterion
   readings". */

#ifndef CRUSH_CRITERION_KERNEL_H
#define CRUSH_CRITERION_KERNEL_H

#include <cmath>

namespace CrushKernels {

// Pressure measure of the criterion.
//   mean: F / (pi a^2), the mean pressure over the Hertz contact (printed);
//   peak: 3 F / (2 pi a^2), the pressure at the centre of the Hertz contact,
//         1.5 times the mean. F >= (2/3) sigma_lim pi a^2 with
//         a^3 = 3 F R* / (4 E*) gives F_lim (2/3)^3 = F_lim / 3.375.
// Called by FixCrushParticle::init for the factor on every F_lim.
enum PressureMeasure { PRESSURE_MEAN = 0, PRESSURE_PEAK = 1 };
inline double pressure_limit_factor(int measure)
{
  return measure == PRESSURE_PEAK ? 8.0 / 27.0 : 1.0;
}

// Force compared with the limit.
//   normal:  the normal force F_n (printed);
//   sliding: the total force of a contact that slides, F_n sqrt(1 + mu^2)
//            (|F_t| <= mu F_n: the largest total force a contact with this
//            F_n can carry), compared with the same F_lim. The criterion
//            F_n sqrt(1 + mu^2) >= F_lim is F_n >= F_lim / sqrt(1 + mu^2):
//            a bound, from above, of the reading with the total force.
// Called by FixCrushParticle::init per pair of material types (mu of the pair).
enum ForceMeasure { FORCE_NORMAL = 0, FORCE_SLIDING = 1 };
inline double force_limit_factor(int measure, double mu)
{
  return measure == FORCE_SLIDING ? 1.0 / std::sqrt(1.0 + mu * mu) : 1.0;
}

// Factor on the limit overlap for a factor k on F_lim: Hertz F ~ delta^(3/2),
// so delta_lim ~ F_lim^(2/3). Called by FixCrushParticle::init.
inline double limit_overlap_factor(double k)
{
  return std::cbrt(k * k);
}

// Scale factor of the size term sigma_lim0 f (d / (N_eff d0))^(-3/m).
//   printed: N_eff = N, the scene's up-scaling factor: an up-scaled grain is
//            as strong as the real grain it stands for (scalable law);
//   no_N:    N_eff = 1, the size term at the scaled diameter: at N = 39,
//            m = 10 the strength falls by 39^(3/10) = 3.0 and F_lim by
//            39^(9/10) = 27. Not scalable; a bracket only.
// Called by FixCrushParticle::assign_strength and check_timestep.
enum SizeLaw { SIZE_PRINTED = 0, SIZE_NO_N = 1 };
inline double size_law_scale(int law, double N)
{
  return law == SIZE_NO_N ? 1.0 : N;
}

}  // namespace CrushKernels

#endif
