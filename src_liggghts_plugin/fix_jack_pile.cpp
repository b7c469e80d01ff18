/* ----------------------------------------------------------------------
   fix jack/pile: jacking controller of the pile (SPEC section 4 item 5).
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

std::string str(const char *a) { return std::string(a ? a : ""); }

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
      error->all(FLERR, ("fix jack/pile: cannot open file '" + str(file_name_) +
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

double FixJackPile::parse_number(const char *key, const char *value, const char *range)
{
  char *end = NULL;
  const double v = strtod(value, &end);
  if (end == value || *end != '\0')
    error->all(FLERR, ("fix jack/pile: value '" + str(value) + "' of keyword '" + key +
                       "' is not a number; allowed: " + range).c_str());
  return v;
}

void FixJackPile::parse_args(int narg, char **arg)
{
  // fix ID group jack/pile cone C shaft S mode monotonic|cyclic v V depth D
  //     [stroke S v_unload VU pause T zero_tol F0 strokes absolute|relative pause_servo G]
  //     [surface Z] [sector ANGLE] [file F] [every N] [check_motion yes|no]
  static const char *kKeywords =
      "cone, shaft, mode, v, depth, stroke, v_unload, pause, zero_tol, strokes, pause_servo, "
      "surface, sector, file, every, check_motion";
  bool have_mode = false, have_v = false, have_depth = false;
  bool have_stroke = false, have_vu = false, have_pause = false;
  const char *cyclic_key = NULL;  // first cyclic-only keyword given
  int iarg = 3;
  while (iarg < narg) {
    const std::string key = arg[iarg];
    if (iarg + 2 > narg)
      error->all(FLERR, ("fix jack/pile: keyword '" + key + "' needs a value").c_str());
    const char *val = arg[iarg + 1];
    if (key == "cone") {
      delete[] cone_id_;
      cone_id_ = copy_string(val);
    } else if (key == "shaft") {
      delete[] shaft_id_;
      shaft_id_ = copy_string(val);
    } else if (key == "mode") {
      if (strcmp(val, "monotonic") == 0) params_.mode = JACK_MONOTONIC;
      else if (strcmp(val, "cyclic") == 0) params_.mode = JACK_CYCLIC;
      else
        error->all(FLERR, ("fix jack/pile: unknown mode '" + str(val) +
                           "'; keyword 'mode' must be 'monotonic' or 'cyclic'").c_str());
      have_mode = true;
    } else if (key == "v") {
      params_.v_push = parse_number("v", val, "> 0 (m/s)");
      if (!(params_.v_push > 0.0) || !std::isfinite(params_.v_push))
        error->all(FLERR, ("fix jack/pile: keyword 'v' (push velocity) must be > 0 (m/s), got " +
                           str(val)).c_str());
      have_v = true;
    } else if (key == "depth") {
      params_.depth = parse_number("depth", val, "> 0 (m)");
      if (!(params_.depth > 0.0) || !std::isfinite(params_.depth))
        error->all(FLERR, ("fix jack/pile: keyword 'depth' (target tip depth) must be > 0 (m), got " +
                           str(val)).c_str());
      have_depth = true;
    } else if (key == "stroke") {
      params_.stroke = parse_number("stroke", val, "> 0 (m)");
      if (!(params_.stroke > 0.0) || !std::isfinite(params_.stroke))
        error->all(FLERR, ("fix jack/pile: keyword 'stroke' must be > 0 (m), got " +
                           str(val)).c_str());
      have_stroke = true;
      if (!cyclic_key) cyclic_key = "stroke";
    } else if (key == "v_unload") {
      params_.v_unload = parse_number("v_unload", val, "> 0 (m/s)");
      if (!(params_.v_unload > 0.0) || !std::isfinite(params_.v_unload))
        error->all(FLERR, ("fix jack/pile: keyword 'v_unload' (upward unloading velocity) must be "
                           "> 0 (m/s), got " + str(val)).c_str());
      have_vu = true;
      if (!cyclic_key) cyclic_key = "v_unload";
    } else if (key == "pause") {
      params_.pause = parse_number("pause", val, ">= 0 (s)");
      if (!(params_.pause >= 0.0) || !std::isfinite(params_.pause))
        error->all(FLERR, ("fix jack/pile: keyword 'pause' (duration) must be >= 0 (s), got " +
                           str(val)).c_str());
      have_pause = true;
      if (!cyclic_key) cyclic_key = "pause";
    } else if (key == "zero_tol") {
      params_.zero_tol = parse_number("zero_tol", val, ">= 0 (N)");
      if (!(params_.zero_tol >= 0.0) || !std::isfinite(params_.zero_tol))
        error->all(FLERR, ("fix jack/pile: keyword 'zero_tol' (head force tolerance) must be "
                           ">= 0 (N), got " + str(val)).c_str());
      if (!cyclic_key) cyclic_key = "zero_tol";
    } else if (key == "pause_servo") {
      params_.pause_servo = parse_number("pause_servo", val, ">= 0 (m/s per N)");
      if (!(params_.pause_servo >= 0.0) || !std::isfinite(params_.pause_servo))
        error->all(FLERR, ("fix jack/pile: keyword 'pause_servo' (gain) must be >= 0 (m/s per N), "
                           "got " + str(val)).c_str());
      if (!cyclic_key) cyclic_key = "pause_servo";
    } else if (key == "strokes") {
      if (strcmp(val, "absolute") == 0) params_.strokes = JACK_STROKES_ABSOLUTE;
      else if (strcmp(val, "relative") == 0) params_.strokes = JACK_STROKES_RELATIVE;
      else
        error->all(FLERR, ("fix jack/pile: keyword 'strokes' must be 'absolute' or 'relative', "
                           "got '" + str(val) + "'").c_str());
      if (!cyclic_key) cyclic_key = "strokes";
    } else if (key == "surface") {
      surface_z_ = parse_number("surface", val, "a finite z (m)");
      if (!std::isfinite(surface_z_))
        error->all(FLERR, ("fix jack/pile: keyword 'surface' must be a finite z (m), got " +
                           str(val)).c_str());
      have_surface_ = true;
    } else if (key == "sector") {
      sector_deg_ = parse_number("sector", val, "> 0 and <= 360 (degrees)");
      if (!(sector_deg_ > 0.0 && sector_deg_ <= 360.0))
        error->all(FLERR, ("fix jack/pile: keyword 'sector' (simulated sector of the chamber) must be "
                           "> 0 and <= 360 (degrees), got " + str(val)).c_str());
    } else if (key == "file") {
      delete[] file_name_;
      file_name_ = copy_string(val);
    } else if (key == "every") {
      const double e = parse_number("every", val, "an integer >= 1 (steps)");
      if (!(e >= 1.0) || e != std::floor(e) || e > 2147483647.0)
        error->all(FLERR, ("fix jack/pile: keyword 'every' must be an integer >= 1 (steps), got " +
                           str(val)).c_str());
      every_ = (int)e;
    } else if (key == "check_motion") {
      if (strcmp(val, "yes") == 0) check_motion_ = true;
      else if (strcmp(val, "no") == 0) check_motion_ = false;
      else
        error->all(FLERR, ("fix jack/pile: keyword 'check_motion' must be 'yes' or 'no', got '" +
                           str(val) + "'").c_str());
    } else {
      error->all(FLERR, ("fix jack/pile: unknown keyword '" + key + "'; expected " +
                         kKeywords).c_str());
    }
    iarg += 2;
  }

  if (!cone_id_)
    error->all(FLERR, "fix jack/pile: missing required keyword 'cone' (ID of the fix "
                      "mesh/surface/stress of the cone tip)");
  if (!shaft_id_)
    error->all(FLERR, "fix jack/pile: missing required keyword 'shaft' (ID of the fix "
                      "mesh/surface/stress of the shaft)");
  if (strcmp(cone_id_, shaft_id_) == 0)
    error->all(FLERR, ("fix jack/pile: keywords 'cone' and 'shaft' name the same fix '" +
                       str(cone_id_) + "'; the cone and the shaft must be separate meshes").c_str());
  if (!have_mode)
    error->all(FLERR, "fix jack/pile: missing required keyword 'mode' (monotonic or cyclic)");
  if (!have_v)
    error->all(FLERR, "fix jack/pile: missing required keyword 'v' (push velocity > 0, m/s)");
  if (!have_depth)
    error->all(FLERR, "fix jack/pile: missing required keyword 'depth' (target tip depth > 0, m)");
  if (params_.mode == JACK_MONOTONIC) {
    if (cyclic_key)
      error->all(FLERR, ("fix jack/pile: keyword '" + str(cyclic_key) +
                         "' applies to mode cyclic only; mode monotonic takes v and depth").c_str());
  } else {
    if (!have_stroke)
      error->all(FLERR, "fix jack/pile: mode cyclic needs keyword 'stroke' (> 0, m)");
    if (!have_vu)
      error->all(FLERR, "fix jack/pile: mode cyclic needs keyword 'v_unload' (> 0, m/s)");
    if (!have_pause)
      error->all(FLERR, "fix jack/pile: mode cyclic needs keyword 'pause' (>= 0, s)");
  }
  const char *bad = jack_invalid_param(params_);
  if (bad)  // cannot happen after the checks above; kept as a guard
    error->all(FLERR, ("fix jack/pile: invalid value of keyword '" + str(bad) + "'").c_str());
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
    error->all(FLERR, ("fix jack/pile: keyword '" + str(key) + "': no fix with ID '" +
                       str(mesh_id) + "'; give the ID of a fix mesh/surface/stress").c_str());
  Fix *f = modify->fix[ifix];
  FixMeshSurface *mesh = dynamic_cast<FixMeshSurface *>(f);
  MeshModuleStress *module = NULL;
  if (mesh) module = dynamic_cast<MeshModuleStress *>(mesh->get_module("stress"));
  if (!mesh || !module || !module->trackStress())
    error->all(FLERR, ("fix jack/pile: keyword '" + str(key) + "': fix '" + str(mesh_id) +
                       "' (" + str(f->style) + ") is not a fix mesh/surface/stress with "
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
    error->all(FLERR, ("fix jack/pile: mesh of fix '" + str(fix->id) + "' has no elements").c_str());
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
