// SPDX-License-Identifier: GPL-2.0-or-later
/* ----------------------------------------------------------------------
   fix crush/particle: crushable grains (docs/model.md §2). See the header and
   docs/fix_crush_particle.md. The model math lives in crush_*_kernel.h.
------------------------------------------------------------------------- */

#include "fix_crush_particle.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string>

#include "atom.h"
#include "atom_vec.h"
#include "comm.h"
#include "crush_args.h"
#include "crush_breakage_index_kernel.h"
#include "crush_breakage_kernel.h"
#include "crush_criterion_kernel.h"
#include "crush_density_scale_kernel.h"
#include "crush_energy.h"
#include "crush_energy_kernel.h"
#include "crush_error.h"
#include "crush_fragment_kernel.h"
#include "crush_stability_kernel.h"
#include "crush_strength_kernel.h"
#include "crush_wall_contacts.h"
#include "domain.h"
#include "error.h"
#include "fix_mesh_surface.h"
#include "fix_property_global.h"
#include "fix_wall_gran.h"
#include "force.h"
#include "memory.h"
#include "modify.h"
#include "neigh_list.h"
#include "neighbor.h"
#include "pair.h"
#include "properties.h"
#include "tri_mesh.h"
#include "update.h"

using namespace LAMMPS_NS;
using namespace FixConst;
using namespace CrushKernels;

namespace {

// restart: 9 counters, then (format 2) the Br settings and kBrBins values of
// J0 and of the fines (see write_restart)
const int kRestartGlobalSize = 9;
const int kRestartBrSettings = 5;
// list[5] of the restart record: 0 not initialised, 1 initialised (files
// written before the Br bins, no bins follow), 2 initialised with the bins
const double kRestartFormatBins = 2.0;
// one event record: step time tag d x y z F_n F_lim partner generation,
// then with keyword energy: E_el_before E_el_after KE_before KE_frag0
const int kEventRecord = 11;
const int kEventEnergy = 4;

std::string str(const char *a) { return std::string(a ? a : ""); }

}  // namespace

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

  if (events_file_) {
    int ok = 1;
    if (comm->me == 0) {
      events_ = fopen(events_file_, events_append_ ? "a" : "w");
      ok = events_ ? 1 : 0;
      if (events_ && !events_append_) {
        fprintf(events_, "# fix crush/particle %s: one line per breakage event\n", id);
        fprintf(events_, "# step time parent_tag parent_diameter x y z F_n F_lim partner generation%s\n",
                energy_on_ ? " E_el_before E_el_after KE_before KE_frag0 KE_gain v_max n_steps" : "");
        fflush(events_);
      }
    }
    MPI_Bcast(&ok, 1, MPI_INT, 0, world);
    if (!ok)
      error->all(FLERR, ("fix crush/particle: cannot open file '" + str(events_file_) +
                         "' given to keyword 'events'").c_str());
  }
}

/* ---------------------------------------------------------------------- */

void FixCrushParticle::parse_args(int narg, char **arg)
{
  // fix ID group crush/particle sigma_lim0 S m M d0 D scale N var V d_comm DC seed P [...]
  CrushArgs a(error, "fix crush/particle", narg, arg, 3,
              {"sigma_lim0", "m", "d0", "scale", "var", "d_comm", "seed", "br", "d_max", "d_min",
               "omega", "fines_grading", "d_frag_min", "events", "events_append", "dt_check",
               "dt_frac", "dt_omega", "margin_skip", "density_scale", "energy", "energy_window",
               "energy_budget", "pressure", "force", "size_law", "scatter", "f_min"});
  while (a.next()) {
    if (a.is("sigma_lim0")) sigma_lim0_ = a.number(arg_positive("Pa"));
    else if (a.is("m")) m_ = a.number(arg_positive(""));
    else if (a.is("d0")) d0_ = a.number(arg_positive("m"));
    else if (a.is("scale")) scale_N_ = a.number(arg_positive(""));
    else if (a.is("var")) var_ = a.number(arg_non_negative(""));
    else if (a.is("d_comm")) d_comm_ = a.number(arg_positive("m"));
    else if (a.is("seed")) seed_ = (uint64_t)a.prime_seed();
    else if (a.is("br")) {}  // br d_max DMAX d_min DMIN omega W: a heading only
    else if (a.is("d_max")) d_max_ = a.number(arg_positive("m"));
    else if (a.is("d_min")) d_min_ = a.number(arg_positive("m"));
    else if (a.is("omega")) omega_ = a.number(arg_range(0.0, false, 3.0, true, "in (0, 3]"));
    else if (a.is("fines_grading")) fines_fractal_ = a.choice({"fractal", "d_min"}) == 0;
    else if (a.is("d_frag_min")) d_frag_min_ = a.number(arg_non_negative("m"));
    else if (a.is("events")) {
      const std::string f = a.word("a file name");
      delete[] events_file_;
      events_file_ = new char[f.size() + 1];
      strcpy(events_file_, f.c_str());
    }
    else if (a.is("events_append")) events_append_ = a.yes_no();
    else if (a.is("dt_check")) dt_check_error_ = a.choice({"warn", "error"}) == 1;
    else if (a.is("dt_frac")) dt_frac_ = a.number(arg_range(0.0, false, 1.0, true, "in (0, 1]"));
    else if (a.is("dt_omega")) dt_omega_ = a.number(arg_range(0.0, false, 2.0, false, "in (0, 2)"));
    else if (a.is("margin_skip")) margin_skip_ = a.yes_no();
    else if (a.is("density_scale")) d_scale_ref_ = a.number(arg_non_negative("m"));  // 0: off
    else if (a.is("energy")) energy_on_ = a.yes_no();
    else if (a.is("energy_budget")) energy_budget_ = a.yes_no();
    else if (a.is("energy_window")) energy_window_ = (int)a.integer(1, 1000000000, "an integer >= 1 (steps)");
    // criterion readings (docs/fix_crush_particle.md "Criterion readings")
    else if (a.is("pressure")) pressure_ = a.choice({"mean", "peak"}) == 1 ? PRESSURE_PEAK : PRESSURE_MEAN;
    else if (a.is("force")) force_ = a.choice({"normal", "sliding"}) == 1 ? FORCE_SLIDING : FORCE_NORMAL;
    else if (a.is("size_law")) size_law_ = a.choice({"printed", "no_N"}) == 1 ? SIZE_NO_N : SIZE_PRINTED;
    else if (a.is("scatter")) scatter_ = a.choice({"normal", "truncated", "weibull"});
    else if (a.is("f_min")) f_min_ = a.number(arg_range(0.0, true, 1.0, false, "in [0, 1)"));
  }

  if (a.given("f_min") && scatter_ != SCATTER_TRUNCATED)
    error->all(FLERR, "fix crush/particle: keyword 'f_min' belongs to 'scatter truncated'");
  if (scatter_ == SCATTER_TRUNCATED && !a.given("f_min"))
    error->all(FLERR, "fix crush/particle: 'scatter truncated' needs keyword 'f_min' (the bound of f, in [0, 1))");
  if (scatter_ == SCATTER_WEIBULL) {
    if (var_ > 0.0 && !(var_ >= 0.01 && var_ <= 5.0))
      error->all(FLERR, "fix crush/particle: 'scatter weibull' needs keyword 'var' in [0.01, 5] "
                        "(the coefficient of variation of the law), or 0");
    if (var_ > 0.0) weibull_k_ = weibull_shape_for_cov(var_);
  }

  if (energy_budget_ && !energy_on_)
    error->all(FLERR, "fix crush/particle: keyword 'energy_budget yes' needs 'energy yes'");

  static const char *required[] = {"sigma_lim0", "m", "d0", "scale", "var", "d_comm", "seed"};
  for (unsigned k = 0; k < sizeof(required) / sizeof(required[0]); k++)
    if (!a.given(required[k]))
      a.fail("missing required keyword '" + str(required[k]) +
             "' (required: sigma_lim0 m d0 scale var d_comm seed)");

  // Einav limit grading: default NE34 sizes (docs/model.md §3) scaled by N
  if (!a.given("d_max")) d_max_ = 0.27e-3 * scale_N_;
  if (!a.given("d_min")) d_min_ = 0.01e-3 * scale_N_;
  if (!(d_max_ > d_min_))
    error->all(FLERR, "fix crush/particle: keyword 'd_max' must be larger than 'd_min'");

  J0_.assign(kBrBins, 0.0);
  J_fines_.assign(kBrBins, 0.0);
  U_.assign(kBrBins, 0.0);
  br_limit_bins(omega_, br_grid(d_min_, d_max_), &U_[0]);
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

  walls_.clear();
  for (int k = 0; k < modify->nfix; k++)
    if (strncmp(modify->fix[k]->style, "wall/gran", 9) == 0)
      walls_.push_back(static_cast<FixWallGran *>(modify->fix[k]));

  if (energy_on_) {
    if (!energy_) energy_ = new CrushEnergy(lmp);
    energy_->init(pair_, walls_, E_, nu_, seed_, d_frag_min_);
    if (!energy_->springs_counted() && comm->me == 0)
      error->warning(FLERR, "fix crush/particle: keyword 'energy': the pair style is not 'gran model hertz "
                            "tangential history' (with no other history): tangential springs and friction "
                            "dissipation are not counted");
    if (energy_budget_) {
      FixPropertyGlobal *mu = static_cast<FixPropertyGlobal *>(modify->find_fix_property(
          "coefficientFriction", "property/global", "peratomtypepair", ntypes_mat_, ntypes_mat_, style));
      std::vector<double> m(ntypes_mat_ * ntypes_mat_);
      for (int a = 0; a < ntypes_mat_; a++)
        for (int b = 0; b < ntypes_mat_; b++) m[a * ntypes_mat_ + b] = mu->compute_array(a, b);
      energy_->set_friction(m);
    }
  }

  candidate_slot_.clear();
  candidates_.clear();
  cache_step_ = -1;
  full_scan_pending_ = true;
}

/* ---------------------------------------------------------------------- */

bool FixCrushParticle::eligible(int i) const
{
  return (atom->mask[i] & groupbit) && 2.0 * atom->radius[i] >= d_comm_;
}

void FixCrushParticle::assign_strength(int i)
{
  const double d = 2.0 * atom->radius[i];
  const double f = strength_factor_law(scatter_, seed_, (uint64_t)atom->tag[i], var_, f_min_, weibull_k_);
  crush_[i][0] = size_effect_strength(sigma_lim0_, f, d, size_law_scale(size_law_, scale_N_), d0_, m_);
}

double FixCrushParticle::F_lim(int i, double R_star, int ti, int tj) const
{
  return limit_force(crush_[i][0], R_star, E_star(ti, tj)) * limit_factor(ti, tj);
}

double FixCrushParticle::delta_lim(int i, double R_star, int ti, int tj) const
{
  return limit_overlap(crush_[i][0], R_star, E_star(ti, tj)) * limit_overlap_factor(limit_factor(ti, tj));
}

void FixCrushParticle::assign_missing_strengths()
{
  const int nlocal = atom->nlocal;
  for (int i = 0; i < nlocal; i++)
    if (crush_[i][0] < 0.0) assign_strength(i);
}

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
  if (!initialized_) {
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

/* ----------------------------------------------------------------------
   The time step must hold for the smallest particle that can ever exist:
   the smallest fragment of the smallest breakable particle (docs/model.md §5),
   and for the stiffest contact it can have (grain-steel, fragment-steel):
   the Rayleigh time does not see the partner. Derivation of the contact
   bound: docs/stability.md, "Time step and blow-up detection".
------------------------------------------------------------------------- */

namespace {
// The stiffest contact found for one class of particles (present grains or
// the smallest fragment that can occur) and where: omega = sqrt(k_max / m*)
struct StiffestContact { double omega, r, m, p, type; };

// The class's stiffest contact over all ranks (rank 0 needs it for the log).
StiffestContact stiffest_over_ranks(const StiffestContact &local, MPI_Comm world)
{
  struct { double v; int rank; } in, out;
  MPI_Comm_rank(world, &in.rank);
  in.v = local.omega;
  MPI_Allreduce(&in, &out, 1, MPI_DOUBLE_INT, MPI_MAXLOC, world);
  StiffestContact g = local;
  MPI_Bcast(&g, 5, MPI_DOUBLE, out.rank, world);
  return g;
}
}  // namespace

void FixCrushParticle::check_timestep()
{
  // smallest fragment of a particle just above the comminution limit, unless
  // fragments that fine go to fines
  const double r_frag_min = std::max(small_fragment_ratio() * 0.5 * d_comm_, 0.5 * d_frag_min_);
  // Contact pressure bound of particles that cannot break (below d_comm,
  // future fragments): the strength of the strongest breakable particle, a
  // d_comm particle with a strength factor 3 standard deviations above 1.
  // Breakable particles are bounded by their own sigma_lim (they break there).
  const double p_unbreakable =
      size_effect_strength(sigma_lim0_, 1.0 + 3.0 * var_, d_comm_, size_law_scale(size_law_, scale_N_), d0_, m_);
  double local[2] = {1e300, 1e300}, global[2];  // [0] T_R min, [1] r min ever
  StiffestContact grain = {0.0, 0.0, 0.0, 0.0, 0.0}, frag = grain;
  const int nlocal = atom->nlocal;
  std::vector<int> types_local(ntypes_mat_ + 1, 0), types_all(ntypes_mat_ + 1, 0);
  for (int i = 0; i < nlocal; i++) {
    if (!(atom->mask[i] & groupbit)) continue;
    double r = atom->radius[i];
    if (eligible(i)) r = std::min(r, r_frag_min);
    const int t = atom->type[i] - 1;
    if (atom->type[i] <= ntypes_mat_) types_local[atom->type[i]] = 1;
    const double G = shear_modulus(E_[t], nu_[t]);
    // the density the particle of that radius has (scaled below density_scale)
    const double rho = atom->density[i] * density_scale_factor(2.0 * r, d_scale_ref_);
    local[0] = std::min(local[0], rayleigh_time(r, rho, G, nu_[t]));
    local[1] = std::min(local[1], r);
    // stiffest contact of the particle as it is (its mass is scaled already)
    const double p = eligible(i) ? crush_[i][0] : p_unbreakable;
    const double w = contact_omega_max(p, atom->radius[i], atom->rmass[i]);
    if (w > grain.omega) { grain.omega = w; grain.r = atom->radius[i]; grain.m = atom->rmass[i]; grain.p = p; grain.type = atom->type[i]; }
    // and of the smallest fragment it can leave (it cannot break)
    if (eligible(i)) {
      const double mf = sphere_mass(r_frag_min, rho);
      const double wf = contact_omega_max(p_unbreakable, r_frag_min, mf);
      if (wf > frag.omega) { frag.omega = wf; frag.r = r_frag_min; frag.m = mf; frag.p = p_unbreakable; frag.type = atom->type[i]; }
    }
  }
  MPI_Allreduce(local, global, 2, MPI_DOUBLE, MPI_MIN, world);
  if (global[0] >= 1e299) return;  // no particles yet
  MPI_Allreduce(&types_local[0], &types_all[0], ntypes_mat_ + 1, MPI_INT, MPI_MAX, world);
  grain = stiffest_over_ranks(grain, world);
  frag = stiffest_over_ranks(frag, world);
  const double dt = update->dt;
  if (comm->me == 0) {
    char line[512];
    snprintf(line, sizeof(line),
             "fix crush/particle: smallest radius that can occur %g, its Rayleigh time T_R %g, "
             "dt/T_R = %g (limit dt_frac = %g)\n",
             global[1], global[0], dt / global[0], dt_frac_);
    if (screen) fputs(line, screen);
    if (logfile) fputs(line, logfile);
    // every pair of types checked: the class's particle against each particle
    // type of the group (an equal partner, R* = r/2) and each wall type (R* = r)
    std::vector<int> walls_seen(ntypes_mat_ + 1, 0);
    for (size_t w = 0; w < walls_.size(); w++) {
      if (walls_[w]->is_mesh_wall()) {
        for (int im = 0; im < walls_[w]->n_meshes(); im++) {
          const int wt = walls_[w]->mesh_list()[im]->atomTypeWall();
          if (wt >= 1 && wt <= ntypes_mat_) walls_seen[wt] = 1;
        }
      } else {
        const int wt = walls_[w]->atom_type_wall();
        if (wt >= 1 && wt <= ntypes_mat_) walls_seen[wt] = 1;
      }
    }
    const StiffestContact *cls[2] = {&grain, &frag};
    const char *cname[2] = {"grain", "fragment"};
    std::string report;
    for (int c = 0; c < 2; c++) {
      const StiffestContact &s = *cls[c];
      if (!(s.omega > 0.0)) continue;
      const int ti = (int)s.type;
      for (int pass = 0; pass < 2; pass++)
        for (int tj = 1; tj <= ntypes_mat_; tj++) {
          if (!(pass == 0 ? types_all[tj] : walls_seen[tj])) continue;
          const double Rs = pass == 0 ? 0.5 * s.r : s.r;
          const double Es = E_star(ti, tj);
          snprintf(line, sizeof(line),
                   "fix crush/particle: stiffest contact %s (type %d, r %g, mass %g) - %s type %d: "
                   "p_max %g, E* %g, overlap/r %g, k_max %g, omega_max dt = %g (limit dt_omega = %g)\n",
                   cname[c], ti, s.r, s.m, pass == 0 ? "particle" : "wall", tj, s.p, Es,
                   hertz_overlap_at_pressure(s.p, Rs, Es) / s.r, hertz_stiffness_at_pressure(s.p, Rs),
                   s.omega * dt, dt_omega_);
          report += line;
        }
    }
    // once, and again when it changes (decks that run in chunks call setup often)
    if (report != last_contact_report_) {
      if (screen) fputs(report.c_str(), screen);
      if (logfile) fputs(report.c_str(), logfile);
      last_contact_report_ = report;
    }
  }
  if (dt > dt_frac_ * global[0]) {
    char msg[512];
    snprintf(msg, sizeof(msg),
             "fix crush/particle: time step %g exceeds dt_frac * T_R = %g * %g for the smallest "
             "particle that can occur (radius %g); reduce the time step",
             dt, dt_frac_, global[0], global[1]);
    if (dt_check_error_) error->all(FLERR, msg);
    else if (comm->me == 0) error->warning(FLERR, msg);
  }
  const StiffestContact &s = (frag.omega > grain.omega) ? frag : grain;
  if (s.omega * dt > dt_omega_) {
    char msg[640];
    snprintf(msg, sizeof(msg),
             "fix crush/particle: time step %g exceeds dt_omega / omega_max = %g / %g of the stiffest "
             "contact that can occur (%s of radius %g, mass %g, contact pressure up to %g): "
             "omega_max dt = %g; reduce the time step or raise the mass of fine particles (density_scale)",
             dt, dt_omega_, s.omega, (&s == &frag) ? "fragment" : "grain", s.r, s.m, s.p, s.omega * dt);
    if (dt_check_error_) error->all(FLERR, msg);
    else if (comm->me == 0) error->warning(FLERR, msg);
  }
}

/* ----------------------------------------------------------------------
   Record a contact of particle i that reached its limit; keep the contact
   with the largest F_n / F_lim per particle (one break per step).
------------------------------------------------------------------------- */

void FixCrushParticle::consider(int i, double delta, double R_star, int ti, int tj, int partner)
{
  const double F_n = hertz_normal_force(delta, R_star, E_star(ti, tj));
  const double F_lim = this->F_lim(i, R_star, ti, tj);
  const double ratio = F_n / F_lim;
  if ((int)candidate_slot_.size() < atom->nlocal) candidate_slot_.resize(atom->nmax, -1);
  int &slot = candidate_slot_[i];
  if (slot >= 0) {
    if (ratio > candidates_[slot].ratio) {
      Candidate &c = candidates_[slot];
      c.F_n = F_n; c.F_lim = F_lim; c.ratio = ratio; c.partner = partner;
    }
    return;
  }
  Candidate c = {atom->tag[i], i, F_n, F_lim, ratio, partner};
  slot = (int)candidates_.size();
  candidates_.push_back(c);
}

void FixCrushParticle::find_candidates_pairs()
{
  NeighList *list = pair_->list;
  if (!list) return;
  double **x = atom->x;
  const double *radius = atom->radius;
  const int nlocal = atom->nlocal;
  const int nall = nlocal + atom->nghost;
  const int inum = list->inum;
  const int *ilist = list->ilist;

  // A full scan (every list, new reference positions) after a neighbour-list
  // build (new pairs, new ghosts, new particles), when the reference arrays
  // do not match, or when most lists had to be looked at anyway.
  bool full = !margin_skip_ || full_scan_pending_ || (int)r0_.size() != nall ||
              scanned_since_full_ >= 1.0;
  double D2 = 0.0;
  if (!full) {
    // every step over owned and ghost particles: kept free of branches and
    // early exits (LAMMPS stores x contiguously, x[k] = x[0] + 3 k)
    const double *xk = x[0];
    const double *x0 = &x0_[0];
    double *d2v = &d2_[0];
    int changed = 0;
    for (int k = 0; k < nall; k++) {
      const double dx = xk[3 * k] - x0[3 * k], dy = xk[3 * k + 1] - x0[3 * k + 1],
                   dz = xk[3 * k + 2] - x0[3 * k + 2];
      const double d2 = dx * dx + dy * dy + dz * dz;
      d2v[k] = d2;
      D2 = d2 > D2 ? d2 : D2;
      // a radius changed (e.g. fix adapt): the limit overlaps changed too
      changed |= (radius[k] != r0_[k]);
    }
    if (changed) full = true;
  }
  if (full && margin_skip_) {
    x0_.resize(3 * nall);
    r0_.resize(nall);
    d2_.assign(nall, 0.0);
    for (int k = 0; k < nall; k++) {
      x0_[3 * k] = x[k][0]; x0_[3 * k + 1] = x[k][1]; x0_[3 * k + 2] = x[k][2];
      r0_[k] = radius[k];
    }
    D2 = 0.0;
  }
  if (margin_skip_ && (int)margin_.size() < atom->nlocal) margin_.resize(atom->nmax, 0.0);
  full_scan_pending_ = false;
  last_scan_full_ = full;

  const double D = sqrt(D2);
  int scanned = 0;
  for (int ii = 0; ii < inum; ii++) {
    const int i = ilist[ii];
    if (!full && margin_holds(d2_[i], D2, margin_[i])) continue;
    pairs_scan(i, D);
    scanned++;
  }
  // a full scan starts afresh; after a partial one, its share of the lists adds up
  scanned_since_full_ = full ? 0.0 : scanned_since_full_ + (inum > 0 ? (double)scanned / inum : 0.0);
  lists_scanned_ += scanned;
  lists_total_ += inum;
}

/* ----------------------------------------------------------------------
   Test every pair in the contact list of particle i; with margin_skip also
   store the list's margin: the smallest overlap any of its pairs still lacks
   to reach a limit, less what particles may already have moved since the
   reference positions (|x_i - x0_i| exactly, the rank's largest for j).
------------------------------------------------------------------------- */

void FixCrushParticle::pairs_scan(int i, double D)
{
  NeighList *list = pair_->list;
  double **x = atom->x;
  const double *radius = atom->radius;
  const int *type = atom->type;
  const int nlocal = atom->nlocal;
  const bool i_on = eligible(i);
  const double xi = x[i][0], yi = x[i][1], zi = x[i][2], ri = radius[i];
  const int *jlist = list->firstneigh[i];
  const int jnum = list->numneigh[i];
  double B = 1e300;

  for (int jj = 0; jj < jnum; jj++) {
    const int j = jlist[jj] & NEIGHMASK;
    const bool j_on = j < nlocal && eligible(j);
    if (!i_on && !j_on) continue;
    const double dx = xi - x[j][0], dy = yi - x[j][1], dz = zi - x[j][2];
    const double radsum = ri + radius[j];
    const double rsq = dx * dx + dy * dy + dz * dz;
    const double rirj = ri * radius[j];
    const double coef = overlap_coef(type[i], type[j]);
    if (margin_skip_) {
      // pairs not yet in contact (delta < 0) count with their gap: rattlers
      // and loose neighbours then do not force their lists to be rescanned
      const double delta = radsum - sqrt(rsq);
      if (i_on) B = std::min(B, pair_limit_margin(delta, radsum, rirj, crush_[i][0], coef));
      if (j_on) B = std::min(B, pair_limit_margin(delta, radsum, rirj, crush_[j][0], coef));
    }
    if (rsq >= radsum * radsum) continue;
    // multiply-only limit test; the exact overlap and R* only for the few
    // contacts that pass it
    const bool i_hit = i_on && pair_limit_reached(rsq, radsum, rirj, crush_[i][0], coef);
    const bool j_hit = j_on && pair_limit_reached(rsq, radsum, rirj, crush_[j][0], coef);
    if (!i_hit && !j_hit) continue;
    const double delta = radsum - sqrt(rsq);
    const double R_star = effective_radius(ri, radius[j]);
    if (i_hit) consider(i, delta, R_star, type[i], type[j], PARTNER_PARTICLE);
    if (j_hit) consider(j, delta, R_star, type[j], type[i], PARTNER_PARTICLE);
  }
  if (margin_skip_) {
    // positions moved since x0 by at most sqrt(d2_i) (i) and D (any j); the
    // margin must cover that too (both 0 in a full scan)
    margin_[i] = B - sqrt(d2_[i]) - D;
  }
}

void FixCrushParticle::find_candidates_walls()
{
  const int nlocal = atom->nlocal;
  // with margin_skip: new references with the pair scan's, else the
  // particles whose wall margins may be used up are looked at again
  // (the pair scan sized d2_ to the particles present if it ran)
  const bool skip_on = margin_skip_ && (int)d2_.size() >= nlocal;
  const bool full = wall_references(!skip_on || last_scan_full_);
  if (skip_on) {
    if ((int)wall_margin_.size() < nlocal) {
      wall_margin_.resize(atom->nmax, 0.0);
      wall_stamp_.resize(atom->nmax, -1);
    }
    wall_scan_++;
    if (full) wall_full_scan_ = wall_scan_;
  }

  const double *radius = atom->radius;
  const int *type = atom->type;
  for_each_wall_neighbour(
      walls_, atom, [&](int i) { return eligible(i) && (full || !wall_skip(i)); },
      [&](int i, int, int, int, int wtype, double deltan) {
        const double lim = delta_lim(i, radius[i], type[i], wtype);
        // particles near the wall but not touching it count with their gap
        if (skip_on) wall_margin_update(i, lim + deltan);
        // contacts at shared mesh edges are seen once per triangle with the
        // same overlap: harmless for a maximum
        if (deltan < 0.0 && -deltan >= lim) consider(i, -deltan, radius[i], type[i], wtype, PARTNER_WALL);
      });
}

/* ----------------------------------------------------------------------
   Reference node positions of the mesh walls (full: take them now) and the
   largest squared node displacement since, walls_D2_. A point of a triangle
   is a fixed barycentric mix of its nodes, so it moved at most as far as the
   farthest of them. Primitive walls do not move along their normal. Returns
   whether the wall scan must be full: asked to, or the triangles changed
   (they migrate only with a neighbour-list build, which forces a full scan).
------------------------------------------------------------------------- */

bool FixCrushParticle::wall_references(bool full)
{
  if (full && !margin_skip_) return true;
  size_t n = 0;
  for (size_t w = 0; w < walls_.size(); w++)
    if (walls_[w]->is_mesh_wall())
      for (int im = 0; im < walls_[w]->n_meshes(); im++) {
        TriMesh *mesh = walls_[w]->mesh_list()[im]->triMesh();
        n += 9 * (size_t)(mesh->sizeLocal() + mesh->sizeGhost());
      }
  if (n != mesh_x0_.size()) full = true;
  if (full) mesh_x0_.resize(n);
  double D2 = 0.0;
  size_t off = 0;
  for (size_t w = 0; w < walls_.size(); w++) {
    if (!walls_[w]->is_mesh_wall()) continue;
    for (int im = 0; im < walls_[w]->n_meshes(); im++) {
      TriMesh *mesh = walls_[w]->mesh_list()[im]->triMesh();
      const int ntri = mesh->sizeLocal() + mesh->sizeGhost();
      for (int t = 0; t < ntri; t++)
        for (int a = 0; a < 3; a++, off += 3) {
          double p[3];
          mesh->node(t, a, p);
          if (full) {
            mesh_x0_[off] = p[0]; mesh_x0_[off + 1] = p[1]; mesh_x0_[off + 2] = p[2];
          } else {
            const double dx = p[0] - mesh_x0_[off], dy = p[1] - mesh_x0_[off + 1],
                         dz = p[2] - mesh_x0_[off + 2];
            D2 = std::max(D2, dx * dx + dy * dy + dz * dz);
          }
        }
    }
  }
  walls_D2_ = full ? 0.0 : D2;
  return full;
}

// May particle i's wall contacts be skipped in this (partial) scan? Decided
// on the margin stored before the scan, if it was stored since the last full
// scan (the present references); once its contacts are being looked at
// again (stamp), every visit of them is.
bool FixCrushParticle::wall_skip(int i)
{
  const int stamp = wall_stamp_[i];
  if (stamp == wall_scan_ || stamp < wall_full_scan_) return false;
  return margin_holds(d2_[i], walls_D2_, wall_margin_[i]);
}

// Margin of one wall contact of particle i (limit overlap less overlap, or
// plus the gap), stored less how far i and the walls moved since the
// references, so that it is tested against the motion since x0_ later (as
// FixCrushParticle::pairs_scan stores a list's margin).
void FixCrushParticle::wall_margin_update(int i, double margin)
{
  const double m = margin - sqrt(d2_[i]) - sqrt(walls_D2_);
  if (wall_stamp_[i] != wall_scan_) {
    wall_stamp_[i] = wall_scan_;
    wall_margin_[i] = m;
  } else if (m < wall_margin_[i]) {
    wall_margin_[i] = m;
  }
}

/* ---------------------------------------------------------------------- */

// Reset only the slots used (cheap when nothing breaks).
void FixCrushParticle::clear_candidates()
{
  for (size_t k = 0; k < candidates_.size(); k++)
    if (candidates_[k].i < (int)candidate_slot_.size()) candidate_slot_[candidates_[k].i] = -1;
  candidates_.clear();
}

// keyword energy_budget: friction dissipation around the pair force
void FixCrushParticle::pre_force(int) { if (energy_budget_ && energy_) energy_->friction_pre(); }
void FixCrushParticle::post_force(int) { if (energy_budget_ && energy_) energy_->friction_post(update->dt); }

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

void FixCrushParticle::write_events(const std::vector<double> &local_records, int nrec_local)
{
  if (!events_file_) return;
  const int rec = kEventRecord + (energy_on_ ? kEventEnergy : 0);
  const int nprocs = comm->nprocs;
  int n = nrec_local * rec;
  std::vector<int> counts(nprocs), displs(nprocs);
  MPI_Gather(&n, 1, MPI_INT, &counts[0], 1, MPI_INT, 0, world);
  int total = 0;
  if (comm->me == 0)
    for (int p = 0; p < nprocs; p++) { displs[p] = total; total += counts[p]; }
  std::vector<double> all(total + 1);
  std::vector<double> send(local_records);
  send.push_back(0.0);
  MPI_Gatherv(&send[0], n, MPI_DOUBLE, &all[0], &counts[0], &displs[0], MPI_DOUBLE, 0, world);
  if (comm->me != 0 || !events_) return;
  // lines in order of parent tag, as on one rank
  std::vector<std::pair<double, int> > order;
  for (int k = 0; k < total / rec; k++) order.push_back(std::make_pair(all[k * rec + 2], k));
  std::sort(order.begin(), order.end());
  for (size_t q = 0; q < order.size(); q++) {
    const double *e = &all[order[q].second * rec];
    // with energy, the line waits for the end of the event's window
    if (energy_on_) event_lines_.push_back(std::vector<double>(e, e + rec));
    else write_event_line(e, NULL);
  }
  fflush(events_);
}

// extra: with energy, E_el_before E_el_after KE_before KE_frag0 KE_gain v_max n_steps
void FixCrushParticle::write_event_line(const double *e, const double *extra)
{
  // the diameter in full precision: Br can be recomputed from this file
  fprintf(events_, "%.0f %.10g %.0f %.17g %.10g %.10g %.10g %.10g %.10g %s %.0f", e[0], e[1], e[2], e[3],
          e[4], e[5], e[6], e[7], e[8], e[9] == PARTNER_WALL ? "wall" : "particle", e[10]);
  if (extra)
    fprintf(events_, " %.10g %.10g %.10g %.10g %.10g %.10g %.0f", extra[0], extra[1], extra[2], extra[3], extra[4],
            extra[5], extra[6]);
  fputc('\n', events_);
}

/* ----------------------------------------------------------------------
   Energy accounting (keyword energy, crush_energy.h)
------------------------------------------------------------------------- */

// Per local parent: E_el_before E_el_after KE_before KE_frag0 (4 values each,
// in *local); the same for all events of the step are summed over ranks and
// their fragments watched from now on.
void FixCrushParticle::energy_of_breaks(const std::vector<int> &parents,
                                        const std::vector<std::pair<int, int> > &order,
                                        const std::vector<int> &first_tag, std::vector<double> *local)
{
  const int nall = atom->nlocal + atom->nghost;
  const int np_local = (int)parents.size(), np_all = (int)order.size();
  std::vector<char> is_parent(nall, 0);
  for (int k = 0; k < nall; k++) {
    std::vector<std::pair<int, int> >::const_iterator it =
        std::lower_bound(order.begin(), order.end(), std::make_pair(atom->tag[k], -1));
    is_parent[k] = (it != order.end() && it->first == atom->tag[k]) ? 1 : 0;
  }
  std::vector<double> Eb, Ea;
  energy_->break_energies(parents, is_parent, &Eb, &Ea);

  local->assign(kEventEnergy * np_local, 0.0);
  std::vector<double> info(kEventEnergy * np_all + 1, 0.0), info_all(kEventEnergy * np_all + 1, 0.0);
  double rf[kFragments], xf[kFragments][3];
  for (int k = 0; k < np_local; k++) {
    const int i = parents[k];
    double *v = atom->v[i];
    double KEb = kinetic_energy(atom->rmass[i], v);
    if (atom->omega_flag)
      KEb += kinetic_energy(0.4 * atom->rmass[i] * atom->radius[i] * atom->radius[i], atom->omega[i]);
    // fragments take the parent's velocity and no spin
    // (times the density-scaling velocity factor, as break_particles does)
    const int nf = energy_->fragments(atom->x[i], atom->radius[i], atom->tag[i], rf, xf);
    const double vf = fragment_speed_factor(rf, nf, atom->density[i]);
    const double vfrag[3] = {vf * v[0], vf * v[1], vf * v[2]};
    double KEf = 0.0;
    for (int f = 0; f < nf; f++)
      KEf += kinetic_energy(sphere_mass(rf[f], atom->density[i]) * density_scale_factor(2.0 * rf[f], d_scale_ref_), vfrag);
    const double vals[kEventEnergy] = {Eb[k], Ea[k], KEb, KEf};
    const int pos = (int)(std::lower_bound(order.begin(), order.end(), std::make_pair(atom->tag[i], -1)) - order.begin());
    for (int q = 0; q < kEventEnergy; q++) {
      (*local)[kEventEnergy * k + q] = vals[q];
      info[kEventEnergy * pos + q] = vals[q];
    }
  }
  MPI_Allreduce(&info[0], &info_all[0], kEventEnergy * np_all + 1, MPI_DOUBLE, MPI_SUM, world);
  std::vector<int> tags(np_all), nfrag(np_all);
  for (int k = 0; k < np_all; k++) {
    const double *e = &info_all[kEventEnergy * k];
    energy_sums_[0] += e[0];
    energy_sums_[1] += e[1];
    energy_sums_[2] += e[0] + e[2] - e[1] - e[3];
    tags[k] = order[k].first;
    nfrag[k] = order[k].second;
  }
  energy_->watch(update->ntimestep, tags, first_tag, nfrag, info_all);
}

void FixCrushParticle::energy_observe()
{
  energy_->observe(update->ntimestep, energy_window_);
  energy_write_closed();
}

// Events whose window is over: sums, and their lines in the events file.
void FixCrushParticle::energy_write_closed()
{
  std::vector<CrushEnergy::Event> &closed = energy_->closed();
  for (size_t k = 0; k < closed.size(); k++) {
    energy_sums_[3] += closed[k].KE_max - closed[k].KE_frag0;
    energy_sums_[4] = std::max(energy_sums_[4], closed[k].v_max);
  }
  if (comm->me == 0 && events_ && !closed.empty()) {
    for (size_t k = 0; k < closed.size(); k++) {
      const CrushEnergy::Event &c = closed[k];
      for (size_t q = 0; q < event_lines_.size(); q++) {
        const std::vector<double> &e = event_lines_[q];
        if ((bigint)e[0] != c.step || (int)e[2] != c.parent_tag) continue;
        const double extra[7] = {e[kEventRecord], e[kEventRecord + 1], e[kEventRecord + 2], e[kEventRecord + 3],
                                 c.KE_max - c.KE_frag0, c.v_max, (double)c.n_obs};
        write_event_line(&e[0], extra);
        event_lines_.erase(event_lines_.begin() + q);
        break;
      }
    }
    fflush(events_);
  }
  closed.clear();
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

/* ----------------------------------------------------------------------
   per-atom arrays
------------------------------------------------------------------------- */

double FixCrushParticle::memory_usage()
{
  return (double)atom->nmax * 2 * sizeof(double);
}

void FixCrushParticle::grow_arrays(int nmax)
{
  memory->grow(crush_, nmax, 2, "crush/particle:crush");
  array_atom = crush_;
}

void FixCrushParticle::copy_arrays(int i, int j, int)
{
  crush_[j][0] = crush_[i][0];
  crush_[j][1] = crush_[i][1];
}

void FixCrushParticle::set_arrays(int i)
{
  crush_[i][0] = -1.0;  // drawn from the tag at the next neighbor build
  crush_[i][1] = 0.0;
}

int FixCrushParticle::pack_exchange(int i, double *buf)
{
  buf[0] = crush_[i][0];
  buf[1] = crush_[i][1];
  return 2;
}

int FixCrushParticle::unpack_exchange(int nlocal, double *buf)
{
  crush_[nlocal][0] = buf[0];
  crush_[nlocal][1] = buf[1];
  return 2;
}

int FixCrushParticle::pack_restart(int i, double *buf)
{
  buf[0] = 3;
  buf[1] = crush_[i][0];
  buf[2] = crush_[i][1];
  return 3;
}

void FixCrushParticle::unpack_restart(int nlocal, int nth)
{
  double **extra = atom->extra;
  int m = 0;
  for (int i = 0; i < nth; i++) m += static_cast<int>(extra[nlocal][m]);
  m++;
  crush_[nlocal][0] = extra[nlocal][m++];
  crush_[nlocal][1] = extra[nlocal][m++];
}

int FixCrushParticle::maxsize_restart() { return 3; }
int FixCrushParticle::size_restart(int) { return 3; }

/* ----------------------------------------------------------------------
   global state in restart files
------------------------------------------------------------------------- */

// Layout: the 9 counters of the first format, then the Br settings the bins
// depend on (d_min, d_max, omega, fines_grading, number of bins), J0 and the
// fines' bin integrals (kBrBins each). list[5]: 0 not initialised, 1 the
// first format (no bins follow), 2 bins follow. Builds of the first format
// read a new file as before (they ignore what follows the counters).
void FixCrushParticle::write_restart(FILE *fp)
{
  const int off = kRestartGlobalSize + kRestartBrSettings;
  std::vector<double> list(off + 2 * kBrBins);
  const double head[kRestartGlobalSize + kRestartBrSettings] = {
      n_events_, n_created_, fines_mass_, mass0_, integral0_,
      initialized_ ? kRestartFormatBins : 0.0, (double)maxtag_ever_, (double)seed_, current_time(),
      d_min_, d_max_, omega_, fines_fractal_ ? 1.0 : 0.0, (double)kBrBins};
  std::copy(head, head + off, list.begin());
  std::copy(J0_.begin(), J0_.end(), list.begin() + off);
  std::copy(J_fines_.begin(), J_fines_.end(), list.begin() + off + kBrBins);
  if (comm->me == 0) {
    int size = (int)list.size() * sizeof(double);
    fwrite(&size, sizeof(int), 1, fp);
    fwrite(&list[0], sizeof(double), list.size(), fp);
  }
}

void FixCrushParticle::restart(char *buf)
{
  double *list = (double *)buf;
  n_events_ = list[0];
  n_created_ = list[1];
  fines_mass_ = list[2];
  mass0_ = list[3];
  integral0_ = list[4];
  initialized_ = list[5] > 0.5;
  if (initialized_ && list[5] != kRestartFormatBins)
    // The binned initial grading cannot be rebuilt from the old record.
    error->all(FLERR, "fix crush/particle: the restart file was written by a version without Br size "
                      "bins (before fines_grading); its initial grading per bin is missing, so Br cannot "
                      "be continued. Continue that run with the version that wrote it, or start from a "
                      "data file");
  if (list[5] == kRestartFormatBins) {
    const double *br = list + kRestartGlobalSize;
    // the stored bins hold only for the settings they were made with
    if (br[0] != d_min_ || br[1] != d_max_ || br[2] != omega_ || (br[3] > 0.5) != fines_fractal_ ||
        (int)br[4] != kBrBins) {
      char msg[512];
      snprintf(msg, sizeof(msg),
               "fix crush/particle: the Br settings differ from those in the restart file "
               "(d_min %g, d_max %g, omega %g, fines_grading %s); give the same 'd_min', 'd_max', "
               "'omega' and 'fines_grading' to continue the run",
               br[0], br[1], br[2], br[3] > 0.5 ? "fractal" : "d_min");
      error->all(FLERR, msg);
    }
    const int off = kRestartGlobalSize + kRestartBrSettings;
    J0_.assign(list + off, list + off + kBrBins);
    J_fines_.assign(list + off + kBrBins, list + off + 2 * kBrBins);
  }
  maxtag_ever_ = (int)list[6];
  // strengths of fragments made after the restart, and the fragments'
  // orientations, are drawn from the seed: another seed forks the run
  if (list[7] != 0.0 && (uint64_t)list[7] != seed_) {
    char msg[256];
    snprintf(msg, sizeof(msg),
             "fix crush/particle: 'seed' %llu differs from the seed %llu in the restart file; give "
             "the same 'seed' to continue the run (a new seed: start from a data file)",
             (unsigned long long)seed_, (unsigned long long)list[7]);
    error->all(FLERR, msg);
  }
  // LIGGGHTS 3.8 restarts its clock at 0: the offset is set at the next setup
  restart_time_ = list[8];
  restart_time_pending_ = true;
}

// Simulation time, continuous across restart files.
double FixCrushParticle::current_time() const
{
  return update->get_cur_time() + time_offset_;
}
