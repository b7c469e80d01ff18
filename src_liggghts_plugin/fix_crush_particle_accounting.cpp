// SPDX-License-Identifier: GPL-2.0-or-later
/* ----------------------------------------------------------------------
   fix crush/particle: accounting. The initial mass and grading Br counts
   from (take_initial_grading, called by FixCrushParticle::setup on the
   first run), the global outputs f_ID[1..15] (compute_globals,
   compute_vector; docs/fix_crush_particle.md "Restart, output") and the
   fix's own count of atoms, which stops a run that loses grains
   (count_atoms, check_atom_count, called by the setup and neighbour hooks
   and by break_particles). Br math: crush_breakage_index_kernel.h.
   Exercised by tests/integration/test_crush_br.py (Br, fines, mass
   balance), test_lost_atoms.py (the atom count), test_energy.py (outputs
   [9..15]), test_crush_parallel.py (outputs at 1 and 2 ranks).
------------------------------------------------------------------------- */

#include "fix_crush_particle.h"

#include <algorithm>
#include <cstdio>
#include <vector>

#include "atom.h"
#include "comm.h"
#include "crush_breakage_index_kernel.h"
#include "crush_energy.h"
#include "crush_error.h"
#include "error.h"
#include "update.h"

using namespace LAMMPS_NS;
using namespace FixConst;
using namespace CrushKernels;

/* ---------------------------------------------------------------------- */

// Initial solid mass and grading F0 of the group (Br relative to the start),
// once: later runs and restart files carry them.
void FixCrushParticle::take_initial_grading()
{
  // initial solid mass and initial grading F0 (docs/model.md §2.8: Br relative to the
  // start), per Br size bin: [0] mass, [1] unbinned integral, then the
  // particle histogram (crush_breakage_index_kernel.h)
  const BrGrid grid = br_grid(d_min_, d_max_);
  const int nh = 2 * grid.n + 1;
  std::vector<double> local(2 + nh, 0.0), global(2 + nh);
  const int nlocal = atom->nlocal;
  for (int i = 0; i < nlocal; i++) {
    if (!(atom->mask[i] & groupbit)) continue;
    const double m = true_mass(i);
    local[0] += m;
    local[1] += breakage_integral_term(m, 2.0 * atom->radius[i], d_min_, d_max_);
    br_histogram_add(m, 2.0 * atom->radius[i], grid, &local[2]);
  }
  MPI_Allreduce(&local[0], &global[0], 2 + nh, MPI_DOUBLE, MPI_SUM, world);
  mass0_ = global[0];
  integral0_ = (global[0] > 0.0) ? global[1] / global[0] : 0.0;
  J0_.assign(grid.n, 0.0);
  br_histogram_integrals(&global[2], grid, &J0_[0]);
  for (int b = 0; b < grid.n; b++) J0_[b] = (global[0] > 0.0) ? J0_[b] / global[0] : 0.0;
  initialized_ = true;

  double dmax_local = 0.0, dmax_all;
  for (int i = 0; i < nlocal; i++)
    if (atom->mask[i] & groupbit) dmax_local = std::max(dmax_local, 2.0 * atom->radius[i]);
  MPI_Allreduce(&dmax_local, &dmax_all, 1, MPI_DOUBLE, MPI_MAX, world);
  if (dmax_all > d_max_ && comm->me == 0) {
    char msg[256];
    snprintf(msg, sizeof(msg),
             "fix crush/particle: grains up to d = %g exceed the Br grading limit d_max = %g; "
             "Br sees them as d_max: their breakage into sizes still above d_max does not count (set 'd_max')", dmax_all, d_max_);
    error->warning(FLERR, msg);
  }
}

/* ----------------------------------------------------------------------
   Lost grains. Stock LIGGGHTS 3.8 looks for lost atoms only at thermo
   output, by comparing the atom count with that of the previous output
   (Comm::exchange recounts atom->natoms at every re-neighbouring), and only
   under `thermo_modify lost error`: a break adds 13 atoms, so a grain lost
   in the same interval would go unnoticed. The fix keeps its own count and
   checks it after every exchange, where atoms leave the box (setup_pre_
   neighbor and pre_neighbor), and before each break: natoms_counted_ atoms
   with tags up to maxtag_ever_ must be there. The count is taken before the
   set-up exchange of each run (atoms created or deleted by commands between
   runs are accepted) and advanced by what the breaks create and delete.
   Atoms that another fix inserts get new tags above maxtag_ever_ and are
   taken into the count at the next check, so a loss in the same interval
   as an insertion is still seen. Fewer atoms than counted stop the run: a
   lost grain would also make the mass balance and Br wrong. Nothing of this
   touches what stock LIGGGHTS counts or checks (docs/liggghts-patches.md).
------------------------------------------------------------------------- */

void FixCrushParticle::count_atoms()
{
  bigint nlocal = atom->nlocal;
  MPI_Allreduce(&nlocal, &natoms_counted_, 1, MPI_LMP_BIGINT, MPI_SUM, world);
  int maxtag_local = 0, maxtag_all;
  for (int i = 0; i < atom->nlocal; i++) maxtag_local = std::max(maxtag_local, atom->tag[i]);
  MPI_Allreduce(&maxtag_local, &maxtag_all, 1, MPI_INT, MPI_MAX, world);
  maxtag_ever_ = std::max(maxtag_ever_, maxtag_all);
}

void FixCrushParticle::check_atom_count()
{
  const int nlocal = atom->nlocal;
  const int *tag = atom->tag;
  bigint local[2] = {0, nlocal}, all[2];  // atoms with known tags, all atoms
  int maxtag_local = 0, maxtag_all;
  for (int i = 0; i < nlocal; i++) {
    if (tag[i] <= maxtag_ever_) local[0]++;
    maxtag_local = std::max(maxtag_local, tag[i]);
  }
  MPI_Allreduce(local, all, 2, MPI_LMP_BIGINT, MPI_SUM, world);
  MPI_Allreduce(&maxtag_local, &maxtag_all, 1, MPI_INT, MPI_MAX, world);
  if (all[0] < natoms_counted_) {
    char msg[1024];
    snprintf(msg, sizeof(msg),
             "fix crush/particle (fix %s): " BIGINT_FORMAT " atoms lost by step " BIGINT_FORMAT
             " (expected " BIGINT_FORMAT ", found " BIGINT_FORMAT "): grains left the simulation "
             "box or were deleted during the run; the deck must not lose grains (the mass balance "
             "and Br count every grain)",
             id, natoms_counted_ - all[0], update->ntimestep, natoms_counted_, all[0]);
    crush_error_all(lmp, FLERR, msg);
  }
  natoms_counted_ = all[1];
  maxtag_ever_ = std::max(maxtag_ever_, maxtag_all);
}

/* ---------------------------------------------------------------------- */

// Called for thermo (and other) output only: one histogram of the particles
// per rank, summed with one MPI_Allreduce (2 kBrBins + 4 doubles).
void FixCrushParticle::compute_globals()
{
  if (cache_step_ == update->ntimestep) return;
  const BrGrid grid = br_grid(d_min_, d_max_);
  const int nh = 2 * grid.n + 1;
  // [0] particle mass, [1] lists scanned, [2] lists total, [3...] histogram
  std::vector<double> local(3 + nh, 0.0), global(3 + nh);
  local[1] = lists_scanned_;
  local[2] = lists_total_;
  double rmin_local = 1e300, rmin_all;
  const int nlocal = atom->nlocal;
  for (int i = 0; i < nlocal; i++) {
    if (!(atom->mask[i] & groupbit)) continue;
    local[0] += true_mass(i);
    br_histogram_add(true_mass(i), 2.0 * atom->radius[i], grid, &local[3]);
    rmin_local = std::min(rmin_local, atom->radius[i]);
  }
  MPI_Allreduce(&local[0], &global[0], 3 + nh, MPI_DOUBLE, MPI_SUM, world);
  MPI_Allreduce(&rmin_local, &rmin_all, 1, MPI_DOUBLE, MPI_MIN, world);

  // bin integrals of the current grading: particles plus fines, over the total mass
  const double M = global[0] + fines_mass_;
  std::vector<double> J(J_fines_);
  br_histogram_integrals(&global[3], grid, &J[0]);
  double I = 0.0, I0 = 0.0;
  for (int b = 0; b < grid.n; b++) {
    J[b] = (M > 0.0) ? J[b] / M : 0.0;
    I += J[b];
    I0 += J0_[b];
  }
  cache_[0] = n_events_;
  cache_[1] = n_created_;
  cache_[2] = fines_mass_;
  cache_[3] = global[0];
  cache_[4] = bounded_breakage_index(&J[0], &J0_[0], &U_[0], grid.n);
  cache_[5] = (rmin_all < 1e299) ? rmin_all : 0.0;
  cache_[6] = (global[2] > 0.0) ? global[1] / global[2] : 0.0;
  cache_[7] = breakage_index(I, I0, fractal_grading_integral(d_min_, d_max_, omega_));
  for (int q = 0; q < 5; q++) cache_[8 + q] = energy_sums_[q];
  cache_[13] = energy_ ? energy_->total_elastic(groupbit) : 0.0;
  cache_[14] = (energy_ && energy_budget_) ? energy_->friction_dissipated() : 0.0;
  cache_step_ = update->ntimestep;
}

double FixCrushParticle::compute_vector(int n)
{
  compute_globals();
  return cache_[n];
}
