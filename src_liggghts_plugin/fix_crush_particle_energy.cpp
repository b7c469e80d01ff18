// SPDX-License-Identifier: GPL-2.0-or-later
/* ----------------------------------------------------------------------
   fix crush/particle: the energy hooks (keyword energy, energy_budget).
   The fix calls them; the energies themselves are computed by CrushEnergy
   (crush_energy.{h,cpp}, kernels crush_energy_kernel.h).
   init_energy: called by FixCrushParticle::init; pre_force/post_force:
   friction dissipation every step (energy_budget); energy_of_breaks: by
   break_particles before the fragments exist; energy_observe: by
   end_of_step while fragments are watched; energy_write_closed: events
   whose window is over, to the sums and the event log.
   Exercised by tests/integration/test_energy.py.
------------------------------------------------------------------------- */

#include "fix_crush_particle.h"

#include <algorithm>
#include <vector>

#include "atom.h"
#include "comm.h"
#include "crush_breakage_kernel.h"
#include "crush_density_scale_kernel.h"
#include "crush_energy.h"
#include "crush_energy_kernel.h"
#include "crush_event_log_kernel.h"
#include "crush_fragment_kernel.h"
#include "error.h"
#include "fix_property_global.h"
#include "modify.h"
#include "update.h"

using namespace LAMMPS_NS;
using namespace FixConst;
using namespace CrushKernels;

/* ---------------------------------------------------------------------- */

// The energy bookkeeping and, with energy_budget, the friction coefficients.
void FixCrushParticle::init_energy()
{
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

// keyword energy_budget: friction dissipation around the pair force
void FixCrushParticle::pre_force(int) { if (energy_budget_ && energy_) energy_->friction_pre(); }
void FixCrushParticle::post_force(int) { if (energy_budget_ && energy_) energy_->friction_post(update->dt); }

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
        const double extra[kEventLineEnergy] = {e[kEventRecord], e[kEventRecord + 1], e[kEventRecord + 2], e[kEventRecord + 3],
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
