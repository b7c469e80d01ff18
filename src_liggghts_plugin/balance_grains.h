// SPDX-License-Identifier: GPL-2.0-or-later
/* ----------------------------------------------------------------------
   balance/grains: static load balancing for LIGGGHTS 3.8. Moves the cuts
   of the processor grid (comm->xsplit/ysplit/zsplit) to the quantiles of
   the grains along each balanced dimension, so that every slab of ranks
   holds about the same number of grains; migrates the grains and the mesh
   elements to their new ranks. Cut placement: crush_balance_kernel.h.
   Doc: docs/balance_grains.md
------------------------------------------------------------------------- */

#ifdef COMMAND_CLASS

CommandStyle(balance/grains,BalanceGrains)

#else

#ifndef LMP_BALANCE_GRAINS_H
#define LMP_BALANCE_GRAINS_H

#include <string>
#include <vector>

#include "pointers.h"

namespace LAMMPS_NS {

class BalanceGrains : protected Pointers {
 public:
  BalanceGrains(class LAMMPS *);
  void command(int, char **);

 private:
  // grains (atoms of the group) on each rank, gathered on every rank
  std::vector<double> per_rank_counts(int groupbit);
  // the cuts of dimension d as a vector of procgrid[d] + 1 fractions
  std::vector<double> splits(int d);
  void set_splits(int d, const std::vector<double> &s);
  // grains of the group outside this rank's sub-domain, summed over ranks
  double misplaced(int groupbit);
  void message(const std::string &line);
};

}  // namespace LAMMPS_NS

#endif
#endif
