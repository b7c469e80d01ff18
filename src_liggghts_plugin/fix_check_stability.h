// SPDX-License-Identifier: GPL-2.0-or-later
/* ----------------------------------------------------------------------
   fix check/stability: stops a run that goes numerically unstable, with an
   error naming the step, the particle and the likely cause, before atoms
   are lost. Two cheap signals: (a) a particle moving more than a fraction
   of its radius in one step (every step), (b) a pair overlapping by more
   than a fraction of the smaller radius (every overlap_every steps and at
   the start of every run).
   Doc: docs/fix_check_stability.md
------------------------------------------------------------------------- */

#ifdef FIX_CLASS

FixStyle(check/stability,FixCheckStability)

#else

#ifndef LMP_FIX_CHECK_STABILITY_H
#define LMP_FIX_CHECK_STABILITY_H

#include <string>
#include <vector>

#include "fix.h"

namespace LAMMPS_NS {

class FixCheckStability : public Fix {
 public:
  FixCheckStability(class LAMMPS *, int, char **);
  int setmask();
  void init();
  void setup(int);
  void end_of_step();
  double compute_vector(int);

 private:
  double move_frac_;      // signal (a): |v| dt > move_frac r (0: off)
  double overlap_frac_;   // signal (b): delta > overlap_frac min(r_i, r_j) (0: off)
  int overlap_every_;     // steps between overlap scans
  class Pair *pair_;
  std::vector<double> E_, nu_;  // per material type, for the particle's Rayleigh time
  double max_move_seen_;        // largest |v| dt / r seen on this rank (output [1])
  double max_overlap_seen_;     // largest delta / r_min at the scans (output [2])

  // particle data carried to rank 0 for the message
  struct Culprit {
    double ratio;  // signal value / its limit (> 1: fired)
    double tag, type, radius, x[3], v[3], mass, density, partner_tag, partner_radius;
  };
  void check_moves();
  void check_overlaps();
  void stop(const Culprit &local, const char *signal);
  std::string likely_cause(const Culprit &c, bool overlap) const;
};

}

#endif
#endif
