// SPDX-License-Identifier: GPL-2.0-or-later
/* ----------------------------------------------------------------------
   fix crush/particle: the breakage criterion (docs/model.md §2.1-2.3).
   Which particles can break (eligible), the strength each one draws
   (assign_strength), the limit force and overlap of a contact (F_lim,
   delta_lim: fix_crush_particle_criterion.h) and the material table and
   reading they use (init_criterion, called by FixCrushParticle::init).
   The formulas are the kernels crush_criterion_kernel.h and
   crush_strength_kernel.h. Also the utilisation F_n / F_lim of every
   particle, for compute crush/atom.
   Exercised by tests/integration/test_crush_single_grain.py (the limit of
   one grain between plates), test_crush_readings.py (the readings and
   scatter laws, utilisation), test_strength_draws.py (the drawn strengths).
------------------------------------------------------------------------- */

#include "fix_crush_particle.h"
#include "fix_crush_particle_criterion.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "atom.h"
#include "comm.h"
#include "crush_breakage_kernel.h"
#include "crush_criterion_kernel.h"
#include "crush_strength_kernel.h"
#include "crush_wall_contacts.h"
#include "fix_property_global.h"
#include "modify.h"
#include "neigh_list.h"
#include "neighbor.h"
#include "pair.h"
#include "properties.h"

using namespace LAMMPS_NS;
using namespace FixConst;
using namespace CrushKernels;

/* ---------------------------------------------------------------------- */

// The material table (E* per pair of particle and wall types) and the
// reading's factor on F_lim per type pair, from the deck's material
// properties; the reading is logged when it is not the printed one.
void FixCrushParticle::init_criterion()
{
  // material table for particles and walls
  ntypes_mat_ = atom->get_properties()->max_type();
  FixPropertyGlobal *Y = static_cast<FixPropertyGlobal *>(
      modify->find_fix_property("youngsModulus", "property/global", "peratomtype", ntypes_mat_, 0, style));
  FixPropertyGlobal *nu = static_cast<FixPropertyGlobal *>(
      modify->find_fix_property("poissonsRatio", "property/global", "peratomtype", ntypes_mat_, 0, style));
  E_.assign(ntypes_mat_, 0.0);
  nu_.assign(ntypes_mat_, 0.0);
  E_star_.assign(ntypes_mat_ * ntypes_mat_, 0.0);
  overlap_coef_.assign(ntypes_mat_ * ntypes_mat_, 0.0);
  for (int t = 0; t < ntypes_mat_; t++) {
    E_[t] = Y->compute_vector(t);
    nu_[t] = nu->compute_vector(t);
  }
  // the reading's factor on F_lim per type pair (friction for 'force sliding')
  limit_factor_.assign(ntypes_mat_ * ntypes_mat_, pressure_limit_factor(pressure_));
  if (force_ == FORCE_SLIDING) {
    FixPropertyGlobal *mu = static_cast<FixPropertyGlobal *>(modify->find_fix_property(
        "coefficientFriction", "property/global", "peratomtypepair", ntypes_mat_, ntypes_mat_, style));
    for (int a = 0; a < ntypes_mat_; a++)
      for (int b = 0; b < ntypes_mat_; b++)
        limit_factor_[a * ntypes_mat_ + b] *= force_limit_factor(FORCE_SLIDING, mu->compute_array(a, b));
  }
  for (int a = 0; a < ntypes_mat_; a++)
    for (int b = 0; b < ntypes_mat_; b++) {
      const int ab = a * ntypes_mat_ + b;
      E_star_[ab] = effective_modulus(E_[a], nu_[a], E_[b], nu_[b]);
      overlap_coef_[ab] = limit_overlap_coefficient(E_star_[ab]) * limit_overlap_factor(limit_factor_[ab]);
    }
  if (comm->me == 0 && (pressure_ != PRESSURE_MEAN || force_ != FORCE_NORMAL || size_law_ != SIZE_PRINTED ||
                        scatter_ != SCATTER_NORMAL)) {
    char line[512];
    snprintf(line, sizeof(line),
             "fix crush/particle: criterion reading: pressure %s, force %s, size_law %s, scatter %s "
             "(f_min %g, Weibull shape %g); F_lim of grain-grain contacts (type 1) x %g of the printed reading\n",
             pressure_ == PRESSURE_PEAK ? "peak" : "mean", force_ == FORCE_SLIDING ? "sliding" : "normal",
             size_law_ == SIZE_NO_N ? "no_N" : "printed",
             scatter_ == SCATTER_WEIBULL ? "weibull" : (scatter_ == SCATTER_TRUNCATED ? "truncated" : "normal"),
             f_min_, weibull_k_, limit_factor_[0]);
    if (screen) fputs(line, screen);
    if (logfile) fputs(line, logfile);
  }
}

/* ---------------------------------------------------------------------- */

void FixCrushParticle::assign_strength(int i)
{
  const double d = 2.0 * atom->radius[i];
  const double f = strength_factor_law(scatter_, seed_, (uint64_t)atom->tag[i], var_, f_min_, weibull_k_);
  crush_[i][0] = size_effect_strength(sigma_lim0_, f, d, size_law_scale(size_law_, scale_N_), d0_, m_);
}
void FixCrushParticle::assign_missing_strengths()
{
  const int nlocal = atom->nlocal;
  for (int i = 0; i < nlocal; i++)
    if (crush_[i][0] < 0.0) assign_strength(i);
}

/* ----------------------------------------------------------------------
   Utilisation of every owned particle (compute crush/atom): the largest
   F_n / F_lim over its particle and wall contacts in the present positions,
   with the criterion reading of the fix (1 = at its limit). Particles that
   cannot break (below d_comm, outside the group) and particles without a
   contact get 0. Every contact is evaluated (no margin skip): this costs a
   full scan, and runs only when an output asks for it.
------------------------------------------------------------------------- */

void FixCrushParticle::utilisation(std::vector<double> *out)
{
  const int nlocal = atom->nlocal;
  std::vector<double> &u = *out;
  u.assign(nlocal, 0.0);
  double **x = atom->x;
  const double *radius = atom->radius;
  const int *type = atom->type;
  NeighList *list = pair_ ? pair_->list : NULL;
  if (list) {
    for (int ii = 0; ii < list->inum; ii++) {
      const int i = list->ilist[ii];
      const bool i_on = eligible(i);
      const int *jlist = list->firstneigh[i];
      for (int jj = 0; jj < list->numneigh[i]; jj++) {
        const int j = jlist[jj] & NEIGHMASK;
        const bool j_on = j < nlocal && eligible(j);
        if (!i_on && !j_on) continue;
        const double dx = x[i][0] - x[j][0], dy = x[i][1] - x[j][1], dz = x[i][2] - x[j][2];
        const double radsum = radius[i] + radius[j];
        const double rsq = dx * dx + dy * dy + dz * dz;
        if (rsq >= radsum * radsum) continue;
        const double R_star = effective_radius(radius[i], radius[j]);
        const double F_n = hertz_normal_force(radsum - sqrt(rsq), R_star, E_star(type[i], type[j]));
        if (i_on) u[i] = std::max(u[i], F_n / F_lim(i, R_star, type[i], type[j]));
        if (j_on) u[j] = std::max(u[j], F_n / F_lim(j, R_star, type[j], type[i]));
      }
    }
  }
  for_each_wall_neighbour(
      walls_, atom, [&](int i) { return eligible(i); },
      [&](int i, int, int, int, int wtype, double deltan) {
        if (!(deltan < 0.0)) return;
        const double F_n = hertz_normal_force(-deltan, radius[i], E_star(type[i], wtype));
        u[i] = std::max(u[i], F_n / F_lim(i, radius[i], type[i], wtype));
      });
}
