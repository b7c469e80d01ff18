// SPDX-License-Identifier: GPL-2.0-or-later
/* ----------------------------------------------------------------------
   compute stress/grain: per-particle stress over every contact (docs/model.md
   §4.7). See the header and docs/compute_stress_grain.md.

   The forces are LIGGGHTS' own: compute pair/gran/local and compute
   wall/gran/local evaluate every contact again from the current positions
   and contact histories without adding the forces to the particles
   (PairGran::compute_pgl, FixWallGran::post_force_pgl). Evaluated at the end
   of a step (an output), positions, meshes and histories are those the
   step's forces were computed with, so these are the step's contact forces
   (velocity-dependent terms, i.e. viscous contact damping, would see the
   end-of-step velocities; the decks of this project have none).

   Contact points: pair/gran/local gives c = (r_j x_i + r_i x_j)/(r_i + r_j)
   on the line of centres (s^c = r_i/(r_i + r_j) times the branch vector),
   wall/gran/local the point of the mesh nearest to the centre.

   Parallel: compute pair/gran/local lists a pair whose partner is a ghost
   on one rank only (with newton off it keeps the pair on the rank of the
   particle with the larger tag), so each term is added to the copy of the
   particle at hand, owned or ghost, and the ghosts' sums are sent to their
   owners (reverse communication).
------------------------------------------------------------------------- */

#include "compute_stress_grain.h"

#include <cmath>
#include <cstring>

#include "atom.h"
#include "comm.h"
#include "compute_pair_gran_local.h"
#include "crush_args.h"
#include "domain.h"
#include "error.h"
#include "fix_wall_gran.h"
#include "group.h"
#include "memory.h"
#include "modify.h"
#include "update.h"

using namespace LAMMPS_NS;

/* ---------------------------------------------------------------------- */

ComputeStressGrain::ComputeStressGrain(LAMMPS *lmp, int &iarg, int narg, char **arg) :
  Compute(lmp, iarg, narg, arg),
  wall_none_(false), pair_(NULL), wall_(NULL), nmax_(0), sum_(NULL), out_(NULL)
{
  peratom_flag = 1;
  size_peratom_cols = 9;
  comm_reverse = 9;

  // compute ID group stress/grain [pair_local CID] [wall_local CID|none]
  CrushArgs a(error, "compute stress/grain", narg, arg, iarg, {"pair_local", "wall_local"});
  while (a.next()) {
    if (a.is("pair_local")) {
      pair_id_ = a.word("the ID of a compute pair/gran/local");
    } else {
      const std::string val = a.word("the ID of a compute wall/gran/local, or none");
      if (val == "none") wall_none_ = true;
      else wall_id_ = val;
    }
  }
  iarg = narg;
  if (!atom->radius_flag)
    error->all(FLERR, "compute stress/grain needs per-particle radii (atom_style granular)");
}

ComputeStressGrain::~ComputeStressGrain()
{
  memory->destroy(sum_);
  memory->destroy(out_);
}

/* ----------------------------------------------------------------------
   the deck's compute pair/gran/local or wall/gran/local: the one named, or
   the only one of its style (LIGGGHTS allows one per pair style or wall fix)
------------------------------------------------------------------------- */

ComputePairGranLocal *ComputeStressGrain::find_local(const char *key, const std::string &id,
                                                     bool wall)
{
  const char *style = wall ? "wall/gran/local" : "pair/gran/local";
  const char *needs = wall ? "pos id force" : "id force contactPoint";
  int ic = -1;
  if (id.empty()) {
    for (int k = 0; k < modify->ncompute; k++)
      if (strcmp(modify->compute[k]->style, style) == 0) ic = k;
    if (ic < 0)
      error->all(FLERR, ("compute stress/grain needs the contact forces of a compute " +
                         arg_text(style) + ": define 'compute CID all " + style + " " + needs +
                         "' before the first run (e.g. inputs/contacts_local.in)" +
                         (wall ? ", or give 'wall_local none' when the deck has no mesh walls"
                               : "")).c_str());
  } else {
    ic = modify->find_compute(id.c_str());
    if (ic < 0)
      error->all(FLERR, ("compute stress/grain: keyword '" + arg_text(key) +
                         "': no compute with ID '" +
                         id + "'").c_str());
  }
  Compute *c = modify->compute[ic];
  ComputePairGranLocal *p = dynamic_cast<ComputePairGranLocal *>(c);
  if (!p || strcmp(c->style, style) != 0)
    error->all(FLERR, ("compute stress/grain: keyword '" + arg_text(key) + "': compute '" +
                       arg_text(c->id) + "' (" + arg_text(c->style) + ") is not a compute " +
                       style).c_str());
  const bool ok = p->offset_id1() >= 0 && p->offset_f() >= 0 &&
                  (wall ? p->offset_x1() >= 0 : p->offset_contact_point() >= 0);
  if (!ok)
    error->all(FLERR, ("compute stress/grain: compute '" + arg_text(c->id) + "' must store " +
                       needs +
                       " (list these keywords in its compute command)").c_str());
  if (c->igroup != 0 && comm->me == 0)
    error->warning(FLERR, ("compute stress/grain: compute '" + arg_text(c->id) + "' has group '" +
                           arg_text(group->names[c->igroup]) + "', not 'all': contacts with "
                           "particles outside it are not counted").c_str());
  return p;
}

/* ---------------------------------------------------------------------- */

void ComputeStressGrain::init()
{
  if (atom->map_style == 0)
    error->all(FLERR, "compute stress/grain needs an atom map (atom_modify map array)");

  // walls: mesh walls through wall/gran/local; primitive walls (planes,
  // cylinders) have no contact list in LIGGGHTS, their forces would be lost
  bool mesh_wall = false;
  for (int k = 0; k < modify->nfix; k++) {
    FixWallGran *w = dynamic_cast<FixWallGran *>(modify->fix[k]);
    if (!w) continue;
    if (w->is_mesh_wall()) {
      mesh_wall = true;
    } else {
      error->all(FLERR, ("compute stress/grain: fix " + arg_text(modify->fix[k]->id) +
                         " is a primitive wall/gran (plane or cylinder), whose contacts "
                         "LIGGGHTS does not list, so its forces would be missing from the "
                         "stress; use a mesh wall (fix mesh/surface in the deck's mesh wall "
                         "fix) instead").c_str());
    }
  }
  pair_ = find_local("pair_local", pair_id_, false);
  wall_ = NULL;
  if (mesh_wall) {
    if (wall_none_)
      error->all(FLERR, "compute stress/grain: 'wall_local none', but the deck has a mesh wall "
                        "fix: its contacts would be missing; define 'compute CID all "
                        "wall/gran/local pos id force' before the first run and pass it");
    wall_ = find_local("wall_local", wall_id_, true);
  } else if (!wall_id_.empty()) {
    wall_ = find_local("wall_local", wall_id_, true);
  }
}

/* ---------------------------------------------------------------------- */

void ComputeStressGrain::add_term(int k, const double *s, const double *f)
{
  double *d = sum_[k];
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++) d[3 * a + b] += s[a] * f[b];
}

void ComputeStressGrain::compute_peratom()
{
  invoked_peratom = update->ntimestep;

  if (atom->nmax > nmax_) {
    memory->destroy(sum_);
    memory->destroy(out_);
    nmax_ = atom->nmax;
    memory->create(sum_, nmax_, 9, "stress/grain:sum");
    memory->create(out_, nmax_, 9, "stress/grain:out");
    array_atom = out_;
  }
  const int nlocal = atom->nlocal;
  const int nall = nlocal + atom->nghost;
  for (int k = 0; k < nall; k++)
    for (int c = 0; c < 9; c++) sum_[k][c] = 0.0;

  double **x = atom->x;
  double s[3], f[3];

  // particle-particle: force on the first particle, minus that on the second
  pair_->compute_local();
  {
    double **a = pair_->array_local;
    const int rows = pair_->size_local_rows;
    const int oid = pair_->offset_id1(), of = pair_->offset_f(),
              ocp = pair_->offset_contact_point();
    for (int r = 0; r < rows; r++) {
      const double *row = a[r];
      const int i = atom->map(static_cast<int>(lround(row[oid])));
      const int j = atom->map(static_cast<int>(lround(row[oid + 1])));
      if (i < 0 || j < 0)
        error->one(FLERR, "compute stress/grain: a particle of a contact is not known on its "
                          "rank (internal error)");
      for (int d = 0; d < 3; d++) {
        f[d] = row[of + d];
        s[d] = row[ocp + d] - x[i][d];
      }
      domain->minimum_image(s);
      add_term(i, s, f);
      for (int d = 0; d < 3; d++) {
        f[d] = -f[d];
        s[d] = row[ocp + d] - x[j][d];
      }
      domain->minimum_image(s);
      add_term(j, s, f);
    }
  }

  // particle-mesh wall: id columns are (mesh, triangle, particle); pos starts
  // with the contact point on the mesh; the particle is owned
  if (wall_) {
    wall_->compute_local();
    double **a = wall_->array_local;
    const int rows = wall_->size_local_rows;
    const int oid = wall_->offset_id1(), of = wall_->offset_f(), ox = wall_->offset_x1();
    for (int r = 0; r < rows; r++) {
      const double *row = a[r];
      const int i = atom->map(static_cast<int>(lround(row[oid + 2])));
      if (i < 0)
        error->one(FLERR, "compute stress/grain: the particle of a wall contact is not known "
                          "on its rank (internal error)");
      for (int d = 0; d < 3; d++) {
        f[d] = row[of + d];
        s[d] = row[ox + d] - x[i][d];
      }
      domain->minimum_image(s);
      add_term(i, s, f);
    }
  }

  comm->reverse_comm_compute(this);

  const double *radius = atom->radius;
  const int *mask = atom->mask;
  for (int i = 0; i < nlocal; i++) {
    double *o = out_[i];
    if (!(mask[i] & groupbit) || radius[i] <= 0.0) {
      for (int c = 0; c < 9; c++) o[c] = 0.0;
      continue;
    }
    // compression positive: minus the sum over the particle volume
    const double w = -1.0 / (4.0 / 3.0 * M_PI * radius[i] * radius[i] * radius[i]);
    const double *t = sum_[i];   // t[3a+b] = sum s_a F_b
    o[0] = w * t[0];
    o[1] = w * t[4];
    o[2] = w * t[8];
    o[3] = 0.5 * w * (t[1] + t[3]);
    o[4] = 0.5 * w * (t[2] + t[6]);
    o[5] = 0.5 * w * (t[5] + t[7]);
    o[6] = 0.5 * w * (t[1] - t[3]);
    o[7] = 0.5 * w * (t[2] - t[6]);
    o[8] = 0.5 * w * (t[5] - t[7]);
  }
}

/* ---------------------------------------------------------------------- */

int ComputeStressGrain::pack_reverse_comm(int n, int first, double *buf)
{
  int m = 0;
  for (int i = first; i < first + n; i++)
    for (int c = 0; c < 9; c++) buf[m++] = sum_[i][c];
  return 9;
}

void ComputeStressGrain::unpack_reverse_comm(int n, int *list, double *buf)
{
  int m = 0;
  for (int i = 0; i < n; i++)
    for (int c = 0; c < 9; c++) sum_[list[i]][c] += buf[m++];
}

double ComputeStressGrain::memory_usage()
{
  return 2.0 * nmax_ * 9 * sizeof(double);
}
