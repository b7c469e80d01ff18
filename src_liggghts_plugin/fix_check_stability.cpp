// SPDX-License-Identifier: GPL-2.0-or-later
/* ----------------------------------------------------------------------
   fix check/stability: see the header and docs/fix_check_stability.md.
   The tests are crush_stability_kernel.h (unit-tested).
------------------------------------------------------------------------- */

#include "fix_check_stability.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "atom.h"
#include "comm.h"
#include "crush_args.h"
#include "crush_breakage_kernel.h"
#include "crush_stability_kernel.h"
#include "error.h"
#include "fix_property_global.h"
#include "force.h"
#include "modify.h"
#include "neigh_list.h"
#include "pair.h"
#include "properties.h"
#include "update.h"

using namespace LAMMPS_NS;
using namespace FixConst;
using namespace CrushKernels;


/* ---------------------------------------------------------------------- */

FixCheckStability::FixCheckStability(LAMMPS *lmp, int narg, char **arg) :
  Fix(lmp, narg, arg), move_frac_(0.1), overlap_frac_(1.5), overlap_every_(100), pair_(NULL),
  max_move_seen_(0.0), max_overlap_seen_(0.0)
{
  if (!atom->radius_flag || !atom->rmass_flag)
    error->all(FLERR, "fix check/stability needs per-atom radius and mass: use atom_style granular (sphere)");
  // fix ID group check/stability [every N] [move F] [overlap F] [overlap_every N]
  nevery = 1;
  CrushArgs a(error, "fix check/stability", narg, arg, 3, {"every", "move", "overlap", "overlap_every"});
  while (a.next()) {
    if (a.is("every")) nevery = (int)a.integer(1, 1000000000, "an integer >= 1 (steps)");
    else if (a.is("move")) move_frac_ = a.number(arg_non_negative("fraction of the radius; 0 = off"));
    else if (a.is("overlap")) overlap_frac_ = a.number(arg_non_negative("fraction of the smaller radius; 0 = off"));
    else if (a.is("overlap_every")) overlap_every_ = (int)a.integer(1, 1000000000, "an integer >= 1 (steps)");
  }
  if (overlap_every_ % nevery != 0)
    a.fail("keyword 'overlap_every' must be a multiple of 'every' (steps), got " +
           std::to_string(overlap_every_) + " and " + std::to_string(nevery));
  vector_flag = 1;
  size_vector = 2;
  global_freq = 1;
  extvector = 0;
}

int FixCheckStability::setmask()
{
  return END_OF_STEP;
}

void FixCheckStability::init()
{
  pair_ = force->pair_match("gran", 0);
  if (overlap_frac_ > 0.0 && !pair_)
    error->all(FLERR, "fix check/stability: keyword 'overlap' needs a granular pair style (pair_style gran ...); use 'overlap 0' without one");
  // materials, for the Rayleigh time of a particle named in an error
  const int nt = atom->get_properties()->max_type();
  FixPropertyGlobal *Y = static_cast<FixPropertyGlobal *>(
      modify->find_fix_property("youngsModulus", "property/global", "peratomtype", nt, 0, style, false));
  FixPropertyGlobal *nu = static_cast<FixPropertyGlobal *>(
      modify->find_fix_property("poissonsRatio", "property/global", "peratomtype", nt, 0, style, false));
  E_.assign(nt + 1, 0.0);
  nu_.assign(nt + 1, 0.0);
  if (Y && nu)
    for (int t = 1; t <= nt; t++) { E_[t] = Y->compute_vector(t - 1); nu_[t] = nu->compute_vector(t - 1); }
}

/* ----------------------------------------------------------------------
   At the start of every run both signals, so that particles inserted
   overlapping stop the run before its first step.
------------------------------------------------------------------------- */

void FixCheckStability::setup(int)
{
  max_move_seen_ = 0.0;
  max_overlap_seen_ = 0.0;
  check_overlaps();
  check_moves();
}

void FixCheckStability::end_of_step()
{
  check_moves();
  if (update->ntimestep % overlap_every_ == 0) check_overlaps();
}

/* ----------------------------------------------------------------------
   Signal (a): |v| dt > move_frac r. One pass over the owned particles with a
   multiply-add and a comparison each; the division happens only when the
   step's maximum grows. One MPI_Allreduce of one number per check.
------------------------------------------------------------------------- */

void FixCheckStability::check_moves()
{
  if (!(move_frac_ > 0.0)) return;
  const double dt2 = update->dt * update->dt;
  double **v = atom->v;
  const double *radius = atom->radius;
  const int *mask = atom->mask;
  const int nlocal = atom->nlocal;
  double q_max = 0.0;  // largest (|v| dt / r)^2 this step
  int i_max = -1;
  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    const double s2 = (v[i][0] * v[i][0] + v[i][1] * v[i][1] + v[i][2] * v[i][2]) * dt2;
    const double r2 = radius[i] * radius[i];
    if (s2 > q_max * r2 && r2 > 0.0) { q_max = s2 / r2; i_max = i; }
  }
  double q_all;
  MPI_Allreduce(&q_max, &q_all, 1, MPI_DOUBLE, MPI_MAX, world);
  max_move_seen_ = std::max(max_move_seen_, std::sqrt(q_all));
  if (!(q_all > move_frac_ * move_frac_)) return;
  Culprit c;
  memset(&c, 0, sizeof(c));
  c.ratio = -1.0;
  if (i_max >= 0) {
    c.ratio = std::sqrt(q_max) / move_frac_;
    c.tag = atom->tag[i_max]; c.type = atom->type[i_max]; c.radius = radius[i_max];
    c.mass = atom->rmass[i_max]; c.density = atom->density ? atom->density[i_max] : 0.0;
    for (int k = 0; k < 3; k++) { c.x[k] = atom->x[i_max][k]; c.v[k] = v[i_max][k]; }
    c.partner_tag = -1;
  }
  stop(c, "move");
}

/* ----------------------------------------------------------------------
   Signal (b): delta > overlap_frac min(r_i, r_j) over the pair list of the
   granular pair style (pairs between owned particles and their neighbours,
   ghosts included). No square root (crush_stability_kernel.h).
------------------------------------------------------------------------- */

void FixCheckStability::check_overlaps()
{
  if (!(overlap_frac_ > 0.0) || !pair_ || !pair_->list) return;
  NeighList *list = pair_->list;
  double **x = atom->x;
  const double *radius = atom->radius;
  const int *mask = atom->mask;
  const int nall = atom->nlocal + atom->nghost;
  double worst = 0.0;  // largest delta / r_min among pairs over the limit
  int iw = -1, jw = -1;
  double d_max = 0.0;  // largest delta / r_min of all contacts (output [2])
  for (int ii = 0; ii < list->inum; ii++) {
    const int i = list->ilist[ii];
    if (!(mask[i] & groupbit)) continue;
    const int *jlist = list->firstneigh[i];
    const int jnum = list->numneigh[i];
    for (int jj = 0; jj < jnum; jj++) {
      const int j = jlist[jj] & NEIGHMASK;
      if (j >= nall) continue;
      const double dx = x[i][0] - x[j][0], dy = x[i][1] - x[j][1], dz = x[i][2] - x[j][2];
      const double rsq = dx * dx + dy * dy + dz * dz;
      const double radsum = radius[i] + radius[j];
      if (rsq >= radsum * radsum) continue;  // not in contact
      // contacts only: the square root is paid for overlapping pairs
      const double r_min = std::min(radius[i], radius[j]);
      const double f = (radsum - std::sqrt(rsq)) / r_min;
      d_max = std::max(d_max, f);
      if (overlap_too_deep(rsq, radius[i], radius[j], overlap_frac_) && f > worst) {
        worst = f; iw = i; jw = j;
      }
    }
  }
  double g[2] = {d_max, worst}, gall[2];
  MPI_Allreduce(g, gall, 2, MPI_DOUBLE, MPI_MAX, world);
  max_overlap_seen_ = std::max(max_overlap_seen_, gall[0]);
  if (!(gall[1] > 0.0)) return;
  Culprit c;
  memset(&c, 0, sizeof(c));
  c.ratio = -1.0;
  if (iw >= 0) {
    c.ratio = worst / overlap_frac_;
    // name the smaller particle of the pair (the one the fraction refers to)
    const int p = (radius[jw] < radius[iw]) ? jw : iw, q = (p == iw) ? jw : iw;
    c.tag = atom->tag[p]; c.type = atom->type[p]; c.radius = radius[p];
    c.mass = atom->rmass[p]; c.density = atom->density ? atom->density[p] : 0.0;
    for (int k = 0; k < 3; k++) { c.x[k] = x[p][k]; c.v[k] = atom->v[p][k]; }
    c.partner_tag = atom->tag[q];
    c.partner_radius = radius[q];
  }
  stop(c, "overlap");
}

/* ----------------------------------------------------------------------
   The rank that holds the worst particle sends it to all; every rank stops
   with the same error (error->all writes it to the screen and the log).
------------------------------------------------------------------------- */

void FixCheckStability::stop(const Culprit &local, const char *signal)
{
  struct { double v; int rank; } in, out;
  in.v = local.ratio;
  in.rank = comm->me;
  MPI_Allreduce(&in, &out, 1, MPI_DOUBLE_INT, MPI_MAXLOC, world);
  Culprit c = local;
  MPI_Bcast(&c, (int)(sizeof(Culprit) / sizeof(double)), MPI_DOUBLE, out.rank, world);
  const bool overlap = strcmp(signal, "overlap") == 0;
  const double speed = std::sqrt(c.v[0] * c.v[0] + c.v[1] * c.v[1] + c.v[2] * c.v[2]);
  char what[512];
  if (overlap)
    snprintf(what, sizeof(what),
             "overlaps particle %.0f (radius %g) by %g of its radius (limit overlap %g)",
             c.partner_tag, c.partner_radius, c.ratio * overlap_frac_, overlap_frac_);
  else
    snprintf(what, sizeof(what), "moves %g of its radius in one step, |v| dt = %g (limit move %g)",
             c.ratio * move_frac_, speed * update->dt, move_frac_);
  char msg[2048];
  snprintf(msg, sizeof(msg),
           "fix check/stability: unstable at step " BIGINT_FORMAT ", signal '%s': particle %.0f "
           "(type %.0f, radius %g, mass %g) at (%g, %g, %g), speed %g: %s; likely cause: %s",
           update->ntimestep, signal, c.tag, c.type, c.radius, c.mass, c.x[0], c.x[1], c.x[2], speed,
           what, likely_cause(c, overlap).c_str());
  error->all(FLERR, msg);
}

std::string FixCheckStability::likely_cause(const Culprit &c, bool overlap) const
{
  if (overlap)
    return "particles inserted or created overlapping (create_atoms, insertion, read_data), or a "
           "contact driven far past any breakage limit by a time step too large for the stiffest "
           "contact; no contact law pushes a stable pair this deep";
  // the particle's own Rayleigh time with the mass it has (density scaling included)
  const int t = (int)c.type;
  std::string s;
  char buf[512];
  if (t >= 1 && t < (int)E_.size() && E_[t] > 0.0 && c.radius > 0.0) {
    const double V = 4.0 / 3.0 * kPi * c.radius * c.radius * c.radius;
    const double rho_eff = c.mass / V;
    const double T_R = rayleigh_time(c.radius, rho_eff, shear_modulus(E_[t], nu_[t]), nu_[t]);
    const double ratio = update->dt / T_R;
    const double scale = (c.density > 0.0) ? rho_eff / c.density : 1.0;
    if (ratio > 0.2) {
      snprintf(buf, sizeof(buf),
               "the time step is too large for this particle: dt / T_R = %g with its Rayleigh time "
               "T_R = %g (radius and mass as they are; mass scaled by %g)%s", ratio, T_R, scale,
               (scale <= 1.0 + 1e-12) ? "; density scaling of fine particles is off (fix "
                                        "crush/particle density_scale) or does not reach this size"
                                      : "");
      return buf;
    }
    snprintf(buf, sizeof(buf), "this particle's dt / T_R = %g is not above 0.2, so ", ratio);
    s = buf;
  }
  return s + "the time step is too large for its stiffest contact (steel, a pile or a "
             "fragment: see the 'stiffest contact' lines of fix crush/particle in the log), or it "
             "was pushed out of a deep overlap (inserted overlapping, or a break releasing the "
             "energy stored in its contacts into light fragments)";
}

/* ---------------------------------------------------------------------- */

double FixCheckStability::compute_vector(int n)
{
  // [0] largest |v| dt / r, [1] largest delta / r_min at the overlap scans,
  // both since the start of the run, over all ranks (already reduced)
  return (n == 0) ? max_move_seen_ : max_overlap_seen_;
}
