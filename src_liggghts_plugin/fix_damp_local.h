/* ----------------------------------------------------------------------
   fix damp/local: PFC-style local (non-viscous) damping,
   F_i <- F_i - alpha |F_i| sign(v_i) on each translational component.
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

 private:
  double alpha_;
};

}

#endif
#endif
