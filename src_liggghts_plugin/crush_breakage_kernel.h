// SPDX-License-Identifier: GPL-2.0-or-later
/* Grain breakage model of docs/model.md §2.4-§2.5 (Russell & Muir Wood criterion,
   size effect with scatter, Rayleigh time): stateless kernels with no
   LIGGGHTS dependency, unit-tested in tests/unit/test_breakage_kernel.cpp. */

#ifndef CRUSH_BREAKAGE_KERNEL_H
#define CRUSH_BREAKAGE_KERNEL_H

#include <cmath>
#include <cstdint>

namespace CrushKernels {

static const double kPi = 3.14159265358979323846;

// Effective radius R*, 1/R* = 1/r_p + 1/r_q; a wall (r_q <= 0) has 1/r_q = 0.
// Called by FixCrushParticle for every particle-particle and particle-wall contact.
inline double effective_radius(double r_p, double r_q)
{
  return (r_q > 0.0) ? r_p * r_q / (r_p + r_q) : r_p;
}

// Effective modulus E*, 1/E* = (1 - nu_p^2)/E_p + (1 - nu_q^2)/E_q.
// Called by FixCrushParticle::init for every pair of material types.
inline double effective_modulus(double E_p, double nu_p, double E_q, double nu_q)
{
  return 1.0 / ((1.0 - nu_p * nu_p) / E_p + (1.0 - nu_q * nu_q) / E_q);
}

// Hertz normal force at overlap delta: F = 4/3 E* sqrt(R*) delta^(3/2).
inline double hertz_normal_force(double delta, double R_star, double E_star)
{
  return (delta > 0.0) ? 4.0 / 3.0 * E_star * std::sqrt(R_star * delta) * delta : 0.0;
}

// Limit force F_lim = (pi sigma_lim)^3 (3 R* / (4 E*))^2: the force at which the
// mean Hertz contact pressure F / (pi a^2) reaches sigma_lim.
inline double limit_force(double sigma_lim, double R_star, double E_star)
{
  const double ps = kPi * sigma_lim;
  const double g = 3.0 * R_star / (4.0 * E_star);
  return ps * ps * ps * g * g;
}

// Overlap at which the Hertz force reaches F_lim: delta_lim = R* (3 pi sigma_lim / (4 E*))^2.
// Comparing overlaps avoids a square root per contact in FixCrushParticle::end_of_step.
inline double limit_overlap(double sigma_lim, double R_star, double E_star)
{
  const double g = 3.0 * kPi * sigma_lim / (4.0 * E_star);
  return R_star * g * g;
}

// Overlap coefficient c = (3 pi / (4 E*))^2, so that delta_lim = R* sigma_lim^2 c.
// Called by FixCrushParticle::init once per pair of material types.
inline double limit_overlap_coefficient(double E_star)
{
  const double g = 3.0 * kPi / (4.0 * E_star);
  return g * g;
}

// Has a particle-particle contact reached the limit of one of its particles?
// Same answer as radsum - sqrt(rsq) >= limit_overlap(sigma_lim, R*, E*) with
// R* = r_p r_q / radsum, but with multiplications only: with
// lim = r_p r_q sigma_lim^2 c the test is radsum^2 - lim >= radsum sqrt(rsq),
// i.e. A = radsum^2 - lim >= 0 and A^2 >= radsum^2 rsq. This is the test
// FixCrushParticle::find_candidates_pairs runs on every contact of every step;
// a square root and three divisions per contact cost about 7 % of a stock step.
inline bool pair_limit_reached(double rsq, double radsum, double rp_rq,
                               double sigma_lim, double coef)
{
  const double radsum_sq = radsum * radsum;
  const double A = radsum_sq - rp_rq * sigma_lim * sigma_lim * coef;
  return A >= 0.0 && A * A >= radsum_sq * rsq;
}

// Overlap a contact still lacks before particle p reaches its limit,
// delta_lim - delta with delta_lim = r_p r_q sigma_lim^2 c / radsum (negative
// once reached). For particles not in contact delta < 0 is minus their gap
// (radsum - distance). Used by
// FixCrushParticle::find_candidates_pairs to know how far particles may move
// before a contact list must be looked at again.
inline double pair_limit_margin(double delta, double radsum, double rp_rq,
                                double sigma_lim, double coef)
{
  return rp_rq * sigma_lim * sigma_lim * coef / radsum - delta;
}

// May a contact list be skipped? Its margin B holds while the overlap of any
// of its pairs changes by less than B; an overlap changes by at most the sum
// of the two particles' displacements a + b, and (a + b)^2 <= 2 (a^2 + b^2),
// so 2 (a^2 + b^2) < B^2 with B > 0 proves a + b < B without square roots.
// a2: squared displacement of the list's particle, b2: the largest squared
// displacement of any particle on this rank (owned or ghost).
inline bool margin_holds(double a2, double b2, double B)
{
  return B > 0.0 && 2.0 * (a2 + b2) < B * B;
}

// Strength with size effect: sigma_lim = sigma_lim0 f (d / (N d0))^(-3/m).
// Called by FixCrushParticle::assign_strength for initial grains and fragments.
inline double size_effect_strength(double sigma_lim0, double f, double d, double N,
                                   double d0, double m)
{
  return sigma_lim0 * f * std::pow(d / (N * d0), -3.0 / m);
}

// ---------------------------------------------------------------------------
// Counter-based random numbers: every draw is a pure function of
// (seed, tag, stream, counter), so results do not depend on the MPI rank
// count or on the order in which ranks visit particles.

inline uint64_t splitmix64(uint64_t x)
{
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}

enum RandomStream { STREAM_STRENGTH = 1, STREAM_ROTATION = 2 };

// Uniform in (0, 1) (never 0 or 1), draw number `counter` of a stream.
inline double uniform01(uint64_t seed, uint64_t tag, uint64_t stream, uint64_t counter)
{
  uint64_t h = splitmix64(seed);
  h = splitmix64(h ^ tag);
  h = splitmix64(h ^ (stream << 56) ^ counter);
  return ((h >> 11) + 0.5) * (1.0 / 9007199254740992.0);  // 53-bit mantissa
}

// Standard normal by Box-Muller from draws 2k and 2k+1 of a stream.
inline double standard_normal(uint64_t seed, uint64_t tag, uint64_t stream, uint64_t k)
{
  const double u1 = uniform01(seed, tag, stream, 2 * k);
  const double u2 = uniform01(seed, tag, stream, 2 * k + 1);
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * kPi * u2);
}

// Strength factor f ~ Normal(1, var), non-positive draws redrawn (docs/model.md §2.5).
// With var = 0 it is exactly 1.
inline double strength_factor(uint64_t seed, uint64_t tag, double var)
{
  if (var <= 0.0) return 1.0;
  for (uint64_t k = 0;; ++k) {
    const double f = 1.0 + var * standard_normal(seed, tag, STREAM_STRENGTH, k);
    if (f > 0.0) return f;
  }
}

// Rayleigh time T_R = pi r sqrt(rho / G) / (0.1631 nu + 0.8766), docs/model.md §5.
inline double rayleigh_time(double r, double rho, double G, double nu)
{
  return kPi * r * std::sqrt(rho / G) / (0.1631 * nu + 0.8766);
}

// Mass of a sphere of radius r and density rho, 4/3 pi r^3 rho. Called by
// FixCrushParticle for true masses (density scaling), fragments and the fines
// of a break.
inline double sphere_mass(double r, double rho)
{
  return 4.0 * kPi / 3.0 * r * r * r * rho;
}

// Shear modulus from Young's modulus: E = 2 G (1 + nu).
inline double shear_modulus(double E, double nu)
{
  return E / (2.0 * (1.0 + nu));
}

}  // namespace CrushKernels

#endif
