// SPDX-License-Identifier: GPL-2.0-or-later
/* ----------------------------------------------------------------------
   fix crush/particle: crushable grains (docs/model.md §2).
   Russell & Muir Wood criterion on every particle-particle and
   particle-wall contact, size-dependent scattered strength, replacement of
   a broken grain by 14 Apollonian fragments, comminution limit, fines mass
   accounting and the Einav breakage index.
   Doc: docs/fix_crush_particle.md

   Where the code is: one class, its member functions in one file per topic
   (the header-only kernels crush_*_kernel.h hold the model's formulas; the
   fix calls them, never the reverse):
     fix_crush_particle.cpp            the fix: constructor, init, setup and
                                       the time-step hooks, in the order they
                                       use the parts below (detect, pre_exchange)
     fix_crush_particle_args.cpp       the keywords (parse_args)
     fix_crush_particle_criterion.h    the limit of a contact: eligible, F_lim,
                                       delta_lim (inline, used by the scan)
     fix_crush_particle_criterion.cpp  strengths (assign_strength), the material
                                       table and reading (init_criterion),
                                       utilisation for compute crush/atom
     fix_crush_particle_screening.cpp  which contacts reached their limit:
                                       pair and wall scans, margin_skip, consider
     fix_crush_particle_break.cpp      fragments (break_particles), density
                                       scaling, true_mass
     fix_crush_particle_accounting.cpp mass, fines, Br (f_ID[1..15]), the atom
                                       count that stops a run losing grains
     fix_crush_particle_events.cpp     the event log (columns: crush_event_log_kernel.h)
     fix_crush_particle_energy.cpp     the energy hooks (CrushEnergy does the sums)
     fix_crush_particle_restart.cpp    restart files, per-atom arrays
     fix_crush_particle_timestep.cpp   the time-step checks (check_timestep)
------------------------------------------------------------------------- */

#ifdef FIX_CLASS

FixStyle(crush/particle,FixCrushParticle)

#else

#ifndef LMP_FIX_CRUSH_PARTICLE_H
#define LMP_FIX_CRUSH_PARTICLE_H

#include <cstdio>
#include <stdint.h>
#include <string>
#include <vector>

#include "fix.h"

namespace LAMMPS_NS {

class FixCrushParticle : public Fix {
 public:
  FixCrushParticle(class LAMMPS *, int, char **);
  ~FixCrushParticle();
  int setmask();
  void init();
  void setup(int);
  void setup_pre_exchange();
  void setup_pre_neighbor();
  void pre_neighbor();
  void pre_exchange();
  void end_of_step();
  void post_integrate();
  void pre_force(int);
  void post_force(int);
  double compute_vector(int);

  // per-atom data: sigma_lim and generation
  double memory_usage();
  void grow_arrays(int);
  void copy_arrays(int, int, int);
  void set_arrays(int);
  int pack_exchange(int, double *);
  int unpack_exchange(int, double *);
  int pack_restart(int, double *);
  void unpack_restart(int, int);
  int size_restart(int);
  int maxsize_restart();

  // global state
  void write_restart(FILE *);
  void restart(char *);

  enum Partner { PARTNER_PARTICLE = 0, PARTNER_WALL = 1 };

  // Per-particle outputs, read by compute crush/atom (owned particles):
  // strength sigma_lim (Pa), generation (0 initial grain, 1 fragment, ...),
  // mass without density scaling (kg), and the utilisation: the largest
  // F_n / F_lim over the particle's contacts in the present positions (0
  // without contact, and for particles that cannot break).
  double strength(int i) const { return crush_[i][0]; }
  double generation(int i) const { return crush_[i][1]; }
  // mass of particle i without density scaling: what the mass balance,
  // fines and Br count (rmass itself when scaling is off)
  double true_mass(int i) const;
  void utilisation(std::vector<double> *u);

 private:
  // model parameters (docs/model.md §3 names)
  double sigma_lim0_, m_, d0_, scale_N_, var_, d_comm_;
  uint64_t seed_;
  double d_max_, d_min_, omega_;  // Br limit grading
  bool fines_fractal_;            // fines_grading fractal (true) or d_min
  double d_frag_min_;             // fragments finer than this go to fines
  double d_scale_ref_;            // density_scale: finer particles get its Rayleigh time (0: off)
  // criterion readings (crush_criterion_kernel.h) and scatter law
  // (crush_strength_kernel.h); the defaults are the printed model
  int pressure_, force_, size_law_, scatter_;
  double f_min_;                  // scatter truncated: bound of f
  double weibull_k_;              // scatter weibull: shape for var
  bool dt_check_error_;
  double dt_frac_;
  double dt_omega_;  // limit on omega_max dt of the stiffest contact (check_timestep)
  std::string last_contact_report_;  // stiffest-contact lines printed last (check_timestep)
  char *events_file_;
  bool events_append_;
  FILE *events_;

  double **crush_;  // [i][0] sigma_lim (-1 = not yet drawn), [i][1] generation

  // E* for every pair of material types (particle and wall types)
  int ntypes_mat_;
  std::vector<double> E_star_;
  std::vector<double> E_, nu_;
  double E_star(int ti, int tj) const { return E_star_[(ti - 1) * ntypes_mat_ + (tj - 1)]; }
  // (3 pi / (4 E*))^2 k^(2/3) per type pair, k the reading's factor on F_lim
  std::vector<double> overlap_coef_;
  double overlap_coef(int ti, int tj) const { return overlap_coef_[(ti - 1) * ntypes_mat_ + (tj - 1)]; }
  std::vector<double> limit_factor_;  // k per type pair (1: printed reading)
  double limit_factor(int ti, int tj) const { return limit_factor_[(ti - 1) * ntypes_mat_ + (tj - 1)]; }
  // F_lim and the limit overlap of particle i on a contact of types (ti, tj)
  // (inline: fix_crush_particle_criterion.h)
  double F_lim(int i, double R_star, int ti, int tj) const;
  double delta_lim(int i, double R_star, int ti, int tj) const;

  class Pair *pair_;

  // candidate count summed over ranks without blocking (see detect)
  bool count_pending_;
  int count_local_, count_all_;
  MPI_Request count_request_;

  // Contact lists far from any limit are skipped (keyword margin_skip). The
  // skip is exact: a list is looked at again before any pair in it can have
  // reached a limit, from its margin and a bound on how far particles moved
  // since the reference positions x0_ (taken at a full scan).
  bool margin_skip_;
  bool full_scan_pending_;     // after neighbour-list builds, setup, breaks
  // Lists rescanned since the last full scan, in units of all lists: once
  // that work equals one full scan, a full scan with fresh reference
  // positions is cheaper than going on (margins shrink as particles move).
  double scanned_since_full_;
  double lists_scanned_, lists_total_;  // since the fix was defined (output [7])
  std::vector<double> x0_, r0_, d2_;  // reference x, r; squared displacement
  std::vector<double> margin_;        // per owned particle: margin of its list
  void pairs_scan(int i, double D);
  std::vector<class FixWallGran *> walls_;
  // The same skip for wall contacts: per owned particle the margin of its
  // wall contacts (stored less the motion since x0_ at its scan), the
  // reference node positions of every mesh wall (local and ghost triangles)
  // and the largest node displacement since (walls_D2_). A particle's wall
  // contacts are all looked at again once any of them may be at its limit.
  bool last_scan_full_;           // the pair scan of this step took new references
  std::vector<double> wall_margin_;
  std::vector<int> wall_stamp_;   // scan in which the margin was reset
  int wall_scan_, wall_full_scan_;  // this scan, the last full one
  std::vector<double> mesh_x0_;   // nodes of every mesh triangle at the reference
  double walls_D2_;
  bool wall_references(bool full);
  bool wall_skip(int i);
  void wall_margin_update(int i, double margin);

  // Contacts over the limit found at the end of a step, broken in the next
  // pre_exchange (atoms can be created and deleted only there).
  struct Candidate {
    int tag;
    int i;  // local index when found
    double F_n, F_lim, ratio;
    int partner;
  };
  std::vector<Candidate> candidates_;
  std::vector<int> candidate_slot_;

  // global counters, kept in restart files
  double n_events_, n_created_, fines_mass_;
  double mass0_, integral0_;  // initial solid mass and Br integral of F0
  // Br size bins (crush_breakage_index_kernel.h): integrals of F0 over each
  // bin (normalised), of the fines (unnormalised, summed over ranks at every
  // break) and of the limit grading
  std::vector<double> J0_, J_fines_, U_;
  bool initialized_;
  int maxtag_ever_;
  bigint natoms_counted_;  // atoms at the last count or check + created - deleted by breaks
  double time_offset_;  // restores the simulation time after read_restart
  double restart_time_;
  bool restart_time_pending_;

  // cache for compute_vector
  bigint cache_step_;
  double cache_[15];

  // Energy accounting (keyword energy, crush_energy.h): off by default.
  class CrushEnergy *energy_;
  bool energy_on_;
  bool energy_budget_;  // friction dissipation every step (keyword energy_budget)
  int energy_window_;  // steps the fragments of an event are watched
  int nall_at_borders_;  // owned + ghost atoms after the last borders (ghost lists valid)
  // sums over events: elastic energy before, after, released by breaks
  // (elastic + kinetic before minus after), kinetic energy gained by the
  // fragments over the window; largest fragment speed
  double energy_sums_[5];
  std::vector<std::vector<double> > event_lines_;  // rank 0: records awaiting their window
  // the energy hooks (fix_crush_particle_energy.cpp)
  void energy_of_breaks(const std::vector<int> &parents, const std::vector<std::pair<int, int> > &order,
                        const std::vector<int> &first_tag, std::vector<double> *records);
  void energy_observe();
  void energy_write_closed();
  void init_energy();

  // the keywords (fix_crush_particle_args.cpp)
  void parse_args(int narg, char **arg);
  // the criterion (fix_crush_particle_criterion.{h,cpp})
  void init_criterion();
  bool eligible(int i) const;
  void assign_strength(int i);
  void assign_missing_strengths();
  // screening and its schedule (fix_crush_particle_screening.cpp, detect in fix_crush_particle.cpp)
  void consider(int i, double delta, double R_star, int ti, int tj, int partner);
  void clear_candidates();
  void detect(bool blocking);
  void finish_count();
  void find_candidates_pairs();
  void find_candidates_walls();
  // fragmentation (fix_crush_particle_break.cpp)
  void break_particles();
  double fragment_speed_factor(const double *r, int n, double rho) const;
  // accounting (fix_crush_particle_accounting.cpp)
  void take_initial_grading();
  void count_atoms();
  void check_atom_count();
  void compute_globals();
  // the event log (fix_crush_particle_events.cpp)
  void open_event_log();
  void write_events(const std::vector<double> &local_records, int nrec_local);
  void write_event_line(const double *e, const double *extra);
  // time-step checks (fix_crush_particle_timestep.cpp)
  void check_timestep();
  // simulation time, continuous across restart files (fix_crush_particle.cpp)
  double current_time() const;
};

}

#endif
#endif
