// SPDX-License-Identifier: GPL-2.0-or-later
/* ----------------------------------------------------------------------
   fix damp/local: PFC-style local damping (docs/model.md §2.3).
------------------------------------------------------------------------- */

#include "fix_damp_local.h"

#include <cstdlib>
#include <cstring>
#include <string>

#include "atom.h"
#include "crush_args.h"
#include "crush_damping_kernel.h"
#include "error.h"
#include "force.h"
#include "modify.h"
#include "update.h"

using namespace LAMMPS_NS;
using namespace FixConst;

/* ---------------------------------------------------------------------- */

FixDampLocal::FixDampLocal(LAMMPS *lmp, int narg, char **arg) :
  Fix(lmp, narg, arg),
  alpha_(-1.0), energy_(false), dissipated_(0.0)
{
  // fix ID group damp/local alpha A [energy yes/no]
  CrushArgs a(error, "fix damp/local", narg, arg, 3, {"alpha", "energy"});
  while (a.next()) {
    if (a.is("alpha"))
      alpha_ = a.number(CrushKernels::arg_range(0.0, true, 1.0, false, "in [0, 1)"));
    else if (a.is("energy"))
      energy_ = a.yes_no();
  }
  if (!a.given("alpha"))
    a.fail("missing required keyword 'alpha' (the local damping coefficient, a number in [0, 1))");
  if (energy_) {
    scalar_flag = 1;
    global_freq = 1;
    extscalar = 1;
  }
}

/* ---------------------------------------------------------------------- */

int FixDampLocal::setmask()
{
  int mask = 0;
  mask |= POST_FORCE;
  mask |= MIN_POST_FORCE;
  return mask;
}

/* ---------------------------------------------------------------------- */

void FixDampLocal::init()
{
  if (strstr(update->integrate_style, "respa"))
    error->all(FLERR, "fix damp/local does not support run_style respa");

  // Damping acts on the unbalanced force, so every fix that adds force must
  // run first: post_force hooks run in the order the fixes were defined.
  int me = -1;
  for (int i = 0; i < modify->nfix; i++)
    if (modify->fix[i] == this) me = i;
  for (int i = me + 1; i < modify->nfix; i++) {
    const char *style = modify->fix[i]->style;
    // fixes known not to add force
    if (strcmp(style, "damp/local") == 0 || strcmp(style, "crush/particle") == 0) continue;
    if (modify->fmask[i] & POST_FORCE) {
      std::string msg = std::string("fix damp/local: fix '") + modify->fix[i]->id +
                        "' (" + modify->fix[i]->style +
                        ") is defined after it and may add force that will not be damped; "
                        "define fix damp/local after all force fixes";
      error->warning(FLERR, msg.c_str());
    }
  }
}

/* ---------------------------------------------------------------------- */

void FixDampLocal::setup(int vflag)
{
  post_force(vflag);
}

void FixDampLocal::min_setup(int vflag)
{
  post_force(vflag);
}

/* ---------------------------------------------------------------------- */

void FixDampLocal::post_force(int)
{
  double **v = atom->v;
  double **f = atom->f;
  const int *mask = atom->mask;
  const int nlocal = atom->nlocal;
  // energy: only in the time loop (not at set-up or in a minimisation)
  const bool count = energy_ && !update->setupflag && update->whichflag == 1;
  double removed = 0.0;

  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    for (int c = 0; c < 3; c++) {
      const double fd = CrushKernels::local_damping_force(f[i][c], v[i][c], alpha_);
      if (count) removed -= (fd - f[i][c]) * v[i][c];
      f[i][c] = fd;
    }
  }
  if (count) dissipated_ += removed * update->dt;
}

double FixDampLocal::compute_scalar()
{
  double all = 0.0;
  MPI_Allreduce(&dissipated_, &all, 1, MPI_DOUBLE, MPI_SUM, world);
  return all;
}

void FixDampLocal::min_post_force(int vflag)
{
  post_force(vflag);
}
