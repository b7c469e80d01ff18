// SPDX-License-Identifier: GPL-2.0-or-later
/* ----------------------------------------------------------------------
   compute stress/grain: per-particle stress of docs/model.md §4.7,
   sigma_p = -(1/V_p) sum_c s^c (x) F^c over every contact of particle p,
   particle-particle and particle-mesh wall, compression positive
   (s^c from the centre to the contact point, F^c the force on p,
   V_p = 4/3 pi r_p^3). The contacts and their forces are those of LIGGGHTS'
   compute pair/gran/local and compute wall/gran/local of the deck.
   Doc: docs/compute_stress_grain.md
------------------------------------------------------------------------- */

#ifdef COMPUTE_CLASS

ComputeStyle(stress/grain,ComputeStressGrain)

#else

#ifndef LMP_COMPUTE_STRESS_GRAIN_H
#define LMP_COMPUTE_STRESS_GRAIN_H

#include <string>

#include "compute.h"

namespace LAMMPS_NS {

class ComputeStressGrain : public Compute {
 public:
  ComputeStressGrain(class LAMMPS *, int &iarg, int narg, char **arg);
  ~ComputeStressGrain();
  void init();
  void compute_peratom();
  int pack_reverse_comm(int, int, double *);
  void unpack_reverse_comm(int, int *, double *);
  double memory_usage();

 private:
  std::string pair_id_, wall_id_;   // deck computes (empty: find them)
  bool wall_none_;                  // 'wall_local none': the deck has no mesh walls
  class ComputePairGranLocal *pair_, *wall_;
  int nmax_;
  double **sum_;                    // sum_c s (x) F per owned and ghost particle (9)
  double **out_;                    // the per-atom array (9 columns)

  class ComputePairGranLocal *find_local(const char *key, const std::string &id, bool wall);
  void add_term(int k, const double *s, const double *f);
};

}

#endif
#endif
