// SPDX-License-Identifier: GPL-2.0-or-later
/* ----------------------------------------------------------------------
   fix crush/particle: the limit of a contact, inline. eligible, F_lim and
   delta_lim are members of FixCrushParticle defined here, in a header of
   their own, because the contact scan calls them for every pair
   (fix_crush_particle_screening.cpp) and the criterion's other users
   (fix_crush_particle_criterion.cpp, fix_crush_particle_timestep.cpp)
   need the same definitions. Included by the fix's .cpp files only. The
   formulas: crush_breakage_kernel.h (limit_force, limit_overlap) and
   crush_criterion_kernel.h (the reading's factors).
------------------------------------------------------------------------- */

#ifndef LMP_FIX_CRUSH_PARTICLE_CRITERION_H
#define LMP_FIX_CRUSH_PARTICLE_CRITERION_H

#include "atom.h"
#include "crush_breakage_kernel.h"
#include "crush_criterion_kernel.h"
#include "fix_crush_particle.h"

namespace LAMMPS_NS {

// Particles of the group at or above the comminution limit d_comm can break.
inline bool FixCrushParticle::eligible(int i) const
{
  return (atom->mask[i] & groupbit) && 2.0 * atom->radius[i] >= d_comm_;
}

// F_lim and the limit overlap of particle i on a contact of types (ti, tj)
// with effective radius R_star, in the fix's criterion reading
inline double FixCrushParticle::F_lim(int i, double R_star, int ti, int tj) const
{
  return CrushKernels::limit_force(crush_[i][0], R_star, E_star(ti, tj)) * limit_factor(ti, tj);
}

inline double FixCrushParticle::delta_lim(int i, double R_star, int ti, int tj) const
{
  return CrushKernels::limit_overlap(crush_[i][0], R_star, E_star(ti, tj)) *
         CrushKernels::limit_overlap_factor(limit_factor(ti, tj));
}

}  // namespace LAMMPS_NS

#endif
