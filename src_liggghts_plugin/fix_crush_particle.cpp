// SPDX-License-Identifier: GPL-2.0-or-later
/* ----------------------------------------------------------------------
   fix crush/particle: crushable grains (docs/model.md §2). This file holds
   the fix itself: construction, the hooks LIGGGHTS calls in a time step
   and the order in which they use the parts, each in its own file (the map
   is in fix_crush_particle.h). The model math lives in crush_*_kernel.h.

   One step: end_of_step -> detect (the contact scan of
   fix_crush_particle_screening.cpp finds the candidates and starts their
   count over ranks) -> post_integrate of the next step collects the count
   -> pre_exchange -> break_particles (fix_crush_particle_break.cpp), on
   the neighbour-list build that count asked for.
   Exercised by every crush test in tests/integration (test_crush_*.py).
------------------------------------------------------------------------- */

#include "fix_crush_particle.h"

#include <algorithm>
#include <cstring>

#include "atom.h"
#include "comm.h"
#include "crush_breakage_index_kernel.h"
#include "crush_breakage_kernel.h"
#include "crush_criterion_kernel.h"
#include "crush_energy.h"
#include "crush_fragment_kernel.h"
#include "crush_strength_kernel.h"
#include "error.h"
#include "fix_wall_gran.h"
#include "force.h"
#include "memory.h"
#include "modify.h"
#include "pair.h"
#include "update.h"

using namespace LAMMPS_NS;
using namespace FixConst;
using namespace CrushKernels;

/* ---------------------------------------------------------------------- */

FixCrushParticle::FixCrushParticle(LAMMPS *lmp, int narg, char **arg) :
  Fix(lmp, narg, arg),
  sigma_lim0_(-1), m_(-1), d0_(-1), scale_N_(-1), var_(-1), d_comm_(-1), seed_(0),
  d_max_(-1), d_min_(-1), omega_(2.6), fines_fractal_(true), d_frag_min_(0.0),
  d_scale_ref_(0.0), pressure_(PRESSURE_MEAN), force_(FORCE_NORMAL), size_law_(SIZE_PRINTED),
  scatter_(SCATTER_NORMAL), f_min_(0.0), weibull_k_(0.0), dt_check_error_(false), dt_frac_(0.2), dt_omega_(1.0), events_file_(NULL), events_append_(false), events_(NULL),
  crush_(NULL), ntypes_mat_(0), pair_(NULL),
  count_pending_(false), count_local_(0), count_all_(0),
  margin_skip_(true), full_scan_pending_(true), scanned_since_full_(0.0),
  lists_scanned_(0.0), lists_total_(0.0), last_scan_full_(true), wall_scan_(0), wall_full_scan_(0),
  walls_D2_(0.0),
  n_events_(0), n_created_(0), fines_mass_(0), mass0_(0), integral0_(0),
  initialized_(false), maxtag_ever_(0), natoms_counted_(0), time_offset_(0.0), restart_time_(0.0),
  restart_time_pending_(false), cache_step_(-1),
  energy_(NULL), energy_on_(false), energy_budget_(false), energy_window_(50), nall_at_borders_(-1)
{
  std::fill(energy_sums_, energy_sums_ + 5, 0.0);
  if (!atom->radius_flag || !atom->rmass_flag)
    error->all(FLERR, "fix crush/particle needs per-atom radius and mass: use atom_style granular (sphere)");
  if (!atom->tag_enable)
    error->all(FLERR, "fix crush/particle needs atom IDs (atom_modify id yes)");

  parse_args(narg, arg);

  // A break whose fragments all go to fines lowers the atom count, which
  // stock LIGGGHTS' `thermo_modify lost error` takes for lost atoms (it
  // compares the count with that of the previous thermo output). The large
  // fragments of every breakable grain (d >= d_comm) are kept, and every
  // break adds atoms, exactly when d_frag_min <= 0.414 d_comm.
  if (d_frag_min_ > large_fragment_ratio() * d_comm_ && comm->me == 0) {
    char msg[1024];
    snprintf(msg, sizeof(msg),
             "fix crush/particle: d_frag_min %g > 0.414 d_comm = %g: grains finer than "
             "d_frag_min/0.414 = %g break entirely into fines and the atom count drops, which "
             "`thermo_modify lost error` reports as 'Lost atoms'; run such a deck with "
             "`thermo_modify lost ignore` (this fix still stops the run when a grain is lost) "
             "or keep d_frag_min <= 0.414 d_comm",
             d_frag_min_, large_fragment_ratio() * d_comm_, d_frag_min_ / large_fragment_ratio());
    error->warning(FLERR, msg);
  }

  restart_global = 1;
  restart_peratom = 1;
  create_attribute = 1;
  force_reneighbor = 1;
  next_reneighbor = -1;
  peratom_flag = 1;
  size_peratom_cols = 2;
  peratom_freq = 1;
  vector_flag = 1;
  size_vector = 15;
  global_freq = 1;
  extvector = 0;

  grow_arrays(atom->nmax);
  atom->add_callback(0);
  atom->add_callback(1);
  for (int i = 0; i < atom->nlocal; i++) set_arrays(i);

  open_event_log();
}

/* ---------------------------------------------------------------------- */

FixCrushParticle::~FixCrushParticle()
{
  finish_count();
  // events still inside their window: written with the steps watched so far
  if (energy_) {
    for (size_t k = 0; k < energy_->open_events().size(); k++) energy_->closed().push_back(energy_->open_events()[k]);
    energy_write_closed();
    delete energy_;
  }
  atom->delete_callback(id, 0);
  atom->delete_callback(id, 1);
  memory->destroy(crush_);
  delete[] events_file_;
  if (events_) fclose(events_);
}

/* ---------------------------------------------------------------------- */

int FixCrushParticle::setmask()
{
  int mask = 0;
  mask |= PRE_EXCHANGE;
  mask |= PRE_NEIGHBOR;
  mask |= END_OF_STEP;
  mask |= POST_INTEGRATE;
  if (energy_budget_) mask |= PRE_FORCE | POST_FORCE;
  return mask;
}

/* ---------------------------------------------------------------------- */

void FixCrushParticle::init()
{
  if (force->newton_pair)
    error->all(FLERR, "fix crush/particle requires 'newton off' (each rank tests the contacts of its own particles)");

  pair_ = force->pair_match("gran", 0);
  if (!pair_)
    error->all(FLERR, "fix crush/particle needs a granular pair style (pair_style gran ...)");

  init_criterion();

  walls_.clear();
  for (int k = 0; k < modify->nfix; k++)
    if (strncmp(modify->fix[k]->style, "wall/gran", 9) == 0)
      walls_.push_back(static_cast<FixWallGran *>(modify->fix[k]));

  if (energy_on_) init_energy();

  candidate_slot_.clear();
  candidates_.clear();
  cache_step_ = -1;
  full_scan_pending_ = true;
}

void FixCrushParticle::setup_pre_neighbor()
{
  check_atom_count();
  assign_missing_strengths();
  full_scan_pending_ = true;
  nall_at_borders_ = atom->nlocal + atom->nghost;
}
void FixCrushParticle::pre_neighbor()
{
  check_atom_count();
  assign_missing_strengths();
  full_scan_pending_ = true;
  nall_at_borders_ = atom->nlocal + atom->nghost;
}

/* ---------------------------------------------------------------------- */

void FixCrushParticle::setup(int)
{
  if (restart_time_pending_) {
    time_offset_ = restart_time_ - update->get_cur_time();
    restart_time_pending_ = false;
  }
  assign_missing_strengths();
  if (!initialized_) take_initial_grading();
  int maxtag_local = 0, maxtag_all;
  for (int i = 0; i < atom->nlocal; i++) maxtag_local = std::max(maxtag_local, atom->tag[i]);
  MPI_Allreduce(&maxtag_local, &maxtag_all, 1, MPI_INT, MPI_MAX, world);
  maxtag_ever_ = std::max(maxtag_ever_, maxtag_all);
  count_atoms();  // losses are looked for from here on (see check_atom_count)
  check_timestep();
  // Contacts over the limit at the end of the previous run (or in the state
  // read from a restart file) break at the first step, as in one long run.
  detect(true);
  cache_step_ = -1;
}

void FixCrushParticle::end_of_step()
{
  if (energy_ && energy_->watching()) energy_observe();
  detect(false);
}

/* ----------------------------------------------------------------------
   Find the contacts over their limit. Every rank must agree on whether the
   next step rebuilds neighbour lists (to break particles), so the candidate
   count is summed over ranks. In the time loop that sum is started here
   without waiting (MPI_Iallreduce) and collected in post_integrate of the
   next step, just before Neighbor::decide: the ranks then meet only at the
   forward communication they meet at anyway. At setup it is summed at once.
------------------------------------------------------------------------- */

void FixCrushParticle::detect(bool blocking)
{
  finish_count();
  clear_candidates();

  find_candidates_pairs();
  find_candidates_walls();

  count_local_ = (int)candidates_.size();
  if (blocking) {
    MPI_Allreduce(&count_local_, &count_all_, 1, MPI_INT, MPI_SUM, world);
    next_reneighbor = (count_all_ > 0) ? update->ntimestep + 1 : -1;
  } else {
    MPI_Iallreduce(&count_local_, &count_all_, 1, MPI_INT, MPI_SUM, world, &count_request_);
    count_pending_ = true;
    next_reneighbor = -1;
  }
}

// Collect the candidate count summed in the previous step (see detect).
void FixCrushParticle::post_integrate()
{
  if (!count_pending_) return;
  finish_count();
  next_reneighbor = (count_all_ > 0) ? update->ntimestep : -1;
}

void FixCrushParticle::finish_count()
{
  if (!count_pending_) return;
  MPI_Wait(&count_request_, MPI_STATUS_IGNORE);
  count_pending_ = false;
}

/* ---------------------------------------------------------------------- */

void FixCrushParticle::pre_exchange()
{
  if (next_reneighbor != update->ntimestep) return;
  break_particles();
  next_reneighbor = -1;
  cache_step_ = -1;
}

// Simulation time, continuous across restart files.
double FixCrushParticle::current_time() const
{
  return update->get_cur_time() + time_offset_;
}
