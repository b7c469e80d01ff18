// SPDX-License-Identifier: GPL-2.0-or-later
/* ----------------------------------------------------------------------
   compute crush/atom: per-particle state of fix crush/particle. See the
   header and docs/compute_crush_atom.md.
------------------------------------------------------------------------- */

#include "compute_crush_atom.h"

#include <cstring>

#include "atom.h"
#include "error.h"
#include "fix_crush_particle.h"
#include "memory.h"
#include "modify.h"
#include "update.h"

using namespace LAMMPS_NS;

namespace {
const int kColumns = 4;  // sigma_lim, generation, true mass, utilisation
}

ComputeCrushAtom::ComputeCrushAtom(LAMMPS *lmp, int &iarg, int narg, char **arg) :
  Compute(lmp, iarg, narg, arg), fix_(NULL), nmax_(0), out_(NULL)
{
  // compute ID group crush/atom FIX_ID
  if (narg != iarg + 1)
    error->all(FLERR, "compute crush/atom: expected one argument, the ID of a fix crush/particle "
                      "(compute ID group crush/atom FIX_ID)");
  fix_id_ = arg[iarg];
  iarg = narg;
  peratom_flag = 1;
  size_peratom_cols = kColumns;
}

ComputeCrushAtom::~ComputeCrushAtom() { memory->destroy(out_); }

void ComputeCrushAtom::init()
{
  const int ifix = modify->find_fix(fix_id_.c_str());
  if (ifix < 0)
    error->all(FLERR, ("compute crush/atom: no fix with ID '" + fix_id_ + "'").c_str());
  if (strcmp(modify->fix[ifix]->style, "crush/particle") != 0)
    error->all(FLERR, ("compute crush/atom: fix '" + fix_id_ + "' is not a fix crush/particle").c_str());
  fix_ = static_cast<FixCrushParticle *>(modify->fix[ifix]);
}

void ComputeCrushAtom::compute_peratom()
{
  invoked_peratom = update->ntimestep;
  if (atom->nmax > nmax_) {
    memory->destroy(out_);
    nmax_ = atom->nmax;
    memory->create(out_, nmax_, kColumns, "crush/atom:out");
    array_atom = out_;
  }
  const int nlocal = atom->nlocal;
  fix_->utilisation(&u_);
  for (int i = 0; i < nlocal; i++) {
    if (!(atom->mask[i] & groupbit)) {
      for (int c = 0; c < kColumns; c++) out_[i][c] = 0.0;
      continue;
    }
    out_[i][0] = fix_->strength(i);
    out_[i][1] = fix_->generation(i);
    out_[i][2] = fix_->true_mass(i);
    out_[i][3] = u_[i];
  }
}

double ComputeCrushAtom::memory_usage() { return (double)nmax_ * kColumns * sizeof(double); }
