// SPDX-License-Identifier: GPL-2.0-or-later
/* ----------------------------------------------------------------------
   Energy accounting of breaks (see crush_energy.h). The contact energies
   are those of crush_energy_kernel.h.
------------------------------------------------------------------------- */

#include "crush_energy.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "atom.h"
#include "comm.h"
#include "crush_breakage_kernel.h"
#include "crush_energy_kernel.h"
#include "crush_fragment_kernel.h"
#include "crush_wall_contacts.h"
#include "fix_mesh_surface.h"
#include "fix_wall_gran.h"
#include "neigh_list.h"
#include "pair.h"
#include "pair_gran.h"
#include "pair_gran_proxy.h"
#include "primitive_wall.h"
#include "tri_mesh.h"

using namespace LAMMPS_NS;
using namespace CrushKernels;

CrushEnergy::CrushEnergy(LAMMPS *lmp) :
  Pointers(lmp), pair_(NULL), ntypes_(0), shear_offset_(-1), seed_(0), d_frag_min_(0.0),
  friction_local_(0.0)
{
}

void CrushEnergy::init(Pair *pair, const std::vector<FixWallGran *> &walls, const std::vector<double> &E,
                       const std::vector<double> &nu, uint64_t seed, double d_frag_min)
{
  pair_ = pair;
  walls_ = walls;
  seed_ = seed;
  d_frag_min_ = d_frag_min;
  ntypes_ = (int)E.size();
  E_star_.assign(ntypes_ * ntypes_, 0.0);
  G_star_.assign(ntypes_ * ntypes_, 0.0);
  for (int a = 0; a < ntypes_; a++)
    for (int b = 0; b < ntypes_; b++) {
      E_star_[a * ntypes_ + b] = effective_modulus(E[a], nu[a], E[b], nu[b]);
      G_star_[a * ntypes_ + b] = effective_shear_modulus(E[a], nu[a], E[b], nu[b]);
    }
  // The stored tangential displacement of `tangential history`. LIGGGHTS
  // names it "shearx" but does not look such names up; it is the pair's only
  // history (offset 0) when the pair keeps exactly its 3 values, as
  // `model hertz tangential history` does. Otherwise the springs (and
  // friction dissipation) are not counted, and the fix says so.
  shear_offset_ = -1;
  if (pair_) {
    PairGran *pg = static_cast<PairGran *>(pair_);
    if (pg->contact_match("tangential", "history") && pg->dnum_pair() == 3) shear_offset_ = 0;
  }
}

/* ----------------------------------------------------------------------
   Every particle pair of the granular pair list in contact, for
   total_elastic and break_energies: for each pair with keep(i, j) true and
   overlap > 0, visit(i, j, U) with U the contact's elastic
   energy (normal Hertz plus the history spring, crush_energy_kernel.h).
------------------------------------------------------------------------- */

template <class Keep, class Visit>
void CrushEnergy::each_pair_contact(Keep keep, Visit visit)
{
  NeighList *list = pair_ ? pair_->list : NULL;
  if (!list) return;
  double **x = atom->x;
  const double *radius = atom->radius;
  const int *type = atom->type;
  NeighList *hl = pair_->listgranhistory;
  const int dnum = static_cast<PairGran *>(pair_)->dnum();
  for (int ii = 0; ii < list->inum; ii++) {
    const int i = list->ilist[ii];
    const int *jlist = list->firstneigh[i];
    const double *hist = (hl && shear_offset_ >= 0) ? hl->firstdouble[i] : NULL;
    for (int jj = 0; jj < list->numneigh[i]; jj++) {
      const int j = jlist[jj] & NEIGHMASK;
      if (!keep(i, j)) continue;
      const double dx = x[i][0] - x[j][0], dy = x[i][1] - x[j][1], dz = x[i][2] - x[j][2];
      const double delta = radius[i] + radius[j] - sqrt(dx * dx + dy * dy + dz * dz);
      if (!(delta > 0.0)) continue;
      double s2 = 0.0;
      if (hist) {
        const double *s = &hist[dnum * jj + shear_offset_];
        s2 = s[0] * s[0] + s[1] * s[1] + s[2] * s[2];
      }
      visit(i, j,
            contact_elastic_energy(delta, effective_radius(radius[i], radius[j]), Es(type[i], type[j]),
                                   Gs(type[i], type[j]), s2));
    }
  }
}

/* ---------------------------------------------------------------------- */

double CrushEnergy::total_elastic(int groupbit)
{
  const double *radius = atom->radius;
  const int *type = atom->type;
  const int *mask = atom->mask;
  const int nlocal = atom->nlocal;
  double U = 0.0;

  each_pair_contact([&](int i, int j) { return (mask[i] & groupbit) || (mask[j] & groupbit); },
                    [&](int, int j, double U_c) {
                      // newton off: a pair with a ghost is in the lists of both ranks
                      U += ((j < nlocal) ? 1.0 : 0.5) * U_c;
                    });
  std::vector<WallHit> hits;
  wall_hits(NULL, groupbit, &hits);
  for (size_t b = 0, e; b < hits.size(); b = e) {
    for (e = b; e < hits.size() && hits[e].i == hits[b].i; e++) {}
    U += wall_hits_energy(hits, b, e, radius[hits[b].i], type[hits[b].i]);
  }

  double U_all = 0.0;
  MPI_Allreduce(&U, &U_all, 1, MPI_DOUBLE, MPI_SUM, world);
  return U_all;
}

/* ----------------------------------------------------------------------
   Wall contacts of owned particles (only those with want[i] where want is
   given), each with its overlap, in order of particle. A sphere at a shared
   edge of a mesh is seen by both triangles with the same overlap: per
   particle and mesh, equal overlaps count once (wall_hits_energy).
------------------------------------------------------------------------- */

void CrushEnergy::wall_hits(const std::vector<int> *want, int groupbit, std::vector<WallHit> *hits)
{
  const int *mask = atom->mask;
  hits->clear();
  for_each_wall_neighbour(
      walls_, atom, [&](int i) { return (mask[i] & groupbit) && !(want && (*want)[i] < 0); },
      [&](int i, int w, int im, int t, int wtype, double dn) {
        if (dn >= 0.0) return;
        WallHit h = {i, w, im, t, wtype, dn};
        hits->push_back(h);
      });
  std::sort(hits->begin(), hits->end());
}

// Normal energy of the hits of one particle (radius r, type), hits[b, e):
// equal overlaps on the same mesh count once.
double CrushEnergy::wall_hits_energy(const std::vector<WallHit> &hits, size_t b, size_t e, double r, int type)
{
  double U = 0.0;
  for (size_t h = b; h < e; h++) {
    bool dup = false;
    for (size_t q = b; q < h && !dup; q++)
      dup = hits[h].mesh >= 0 && hits[q].wall == hits[h].wall && hits[q].mesh == hits[h].mesh &&
            std::fabs(hits[q].dn - hits[h].dn) <= 1e-12 * std::fabs(hits[h].dn);
    if (!dup) U += hertz_normal_energy(-hits[h].dn, r, Es(type, hits[h].wtype));
  }
  return U;
}

double CrushEnergy::wall_energy_sphere(const double *xc, double r, int type, const std::vector<WallHit> &parent_hits)
{
  double dv[3];
  double xs[3] = {xc[0], xc[1], xc[2]};
  std::vector<WallHit> hits;
  for (size_t h = 0; h < parent_hits.size(); h++) {
    WallHit hit = parent_hits[h];
    FixWallGran *wall = walls_[hit.wall];
    if (hit.mesh >= 0) {
      int barysign;
      // iPart only matters for non-spherical particles
      hit.dn = wall->mesh_list()[hit.mesh]->triMesh()->resolveTriSphereContact(0, hit.tri, r, xs, dv, barysign);
    } else {
      hit.dn = wall->primitiveWall()->resolveContact(xs, r, dv);
    }
    if (hit.dn < 0.0) hits.push_back(hit);
  }
  return wall_hits_energy(hits, 0, hits.size(), r, type);
}

/* ---------------------------------------------------------------------- */

int CrushEnergy::fragments(const double *xp, double r, int tag, double *rf, double (*xf)[3]) const
{
  double frag_r[kFragments], frag_off[kFragments][3], R[3][3], off[3];
  apollonian_fragments(r, frag_r, frag_off);
  event_rotation(seed_, (uint64_t)tag, R);
  int n = 0;
  for (int f = 0; f < kFragments; f++) {
    if (2.0 * frag_r[f] < d_frag_min_) continue;
    rotate(R, frag_off[f], off);
    rf[n] = frag_r[f];
    xf[n][0] = xp[0] + off[0]; xf[n][1] = xp[1] + off[1]; xf[n][2] = xp[2] + off[2];
    n++;
  }
  return n;
}

/* ---------------------------------------------------------------------- */

void CrushEnergy::break_energies(const std::vector<int> &parents, const std::vector<char> &is_parent,
                                 std::vector<double> *E_before, std::vector<double> *E_after)
{
  double **x = atom->x;
  const double *radius = atom->radius;
  const int *type = atom->type;
  const int *tag = atom->tag;
  const int nlocal = atom->nlocal;
  const int np = (int)parents.size();
  E_before->assign(np, 0.0);
  E_after->assign(np, 0.0);
  if (np == 0) return;

  std::vector<int> slot(nlocal, -1);
  for (int k = 0; k < np; k++) slot[parents[k]] = k;

  // the parent's particle partners in contact: copies (ghosts are
  // overwritten once fragments are created)
  struct Partner {
    double x[3], r;
    int type, tag;
    bool parent;
  };
  std::vector<std::vector<Partner> > partners(np);

  each_pair_contact([&](int i, int j) { return slot[i] >= 0 || (j < nlocal && slot[j] >= 0); },
                    [&](int i, int j, double U) {
                      const int ki = slot[i], kj = (j < nlocal) ? slot[j] : -1;
                      const double w = (is_parent[i] && is_parent[j]) ? 0.5 : 1.0;
                      if (ki >= 0) {
                        (*E_before)[ki] += w * U;
                        Partner p = {{x[j][0], x[j][1], x[j][2]}, radius[j], type[j], tag[j], is_parent[j] != 0};
                        partners[ki].push_back(p);
                      }
                      if (kj >= 0) {
                        (*E_before)[kj] += w * U;
                        Partner p = {{x[i][0], x[i][1], x[i][2]}, radius[i], type[i], tag[i], is_parent[i] != 0};
                        partners[kj].push_back(p);
                      }
                    });

  std::vector<WallHit> all_hits;
  wall_hits(&slot, ~0, &all_hits);
  std::vector<std::vector<WallHit> > parent_hits(np);
  for (size_t h = 0; h < all_hits.size(); h++) parent_hits[slot[all_hits[h].i]].push_back(all_hits[h]);

  double rf[kFragments], xf[kFragments][3], rg[kFragments], xg[kFragments][3];
  for (int k = 0; k < np; k++) {
    const int i = parents[k];
    const int ti = type[i];
    const std::vector<WallHit> &hits = parent_hits[k];
    (*E_before)[k] += wall_hits_energy(hits, 0, hits.size(), radius[i], ti);

    // after: the fragments with the partners (or the partners' fragments),
    // with the walls the parent touched and with each other. A fragment
    // overlaps only what its parent overlapped (it lies inside the parent).
    const int nf = fragments(x[i], radius[i], tag[i], rf, xf);
    double U = 0.0;
    for (int f = 0; f < nf; f++) {
      for (size_t q = 0; q < partners[k].size(); q++) {
        const Partner &p = partners[k][q];
        const double Esij = Es(ti, p.type);
        if (!p.parent) {
          const double d = rf[f] + p.r - sqrt((xf[f][0] - p.x[0]) * (xf[f][0] - p.x[0]) +
                                              (xf[f][1] - p.x[1]) * (xf[f][1] - p.x[1]) +
                                              (xf[f][2] - p.x[2]) * (xf[f][2] - p.x[2]));
          U += hertz_normal_energy(d, effective_radius(rf[f], p.r), Esij);
        } else {
          // both break in this step: half of each fragment pair, as before
          const int ng = fragments(p.x, p.r, p.tag, rg, xg);
          for (int g = 0; g < ng; g++) {
            const double d = rf[f] + rg[g] - sqrt((xf[f][0] - xg[g][0]) * (xf[f][0] - xg[g][0]) +
                                                  (xf[f][1] - xg[g][1]) * (xf[f][1] - xg[g][1]) +
                                                  (xf[f][2] - xg[g][2]) * (xf[f][2] - xg[g][2]));
            U += 0.5 * hertz_normal_energy(d, effective_radius(rf[f], rg[g]), Esij);
          }
        }
      }
      U += wall_energy_sphere(xf[f], rf[f], ti, hits);
      // fragments are tangent to each other: only round-off overlaps
      for (int g = f + 1; g < nf; g++) {
        const double d = rf[f] + rf[g] - sqrt((xf[f][0] - xf[g][0]) * (xf[f][0] - xf[g][0]) +
                                              (xf[f][1] - xf[g][1]) * (xf[f][1] - xf[g][1]) +
                                              (xf[f][2] - xf[g][2]) * (xf[f][2] - xf[g][2]));
        U += hertz_normal_energy(d, effective_radius(rf[f], rf[g]), Es(ti, ti));
      }
    }
    (*E_after)[k] = U;
  }
}

/* ---------------------------------------------------------------------- */

void CrushEnergy::watch(bigint step, const std::vector<int> &parent_tags, const std::vector<int> &first_tags,
                        const std::vector<int> &n_frag, const std::vector<double> &info)
{
  for (size_t k = 0; k < parent_tags.size(); k++) {
    Event e;
    e.parent_tag = parent_tags[k];
    e.first_tag = first_tags[k];
    e.n_frag = n_frag[k];
    e.step = step;
    e.E_before = info[4 * k];
    e.E_after = info[4 * k + 1];
    e.KE_before = info[4 * k + 2];
    e.KE_frag0 = info[4 * k + 3];
    e.KE_max = e.KE_frag0;
    e.v_max = 0.0;
    e.n_obs = 0;
    events_.push_back(e);
  }
}

void CrushEnergy::observe(bigint step, int window)
{
  const int ne = (int)events_.size();
  if (ne == 0) return;
  // events in order of first tag: a fragment's event by binary search
  std::vector<std::pair<int, int> > by_tag(ne);
  for (int k = 0; k < ne; k++) by_tag[k] = std::make_pair(events_[k].first_tag, k);
  std::sort(by_tag.begin(), by_tag.end());
  const int tag_min = by_tag[0].first;

  std::vector<double> ke(ne, 0.0), ke_all(ne), vmax(ne, 0.0), vmax_all(ne);
  const int nlocal = atom->nlocal;
  const int *tag = atom->tag;
  double **v = atom->v;
  for (int i = 0; i < nlocal; i++) {
    if (tag[i] < tag_min) continue;
    std::vector<std::pair<int, int> >::iterator it =
        std::upper_bound(by_tag.begin(), by_tag.end(), std::make_pair(tag[i], ne));
    if (it == by_tag.begin()) continue;
    --it;
    const Event &e = events_[it->second];
    if (tag[i] >= e.first_tag + e.n_frag) continue;
    double K = kinetic_energy(atom->rmass[i], v[i]);
    if (atom->omega_flag) {
      // rotation, where the deck integrates it: I = 2/5 m r^2
      const double I = 0.4 * atom->rmass[i] * atom->radius[i] * atom->radius[i];
      K += kinetic_energy(I, atom->omega[i]);
    }
    ke[it->second] += K;
    const double s = sqrt(v[i][0] * v[i][0] + v[i][1] * v[i][1] + v[i][2] * v[i][2]);
    vmax[it->second] = std::max(vmax[it->second], s);
  }
  MPI_Allreduce(&ke[0], &ke_all[0], ne, MPI_DOUBLE, MPI_SUM, world);
  MPI_Allreduce(&vmax[0], &vmax_all[0], ne, MPI_DOUBLE, MPI_MAX, world);

  std::vector<Event> open;
  for (int k = 0; k < ne; k++) {
    Event &e = events_[k];
    e.KE_max = std::max(e.KE_max, ke_all[k]);
    e.v_max = std::max(e.v_max, vmax_all[k]);
    e.n_obs++;
    if (step - e.step + 1 >= window) closed_.push_back(e);
    else open.push_back(e);
  }
  events_.swap(open);
}

/* ----------------------------------------------------------------------
   Friction dissipation. LIGGGHTS' tangential history model, per step:
   s_trial = s_old + v_tr dt with its normal part removed; F_t = -k_t s_trial;
   where k_t |s_trial| > mu F_n the force is capped and s = s_trial scaled
   to k_t |s| = mu F_n. The capped part of the displacement,
   |s_trial| - |s|, slid at the force mu F_n: that is the energy friction
   dissipated in the step. v_tr as in surface_model_default.h (relative
   velocity at the contact point, rotation included); F_n elastic Hertz
   (the decks have no normal viscous damping).
------------------------------------------------------------------------- */

void CrushEnergy::friction_pre()
{
  NeighList *list = pair_ ? pair_->list : NULL;
  NeighList *hl = pair_ ? pair_->listgranhistory : NULL;
  if (!list || !hl || shear_offset_ < 0) return;
  const int dnum = static_cast<PairGran *>(pair_)->dnum();
  first_.resize(list->inum + 1);
  int n = 0;
  for (int ii = 0; ii < list->inum; ii++) {
    first_[ii] = n;
    n += list->numneigh[list->ilist[ii]];
  }
  first_[list->inum] = n;
  s_old_.resize(3 * (size_t)n);
  for (int ii = 0; ii < list->inum; ii++) {
    const int i = list->ilist[ii];
    const double *hist = hl->firstdouble[i];
    double *out = &s_old_[3 * (size_t)first_[ii]];
    for (int jj = 0; jj < list->numneigh[i]; jj++) {
      const double *sh = &hist[dnum * jj + shear_offset_];
      out[3 * jj] = sh[0]; out[3 * jj + 1] = sh[1]; out[3 * jj + 2] = sh[2];
    }
  }
}

void CrushEnergy::friction_post(double dt)
{
  NeighList *list = pair_ ? pair_->list : NULL;
  NeighList *hl = pair_ ? pair_->listgranhistory : NULL;
  if (!list || !hl || shear_offset_ < 0 || (int)first_.size() != list->inum + 1) return;
  const int dnum = static_cast<PairGran *>(pair_)->dnum();
  double **x = atom->x, **v = atom->v, **omega = atom->omega_flag ? atom->omega : NULL;
  const double *radius = atom->radius;
  const int *type = atom->type;
  const int nlocal = atom->nlocal;
  double D = 0.0;
  for (int ii = 0; ii < list->inum; ii++) {
    const int i = list->ilist[ii];
    if (first_[ii + 1] - first_[ii] != list->numneigh[i]) continue;  // list changed: skip
    const int *jlist = list->firstneigh[i];
    const double *hist = hl->firstdouble[i];
    const double *so = &s_old_[3 * (size_t)first_[ii]];
    for (int jj = 0; jj < list->numneigh[i]; jj++) {
      const int j = jlist[jj] & NEIGHMASK;
      const double mu = mu_.empty() ? 0.0 : mu_[(type[i] - 1) * ntypes_ + (type[j] - 1)];
      if (!(mu > 0.0)) continue;
      const double d[3] = {x[i][0] - x[j][0], x[i][1] - x[j][1], x[i][2] - x[j][2]};
      const double r = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      const double delta = radius[i] + radius[j] - r;
      if (!(delta > 0.0) || !(r > 0.0)) continue;
      const double rinv = 1.0 / r;
      const double en[3] = {d[0] * rinv, d[1] * rinv, d[2] * rinv};
      const double vr[3] = {v[i][0] - v[j][0], v[i][1] - v[j][1], v[i][2] - v[j][2]};
      const double vn = vr[0] * en[0] + vr[1] * en[1] + vr[2] * en[2];
      double vt[3] = {vr[0] - vn * en[0], vr[1] - vn * en[1], vr[2] - vn * en[2]};
      if (omega) {
        const double cri = radius[i] - 0.5 * delta, crj = radius[j] - 0.5 * delta;
        double wr[3];
        for (int c = 0; c < 3; c++) wr[c] = (cri * omega[i][c] + crj * omega[j][c]) * rinv;
        vt[0] -= d[2] * wr[1] - d[1] * wr[2];
        vt[1] -= d[0] * wr[2] - d[2] * wr[0];
        vt[2] -= d[1] * wr[0] - d[0] * wr[1];
      }
      double st[3] = {so[3 * jj] + vt[0] * dt, so[3 * jj + 1] + vt[1] * dt, so[3 * jj + 2] + vt[2] * dt};
      const double rs = st[0] * en[0] + st[1] * en[1] + st[2] * en[2];
      st[0] -= rs * en[0]; st[1] -= rs * en[1]; st[2] -= rs * en[2];
      const double trial = sqrt(st[0] * st[0] + st[1] * st[1] + st[2] * st[2]);
      const double R = effective_radius(radius[i], radius[j]);
      const double kt = tangential_stiffness(delta, R, Gs(type[i], type[j]));
      const double Ff = mu * hertz_normal_force(delta, R, Es(type[i], type[j]));
      if (!(kt * trial > Ff)) continue;  // sticking
      const double *sn = &hist[dnum * jj + shear_offset_];
      const double kept = sqrt(sn[0] * sn[0] + sn[1] * sn[1] + sn[2] * sn[2]);
      const double slip = trial - kept;
      if (slip > 0.0) D += ((j < nlocal) ? 1.0 : 0.5) * Ff * slip;  // newton off: ghost pairs twice
    }
  }
  friction_local_ += D;
}

double CrushEnergy::friction_dissipated()
{
  double all = 0.0;
  MPI_Allreduce(&friction_local_, &all, 1, MPI_DOUBLE, MPI_SUM, world);
  return all;
}
