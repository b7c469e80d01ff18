// SPDX-License-Identifier: GPL-2.0-or-later
/* ----------------------------------------------------------------------
   fix snapshot/hdf5: HDF5 snapshots of particles and contacts at events of
   a trigger quantity, e.g. at the end of every push and every pause of
   fix jack/pile. See the header and docs/fix_snapshot_hdf5.md.

   This file: the keywords, the trigger and the contact computes. What a
   snapshot records is gathered in fix_snapshot_hdf5_record.cpp; the HDF5
   file is written by snapshot_hdf5_writer.{h,cpp}.
   Exercised by tests/integration/test_snapshot_hdf5.py and
   test_bad_input.py (wrong keywords).

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
    error->all(FLERR, ("fix snapshot/hdf5: keyword '" + arg_text(key) + "' got '" + t +
                       "'; expected " + what).c_str());
  r.which = t[0];
  std::string name = t.substr(2);
  const size_t b = name.find('[');
  if (b != std::string::npos) {
    if (r.which == 'v' || name[name.size() - 1] != ']')
      error->all(FLERR, ("fix snapshot/hdf5: keyword '" + arg_text(key) + "' got '" + t +
                         "'; expected " + what).c_str());
    const std::string idx = name.substr(b + 1, name.size() - b - 2);
    char *end = NULL;
    const long n = strtol(idx.c_str(), &end, 10);
    if (idx.empty() || *end != '\0' || n < 1 || n > 1000000)
      error->all(FLERR, ("fix snapshot/hdf5: keyword '" + arg_text(key) + "': index of '" + t +
                         "' must be an integer >= 1").c_str());
    r.index = (int)n;
    name = name.substr(0, b);
  }
  if (name.empty())
    error->all(FLERR, ("fix snapshot/hdf5: keyword '" + arg_text(key) + "' got '" + t +
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
                           arg_text(modify->compute[i]->id) +
                           "' and LIGGGHTS allows only one; pass "
                           "it with keyword 'pair_local " + arg_text(modify->compute[i]->id) +
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
    error->all(FLERR, ("fix snapshot/hdf5: keyword '" + arg_text(key) + "': no compute with ID '" +
                       cid + "'").c_str());
  Compute *c = modify->compute[ic];
  const char *style = wall ? "wall/gran/local" : "pair/gran/local";
  ComputePairGranLocal *p = dynamic_cast<ComputePairGranLocal *>(c);
  if (!p || strcmp(c->style, style) != 0)
    error->all(FLERR, ("fix snapshot/hdf5: keyword '" + arg_text(key) + "': compute '" + cid +
                       "' (" +
                       arg_text(c->style) + ") is not a compute " + style).c_str());
  const bool ok = p->offset_x1() >= 0 && p->offset_id1() >= 0 && p->offset_f() >= 0 &&
                  p->offset_fn() >= 0 && p->offset_delta() >= 0 &&
                  (wall || p->offset_contact_point() >= 0);
  if (!ok)
    error->all(FLERR, ("fix snapshot/hdf5: keyword '" + arg_text(key) + "': compute '" + cid +
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
      error->all(FLERR, ("fix snapshot/hdf5: keyword 'values': no " + arg_text(kind) + " '" + r.id +
                         "' (for '" + r.text + "')").c_str());
    if (!flag)
      error->all(FLERR, ("fix snapshot/hdf5: keyword 'values': " + arg_text(kind) + " '" + r.id +
                         "' computes no per-atom values").c_str());
    if (r.index > 0 && (cols == 0 || r.index > cols))
      error->all(FLERR, ("fix snapshot/hdf5: keyword 'values': '" + r.text + "': " +
                         arg_text(kind) +
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
