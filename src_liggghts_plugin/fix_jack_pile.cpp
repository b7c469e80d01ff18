// SPDX-License-Identifier: GPL-2.0-or-later
/* ----------------------------------------------------------------------
   fix jack/pile: jacking controller of the pile (docs/model.md §4.5).
   See the header and docs/fix_jack_pile.md. The phase state machine lives
   in crush_jack_kernel.h.

   Timing within one step n (Verlet):
     initial_integrate  fix move/mesh linear/variable evaluates v_vz =
                        f_ID[1], the velocity this fix computed at the end
                        of step n-1 (or in setup), and moves the mesh by
                        v dt; wherever the move/mesh fixes are defined
     pre_force          mesh/surface/stress zeroes its total force
     post_force         fix wall/gran adds the grain forces on the mesh
     final_integrate    mesh/surface/stress sums the total over the ranks
     end_of_step        this fix: reads the tip position and both totals
                        (those of step n), updates the phase and computes
                        the velocity for step n+1
   so f_ID[...] is current at every step (global_freq = 1) and the forces it
   reports belong to the pile position they were computed at.
------------------------------------------------------------------------- */

#include "fix_jack_pile.h"

#include <cfloat>
#include <cstdio>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string>

#include "abstract_mesh.h"
#include "comm.h"
#include "crush_args.h"
#include "error.h"
#include "fix_mesh_surface.h"
#include "mesh_module_stress.h"
#include "modify.h"
#include "update.h"

using namespace LAMMPS_NS;
using namespace FixConst;
using namespace CrushKernels;

namespace {

const int kRestartSize = 13;


char *copy_string(const char *s)
{
  char *c = new char[strlen(s) + 1];
  strcpy(c, s);
  return c;
}

}  // namespace

/* ---------------------------------------------------------------------- */

FixJackPile::FixJackPile(LAMMPS *lmp, int narg, char **arg) :
  Fix(lmp, narg, arg),
  params_(jack_default_params()),
  cone_id_(NULL), shaft_id_(NULL), cone_(NULL), shaft_(NULL),
  cone_stress_(NULL), shaft_stress_(NULL),
  have_surface_(false), surface_z_(0.0), check_motion_(true),
  sector_deg_(360.0), file_name_(NULL), fp_(NULL), every_(1), reference_written_(false),
  started_(false), z_ref_(0.0), v_cmd_(0.0), dt_cmd_(0.0), depth_(0.0),
  f_cone_(0.0), f_shaft_(0.0), f_head_(0.0), z_tip_prev_(0.0), z_shaft_prev_(0.0),
  time_offset_(0.0), restart_time_(0.0), restart_time_pending_(false)
{
  state_.phase = JACK_PUSH;
  state_.cycle = 1;
  state_.stroke_index = 1;
  state_.stroke_end = 0.0;
  state_.phase_time = 0.0;

  parse_args(narg, arg);
  // the depth reference must be the same number on every rank: a deck may
  // give it as ${var} of an equal-style variable evaluated on each rank
  // (e.g. a mesh's reference point, which LIGGGHTS' mesh totals at the
  // set-up of a run can leave differing in the last digits between ranks)
  MPI_Bcast(&surface_z_, 1, MPI_DOUBLE, 0, world);

  vector_flag = 1;
  size_vector = 7;
  global_freq = 1;
  extvector = 0;
  restart_global = 1;

  if (file_name_) {
    int ok = 1;
    if (comm->me == 0) {
      fp_ = fopen(file_name_, "w");
      ok = fp_ ? 1 : 0;
      if (fp_) {
        fprintf(fp_, "# fix jack/pile %s: mode %s, v %.10g m/s, depth %.10g m", id,
                params_.mode == JACK_CYCLIC ? "cyclic" : "monotonic", params_.v_push, params_.depth);
        if (params_.mode == JACK_CYCLIC)
          fprintf(fp_, ", stroke %.10g m (%s), v_unload %.10g m/s, pause %.10g s, zero_tol %.10g N, "
                       "pause_servo %.10g m/s/N",
                  params_.stroke,
                  params_.strokes == JACK_STROKES_ABSOLUTE ? "absolute" : "relative",
                  params_.v_unload, params_.pause, params_.zero_tol, params_.pause_servo);
        if (sector_deg_ < 360.0)
          fprintf(fp_, ", sector %.10g deg (forces scaled by 360/sector to the whole pile)", sector_deg_);
        fprintf(fp_, "\n# forces on the pile from the grains, + up (resisting the push); "
                     "phase 0 push 1 unload 2 pause 3 done (after this step's update); "
                     "v_next = velocity for the next step (+ up)\n");
        // the depth reference and the column names follow in setup(), once
        // the reference is known (it may be the apex at the first run)
        fflush(fp_);
      }
    }
    MPI_Bcast(&ok, 1, MPI_INT, 0, world);
    if (!ok)
      error->all(FLERR, ("fix jack/pile: cannot open file '" + arg_text(file_name_) +
                         "' given to keyword 'file'").c_str());
  }
}

/* ---------------------------------------------------------------------- */

FixJackPile::~FixJackPile()
{
  if (fp_) fclose(fp_);
  delete[] cone_id_;
  delete[] shaft_id_;
  delete[] file_name_;
}

/* ---------------------------------------------------------------------- */

void FixJackPile::parse_args(int narg, char **arg)
{
  // fix ID group jack/pile cone C shaft S mode monotonic|cyclic v V depth D
  //     [stroke S v_unload VU pause T zero_tol F0 strokes absolute|relative pause_servo G]
  //     [surface Z] [sector ANGLE] [file F] [every N] [check_motion yes|no]
  CrushArgs a(error, "fix jack/pile", narg, arg, 3,
              {"cone", "shaft", "mode", "v", "depth", "stroke", "v_unload", "pause", "zero_tol",
               "strokes", "pause_servo", "surface", "sector", "file", "every", "check_motion"});
  std::string cyclic_key;  // first cyclic-only keyword given
  while (a.next()) {
    if (a.is("cone")) {
      cone_id_ = copy_string(a.word("the ID of the cone's fix mesh/surface/stress").c_str());
    } else if (a.is("shaft")) {
      shaft_id_ = copy_string(a.word("the ID of the shaft's fix mesh/surface/stress").c_str());
    } else if (a.is("mode")) {
      params_.mode = a.choice({"monotonic", "cyclic"}) == 0 ? JACK_MONOTONIC : JACK_CYCLIC;
    } else if (a.is("v")) {
      params_.v_push = a.number(arg_positive("m/s"), "push velocity");
    } else if (a.is("depth")) {
      params_.depth = a.number(arg_positive("m"), "target tip depth");
    } else if (a.is("surface")) {
      surface_z_ = a.number(arg_any("a finite z (m)"));
      have_surface_ = true;
    } else if (a.is("sector")) {
      sector_deg_ = a.number(arg_range(0.0, false, 360.0, true, "> 0 and <= 360 (degrees)"),
                             "simulated sector of the chamber");
    } else if (a.is("file")) {
      file_name_ = copy_string(a.word("a file name").c_str());
    } else if (a.is("every")) {
      every_ = (int)a.integer(1, 2147483647L, "an integer >= 1 (steps)");
    } else if (a.is("check_motion")) {
      check_motion_ = a.yes_no();
    } else {  // the cyclic-only keywords
      if (cyclic_key.empty()) cyclic_key = a.key();
      if (a.is("stroke"))
        params_.stroke = a.number(arg_positive("m"));
      else if (a.is("v_unload"))
        params_.v_unload = a.number(arg_positive("m/s"), "upward unloading velocity");
      else if (a.is("pause"))
        params_.pause = a.number(arg_non_negative("s"), "duration");
      else if (a.is("zero_tol"))
        params_.zero_tol = a.number(arg_non_negative("N"), "head force tolerance");
      else if (a.is("pause_servo"))
        params_.pause_servo = a.number(arg_non_negative("m/s per N"), "gain");
      else
        params_.strokes = a.choice({"absolute", "relative"}) == 0 ? JACK_STROKES_ABSOLUTE
                                                                  : JACK_STROKES_RELATIVE;
    }
  }

  if (!cone_id_)
    error->all(FLERR, "fix jack/pile: missing required keyword 'cone' (ID of the fix "
                      "mesh/surface/stress of the cone tip)");
  if (!shaft_id_)
    error->all(FLERR, "fix jack/pile: missing required keyword 'shaft' (ID of the fix "
                      "mesh/surface/stress of the shaft)");
  if (strcmp(cone_id_, shaft_id_) == 0)
    error->all(FLERR, ("fix jack/pile: keywords 'cone' and 'shaft' name the same fix '" +
                       arg_text(cone_id_) +
                       "'; the cone and the shaft must be separate meshes").c_str());
  if (!a.given("mode"))
    error->all(FLERR, "fix jack/pile: missing required keyword 'mode' (monotonic or cyclic)");
  if (!a.given("v"))
    error->all(FLERR, "fix jack/pile: missing required keyword 'v' (push velocity > 0, m/s)");
  if (!a.given("depth"))
    error->all(FLERR, "fix jack/pile: missing required keyword 'depth' (target tip depth > 0, m)");
  if (params_.mode == JACK_MONOTONIC) {
    if (!cyclic_key.empty())
      error->all(FLERR, ("fix jack/pile: keyword '" + cyclic_key +
                         "' applies to mode cyclic only; mode monotonic takes v and depth").c_str());
  } else {
    if (!a.given("stroke"))
      error->all(FLERR, "fix jack/pile: mode cyclic needs keyword 'stroke' (> 0, m)");
    if (!a.given("v_unload"))
      error->all(FLERR, "fix jack/pile: mode cyclic needs keyword 'v_unload' (> 0, m/s)");
    if (!a.given("pause"))
      error->all(FLERR, "fix jack/pile: mode cyclic needs keyword 'pause' (>= 0, s)");
  }
  const char *bad = jack_invalid_param(params_);
  if (bad)  // cannot happen after the checks above; kept as a guard
    error->all(FLERR, ("fix jack/pile: invalid value of keyword '" + arg_text(bad) + "'").c_str());
}

/* ---------------------------------------------------------------------- */

int FixJackPile::setmask()
{
  int mask = 0;
  mask |= END_OF_STEP;
  return mask;
}

/* ---------------------------------------------------------------------- */

FixMeshSurface *FixJackPile::find_mesh(const char *key, const char *mesh_id,
                                       MeshModuleStress **stress)
{
  const int ifix = modify->find_fix(mesh_id);
  if (ifix < 0)
    error->all(FLERR, ("fix jack/pile: keyword '" + arg_text(key) + "': no fix with ID '" +
                       arg_text(mesh_id) + "'; give the ID of a fix mesh/surface/stress").c_str());
  Fix *f = modify->fix[ifix];
  FixMeshSurface *mesh = dynamic_cast<FixMeshSurface *>(f);
  MeshModuleStress *module = NULL;
  if (mesh) module = dynamic_cast<MeshModuleStress *>(mesh->get_module("stress"));
  if (!mesh || !module || !module->trackStress())
    error->all(FLERR, ("fix jack/pile: keyword '" + arg_text(key) + "': fix '" + arg_text(mesh_id) +
                       "' (" + arg_text(f->style) + ") is not a fix mesh/surface/stress with "
                       "stress on; the controller needs the total force on the mesh").c_str());
  *stress = module;
  return mesh;
}

void FixJackPile::init()
{
  cone_ = find_mesh("cone", cone_id_, &cone_stress_);
  shaft_ = find_mesh("shaft", shaft_id_, &shaft_stress_);
  if (strstr(update->integrate_style, "respa"))
    error->all(FLERR, "fix jack/pile does not support run_style respa");
  if (update->dt <= 0.0)
    error->all(FLERR, "fix jack/pile needs a positive timestep");
}

/* ----------------------------------------------------------------------
   lowest node of the owned elements of a mesh, over all ranks: the apex for
   the cone, the bottom ring for the shaft
------------------------------------------------------------------------- */

double FixJackPile::mesh_min_z(FixMeshSurface *fix)
{
  AbstractMesh *mesh = fix->mesh();
  const int nlocal = mesh->sizeLocal();
  const int nnodes = mesh->numNodes();
  double zmin = DBL_MAX;
  double node[3];
  for (int i = 0; i < nlocal; i++)
    for (int j = 0; j < nnodes; j++) {
      mesh->node_slow(i, j, node);
      if (node[2] < zmin) zmin = node[2];
    }
  double all = DBL_MAX;
  MPI_Allreduce(&zmin, &all, 1, MPI_DOUBLE, MPI_MIN, world);
  if (all == DBL_MAX)
    error->all(FLERR, ("fix jack/pile: mesh of fix '" + arg_text(fix->id) +
                       "' has no elements").c_str());
  return all;
}

/* ---------------------------------------------------------------------- */

void FixJackPile::setup(int)
{
  const double dt = update->dt;
  const double z_tip = mesh_min_z(cone_);
  const double z_shaft = mesh_min_z(shaft_);
  if (restart_time_pending_) {
    time_offset_ = restart_time_ - update->get_cur_time();
    restart_time_pending_ = false;
  }
  // depth is z_ref - z of a mesh node moved by one increment per step: the
  // last increment lands on the stroke end up to a few roundings of numbers
  // of this size (part of the arrival tolerance of the kernel)
  const char *ref_source = started_ ? "from the restart file" :
                           have_surface_ ? "keyword surface" : "the apex z at the first run";
  if (!started_) z_ref_ = have_surface_ ? surface_z_ : z_tip;
  params_.round_off = 64.0 * DBL_EPSILON * (fabs(z_ref_) + fabs(z_tip) + params_.depth);
  if (!started_) {
    depth_ = z_ref_ - z_tip;
    v_cmd_ = jack_start(params_, state_, depth_, dt);
    if (state_.phase == JACK_DONE && comm->me == 0) {
      char msg[256];
      snprintf(msg, sizeof(msg), "fix jack/pile: the tip (depth %g m) is already at the target "
                                 "depth %g m; the pile will not move", depth_, params_.depth);
      error->warning(FLERR, msg);
    }
    started_ = true;
  } else {
    // a new run (or a run after read_restart): keep the phase, recompute the
    // velocity for the current timestep; forces keep their last values
    // (mesh/surface/stress totals are not summed during setup)
    depth_ = z_ref_ - z_tip;
    v_cmd_ = jack_velocity(params_, state_, depth_, f_head_, dt);
  }
  dt_cmd_ = dt;
  z_tip_prev_ = z_tip;
  z_shaft_prev_ = z_shaft;
  write_reference(ref_source);
}

/* ----------------------------------------------------------------------
   the depth reference in the file's header, once per file: post-processing
   needs the tip's position, z_ref - depth (e.g. to place breakage events
   relative to the tip), and z_ref is known only here
------------------------------------------------------------------------- */

void FixJackPile::write_reference(const char *source)
{
  if (!fp_ || reference_written_) return;
  fprintf(fp_, "# z_ref %.17g m: depth = z_ref - z of the cone apex; z_ref = %s\n", z_ref_,
          source);
  fprintf(fp_, "# step time depth F_cone F_shaft F_head phase cycle v_next\n");
  fflush(fp_);
  reference_written_ = true;
}

/* ---------------------------------------------------------------------- */

void FixJackPile::check_motion(double z_tip, double z_shaft)
{
  const double expected = v_cmd_ * dt_cmd_;
  const double moved_cone = z_tip - z_tip_prev_;
  const double moved_shaft = z_shaft - z_shaft_prev_;
  // a millionth of a push step, plus round-off of the positions
  const double tol = 1e-6 * params_.v_push * dt_cmd_ +
                     64.0 * DBL_EPSILON * (fabs(z_tip) + fabs(z_shaft) + fabs(z_tip_prev_));
  const char *which = NULL;
  double moved = 0.0;
  if (fabs(moved_cone - expected) > tol) { which = "cone"; moved = moved_cone; }
  else if (fabs(moved_shaft - expected) > tol) { which = "shaft"; moved = moved_shaft; }
  // every rank must take the same decision (error->all is collective)
  int bad = which ? 1 : 0, bad_any = 0;
  MPI_Allreduce(&bad, &bad_any, 1, MPI_INT, MPI_MAX, world);
  if (bad != bad_any)
    fprintf(stderr, "fix jack/pile: rank %d: check_motion %s: z_tip %.17g prev %.17g z_shaft %.17g "
            "prev %.17g v_cmd %.17g dt %.17g step " BIGINT_FORMAT "\n", comm->me, bad ? "failed" : "passed",
            z_tip, z_tip_prev_, z_shaft, z_shaft_prev_, v_cmd_, dt_cmd_, update->ntimestep);
  if (bad_any) {
    if (!which) { which = "cone"; moved = moved_cone; }
    char msg[1024];
    snprintf(msg, sizeof(msg),
             "fix jack/pile: the %s mesh (fix %s) moved by %.6g m in step " BIGINT_FORMAT
             " but the controller commanded %.6g m (v %.6g m/s * dt). Move both meshes, and "
             "only with it: 'variable vz equal f_%s[1]', 'fix ... all move/mesh mesh %s "
             "linear/variable v_zero v_zero v_vz' (variable zero equal 0) and the same for "
             "mesh %s (docs/fix_jack_pile.md); or set check_motion no",
             which, which[0] == 'c' ? cone_id_ : shaft_id_, moved, update->ntimestep, expected,
             v_cmd_, id, cone_id_, shaft_id_);
    error->all(FLERR, msg);
  }
}

/* ---------------------------------------------------------------------- */

void FixJackPile::end_of_step()
{
  const double z_tip = mesh_min_z(cone_);
  const double z_shaft = mesh_min_z(shaft_);
  if (check_motion_) check_motion(z_tip, z_shaft);

  // totals of this step (summed over ranks in the meshes' final_integrate):
  // force of the grains on each mesh, z component, + up
  // in a chamber sector the grains touch only that sector of the pile:
  // report (and control with) the forces on the whole pile
  f_cone_ = jack_full_pile_force(cone_stress_->f_total(2), sector_deg_);
  f_shaft_ = jack_full_pile_force(shaft_stress_->f_total(2), sector_deg_);
  f_head_ = f_cone_ + f_shaft_;
  depth_ = z_ref_ - z_tip;

  bool changed = false;
  const double dt = update->dt;
  v_cmd_ = jack_update(params_, state_, depth_, f_head_, dt_cmd_, dt, &changed);
  dt_cmd_ = dt;
  z_tip_prev_ = z_tip;
  z_shaft_prev_ = z_shaft;

  write_line(changed);
}

/* ---------------------------------------------------------------------- */

void FixJackPile::write_line(bool force)
{
  if (!fp_) return;
  if (!force && update->ntimestep % every_) return;
  fprintf(fp_, BIGINT_FORMAT " %.16g %.16g %.10g %.10g %.10g %d %d %.16g\n", update->ntimestep,
          current_time(), depth_, f_cone_, f_shaft_, f_head_, state_.phase, state_.cycle,
          v_cmd_);
  fflush(fp_);
}

/* ---------------------------------------------------------------------- */

double FixJackPile::compute_vector(int n)
{
  switch (n) {
    case 0: return v_cmd_;
    case 1: return depth_;
    case 2: return f_cone_;
    case 3: return f_shaft_;
    case 4: return f_head_;
    case 5: return (double)state_.phase;
    case 6: return (double)state_.cycle;
    default: return 0.0;
  }
}

/* ---------------------------------------------------------------------- */

void FixJackPile::write_restart(FILE *fp)
{
  double list[kRestartSize] = {started_ ? 1.0 : 0.0, z_ref_, (double)state_.phase,
                               (double)state_.cycle, (double)state_.stroke_index,
                               state_.stroke_end, state_.phase_time, f_cone_, f_shaft_,
                               f_head_, depth_, v_cmd_, current_time()};
  if (comm->me == 0) {
    int size = kRestartSize * sizeof(double);
    fwrite(&size, sizeof(int), 1, fp);
    fwrite(list, sizeof(double), kRestartSize, fp);
  }
}

void FixJackPile::restart(char *buf)
{
  double *list = (double *)buf;
  started_ = list[0] > 0.5;
  z_ref_ = list[1];
  state_.phase = (int)list[2];
  state_.cycle = (int)list[3];
  state_.stroke_index = (int)list[4];
  state_.stroke_end = list[5];
  state_.phase_time = list[6];
  f_cone_ = list[7];
  f_shaft_ = list[8];
  f_head_ = list[9];
  depth_ = list[10];
  v_cmd_ = list[11];
  restart_time_ = list[12];
  restart_time_pending_ = true;
}

double FixJackPile::current_time() const
{
  return update->get_cur_time() + time_offset_;
}
