// SPDX-License-Identifier: GPL-2.0-or-later
/* ----------------------------------------------------------------------
   fix damp/local: PFC-style local (non-viscous) damping,
   F_i <- F_i - alpha |F_i| sign(v_i) on each translational component;
   keyword energy: the energy it removed (global scalar).
   Doc: docs/fix_damp_local.md
------------------------------------------------------------------------- */

#ifdef FIX_CLASS

FixStyle(damp/local,FixDampLocal)

#else

#ifndef LMP_FIX_DAMP_LOCAL_H
#define LMP_FIX_DAMP_LOCAL_H

#include "fix.h"

namespace LAMMPS_NS {

class FixDampLocal : public Fix {
 public:
  FixDampLocal(class LAMMPS *, int, char **);
  int setmask();
  void init();
  void setup(int);
  void min_setup(int);
  void post_force(int);
  void min_post_force(int);
  double compute_scalar();

 private:
  double alpha_;
  // keyword energy: work the damping force removed, -sum f_damp . v dt
  // over the steps of the runs (the scalar f_ID, summed over ranks)
  bool energy_;
  double dissipated_;
};

}

#endif
#endif
