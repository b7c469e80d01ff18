// SPDX-License-Identifier: GPL-2.0-or-later
/* ----------------------------------------------------------------------
   fix snapshot/hdf5: HDF5 snapshots of particles and contacts at events of
   a trigger quantity, e.g. at the end of every push and every pause of
   fix jack/pile. See the header and docs/fix_snapshot_hdf5.md.

   Cost on a step without a snapshot: one scalar evaluation (a fix or
   compute value, or an equal-style variable) and one comparison.

   Contacts come from LIGGGHTS' own compute pair/gran/local (particle-
   particle) and compute wall/gran/local (particle-mesh wall), created here
   or given by the deck. Both recompute the contact forces from the current
   positions and contact histories without adding them to the particles
   (PairGran::compute_pgl, FixWallGran::post_force_pgl). At end_of_step the
   positions and histories are those the forces of the step were computed
   with, so the recomputed forces are the forces of the step, apart from
   velocity-dependent terms (viscous damping), which see the end-of-step
   velocities.
------------------------------------------------------------------------- */

#include "fix_snapshot_hdf5.h"

#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <numeric>

#include "atom.h"
#include "comm.h"
#include "compute.h"
#include "compute_pair_gran_local.h"
#include "crush_args.h"
#include "error.h"
#include "fix_wall_gran.h"
#include "fix_mesh_surface.h"
#include "force.h"
#include "group.h"
#include "input.h"
#include "modify.h"
#include "pair.h"
#include "update.h"
#include "variable.h"

using namespace LAMMPS_NS;
using namespace FixConst;

namespace {

std::string str(const char *a) { return std::string(a ? a : ""); }

// columns of one packed particle-particle contact row
enum { PP_I, PP_J, PP_CP, PP_F = PP_CP + 3, PP_FN = PP_F + 3, PP_DELTA = PP_FN + 3, PP_NCOL };
// columns of one packed particle-wall contact row
enum { PW_ID, PW_MESH, PW_TRI, PW_CP, PW_F = PW_CP + 3, PW_FN = PW_F + 3,
       PW_DELTA = PW_FN + 3, PW_NCOL };

/* ---------- thin helpers over the serial HDF5 C API (rank 0 only) ---------- */

bool h5_write(hid_t loc, const char *name, hid_t memtype, hid_t filetype, const void *data,
              hsize_t rows, hsize_t cols)
{
  hsize_t dims[2] = {rows, cols};
  hid_t space = H5Screate_simple(cols > 1 ? 2 : 1, dims, NULL);
  if (space < 0) return false;
  hid_t set = H5Dcreate2(loc, name, filetype, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  bool ok = set >= 0;
  // an empty data set is written as such: nothing to transfer
  if (ok && rows > 0) ok = H5Dwrite(set, memtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) >= 0;
  if (set >= 0) H5Dclose(set);
  H5Sclose(space);
  return ok;
}

bool h5_doubles(hid_t loc, const char *name, const std::vector<double> &d, hsize_t rows,
                hsize_t cols)
{
  return h5_write(loc, name, H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, d.empty() ? NULL : &d[0], rows,
                  cols);
}

bool h5_int64s(hid_t loc, const char *name, const std::vector<long long> &d, hsize_t rows,
               hsize_t cols)
{
  return h5_write(loc, name, H5T_NATIVE_LLONG, H5T_STD_I64LE, d.empty() ? NULL : &d[0], rows,
                  cols);
}

bool h5_attr(hid_t loc, const char *name, hid_t memtype, hid_t filetype, const void *v)
{
  hid_t space = H5Screate(H5S_SCALAR);
  hid_t a = H5Acreate2(loc, name, filetype, space, H5P_DEFAULT, H5P_DEFAULT);
  bool ok = a >= 0 && H5Awrite(a, memtype, v) >= 0;
  if (a >= 0) H5Aclose(a);
  H5Sclose(space);
  return ok;
}

bool h5_attr_double(hid_t loc, const char *name, double v)
{
  return h5_attr(loc, name, H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, &v);
}

bool h5_attr_int64(hid_t loc, const char *name, long long v)
{
  return h5_attr(loc, name, H5T_NATIVE_LLONG, H5T_STD_I64LE, &v);
}

bool h5_attr_string(hid_t loc, const char *name, const std::string &s)
{
  hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, s.size() > 0 ? s.size() : 1);
  H5Tset_strpad(type, H5T_STR_NULLTERM);
  bool ok = h5_attr(loc, name, type, type, s.empty() ? "" : s.c_str());
  H5Tclose(type);
  return ok;
}

// rows of a row-major table sorted by the given key columns (all exact
// integers stored as doubles: ids, mesh and triangle indices)
std::vector<size_t> sorted_rows(const std::vector<double> &t, int ncols, int nrows,
                                const std::vector<int> &keys)
{
  std::vector<size_t> order(nrows);
  for (int i = 0; i < nrows; i++) order[i] = i;
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    for (size_t k = 0; k < keys.size(); k++) {
      const double va = t[a * ncols + keys[k]], vb = t[b * ncols + keys[k]];
      if (va != vb) return va < vb;
    }
    return false;
  });
  return order;
}

// columns [c0, c0 + ncol) of the sorted rows
std::vector<double> column_block(const std::vector<double> &t, int ncols,
                                 const std::vector<size_t> &order, int c0, int ncol)
{
  std::vector<double> out(order.size() * ncol);
  for (size_t r = 0; r < order.size(); r++)
    for (int c = 0; c < ncol; c++) out[r * ncol + c] = t[order[r] * ncols + c0 + c];
  return out;
}

std::vector<long long> int_column_block(const std::vector<double> &t, int ncols,
                                        const std::vector<size_t> &order, int c0, int ncol)
{
  std::vector<long long> out(order.size() * ncol);
  for (size_t r = 0; r < order.size(); r++)
    for (int c = 0; c < ncol; c++)
      out[r * ncol + c] = (long long)llround(t[order[r] * ncols + c0 + c]);
  return out;
}

}  // namespace

/* ---------------------------------------------------------------------- */

FixSnapshotHdf5::FixSnapshotHdf5(LAMMPS *lmp, int narg, char **arg) :
  Fix(lmp, narg, arg),
  contacts_(false), own_pair_local_(false), own_wall_local_(false), have_wall_local_(false),
  itrigger_(-1), pair_local_(NULL), wall_local_(NULL),
  have_prev_(false), prev_(0.0), nsnap_(0)
{
  parse_args(narg, arg);

  scalar_flag = 1;     // f_ID = number of snapshots written so far
  global_freq = 1;
  extscalar = 0;
}

/* ---------------------------------------------------------------------- */

FixSnapshotHdf5::~FixSnapshotHdf5()
{
  // the computes created here are deleted by Modify with the others (at
  // exit the pair style is gone before the computes, so they must not
  // unregister from it); 'unfix' removes them in pre_delete
}

/* ---------------------------------------------------------------------- */

FixSnapshotHdf5::Ref FixSnapshotHdf5::parse_ref(const char *key, const char *text, bool peratom)
{
  Ref r;
  r.text = text;
  r.index = 0;
  const std::string t = text;
  const char *what = peratom
      ? "c_ID, c_ID[n], f_ID, f_ID[n] (per-atom) or v_name (atom-style variable)"
      : "c_ID, c_ID[n], f_ID, f_ID[n] (global scalar or vector element) or v_name "
        "(equal-style variable)";
  if (t.size() < 3 || t[1] != '_' || (t[0] != 'c' && t[0] != 'f' && t[0] != 'v'))
    error->all(FLERR, ("fix snapshot/hdf5: keyword '" + str(key) + "' got '" + t +
                       "'; expected " + what).c_str());
  r.which = t[0];
  std::string name = t.substr(2);
  const size_t b = name.find('[');
  if (b != std::string::npos) {
    if (r.which == 'v' || name[name.size() - 1] != ']')
      error->all(FLERR, ("fix snapshot/hdf5: keyword '" + str(key) + "' got '" + t +
                         "'; expected " + what).c_str());
    const std::string idx = name.substr(b + 1, name.size() - b - 2);
    char *end = NULL;
    const long n = strtol(idx.c_str(), &end, 10);
    if (idx.empty() || *end != '\0' || n < 1 || n > 1000000)
      error->all(FLERR, ("fix snapshot/hdf5: keyword '" + str(key) + "': index of '" + t +
                         "' must be an integer >= 1").c_str());
    r.index = (int)n;
    name = name.substr(0, b);
  }
  if (name.empty())
    error->all(FLERR, ("fix snapshot/hdf5: keyword '" + str(key) + "' got '" + t +
                       "'; expected " + what).c_str());
  r.id = name;
  return r;
}

void FixSnapshotHdf5::parse_args(int narg, char **arg)
{
  // fix ID group snapshot/hdf5 file PREFIX trigger X [leaving v1 v2 ...]
  //     [contacts yes|no] [pair_local CID] [wall_local CID] [values X1 X2 ...]
  CrushArgs a(error, "fix snapshot/hdf5", narg, arg, 3,
              {"file", "trigger", "leaving", "contacts", "pair_local", "wall_local", "values"});
  while (a.next()) {
    if (a.is("file")) {
      prefix_ = a.word("the prefix of the snapshot files PREFIX_<step>.h5");
    } else if (a.is("trigger")) {
      trigger_ = parse_ref("trigger", a.word("c_ID, c_ID[n], f_ID, f_ID[n] or v_name").c_str(),
                           false);
    } else if (a.is("leaving")) {  // one or more numbers, up to the next keyword
      while (a.has_value())
        leaving_.push_back(a.number(CrushKernels::arg_any("a finite number (a value of the trigger)")));
      if (leaving_.empty())
        a.fail("keyword 'leaving' needs at least one value");
    } else if (a.is("contacts")) {
      contacts_ = a.yes_no();
    } else if (a.is("pair_local")) {
      pair_local_id_ = a.word("the ID of a compute pair/gran/local");
    } else if (a.is("wall_local")) {
      wall_local_id_ = a.word("the ID of a compute wall/gran/local, or none");
    } else {  // values: one or more per-atom references, up to the next keyword
      while (a.has_value())
        values_.push_back(parse_ref("values", a.word("").c_str(), true));
      if (values_.empty())
        a.fail("keyword 'values' needs at least one per-atom quantity (c_ID, c_ID[n], f_ID, "
               "f_ID[n] or v_name)");
    }
  }

  if (!a.given("file"))
    error->all(FLERR, "fix snapshot/hdf5: missing required keyword 'file' (prefix of the "
                      "snapshot files PREFIX_<step>.h5)");
  if (!a.given("trigger"))
    error->all(FLERR, "fix snapshot/hdf5: missing required keyword 'trigger' (c_ID, c_ID[n], "
                      "f_ID, f_ID[n] or v_name; e.g. f_JACK[6], the phase of fix jack/pile)");
  if (!contacts_ && (!pair_local_id_.empty() || !wall_local_id_.empty()))
    error->all(FLERR, "fix snapshot/hdf5: keywords 'pair_local' and 'wall_local' need "
                      "'contacts yes'");
  for (size_t i = 0; i < values_.size(); i++)
    for (size_t j = 0; j < i; j++)
      if (values_[i].text == values_[j].text)
        error->all(FLERR, ("fix snapshot/hdf5: keyword 'values' names '" + values_[i].text +
                           "' twice").c_str());
}

/* ---------------------------------------------------------------------- */

int FixSnapshotHdf5::setmask()
{
  int mask = 0;
  mask |= END_OF_STEP;
  return mask;
}

/* ----------------------------------------------------------------------
   with contacts: the computes that extract them. LIGGGHTS allows one
   pair/gran/local per pair style and one wall/gran/local per wall fix, and
   only before the first run, so a deck that needs them for its own output
   too passes their IDs (pair_local, wall_local).
------------------------------------------------------------------------- */

void FixSnapshotHdf5::post_create()
{
  if (!contacts_) return;
  const std::string group_name = group->names[igroup];
  // the condition under which LIGGGHTS' compute pair/gran/local refuses to
  // be created (after read_restart it is allowed until the first run)
  const bool after_first_run = update->ntimestep > 0 && !modify->fix_restart_in_progress();

  if (pair_local_id_.empty()) {
    if (!force->pair || !force->pair_match("gran", 0))
      error->all(FLERR, "fix snapshot/hdf5: 'contacts yes' needs a granular pair style "
                        "(pair_style gran) defined before this fix");
    for (int i = 0; i < modify->ncompute; i++)
      if (strcmp(modify->compute[i]->style, "pair/gran/local") == 0)
        error->all(FLERR, ("fix snapshot/hdf5: the deck already has compute pair/gran/local '" +
                           str(modify->compute[i]->id) + "' and LIGGGHTS allows only one; pass "
                           "it with keyword 'pair_local " + str(modify->compute[i]->id) +
                           "'").c_str());
    if (after_first_run)
      error->all(FLERR, "fix snapshot/hdf5: 'contacts yes' creates a compute pair/gran/local, "
                        "which LIGGGHTS allows only before the first run; define this fix "
                        "before the first run, or define 'compute CID all pair/gran/local pos "
                        "id force force_normal delta contactPoint' before the first run and "
                        "pass it with 'pair_local CID'");
    pair_local_id_ = std::string(id) + "_pp";
    const char *a[] = {pair_local_id_.c_str(), group_name.c_str(), "pair/gran/local", "pos",
                       "id", "force", "force_normal", "delta", "contactPoint"};
    modify->add_compute(9, const_cast<char **>(a));
    own_pair_local_ = true;
  }

  if (wall_local_id_ == "none") {
    // no particle-wall contacts: a deck that must unfix its wall fix later
    // cannot have a wall/gran/local (LIGGGHTS refuses the unfix)
    wall_local_id_.clear();
  } else if (wall_local_id_.empty()) {
    // LIGGGHTS' wall/gran/local attaches to the last fix wall/gran with mesh
    // walls; primitive walls (planes, cylinders) have no contact list
    bool mesh_wall = false;
    for (int i = 0; i < modify->nfix; i++) {
      FixWallGran *w = dynamic_cast<FixWallGran *>(modify->fix[i]);
      if (w && w->is_mesh_wall()) mesh_wall = true;
    }
    bool deck_has_one = false;
    for (int i = 0; i < modify->ncompute; i++)
      if (strcmp(modify->compute[i]->style, "wall/gran/local") == 0) {
        wall_local_id_ = modify->compute[i]->id;   // reuse: only one is allowed
        deck_has_one = true;
      }
    if (mesh_wall && !deck_has_one) {
      if (after_first_run)
        error->all(FLERR, "fix snapshot/hdf5: 'contacts yes' with mesh walls creates a compute "
                          "wall/gran/local, which LIGGGHTS allows only before the first run; "
                          "define this fix before the first run, or pass 'wall_local CID'");
      wall_local_id_ = std::string(id) + "_pw";
      const char *a[] = {wall_local_id_.c_str(), group_name.c_str(), "wall/gran/local", "pos",
                         "id", "force", "force_normal", "delta"};
      modify->add_compute(8, const_cast<char **>(a));
      own_wall_local_ = true;
    }
  }
  have_wall_local_ = !wall_local_id_.empty();
}

/* ---------------------------------------------------------------------- */

void FixSnapshotHdf5::pre_delete(bool unfixflag)
{
  // 'unfix': the pair style and wall fixes still exist, unregister from them
  if (!unfixflag) return;
  if (own_pair_local_ && modify->find_compute(pair_local_id_.c_str()) >= 0)
    modify->delete_compute(pair_local_id_.c_str(), true);
  if (own_wall_local_ && modify->find_compute(wall_local_id_.c_str()) >= 0)
    modify->delete_compute(wall_local_id_.c_str(), true);
  own_pair_local_ = own_wall_local_ = false;
}

/* ---------------------------------------------------------------------- */

void FixSnapshotHdf5::check_local_compute(const char *key, const std::string &cid, bool wall,
                                          ComputePairGranLocal **out)
{
  const int ic = modify->find_compute(cid.c_str());
  if (ic < 0)
    error->all(FLERR, ("fix snapshot/hdf5: keyword '" + str(key) + "': no compute with ID '" +
                       cid + "'").c_str());
  Compute *c = modify->compute[ic];
  const char *style = wall ? "wall/gran/local" : "pair/gran/local";
  ComputePairGranLocal *p = dynamic_cast<ComputePairGranLocal *>(c);
  if (!p || strcmp(c->style, style) != 0)
    error->all(FLERR, ("fix snapshot/hdf5: keyword '" + str(key) + "': compute '" + cid + "' (" +
                       str(c->style) + ") is not a compute " + style).c_str());
  const bool ok = p->offset_x1() >= 0 && p->offset_id1() >= 0 && p->offset_f() >= 0 &&
                  p->offset_fn() >= 0 && p->offset_delta() >= 0 &&
                  (wall || p->offset_contact_point() >= 0);
  if (!ok)
    error->all(FLERR, ("fix snapshot/hdf5: keyword '" + str(key) + "': compute '" + cid +
                       "' must store " + (wall ? "pos id force force_normal delta"
                                               : "pos id force force_normal delta contactPoint") +
                       " (list these keywords in the compute command)").c_str());
  if (c->igroup != igroup && comm->me == 0)
    error->warning(FLERR, ("fix snapshot/hdf5: compute '" + cid + "' has a different group "
                           "than the fix; its contacts are written as they are").c_str());
  *out = p;
}

void FixSnapshotHdf5::init()
{
  if (strstr(update->integrate_style, "respa"))
    error->all(FLERR, "fix snapshot/hdf5 does not support run_style respa");

  // trigger
  const Ref &t = trigger_;
  if (t.which == 'f') {
    itrigger_ = modify->find_fix(t.id.c_str());
    if (itrigger_ < 0)
      error->all(FLERR, ("fix snapshot/hdf5: keyword 'trigger': no fix with ID '" + t.id +
                         "'").c_str());
    Fix *f = modify->fix[itrigger_];
    if (t.index == 0 && !f->scalar_flag)
      error->all(FLERR, ("fix snapshot/hdf5: keyword 'trigger': fix '" + t.id +
                         "' computes no global scalar; use f_" + t.id + "[n]").c_str());
    if (t.index > 0 && (!f->vector_flag || t.index > f->size_vector))
      error->all(FLERR, ("fix snapshot/hdf5: keyword 'trigger': fix '" + t.id +
                         "' has no global vector element " + std::to_string(t.index) +
                         (f->vector_flag ? " (allowed: 1.." + std::to_string(f->size_vector) + ")"
                                         : std::string(" (no global vector)"))).c_str());
    if (f->global_freq != 1)
      error->all(FLERR, ("fix snapshot/hdf5: keyword 'trigger': fix '" + t.id +
                         "' gives its global values every " + std::to_string(f->global_freq) +
                         " steps; the trigger is read every step").c_str());
    // end_of_step of fixes runs in the order of definition: read after the
    // trigger fix has updated its value for this step
    const int me = modify->find_fix(id);
    if (itrigger_ > me)
      error->all(FLERR, ("fix snapshot/hdf5: keyword 'trigger': fix '" + t.id + "' is defined "
                         "after this fix; define fix snapshot/hdf5 after it, so that it reads "
                         "the value of the current step").c_str());
  } else if (t.which == 'c') {
    itrigger_ = modify->find_compute(t.id.c_str());
    if (itrigger_ < 0)
      error->all(FLERR, ("fix snapshot/hdf5: keyword 'trigger': no compute with ID '" + t.id +
                         "'").c_str());
    Compute *c = modify->compute[itrigger_];
    if (t.index == 0 && !c->scalar_flag)
      error->all(FLERR, ("fix snapshot/hdf5: keyword 'trigger': compute '" + t.id +
                         "' computes no global scalar").c_str());
    if (t.index > 0 && (!c->vector_flag || t.index > c->size_vector))
      error->all(FLERR, ("fix snapshot/hdf5: keyword 'trigger': compute '" + t.id +
                         "' has no global vector element " + std::to_string(t.index)).c_str());
  } else {
    itrigger_ = input->variable->find(const_cast<char *>(t.id.c_str()));
    if (itrigger_ < 0)
      error->all(FLERR, ("fix snapshot/hdf5: keyword 'trigger': no variable '" + t.id +
                         "'").c_str());
    if (!input->variable->equalstyle(itrigger_))
      error->all(FLERR, ("fix snapshot/hdf5: keyword 'trigger': variable '" + t.id +
                         "' is not equal-style").c_str());
  }

  // per-atom values
  ivalue_.assign(values_.size(), -1);
  for (size_t k = 0; k < values_.size(); k++) {
    const Ref &r = values_[k];
    int cols = 0, flag = 0, freq = 1;
    const char *kind = "compute";
    if (r.which == 'c') {
      ivalue_[k] = modify->find_compute(r.id.c_str());
      if (ivalue_[k] >= 0) {
        Compute *c = modify->compute[ivalue_[k]];
        flag = c->peratom_flag;
        cols = c->size_peratom_cols;
      }
    } else if (r.which == 'f') {
      kind = "fix";
      ivalue_[k] = modify->find_fix(r.id.c_str());
      if (ivalue_[k] >= 0) {
        Fix *f = modify->fix[ivalue_[k]];
        flag = f->peratom_flag;
        cols = f->size_peratom_cols;
        freq = f->peratom_freq;
      }
    } else {
      kind = "variable";
      ivalue_[k] = input->variable->find(const_cast<char *>(r.id.c_str()));
      if (ivalue_[k] >= 0 && !input->variable->atomstyle(ivalue_[k]))
        error->all(FLERR, ("fix snapshot/hdf5: keyword 'values': variable '" + r.id +
                           "' is not atom-style").c_str());
      flag = 1;
    }
    if (ivalue_[k] < 0)
      error->all(FLERR, ("fix snapshot/hdf5: keyword 'values': no " + str(kind) + " '" + r.id +
                         "' (for '" + r.text + "')").c_str());
    if (!flag)
      error->all(FLERR, ("fix snapshot/hdf5: keyword 'values': " + str(kind) + " '" + r.id +
                         "' computes no per-atom values").c_str());
    if (r.index > 0 && (cols == 0 || r.index > cols))
      error->all(FLERR, ("fix snapshot/hdf5: keyword 'values': '" + r.text + "': " + str(kind) +
                         " '" + r.id + "' has " +
                         (cols == 0 ? std::string("a per-atom vector; write it without [n]")
                                    : "per-atom columns 1.." + std::to_string(cols))).c_str());
    if (freq != 1)
      error->all(FLERR, ("fix snapshot/hdf5: keyword 'values': fix '" + r.id + "' gives per-atom "
                         "values every " + std::to_string(freq) + " steps; snapshots need them "
                         "on every step").c_str());
  }

  // contacts
  pair_local_ = wall_local_ = NULL;
  if (contacts_) {
    check_local_compute("pair_local", pair_local_id_, false, &pair_local_);
    if (have_wall_local_) check_local_compute("wall_local", wall_local_id_, true, &wall_local_);
    else {
      bool mesh_wall = false;
      for (int i = 0; i < modify->nfix; i++) {
        FixWallGran *w = dynamic_cast<FixWallGran *>(modify->fix[i]);
        if (w && w->is_mesh_wall()) mesh_wall = true;
      }
      if (mesh_wall && comm->me == 0)
        error->warning(FLERR, "fix snapshot/hdf5: mesh walls were defined after this fix; their "
                              "contacts are not written (define the fix after them)");
    }
  }
}

/* ---------------------------------------------------------------------- */

double FixSnapshotHdf5::eval_trigger()
{
  const Ref &t = trigger_;
  if (t.which == 'f') {
    Fix *f = modify->fix[itrigger_];
    return t.index == 0 ? f->compute_scalar() : f->compute_vector(t.index - 1);
  }
  double v;
  modify->clearstep_compute();
  if (t.which == 'c') {
    Compute *c = modify->compute[itrigger_];
    if (t.index == 0) {
      if (c->invoked_scalar != update->ntimestep) c->compute_scalar();
      v = c->scalar;
    } else {
      if (c->invoked_vector != update->ntimestep) c->compute_vector();
      v = c->vector[t.index - 1];
    }
  } else {
    v = input->variable->compute_equal(itrigger_);
  }
  modify->addstep_compute(update->ntimestep + 1);
  return v;
}

bool FixSnapshotHdf5::leaves_listed(double old_value) const
{
  if (leaving_.empty()) return true;
  for (size_t i = 0; i < leaving_.size(); i++)
    if (fabs(old_value - leaving_[i]) <= 1e-9 * std::max(1.0, fabs(leaving_[i]))) return true;
  return false;
}

/* ---------------------------------------------------------------------- */

void FixSnapshotHdf5::setup(int)
{
  // per-atom computes that need a tally in the force loop (stress/atom,
  // pe/atom) must be tallied on every step: a snapshot step is not known
  // in advance
  for (size_t k = 0; k < values_.size(); k++)
    if (values_[k].which == 'c') {
      Compute *c = modify->compute[ivalue_[k]];
      if (c->pressatomflag || c->peatomflag) c->addstep(update->ntimestep + 1);
    }
  prev_ = eval_trigger();
  have_prev_ = true;
}

void FixSnapshotHdf5::end_of_step()
{
  const double v = eval_trigger();
  if (have_prev_ && v != prev_ && leaves_listed(prev_)) write_snapshot(prev_, v);
  prev_ = v;
  have_prev_ = true;
  for (size_t k = 0; k < values_.size(); k++)
    if (values_[k].which == 'c') {
      Compute *c = modify->compute[ivalue_[k]];
      if (c->pressatomflag || c->peatomflag) c->addstep(update->ntimestep + 1);
    }
}

double FixSnapshotHdf5::compute_scalar()
{
  return (double)nsnap_;
}

/* ---------------------------------------------------------------------- */

int FixSnapshotHdf5::value_columns(const Ref &r, int ivalue) const
{
  if (r.which == 'v' || r.index > 0) return 1;
  const int cols = r.which == 'c' ? modify->compute[ivalue]->size_peratom_cols
                                  : modify->fix[ivalue]->size_peratom_cols;
  return cols == 0 ? 1 : cols;
}

// per-atom value(s) of r for the owned atoms of the group, into buf at rows
// of 'stride' doubles starting at column 'offset'
void FixSnapshotHdf5::fill_value(const Ref &r, int ivalue, int ncol, std::vector<double> &buf,
                                 int stride, int offset)
{
  const int nlocal = atom->nlocal;
  const int *mask = atom->mask;
  double *vec = NULL;
  double **arr = NULL;
  std::vector<double> tmp;
  if (r.which == 'c') {
    Compute *c = modify->compute[ivalue];
    if (c->invoked_peratom != update->ntimestep) {
      modify->clearstep_compute();
      c->compute_peratom();
      modify->addstep_compute(update->ntimestep + 1);
    }
    if (c->size_peratom_cols == 0) vec = c->vector_atom;
    else arr = c->array_atom;
  } else if (r.which == 'f') {
    Fix *f = modify->fix[ivalue];
    if (f->size_peratom_cols == 0) vec = f->vector_atom;
    else arr = f->array_atom;
  } else {
    tmp.assign(nlocal > 0 ? nlocal : 1, 0.0);
    modify->clearstep_compute();
    input->variable->compute_atom(ivalue, igroup, &tmp[0], 1, 0);
    modify->addstep_compute(update->ntimestep + 1);
    vec = &tmp[0];
  }
  int row = 0;
  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    double *dst = &buf[(size_t)row * stride + offset];
    if (vec) dst[0] = vec[i];
    else if (r.index > 0) dst[0] = arr[i][r.index - 1];
    else for (int c = 0; c < ncol; c++) dst[c] = arr[i][c];
    row++;
  }
}

/* ----------------------------------------------------------------------
   gather a row-major table of ncols doubles per row to rank 0; returns the
   total number of rows (on rank 0; 0 elsewhere)
------------------------------------------------------------------------- */

int FixSnapshotHdf5::gather(const std::vector<double> &local, int ncols,
                            std::vector<double> &all)
{
  const int nprocs = comm->nprocs;
  int n = (int)local.size();
  std::vector<int> counts(nprocs, 0), displs(nprocs, 0);
  MPI_Gather(&n, 1, MPI_INT, &counts[0], 1, MPI_INT, 0, world);
  long total = 0;
  if (comm->me == 0) {
    for (int p = 0; p < nprocs; p++) {
      displs[p] = (int)total;
      total += counts[p];
    }
    if (total > 2147483647L)
      error->one(FLERR, "fix snapshot/hdf5: snapshot too large to gather (more than 2^31 values)");
    all.assign(total, 0.0);
  }
  MPI_Gatherv(local.empty() ? NULL : const_cast<double *>(&local[0]), n, MPI_DOUBLE,
              all.empty() ? NULL : &all[0], &counts[0], &displs[0], MPI_DOUBLE, 0, world);
  return comm->me == 0 ? (int)(total / ncols) : 0;
}

/* ----------------------------------------------------------------------
   contacts of one compute pair/gran/local or wall/gran/local, packed into
   rows (PP_* or PW_* columns) and gathered to rank 0. Pairs are stored with
   id_i < id_j and the force on particle i (the compute gives the force on
   its first particle; a swap flips the sign).
------------------------------------------------------------------------- */

void FixSnapshotHdf5::gather_contacts(ComputePairGranLocal *c, bool wall, int &ncols,
                                      std::vector<double> &all, int &nrows)
{
  c->compute_local();
  const int rows = c->size_local_rows;
  double **a = c->array_local;
  const int ox = c->offset_x1(), oid = c->offset_id1(), of = c->offset_f(),
            ofn = c->offset_fn(), od = c->offset_delta();
  ncols = wall ? (int)PW_NCOL : (int)PP_NCOL;
  std::vector<double> local((size_t)rows * ncols);
  for (int r = 0; r < rows; r++) {
    double *row = &local[(size_t)r * ncols];
    const double *src = a[r];
    if (wall) {
      // wall/gran/local: id columns are (mesh index in the wall fix,
      // triangle id, particle id); pos starts with the contact point
      row[PW_ID] = src[oid + 2];
      row[PW_MESH] = src[oid];
      row[PW_TRI] = src[oid + 1];
      for (int d = 0; d < 3; d++) {
        row[PW_CP + d] = src[ox + d];
        row[PW_F + d] = src[of + d];
        row[PW_FN + d] = src[ofn + d];
      }
      row[PW_DELTA] = src[od];
    } else {
      const bool swap = src[oid] > src[oid + 1];
      const double sign = swap ? -1.0 : 1.0;
      row[PP_I] = swap ? src[oid + 1] : src[oid];
      row[PP_J] = swap ? src[oid] : src[oid + 1];
      const int ocp = c->offset_contact_point();
      for (int d = 0; d < 3; d++) {
        row[PP_CP + d] = src[ocp + d];
        row[PP_F + d] = sign * src[of + d];
        row[PP_FN + d] = sign * src[ofn + d];
      }
      row[PP_DELTA] = src[od];
    }
  }
  nrows = gather(local, ncols, all);
}

/* ---------------------------------------------------------------------- */

void FixSnapshotHdf5::write_snapshot(double old_value, double new_value)
{
  const double t0 = MPI_Wtime();
  const int nlocal = atom->nlocal;
  const int *mask = atom->mask;
  const bigint step = update->ntimestep;

  // particles: id type x(3) v(3) radius, then the requested values
  enum { P_ID, P_TYPE, P_X, P_V = P_X + 3, P_R = P_V + 3, P_NBASE };
  std::vector<int> vcols(values_.size());
  int ncols = P_NBASE;
  for (size_t k = 0; k < values_.size(); k++) {
    vcols[k] = value_columns(values_[k], ivalue_[k]);
    ncols += vcols[k];
  }
  int nmine = 0;
  for (int i = 0; i < nlocal; i++)
    if (mask[i] & groupbit) nmine++;
  std::vector<double> local((size_t)nmine * ncols);
  int row = 0;
  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    double *dst = &local[(size_t)row * ncols];
    dst[P_ID] = (double)atom->tag[i];
    dst[P_TYPE] = (double)atom->type[i];
    for (int d = 0; d < 3; d++) {
      dst[P_X + d] = atom->x[i][d];
      dst[P_V + d] = atom->v[i][d];
    }
    dst[P_R] = atom->radius ? atom->radius[i] : 0.0;
    row++;
  }
  int off = P_NBASE;
  for (size_t k = 0; k < values_.size(); k++) {
    fill_value(values_[k], ivalue_[k], vcols[k], local, ncols, off);
    off += vcols[k];
  }
  std::vector<double> parts;
  const int np = gather(local, ncols, parts);

  std::vector<double> pp, pw;
  int pp_cols = PP_NCOL, pw_cols = PW_NCOL, npp = 0, npw = 0;
  if (pair_local_) gather_contacts(pair_local_, false, pp_cols, pp, npp);
  if (wall_local_) gather_contacts(wall_local_, true, pw_cols, pw, npw);

  nsnap_++;
  char name[64];
  snprintf(name, sizeof(name), "_" BIGINT_FORMAT ".h5", step);
  const std::string path = prefix_ + name;

  int ok = 1;
  if (comm->me == 0) {
    hid_t file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    ok = file >= 0;
    if (ok) {
      bool w = true;
      w &= h5_attr_int64(file, "step", (long long)step);
      w &= h5_attr_double(file, "time", update->get_cur_time());
      w &= h5_attr_double(file, "dt", update->dt);
      w &= h5_attr_string(file, "trigger", trigger_.text);
      w &= h5_attr_double(file, "trigger_old", old_value);
      w &= h5_attr_double(file, "trigger_new", new_value);
      w &= h5_attr_int64(file, "snapshot", nsnap_);
      w &= h5_attr_string(file, "fix", id);
      w &= h5_attr_string(file, "group", group->names[igroup]);

      // particles sorted by id
      hid_t g = H5Gcreate2(file, "particles", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
      std::vector<size_t> order = sorted_rows(parts, ncols, np, std::vector<int>(1, P_ID));
      w &= h5_attr_int64(g, "count", np);
      w &= h5_int64s(g, "id", int_column_block(parts, ncols, order, P_ID, 1), np, 1);
      {
        std::vector<long long> t = int_column_block(parts, ncols, order, P_TYPE, 1);
        std::vector<int> ti(t.begin(), t.end());
        w &= h5_write(g, "type", H5T_NATIVE_INT, H5T_STD_I32LE, ti.empty() ? NULL : &ti[0], np, 1);
      }
      w &= h5_doubles(g, "x", column_block(parts, ncols, order, P_X, 3), np, 3);
      w &= h5_doubles(g, "v", column_block(parts, ncols, order, P_V, 3), np, 3);
      w &= h5_doubles(g, "radius", column_block(parts, ncols, order, P_R, 1), np, 1);
      if (!values_.empty()) {
        hid_t gv = H5Gcreate2(g, "values", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
        int c0 = P_NBASE;
        for (size_t k = 0; k < values_.size(); k++) {
          w &= h5_doubles(gv, values_[k].text.c_str(), column_block(parts, ncols, order, c0,
                                                                    vcols[k]),
                          np, vcols[k]);
          c0 += vcols[k];
        }
        H5Gclose(gv);
      }
      H5Gclose(g);

      if (contacts_) {
        hid_t gc = H5Gcreate2(file, "contacts", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
        hid_t g1 = H5Gcreate2(gc, "pp", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
        std::vector<int> k2;
        k2.push_back(PP_I);
        k2.push_back(PP_J);
        order = sorted_rows(pp, pp_cols, npp, k2);
        w &= h5_attr_int64(g1, "count", npp);
        w &= h5_attr_string(g1, "compute", pair_local_id_);
        w &= h5_int64s(g1, "id", int_column_block(pp, pp_cols, order, PP_I, 2), npp, 2);
        w &= h5_doubles(g1, "contact_point", column_block(pp, pp_cols, order, PP_CP, 3), npp, 3);
        w &= h5_doubles(g1, "force", column_block(pp, pp_cols, order, PP_F, 3), npp, 3);
        w &= h5_doubles(g1, "force_normal", column_block(pp, pp_cols, order, PP_FN, 3), npp, 3);
        w &= h5_doubles(g1, "overlap", column_block(pp, pp_cols, order, PP_DELTA, 1), npp, 1);
        H5Gclose(g1);
        if (wall_local_) {
          hid_t g2 = H5Gcreate2(gc, "pw", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
          std::vector<int> k3;
          k3.push_back(PW_ID);
          k3.push_back(PW_MESH);
          k3.push_back(PW_TRI);
          order = sorted_rows(pw, pw_cols, npw, k3);
          w &= h5_attr_int64(g2, "count", npw);
          w &= h5_attr_string(g2, "compute", wall_local_id_);
          // the meshes in the order of the 'mesh' index: those of the fix
          // wall/gran LIGGGHTS attaches wall/gran/local to (the last one
          // with mesh walls)
          std::string wall_fix, meshes;
          for (int i = 0; i < modify->nfix; i++) {
            FixWallGran *fw = dynamic_cast<FixWallGran *>(modify->fix[i]);
            if (!fw || !fw->is_mesh_wall()) continue;
            wall_fix = fw->id;
            meshes.clear();
            for (int m = 0; m < fw->n_meshes(); m++)
              meshes += (m ? " " : "") + str(fw->mesh_list()[m]->id);
          }
          w &= h5_attr_string(g2, "wall_fix", wall_fix);
          w &= h5_attr_string(g2, "meshes", meshes);
          w &= h5_int64s(g2, "id", int_column_block(pw, pw_cols, order, PW_ID, 1), npw, 1);
          {
            std::vector<long long> m = int_column_block(pw, pw_cols, order, PW_MESH, 1);
            std::vector<int> mi(m.begin(), m.end());
            w &= h5_write(g2, "mesh", H5T_NATIVE_INT, H5T_STD_I32LE, mi.empty() ? NULL : &mi[0],
                          npw, 1);
          }
          w &= h5_int64s(g2, "triangle", int_column_block(pw, pw_cols, order, PW_TRI, 1), npw, 1);
          w &= h5_doubles(g2, "contact_point", column_block(pw, pw_cols, order, PW_CP, 3), npw, 3);
          w &= h5_doubles(g2, "force", column_block(pw, pw_cols, order, PW_F, 3), npw, 3);
          w &= h5_doubles(g2, "force_normal", column_block(pw, pw_cols, order, PW_FN, 3), npw, 3);
          w &= h5_doubles(g2, "overlap", column_block(pw, pw_cols, order, PW_DELTA, 1), npw, 1);
          H5Gclose(g2);
        }
        H5Gclose(gc);
      }
      if (H5Fclose(file) < 0) w = false;
      ok = w ? 1 : 2;
    }
  }
  MPI_Bcast(&ok, 1, MPI_INT, 0, world);
  if (ok == 0)
    error->all(FLERR, ("fix snapshot/hdf5: cannot create file '" + path + "' (keyword 'file' "
                       "gives the prefix " + prefix_ + "; does its folder exist?)").c_str());
  if (ok == 2)
    error->all(FLERR, ("fix snapshot/hdf5: writing '" + path + "' failed (HDF5 error above; "
                       "disk full?)").c_str());
  if (comm->me == 0) {
    char line[512];
    snprintf(line, sizeof(line),
             "fix snapshot/hdf5 %s: step " BIGINT_FORMAT ", %s %.10g -> %.10g: wrote %s "
             "(%d particles, %d pair and %d wall contacts, %.3g s)\n",
             id, step, trigger_.text.c_str(), old_value, new_value, path.c_str(), np, npp, npw,
             MPI_Wtime() - t0);
    if (screen) fputs(line, screen);
    if (logfile) fputs(line, logfile);
  }
}
