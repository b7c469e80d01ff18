// SPDX-License-Identifier: GPL-2.0-or-later
/* ----------------------------------------------------------------------
   fix crush/particle: fragmentation. break_particles (called by
   FixCrushParticle::pre_exchange on the step after candidates were found)
   replaces every candidate by its 14 Apollonian fragments
   (crush_fragment_kernel.h), sends fragments finer than d_frag_min to the
   fines, and adds the break's counts, fines and Br bins to the totals
   (fix_crush_particle_accounting.cpp reads them). Density scaling (keyword
   density_scale, crush_density_scale_kernel.h): setup_pre_exchange sets the
   masses at the start of each run, fragment_speed_factor the fragments'
   velocity factor, true_mass the mass without scaling.
   Exercised by tests/integration/test_crush_single_grain.py (fragments,
   tags, mass), test_crush_br.py (fines, Br), test_crush_parallel.py (the
   same tags at 1 and 2 ranks), test_density_scale.py, test_lost_atoms.py.
------------------------------------------------------------------------- */

#include "fix_crush_particle.h"

#include <algorithm>
#include <cstdio>

#include "atom.h"
#include "atom_vec.h"
#include "comm.h"
#include "crush_breakage_index_kernel.h"
#include "crush_breakage_kernel.h"
#include "crush_density_scale_kernel.h"
#include "crush_event_log_kernel.h"
#include "crush_fragment_kernel.h"
#include "error.h"
#include "modify.h"
#include "update.h"

using namespace LAMMPS_NS;
using namespace FixConst;
using namespace CrushKernels;

/* ----------------------------------------------------------------------
   Density scaling (keyword density_scale, crush_density_scale_kernel.h):
   every particle's mass is set from its true density, radius and the
   scaling factor at the start of each run, so that a restart or a second
   run does not scale twice (atom->density stays the true density). Done
   before the borders of the run's set-up, so ghosts carry the new masses.
------------------------------------------------------------------------- */

void FixCrushParticle::setup_pre_exchange()
{
  count_atoms();  // before the set-up exchange: its losses are checked after it
  if (!(d_scale_ref_ > 0.0)) return;
  double n_scaled = 0.0, f_max = 1.0;
  for (int i = 0; i < atom->nlocal; i++) {
    if (!(atom->mask[i] & groupbit)) continue;
    const double r = atom->radius[i];
    const double f = density_scale_factor(2.0 * r, d_scale_ref_);
    atom->rmass[i] = sphere_mass(r, atom->density[i]) * f;
    if (f > 1.0) n_scaled += 1.0;
    f_max = std::max(f_max, f);
  }
  double global[2];  // particles scaled, largest factor
  MPI_Allreduce(&n_scaled, &global[0], 1, MPI_DOUBLE, MPI_SUM, world);
  MPI_Allreduce(&f_max, &global[1], 1, MPI_DOUBLE, MPI_MAX, world);
  if (comm->me == 0) {
    char line[512];
    snprintf(line, sizeof(line),
             "fix crush/particle: density scaling on: particles finer than d = %g have their mass "
             "raised by (d_ref/d)^2 (Rayleigh time of d_ref); %.0f particles scaled now (largest "
             "factor %g), fragments as they are made; mass balance, fines and Br in true mass\n",
             d_scale_ref_, global[0], global[1]);
    if (screen) fputs(line, screen);
    if (logfile) fputs(line, logfile);
  }
}

double FixCrushParticle::true_mass(int i) const
{
  if (!(d_scale_ref_ > 0.0)) return atom->rmass[i];
  return sphere_mass(atom->radius[i], atom->density[i]);
}

/* ----------------------------------------------------------------------
   Velocity factor of the fragments of one break (radii r[0..n), density
   rho) under density scaling: fragment_velocity_factor of the true and
   scaled masses of those kept (not finer than d_frag_min). Called by
   break_particles and energy_of_breaks, so both use the same velocities.
------------------------------------------------------------------------- */

double FixCrushParticle::fragment_speed_factor(const double *r, int n, double rho) const
{
  double sum_true = 0.0, sum_scaled = 0.0;
  for (int f = 0; f < n; f++) {
    if (2.0 * r[f] < d_frag_min_) continue;
    const double mt = sphere_mass(r[f], rho);
    sum_true += mt;
    sum_scaled += mt * density_scale_factor(2.0 * r[f], d_scale_ref_);
  }
  return fragment_velocity_factor(sum_true, sum_scaled);
}

/* ----------------------------------------------------------------------
   Replace every candidate by its fragments. New tags are assigned in the
   order of the parents' tags over all ranks, so tags, strengths and
   orientations do not depend on the number of ranks.
------------------------------------------------------------------------- */

void FixCrushParticle::break_particles()
{
  check_atom_count();
  const int nprocs = comm->nprocs;
  int nlocal = atom->nlocal;

  // resolve candidates to local indices (tags are robust to index changes)
  std::vector<int> parents;
  std::vector<Candidate> cands;
  if (!candidates_.empty()) {
    std::vector<std::pair<int, int> > by_tag;  // (tag, candidate index)
    for (size_t k = 0; k < candidates_.size(); k++) by_tag.push_back(std::make_pair(candidates_[k].tag, (int)k));
    std::sort(by_tag.begin(), by_tag.end());
    for (int i = 0; i < nlocal; i++) {
      std::vector<std::pair<int, int> >::iterator it =
          std::lower_bound(by_tag.begin(), by_tag.end(), std::make_pair(atom->tag[i], -1));
      if (it != by_tag.end() && it->first == atom->tag[i]) {
        parents.push_back(i);
        cands.push_back(candidates_[it->second]);
      }
    }
  }
  clear_candidates();

  // fragments each parent keeps: fragments finer than d_frag_min go to fines
  const double r1 = large_fragment_ratio(), r2 = small_fragment_ratio();
  const int np_local = (int)parents.size();
  std::vector<int> keep(np_local);
  for (int k = 0; k < np_local; k++) {
    const double d = 2.0 * atom->radius[parents[k]];
    keep[k] = (r1 * d >= d_frag_min_ ? 6 : 0) + (r2 * d >= d_frag_min_ ? 8 : 0);
  }

  // global (tag, keep) list, sorted by tag -> tag offsets
  std::vector<int> counts(nprocs), displs(nprocs);
  int two_np = 2 * np_local;
  MPI_Allgather(&two_np, 1, MPI_INT, &counts[0], 1, MPI_INT, world);
  int total2 = 0;
  for (int p = 0; p < nprocs; p++) { displs[p] = total2; total2 += counts[p]; }
  std::vector<int> mine(two_np + 1), all(total2 + 1);
  for (int k = 0; k < np_local; k++) { mine[2 * k] = atom->tag[parents[k]]; mine[2 * k + 1] = keep[k]; }
  MPI_Allgatherv(&mine[0], two_np, MPI_INT, &all[0], &counts[0], &displs[0], MPI_INT, world);
  const int np_all = total2 / 2;
  std::vector<std::pair<int, int> > order(np_all);
  for (int k = 0; k < np_all; k++) order[k] = std::make_pair(all[2 * k], all[2 * k + 1]);
  std::sort(order.begin(), order.end());

  int maxtag_local = 0, maxtag_all;
  for (int i = 0; i < nlocal; i++) maxtag_local = std::max(maxtag_local, atom->tag[i]);
  MPI_Allreduce(&maxtag_local, &maxtag_all, 1, MPI_INT, MPI_MAX, world);
  const int base = std::max(maxtag_all, maxtag_ever_);

  std::vector<int> first_tag(np_all);
  long next = base;
  for (int k = 0; k < np_all; k++) { first_tag[k] = (int)(next + 1); next += order[k].second; }
  if (next > 2147483647L)
    error->all(FLERR, "fix crush/particle: atom IDs would exceed the 32-bit limit");

  // energy of the breaks (keyword energy): before any atom is created
  std::vector<double> energy_local;
  if (energy_on_) {
    // In pre_exchange the ghosts still hold the positions of the previous
    // step (Verlet updates them only on steps without a neighbour build):
    // bring them up to date, as such a step would, while the ghost lists of
    // the last build are still valid (no atom created or deleted since).
    int valid = (atom->nlocal + atom->nghost == nall_at_borders_) ? 1 : 0, ok;
    MPI_Allreduce(&valid, &ok, 1, MPI_INT, MPI_MIN, world);
    if (ok) comm->forward_comm();
    energy_of_breaks(parents, order, first_tag, &energy_local);
  }

  // create fragments; sums[0..2] fines mass, fragments, events, then the
  // fines' Br bin integrals (summed over ranks below)
  const BrGrid grid = br_grid(d_min_, d_max_);
  std::vector<double> sums(3 + grid.n, 0.0), sums_all(3 + grid.n);
  double fines_local = 0.0, created_local = 0.0;
  std::vector<double> records;
  double frag_r[kFragments], frag_off[kFragments][3], R[3][3];
  for (int k = 0; k < np_local; k++) {
    const int i = parents[k];
    const int tag_i = atom->tag[i];
    const int pos = (int)(std::lower_bound(order.begin(), order.end(), std::make_pair(tag_i, -1)) - order.begin());
    int new_tag = first_tag[pos];

    const double r = atom->radius[i];
    const double rho = atom->density[i];
    const double generation = crush_[i][1];
    double xp[3] = {atom->x[i][0], atom->x[i][1], atom->x[i][2]};
    double vp[3] = {atom->v[i][0], atom->v[i][1], atom->v[i][2]};
    const int itype = atom->type[i], imask = atom->mask[i];
    const tagint image = atom->image[i];

    records.push_back((double)update->ntimestep);
    records.push_back(current_time());
    records.push_back((double)tag_i);
    records.push_back(2.0 * r);
    records.push_back(xp[0]); records.push_back(xp[1]); records.push_back(xp[2]);
    records.push_back(cands[k].F_n);
    records.push_back(cands[k].F_lim);
    records.push_back((double)cands[k].partner);
    records.push_back(generation);
    if (energy_on_)
      for (int q = 0; q < kEventEnergy; q++) records.push_back(energy_local[kEventEnergy * k + q]);

    apollonian_fragments(r, frag_r, frag_off);
    event_rotation(seed_, (uint64_t)tag_i, R);
    const double m_parent = true_mass(i);
    // fragments take the parent's velocity, times the density-scaling factor
    // that keeps their momentum that of their true mass (crush_density_scale_kernel.h)
    const double v_factor = fragment_speed_factor(frag_r, kFragments, rho);
    vp[0] *= v_factor; vp[1] *= v_factor; vp[2] *= v_factor;
    double mass_kept = 0.0;
    for (int f = 0; f < kFragments; f++) {
      if (2.0 * frag_r[f] < d_frag_min_) continue;
      double off[3], xf[3];
      rotate(R, frag_off[f], off);
      xf[0] = xp[0] + off[0]; xf[1] = xp[1] + off[1]; xf[2] = xp[2] + off[2];
      atom->avec->create_atom(itype, xf);
      const int m = atom->nlocal - 1;
      atom->tag[m] = new_tag++;
      atom->mask[m] = imask;
      atom->image[m] = image;
      atom->v[m][0] = vp[0]; atom->v[m][1] = vp[1]; atom->v[m][2] = vp[2];
      if (atom->omega_flag) atom->omega[m][0] = atom->omega[m][1] = atom->omega[m][2] = 0.0;
      atom->radius[m] = frag_r[f];
      atom->density[m] = rho;
      const double m_true = sphere_mass(frag_r[f], rho);
      atom->rmass[m] = m_true * density_scale_factor(2.0 * frag_r[f], d_scale_ref_);
      mass_kept += m_true;
      for (int q = 0; q < modify->nfix; q++)
        if (modify->fix[q]->create_attribute) modify->fix[q]->set_arrays(m);
      crush_[m][1] = generation + 1.0;
      assign_strength(m);
      created_local += 1.0;
    }
    fines_local += m_parent - mass_kept;
    // fines of this break into the Br bins (the fragment masses as created)
    const double m1 = sphere_mass(r1 * r, rho);
    const double m2 = sphere_mass(r2 * r, rho);
    br_add_break_fines(fines_fractal_, 2.0 * r, m_parent, r1, r2, m1, m2, 2.0 * (r1 * r) >= d_frag_min_,
                       2.0 * (r2 * r) >= d_frag_min_, omega_, grid, &sums[3]);
  }

  // delete parents, highest index first so the remaining indices stay valid
  std::vector<int> del(parents);
  std::sort(del.begin(), del.end());
  for (int k = (int)del.size() - 1; k >= 0; k--) {
    atom->avec->copy(atom->nlocal - 1, del[k], 1);
    atom->nlocal--;
  }

  sums[0] = fines_local;
  sums[1] = created_local;
  sums[2] = (double)np_local;
  MPI_Allreduce(&sums[0], &sums_all[0], 3 + grid.n, MPI_DOUBLE, MPI_SUM, world);
  for (int b = 0; b < grid.n; b++) J_fines_[b] += sums_all[3 + b];
  fines_mass_ += sums_all[0];
  n_created_ += sums_all[1];
  n_events_ += sums_all[2];
  atom->natoms += (bigint)(sums_all[1] - sums_all[2]);
  natoms_counted_ += (bigint)(sums_all[1] - sums_all[2]);
  maxtag_ever_ = (int)next;
  if (atom->map_style) {
    atom->nghost = 0;
    atom->map_init();
    atom->map_set();
  }

  write_events(records, np_local);
}
