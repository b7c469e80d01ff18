// SPDX-License-Identifier: GPL-2.0-or-later
/* ----------------------------------------------------------------------
   balance/grains: static load balancing (docs/balance_grains.md).

   Sequence, as write_restart and a run's set-up do it in LIGGGHTS 3.8:
   init; contact history from the neighbour lists into the per-atom arrays
   (setup_pre_exchange), so that it travels with the grains; pbc, box,
   exchange. Then the histogram of the grains along each balanced dimension
   (fine bins, summed over the ranks), cuts at its quantiles, mesh elements
   moved with the cuts one rank at a time (their exchange only reaches the
   neighbour ranks), grains moved in one irregular communication, ghosts
   rebuilt. Neighbour lists are rebuilt by the next run's set-up, which is
   forced even for 'run N pre no'.
------------------------------------------------------------------------- */

#include "balance_grains.h"

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "atom.h"
#include "comm.h"
#include "crush_args.h"
#include "crush_balance_kernel.h"
#include "domain.h"
#include "domain_wedge.h"
#include "error.h"
#include "fix.h"
#include "fix_mesh.h"
#include "group.h"
#include "irregular.h"
#include "lammps.h"
#include "modify.h"
#include "multi_node_mesh_parallel.h"
#include "update.h"

using namespace LAMMPS_NS;
using namespace CrushKernels;

namespace {

std::string fmt(const char *format, double a, double b = 0.0, double c = 0.0, double d = 0.0)
{
  char buf[256];
  snprintf(buf, sizeof(buf), format, a, b, c, d);
  return buf;
}

std::string counts_text(const std::vector<double> &n)
{
  double lo = n.empty() ? 0.0 : n[0], hi = lo, sum = 0.0;
  for (size_t i = 0; i < n.size(); i++) {
    lo = std::min(lo, n[i]);
    hi = std::max(hi, n[i]);
    sum += n[i];
  }
  const double mean = n.empty() ? 0.0 : sum / n.size();
  return fmt("min/mean/max %.0f/%.1f/%.0f (max/mean %.4f)", lo, mean, hi, balance_imbalance(n));
}

}  // namespace

/* ---------------------------------------------------------------------- */

BalanceGrains::BalanceGrains(LAMMPS *lmp) : Pointers(lmp) {}

/* ---------------------------------------------------------------------- */

void BalanceGrains::command(int narg, char **arg)
{
  if (domain->box_exist == 0)
    error->all(FLERR, "balance/grains: the simulation box must be defined first");

  // balance/grains [dim x|y|z|xy|xz|yz|xyz] [bins N] [thresh T] [group ID] [out FILE]
  static const std::vector<std::string> dim_words = {"x", "y", "z", "xy", "xz", "yz", "xyz"};
  int dims_mask = 7;  // bit d: balance dimension d (default: every dimension)
  int nbins = 1000;
  double thresh = 1.05;
  std::string group_id = "all", out_file;
  CrushArgs a(error, "balance/grains", narg, arg, 0, {"dim", "bins", "thresh", "group", "out"});
  while (a.next()) {
    if (a.is("dim")) {
      const std::string w = dim_words[a.choice(dim_words)];
      dims_mask = 0;
      for (int d = 0; d < 3; d++)
        if (w.find("xyz"[d]) != std::string::npos) dims_mask |= 1 << d;
    } else if (a.is("bins")) {
      nbins = static_cast<int>(a.integer(10, 1000000, "an integer in [10, 1000000] (histogram bins per box length)"));
    } else if (a.is("thresh")) {
      thresh = a.number(arg_range(1.0, true, HUGE_VAL, false, ">= 1 (max/mean grains per rank)"));
    } else if (a.is("group")) {
      group_id = a.word("a group ID");
    } else if (a.is("out")) {
      out_file = a.word("a file name");
    }
  }
  const int igroup = group->find(group_id.c_str());
  if (igroup < 0) a.fail("group '" + group_id + "' does not exist");
  const int groupbit = group->bitmask[igroup];

  // One rank: nothing to balance, and nothing is touched (cheap no-op).
  if (comm->nprocs == 1) {
    message("balance/grains: 1 rank, nothing to balance\n");
    return;
  }
  if (domain->triclinic)
    error->all(FLERR, "balance/grains: orthogonal boxes only (the box is triclinic)");
  if (dynamic_cast<DomainWedge *>(domain))
    error->all(FLERR, "balance/grains: not for a wedge domain");

  std::vector<int> dims;
  for (int d = 0; d < 3; d++)
    if ((dims_mask & (1 << d)) && comm->procgrid[d] > 1) dims.push_back(d);

  const std::vector<double> before = per_rank_counts(groupbit);
  const double imb_before = balance_imbalance(before);
  if (dims.empty() || imb_before <= thresh) {
    message("balance/grains: grains per rank " + counts_text(before) +
            (dims.empty() ? std::string(": no balanced dimension has more than 1 rank, cuts kept\n")
                          : fmt(": within thresh %g, cuts kept\n", thresh)));
    return;
  }

  const double t_start = MPI_Wtime();
  // As write_restart: everything initialised, contact history into the
  // per-atom arrays, grains in the box and on their current ranks.
  lmp->init();
  modify->setup_pre_exchange();
  domain->pbc();
  domain->reset_box();
  comm->setup();
  comm->exchange();

  // Histogram of the grains along each balanced dimension, over all ranks.
  double **x = atom->x;
  const int *mask = atom->mask;
  const int nlocal = atom->nlocal;
  std::vector<std::vector<double> > target(3), current(3);
  for (size_t id = 0; id < dims.size(); id++) {
    const int d = dims[id];
    std::vector<double> local(nbins, 0.0), hist(nbins, 0.0);
    for (int i = 0; i < nlocal; i++)
      if (mask[i] & groupbit) local[balance_bin((x[i][d] - domain->boxlo[d]) / domain->prd[d], nbins)] += 1.0;
    MPI_Allreduce(local.data(), hist.data(), nbins, MPI_DOUBLE, MPI_SUM, world);
    // thinnest slab: one bin (at most half the mean slab), so that no rank
    // gets an empty sub-domain where grains crowd into one bin
    const int parts = comm->procgrid[d];
    target[d] = balance_cuts(hist, parts, std::min(1.0 / nbins, 0.5 / parts));
    current[d] = splits(d);
  }

  // Mesh elements (fix mesh/surface and its kin) that are already spread
  // over the ranks move by exchange with the neighbour ranks only: move the
  // cuts in steps that change an element's rank by at most one per
  // dimension, and exchange the elements after each step. A mesh not yet
  // spread (no run since it was defined) is cut at the next run's set-up.
  std::vector<AbstractMesh *> meshes;
  for (int i = 0; i < modify->nfix; i++) {
    FixMesh *fm = dynamic_cast<FixMesh *>(modify->fix[i]);
    if (!fm) continue;
    MultiNodeMeshParallel<3> *m = dynamic_cast<MultiNodeMeshParallel<3> *>(fm->mesh());
    if (m && m->isParallel()) meshes.push_back(fm->mesh());
  }
  comm->uniform = 0;
  int steps = 0;
  for (;;) {
    bool done = true;
    for (size_t id = 0; id < dims.size(); id++) {
      const int d = dims[id];
      current[d] = meshes.empty() ? target[d] : balance_step(current[d], target[d]);
      set_splits(d, current[d]);
      if (current[d] != target[d]) done = false;
    }
    domain->set_local_box();
    for (size_t k = 0; k < meshes.size(); k++) meshes[k]->pbcExchangeBorders(1);
    steps++;
    if (done) break;
    if (steps > 64) error->all(FLERR, "balance/grains: internal error: cuts did not converge");
  }

  // Grains to their new ranks, wherever they are (irregular communication),
  // then the ghosts, as write_restart leaves them.
  double nall = atom->nlocal, natoms_before = 0.0, ntotal = 0.0;
  MPI_Allreduce(&nall, &natoms_before, 1, MPI_DOUBLE, MPI_SUM, world);
  comm->setup();
  Irregular *irregular = new Irregular(lmp);
  irregular->migrate_atoms();
  delete irregular;
  nall = atom->nlocal;
  MPI_Allreduce(&nall, &ntotal, 1, MPI_DOUBLE, MPI_SUM, world);
  if (ntotal != natoms_before)
    error->all(FLERR, "balance/grains: grains were lost while moving them to their new ranks");
  const double off = misplaced(~0);
  if (off > 0.0)
    error->all(FLERR, "balance/grains: internal error: grains outside their rank's sub-domain after migration");
  comm->exchange();
  comm->borders();
  // the next run re-does the whole set-up (neighbour lists, mesh lists)
  // even with 'pre no'
  update->first_update = 0;

  const std::vector<double> after = per_rank_counts(groupbit);
  std::string line = "balance/grains: grains per rank before " + counts_text(before) + ", after " +
                     counts_text(after) + "\n  cuts (fractions of the box):";
  for (size_t id = 0; id < dims.size(); id++) {
    const int d = dims[id];
    line += std::string(" ") + "xyz"[d] + ":";
    for (size_t k = 0; k < current[d].size(); k++) line += fmt(" %.17g", current[d][k]);
  }
  if (!meshes.empty()) line += fmt(" (%.0f mesh exchange step(s))", steps);
  double t_used = MPI_Wtime() - t_start, t_max = 0.0;
  MPI_Allreduce(&t_used, &t_max, 1, MPI_DOUBLE, MPI_MAX, world);
  message(line + fmt("; %.3g s\n", t_max));

  if (!out_file.empty() && comm->me == 0) {
    FILE *fp = fopen(out_file.c_str(), "a");
    if (!fp) error->one(FLERR, ("balance/grains: cannot open out file " + out_file).c_str());
    if (ftell(fp) == 0) {
      fprintf(fp, "# balance/grains: step, then max/mean grains per rank before and after, "
                  "then the grains on each rank (rank order) after\n");
    }
    fprintf(fp, "%ld %.6f %.6f", static_cast<long>(update->ntimestep), imb_before, balance_imbalance(after));
    for (size_t r = 0; r < after.size(); r++) fprintf(fp, " %.0f", after[r]);
    fprintf(fp, "\n");
    fclose(fp);
  }
}

/* ---------------------------------------------------------------------- */

std::vector<double> BalanceGrains::per_rank_counts(int groupbit)
{
  double n = 0.0;
  for (int i = 0; i < atom->nlocal; i++)
    if (atom->mask[i] & groupbit) n += 1.0;
  std::vector<double> all(comm->nprocs);
  MPI_Allgather(&n, 1, MPI_DOUBLE, all.data(), 1, MPI_DOUBLE, world);
  return all;
}

std::vector<double> BalanceGrains::splits(int d)
{
  const double *s = d == 0 ? comm->xsplit : d == 1 ? comm->ysplit : comm->zsplit;
  return std::vector<double>(s, s + comm->procgrid[d] + 1);
}

void BalanceGrains::set_splits(int d, const std::vector<double> &s)
{
  double *dst = d == 0 ? comm->xsplit : d == 1 ? comm->ysplit : comm->zsplit;
  std::copy(s.begin(), s.end(), dst);
}

double BalanceGrains::misplaced(int groupbit)
{
  // a grain within round-off of its sub-domain counts as in it: LIGGGHTS'
  // irregular migration and sublo/subhi round the same cut differently, and
  // the next exchange moves such a grain by one rank
  double n = 0.0;
  for (int i = 0; i < atom->nlocal; i++) {
    if (!(atom->mask[i] & groupbit)) continue;
    for (int d = 0; d < 3; d++) {
      const double tol = 1e-9 * domain->prd[d];
      if (atom->x[i][d] < domain->sublo[d] - tol || atom->x[i][d] > domain->subhi[d] + tol) {
        n += 1.0;
        break;
      }
    }
  }
  double total = 0.0;
  MPI_Allreduce(&n, &total, 1, MPI_DOUBLE, MPI_SUM, world);
  return total;
}

void BalanceGrains::message(const std::string &line)
{
  if (comm->me != 0) return;
  if (screen) fputs(line.c_str(), screen);
  if (logfile) fputs(line.c_str(), logfile);
}
