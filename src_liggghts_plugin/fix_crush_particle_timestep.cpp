// SPDX-License-Identifier: GPL-2.0-or-later
/* ----------------------------------------------------------------------
   fix crush/particle: the time-step checks (keywords dt_check, dt_frac,
   dt_omega), called by FixCrushParticle::setup at the start of every run:
   the Rayleigh time of the smallest particle that can ever exist and the
   stiffest contact it can have (docs/stability.md "Time step and blow-up
   detection"; kernels crush_stability_kernel.h, crush_breakage_kernel.h).
   Exercised by tests/integration/test_stability.py,
   test_crush_single_grain.py and test_crush_errors.py (dt_check error).
------------------------------------------------------------------------- */

#include "fix_crush_particle.h"
#include "fix_crush_particle_criterion.h"

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "atom.h"
#include "comm.h"
#include "crush_breakage_kernel.h"
#include "crush_density_scale_kernel.h"
#include "crush_fragment_kernel.h"
#include "crush_stability_kernel.h"
#include "crush_strength_kernel.h"
#include "error.h"
#include "fix_mesh_surface.h"
#include "fix_wall_gran.h"
#include "update.h"

using namespace LAMMPS_NS;
using namespace FixConst;
using namespace CrushKernels;

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
