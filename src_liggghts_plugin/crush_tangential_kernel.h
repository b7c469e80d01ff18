// SPDX-License-Identifier: GPL-2.0-or-later
/* Incremental (force-based) tangential contact update of PFC's Hertz model,
   docs/tangential_incremental.md. The contact stores the tangential FORCE
   and adds -k_t v_t dt to it with the current stiffness k_t, so a fall of
   the normal force does not lower the tangential force unless the Coulomb
   limit mu |F_n| is reached (LIGGGHTS' `tangential history` stores the
   displacement and multiplies it by the current k_t instead).
   Stateless kernels, no LIGGGHTS dependency; unit-tested in
   tests/unit/test_tangential_kernel.cpp. Called, in this order, by
   TangentialModel<TANGENTIAL_INCREMENTAL>::surfacesIntersect
   (tangential_model_incremental.h). */

#ifndef CRUSH_TANGENTIAL_KERNEL_H
#define CRUSH_TANGENTIAL_KERNEL_H

#include <cmath>

namespace CrushKernels {

inline double norm3(const double a[3])
{
  return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
}

// Bring the stored tangential force onto the current contact plane (unit
// normal n): remove its normal part, then restore its length, so that the
// turn of the contact plane (the grains roll around each other) neither
// creates nor destroys tangential force. Step 1 of surfacesIntersect.
inline void tangential_force_rotate(double ft[3], const double n[3])
{
  const double before = norm3(ft);
  const double along_n = ft[0] * n[0] + ft[1] * n[1] + ft[2] * n[2];
  ft[0] -= along_n * n[0];
  ft[1] -= along_n * n[1];
  ft[2] -= along_n * n[2];
  const double after = norm3(ft);
  if (after > 0.0) {
    const double s = before / after;
    ft[0] *= s;
    ft[1] *= s;
    ft[2] *= s;
  }
}

// Elastic increment with the CURRENT stiffness: F_t += -k_t v_t dt, v_t the
// relative tangential velocity at the contact point (i relative to j).
// Step 2 of surfacesIntersect.
inline void tangential_force_increment(double ft[3], const double vt[3], double kt, double dt)
{
  ft[0] -= kt * vt[0] * dt;
  ft[1] -= kt * vt[1] * dt;
  ft[2] -= kt * vt[2] * dt;
}

// Coulomb slip: a force longer than `limit` = mu |F_n| is shortened to it
// (its direction kept). Returns true when the contact slides. Step 3.
inline bool tangential_force_cap(double ft[3], double limit)
{
  const double mag = norm3(ft);
  if (mag <= limit) return false;
  const double s = (mag > 0.0) ? limit / mag : 0.0;
  ft[0] *= s;
  ft[1] *= s;
  ft[2] *= s;
  return true;
}

// One full step of the stored force: rotate, increment, cap. Returns true
// when the contact slides. (The viscous term -gamma_t v_t of a sticking
// contact is added by the caller and not stored, as `tangential history`
// does.)
inline bool tangential_force_step(double ft[3], const double n[3], const double vt[3],
                                  double kt, double dt, double limit)
{
  tangential_force_rotate(ft, n);
  tangential_force_increment(ft, vt, kt, dt);
  return tangential_force_cap(ft, limit);
}

}  // namespace CrushKernels

#endif
