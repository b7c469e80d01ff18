// SPDX-License-Identifier: GPL-2.0-or-later
/* ----------------------------------------------------------------------
   fix crush/particle: contact screening, which contacts have reached their
   limit (docs/fix_crush_particle.md "Contact screening"). Called by
   FixCrushParticle::detect (end_of_step, and setup) through
   find_candidates_pairs and find_candidates_walls; each contact over its
   limit is recorded by consider() as the particle's candidate to break in
   the next pre_exchange (fix_crush_particle_break.cpp). With margin_skip
   the lists far from any limit are skipped, exactly (crush_breakage_kernel.h
   margin_holds, pair_limit_margin). The limit itself: the criterion
   (fix_crush_particle_criterion.{h,cpp}).
   Exercised by tests/integration/test_crush_single_grain.py (particle and
   wall contacts), test_crush_parallel.py (margin_skip yes/no give the same
   events at 1 and 2 ranks, ghost pairs), test_crush_errors.py.
------------------------------------------------------------------------- */

#include "fix_crush_particle.h"
#include "fix_crush_particle_criterion.h"

#include <algorithm>
#include <cmath>

#include "atom.h"
#include "crush_breakage_kernel.h"
#include "crush_criterion_kernel.h"
#include "crush_wall_contacts.h"
#include "fix_mesh_surface.h"
#include "fix_wall_gran.h"
#include "neigh_list.h"
#include "neighbor.h"
#include "pair.h"
#include "tri_mesh.h"

using namespace LAMMPS_NS;
using namespace FixConst;
using namespace CrushKernels;

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
