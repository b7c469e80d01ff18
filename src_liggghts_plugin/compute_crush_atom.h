// SPDX-License-Identifier: GPL-2.0-or-later
/* ----------------------------------------------------------------------
   compute crush/atom: the per-particle state of a fix crush/particle as a
   per-atom array, for dumps, snapshots and atom-style variables:
     [1] sigma_lim (Pa), [2] generation, [3] true mass (kg, without density
     scaling), [4] utilisation: the largest F_n / F_lim over the particle's
     contacts now (FixCrushParticle::utilisation).
   A compute, not the fix's own per-atom array: an atom-style variable
   `f_ID[1]` of a fix that also has a global vector reads the global vector
   (LIGGGHTS' variable rules), and the utilisation is worth its cost only on
   the steps an output asks for it.
   Doc: docs/compute_crush_atom.md
------------------------------------------------------------------------- */

#ifdef COMPUTE_CLASS

ComputeStyle(crush/atom,ComputeCrushAtom)

#else

#ifndef LMP_COMPUTE_CRUSH_ATOM_H
#define LMP_COMPUTE_CRUSH_ATOM_H

#include <string>
#include <vector>

#include "compute.h"

namespace LAMMPS_NS {

class ComputeCrushAtom : public Compute {
 public:
  ComputeCrushAtom(class LAMMPS *, int &iarg, int narg, char **arg);
  ~ComputeCrushAtom();
  void init();
  void compute_peratom();
  double memory_usage();

 private:
  std::string fix_id_;
  class FixCrushParticle *fix_;
  int nmax_;
  double **out_;
  std::vector<double> u_;
};

}

#endif
#endif
