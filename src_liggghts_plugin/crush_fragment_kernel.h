// SPDX-License-Identifier: GPL-2.0-or-later
/* Fragment geometry of docs/model.md §2.6: the parent sphere is replaced by the
   first 14 spheres of an Apollonian packing, in a randomly rotated frame.
   Stateless kernels with no LIGGGHTS dependency, unit-tested in
   tests/unit/test_fragment_kernel.cpp; FixCrushParticle::break_particles calls them. */

#ifndef CRUSH_FRAGMENT_KERNEL_H
#define CRUSH_FRAGMENT_KERNEL_H

#include <cmath>
#include <cstdint>

#include "crush_breakage_kernel.h"

namespace CrushKernels {

static const int kFragments = 14;

// Large fragments: r1 = r / (1 + sqrt 2), centred at +-(r - r1) on the axes,
// tangent to the parent and to their four large neighbours.
inline double large_fragment_ratio()
{
  return 1.0 / (1.0 + std::sqrt(2.0));
}

// Small fragments, centred at (r - r2)/sqrt3 (+-1, +-1, +-1): tangency with the
// parent and with three large fragments gives, with u = r - r2 and a = r - r1,
// u^2 - 2 a u / sqrt3 + a^2 = (r + r1 - u)^2, linear in u. Ratio r2/r = 0.230093...
inline double small_fragment_ratio()
{
  const double r1 = large_fragment_ratio();
  const double a = 1.0 - r1;
  const double s = 1.0 + r1;
  const double u = (s * s - a * a) / (2.0 * s - 2.0 * a / std::sqrt(3.0));
  return 1.0 - u;
}

// Fraction of the parent volume kept by the 14 fragments (0.5239...).
inline double fragment_volume_fraction()
{
  const double r1 = large_fragment_ratio();
  const double r2 = small_fragment_ratio();
  return 6.0 * r1 * r1 * r1 + 8.0 * r2 * r2 * r2;
}

// Radii and centre offsets of the 14 fragments of a parent of radius r, in the
// parent's frame: 6 large first (+x,-x,+y,-y,+z,-z), then 8 small.
inline void apollonian_fragments(double r, double radius[kFragments], double offset[kFragments][3])
{
  const double r1 = large_fragment_ratio() * r;
  const double r2 = small_fragment_ratio() * r;
  for (int k = 0; k < 6; ++k) {
    const int axis = k / 2;
    const double sgn = (k % 2 == 0) ? 1.0 : -1.0;
    radius[k] = r1;
    offset[k][0] = offset[k][1] = offset[k][2] = 0.0;
    offset[k][axis] = sgn * (r - r1);
  }
  const double c = (r - r2) / std::sqrt(3.0);
  for (int k = 0; k < 8; ++k) {
    radius[6 + k] = r2;
    offset[6 + k][0] = (k & 1) ? -c : c;
    offset[6 + k][1] = (k & 2) ? -c : c;
    offset[6 + k][2] = (k & 4) ? -c : c;
  }
}

// Uniformly distributed random rotation (unit quaternion from three uniforms,
// Shoemake's construction) written as a row-major 3x3 matrix.
inline void random_rotation(double u1, double u2, double u3, double R[3][3])
{
  const double s1 = std::sqrt(1.0 - u1), s2 = std::sqrt(u1);
  const double t1 = 2.0 * kPi * u2, t2 = 2.0 * kPi * u3;
  const double w = s2 * std::cos(t2), x = s1 * std::sin(t1);
  const double y = s1 * std::cos(t1), z = s2 * std::sin(t2);
  R[0][0] = 1 - 2 * (y * y + z * z); R[0][1] = 2 * (x * y - z * w); R[0][2] = 2 * (x * z + y * w);
  R[1][0] = 2 * (x * y + z * w); R[1][1] = 1 - 2 * (x * x + z * z); R[1][2] = 2 * (y * z - x * w);
  R[2][0] = 2 * (x * z - y * w); R[2][1] = 2 * (y * z + x * w); R[2][2] = 1 - 2 * (x * x + y * y);
}

// The rotation used for one breakage event: a pure function of the seed and
// the parent's tag, so it is the same on any number of MPI ranks.
inline void event_rotation(uint64_t seed, uint64_t parent_tag, double R[3][3])
{
  random_rotation(uniform01(seed, parent_tag, STREAM_ROTATION, 0),
                  uniform01(seed, parent_tag, STREAM_ROTATION, 1),
                  uniform01(seed, parent_tag, STREAM_ROTATION, 2), R);
}

inline void rotate(const double R[3][3], const double v[3], double out[3])
{
  for (int i = 0; i < 3; ++i) out[i] = R[i][0] * v[0] + R[i][1] * v[1] + R[i][2] * v[2];
}

}  // namespace CrushKernels

#endif
