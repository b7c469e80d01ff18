// SPDX-License-Identifier: GPL-2.0-or-later
/* ----------------------------------------------------------------------
   Energy accounting of breaks for fix crush/particle (keyword energy, off
   by default; docs/fix_crush_particle.md "Energy accounting",
   docs/stability.md). Not a style: the fix owns one CrushEnergy and calls
   it at a break and at the end of steps while fragments are watched.

   - elastic energy of contacts: Hertz normal energy of every particle and
     wall contact, plus the history spring 1/2 k_t |s|^2 of particle pairs
     (crush_energy_kernel.h). Wall contacts count their normal energy only:
     LIGGGHTS keeps the wall history where this class cannot read it.
   - per break: energy of the parent's contacts just before, of the
     fragments' contacts just after (computed from the fragments' exact
     positions, with the neighbours' fragments where they break in the same
     step), kinetic energy of the parent and of the fragments at insertion.
   - over the next `window` steps: the largest kinetic energy the event's
     fragments reach (minus that at insertion) and their largest speed.
------------------------------------------------------------------------- */

#ifndef LMP_CRUSH_ENERGY_H
#define LMP_CRUSH_ENERGY_H

#include <stdint.h>
#include <vector>

#include "lmptype.h"
#include "pointers.h"

namespace LAMMPS_NS {

class CrushEnergy : protected Pointers {
 public:
  explicit CrushEnergy(class LAMMPS *);

  // seed and d_frag_min as in fix crush/particle (fragment layout); E, nu per type
  void init(class Pair *pair, const std::vector<class FixWallGran *> &walls, const std::vector<double> &E,
            const std::vector<double> &nu, uint64_t seed, double d_frag_min);

  // Elastic energy of every contact of the group, summed over ranks (collective).
  double total_elastic(int groupbit);

  // Per parent (owned local indices): elastic energy of its contacts just
  // before the break (a contact between two parents of the same step counts
  // half for each) and just after (the fragments' contacts). is_parent[k],
  // k < nlocal + nghost: 1 where atom k breaks in this step on any rank.
  // Call before any atom is created (ghost data is overwritten then).
  void break_energies(const std::vector<int> &parents, const std::vector<char> &is_parent,
                      std::vector<double> *E_before, std::vector<double> *E_after);

  // Fragments of a break in the order fix crush/particle creates them
  // (those finer than d_frag_min dropped): radii and centres.
  int fragments(const double *xp, double r, int tag, double *rf, double (*xf)[3]) const;

  // Watch the fragments of new events (identical on all ranks):
  // first_tag/n_frag give the fragments' tags; info = 4 values per event
  // (E_before, E_after, KE_before, KE_frag0), summed over ranks.
  void watch(bigint step, const std::vector<int> &parent_tags, const std::vector<int> &first_tags,
             const std::vector<int> &n_frag, const std::vector<double> &info);
  // Once per step while events are watched (collective): kinetic energy and
  // speed of each event's fragments; events whose window is over are moved
  // to closed(). window: steps watched after the break.
  void observe(bigint step, int window);
  bool watching() const { return !events_.empty(); }
  bool springs_counted() const { return shear_offset_ >= 0; }

  // Friction dissipation at grain-grain contacts (keyword energy_budget):
  // friction_pre stores the history springs before the pair force of the
  // step, friction_post (after it) adds mu F_n |slip| of every sliding
  // contact, the slip being the part of the step's tangential displacement
  // that the Coulomb cap removed from the spring. mu per type pair.
  void set_friction(const std::vector<double> &mu) { mu_ = mu; }
  void friction_pre();
  void friction_post(double dt);
  double friction_dissipated();  // summed over ranks (collective)

  struct Event {
    int parent_tag, first_tag, n_frag;
    bigint step;
    double E_before, E_after, KE_before, KE_frag0;
    double KE_max, v_max;  // over the steps observed
    int n_obs;             // steps observed
  };
  // Events closed since the last call (the caller clears them).
  std::vector<Event> &closed() { return closed_; }
  const std::vector<Event> &open_events() const { return events_; }

 private:
  class Pair *pair_;
  std::vector<class FixWallGran *> walls_;
  int ntypes_;
  std::vector<double> E_star_, G_star_;
  double Es(int ti, int tj) const { return E_star_[(ti - 1) * ntypes_ + (tj - 1)]; }
  double Gs(int ti, int tj) const { return G_star_[(ti - 1) * ntypes_ + (tj - 1)]; }
  int shear_offset_;  // of the pair history, -1: no tangential history
  uint64_t seed_;
  double d_frag_min_;

  std::vector<Event> events_, closed_;

  std::vector<double> mu_;       // friction coefficient per type pair
  std::vector<double> s_old_;    // 3 per neighbour-list entry, at friction_pre
  std::vector<int> first_;       // offset of each list's entries in s_old_
  double friction_local_;        // this rank's dissipation so far

  // a particle-wall contact with its overlap dn < 0 (mesh < 0: primitive wall)
  struct WallHit {
    int i, wall, mesh, tri, wtype;
    double dn;
    bool operator<(const WallHit &o) const { return i < o.i || (i == o.i && (wall < o.wall || (wall == o.wall && (mesh < o.mesh || (mesh == o.mesh && tri < o.tri))))); }
  };
  template <class Keep, class Visit>
  void each_pair_contact(Keep keep, Visit visit);
  void wall_hits(const std::vector<int> *want, int groupbit, std::vector<WallHit> *hits);
  double wall_hits_energy(const std::vector<WallHit> &hits, size_t b, size_t e, double r, int type);
  // the fragment (x, r, type) with the walls its parent touched
  double wall_energy_sphere(const double *x, double r, int type, const std::vector<WallHit> &parent_hits);
};

}  // namespace LAMMPS_NS

#endif
