// SPDX-License-Identifier: GPL-2.0-or-later
/* ----------------------------------------------------------------------
   fix servo/radial: radial stress servo of a cylindrical mesh wall
   (docs/model.md §4.4). See the header and docs/fix_servo_radial.md.
   The math lives in crush_servo_kernel.h; finding and checking the mesh,
   the wall velocity and the surface properties of the moved nodes are
   fix_servo_radial_mesh.cpp.

   How the wall moves. Each step the x and y coordinates of every node of
   the mesh (owned and ghost elements, the same factor on every rank) are
   scaled about the axis, R -> R + v_r dt; z is left alone, so the wall
   keeps its height. The nodes are reached as the mesh movers of fix
   move/mesh reach them (MeshMover::get_nodes). Then what LIGGGHTS derives
   from the nodes is brought up to date: element centres and bounding radii
   with the mesh's own updateCenterRbound(), and the surface properties
   (edge lengths, edge unit vectors and normals, facet normals, areas,
   obtuse-angle index; element properties of the mesh) recomputed with the
   formulas of SurfaceMesh/TriMesh (crush_servo_kernel.h); at every set-up
   the fix checks that those formulas reproduce the mesh's own values. A
   uniform scale() would be simpler but stretches the wall vertically too.

   The move is registered with the mesh (registerMove), which makes it a
   moving mesh: it is re-distributed over the ranks at every
   re-neighboring (and its surface properties recomputed by LIGGGHTS
   there), its neighbor lists use the full skin, and it asks for a
   re-neighboring when a node has moved more than half the skin
   (MultiNodeMesh::decideRebuild in FixMesh::pre_force). The nodal wall
   velocity (element property 'v', used by fix wall/gran for the relative
   contact velocity) is the radial expansion.
------------------------------------------------------------------------- */

#include "fix_servo_radial.h"

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string>

#include "comm.h"
#include "container.h"
#include "crush_args.h"
#include "crush_servo_kernel.h"
#include "domain.h"
#include "error.h"
#include "fix_mesh_surface.h"
#include "fix_wall_gran.h"
#include "input.h"
#include "mesh_mover.h"
#include "modify.h"
#include "tri_mesh.h"
#include "update.h"
#include "variable.h"

using namespace LAMMPS_NS;
using namespace FixConst;
using namespace CrushKernels;

namespace {

// setup: largest relative difference allowed between the surface properties
// this fix recomputes from the nodes and the mesh's own
const double kConventionTol = 1e-9;

// Access to the node array of a mesh, as a mesh mover has it; moves nothing
// by itself (the movers' hooks are empty).
class NodeAccess : public MeshMover {
 public:
  NodeAccess(LAMMPS *lmp, AbstractMesh *mesh) : MeshMover(lmp, mesh, NULL) {}
  void post_create() {}
  void pre_delete() {}
  void initial_integrate(double, double, double) {}
};

}  // namespace

/* ---------------------------------------------------------------------- */

FixServoRadial::FixServoRadial(LAMMPS *lmp, int narg, char **arg) :
  Fix(lmp, narg, arg),
  target_(-1.0), gain_(-1.0), vmax_(-1.0), height_const_(-1.0), height_ivar_(-1),
  x0_(0.0), y0_(0.0), sector_deg_(-1.0), fix_mesh_(NULL), mesh_(NULL), node_access_(NULL), registered_(false),
  radius_(0.0), sigma_r_(0.0), v_r_(0.0), height_now_(0.0)
{
  parse_args(narg, arg);

  if (domain->xperiodic || domain->yperiodic || domain->zperiodic)
    error->all(FLERR, "fix servo/radial: needs a non-periodic box (boundary f or m in x, y and z): "
                      "the wall is scaled about its axis, which periodic images do not follow");

  fix_mesh_ = find_mesh(true);
  mesh_ = fix_mesh_->triMesh();
  check_mesh_compatible();
  node_access_ = new NodeAccess(lmp, mesh_);

  vector_flag = 1;
  size_vector = 3;
  global_freq = 1;
  extvector = 0;
  nevery = 1;
}

/* ---------------------------------------------------------------------- */

void FixServoRadial::parse_args(int narg, char **arg)
{
  // fix ID group servo/radial mesh MESH target S gain K [vmax V] height H|v_NAME [axis X0 Y0]
  //     [sector ANGLE]
  CrushArgs a(error, "fix servo/radial", narg, arg, 3,
              {"mesh", "target", "gain", "vmax", "height", "axis", "sector"});
  while (a.next()) {
    if (a.is("mesh")) {
      mesh_id_ = a.word("the ID of a fix mesh/surface/stress");
    } else if (a.is("target")) {
      target_ = a.number(arg_positive("Pa"));
    } else if (a.is("gain")) {
      gain_ = a.number(arg_positive("m/s per Pa"));
    } else if (a.is("vmax")) {
      vmax_ = a.number(arg_positive("m/s"));
    } else if (a.is("sector")) {
      sector_deg_ = a.number(arg_range(0.0, false, 360.0, true, "> 0 and <= 360 (degrees)"));
    } else if (a.is("height")) {
      const std::string v = a.word("a number > 0 (m) or v_NAME (equal-style variable)");
      if (v.compare(0, 2, "v_") == 0) {
        if (v.size() == 2) a.fail("keyword 'height' got 'v_' without a variable name");
        height_var_ = v.substr(2);
      } else {
        height_const_ = a.number_of(v.c_str(), arg_range(0.0, false, HUGE_VAL, false,
                                                         "> 0 (m) or v_NAME (equal-style variable)"));
      }
    } else if (a.is("axis")) {  // two values X0 Y0
      x0_ = a.number(arg_any("a finite x of the axis (m)"));
      y0_ = a.number(arg_any("a finite y of the axis (m)"));
    }
  }

  const char *missing = NULL;
  if (!a.given("mesh")) missing = "mesh";
  else if (!a.given("target")) missing = "target";
  else if (!a.given("gain")) missing = "gain";
  else if (!a.given("height")) missing = "height";
  if (missing)
    a.fail("missing required keyword '" + arg_text(missing) +
           "' (required: mesh ID, target S > 0, gain K > 0, height H > 0 or v_NAME)");
  if (!a.given("vmax")) vmax_ = gain_ * target_;
}

/* ---------------------------------------------------------------------- */

FixServoRadial::~FixServoRadial()
{
  delete node_access_;
}

/* ---------------------------------------------------------------------- */

void FixServoRadial::post_create()
{
  // a moving mesh: parallel re-distribution at re-neighboring, neighbor
  // lists with the full skin, re-neighboring when a node moved skin/2
  mesh_->registerMove(true, false, false);
  registered_ = true;

  if (!mesh_->prop().getElementProperty<MultiVectorContainer<double, 3, 3> >("v"))
    mesh_->prop().addElementProperty<MultiVectorContainer<double, 3, 3> >(
        "v", "comm_exchange_borders", "frame_invariant", "restart_no");
  mesh_->prop().getElementProperty<MultiVectorContainer<double, 3, 3> >("v")->setAll(0.0);
}

/* ---------------------------------------------------------------------- */

void FixServoRadial::pre_delete(bool unfixflag)
{
  // the mesh fix may already be gone (deleted first at the end of a run)
  const int ifix = modify->find_fix(mesh_id_.c_str());
  if (ifix < 0 || modify->fix[ifix] != fix_mesh_ || !registered_) return;

  if (unfixflag) {
    // the wall stands still from now on: the radius is held
    MultiVectorContainer<double, 3, 3> *v =
        mesh_->prop().getElementProperty<MultiVectorContainer<double, 3, 3> >("v");
    if (v) v->setAll(0.0);
  }
  mesh_->unregisterMove(true, false, false);
  registered_ = false;
}

/* ---------------------------------------------------------------------- */

int FixServoRadial::setmask()
{
  int mask = 0;
  mask |= INITIAL_INTEGRATE;
  mask |= END_OF_STEP;
  return mask;
}

/* ---------------------------------------------------------------------- */

void FixServoRadial::init()
{
  if (strstr(update->integrate_style, "respa"))
    error->all(FLERR, "fix servo/radial does not support run_style respa");

  FixMeshSurface *fm = find_mesh(true);
  if (fm != fix_mesh_)
    error->all(FLERR, ("fix servo/radial: fix '" + mesh_id_ + "' was replaced after this fix was "
                       "defined; unfix and define fix servo/radial again").c_str());
  check_mesh_compatible();

  int me = -1;
  for (int i = 0; i < modify->nfix; i++) {
    Fix *f = modify->fix[i];
    if (f == this) { me = i; continue; }
    if (f && strcmp(f->style, style) == 0 &&
        static_cast<FixServoRadial *>(f)->mesh_id_ == mesh_id_)
      error->all(FLERR, ("fix servo/radial: fixes '" + arg_text(f->id) + "' and '" + arg_text(id) +
                         "' both servo mesh '" + mesh_id_ + "'; use one").c_str());
  }

  // the stress read at setup is complete only when the wall forces have been
  // added, i.e. when this fix comes after the fix wall/gran of the mesh
  int last_wall = -1;
  for (int i = 0; i < modify->nfix; i++) {
    FixWallGran *w = dynamic_cast<FixWallGran *>(modify->fix[i]);
    if (!w || !w->is_mesh_wall()) continue;
    for (int k = 0; k < w->n_meshes(); k++)
      if (w->mesh_list()[k] == fix_mesh_) last_wall = i;
  }
  if (last_wall < 0) {
    if (comm->me == 0)
      error->warning(FLERR, ("fix servo/radial: no fix wall/gran uses mesh '" + mesh_id_ +
                             "'; the measured stress is zero and the wall will shrink").c_str());
  } else if (last_wall > me) {
    error->all(FLERR, ("fix servo/radial: define it after fix wall/gran '" +
                       arg_text(modify->fix[last_wall]->id) +
                       "', which puts the grains' forces on mesh '" +
                       mesh_id_ + "'").c_str());
  }

  if (!height_var_.empty()) {
    height_ivar_ = input->variable->find(const_cast<char *>(height_var_.c_str()));
    if (height_ivar_ < 0)
      error->all(FLERR, ("fix servo/radial: variable '" + height_var_ + "' given to keyword "
                         "'height' does not exist").c_str());
    if (!input->variable->equalstyle(height_ivar_))
      error->all(FLERR, ("fix servo/radial: variable '" + height_var_ + "' given to keyword "
                         "'height' must be equal-style").c_str());
  }
}

/* ---------------------------------------------------------------------- */

void FixServoRadial::setup(int)
{
  if (!mesh_->prop().getElementProperty<MultiVectorContainer<double, 3, 3> >("v")) {
    mesh_->prop().addElementProperty<MultiVectorContainer<double, 3, 3> >(
        "v", "comm_exchange_borders", "frame_invariant", "restart_no");
    mesh_->prop().getElementProperty<MultiVectorContainer<double, 3, 3> >("v")->setAll(0.0);
  }
  check_geometry();
  // our formulas for the derived geometry must reproduce the mesh's own
  // (refreshed by fix mesh/surface in setup_pre_force)
  const double dev = refresh_surface_geometry(true);
  if (!(dev <= kConventionTol)) {
    char buf[64];
    snprintf(buf, sizeof(buf), "%g", dev);
    error->all(FLERR, ("fix servo/radial: internal check failed: the recomputed surface geometry "
                       "of mesh '" + mesh_id_ + "' differs from LIGGGHTS' by " + buf +
                       " (a LIGGGHTS version with other mesh conventions?)").c_str());
  }
  // At setup fix mesh/surface has made its reverse communication before fix
  // wall/gran added the forces of the set-up: each contact sits on the owned
  // or ghost copy of its element on the rank of its grain, so count both.
  measure(true);
  v_r_ = servo_radial_velocity(sigma_r_, target_, gain_, vmax_);
}

/* ----------------------------------------------------------------------
   move the wall: R -> R + v_r dt, scaling x and y of every node about the
   axis; then the derived geometry and the nodal velocities
------------------------------------------------------------------------- */

void FixServoRadial::initial_integrate(int)
{
  const double factor = radial_scale_factor(radius_, v_r_, update->dt);
  if (!(factor > 0.0))
    error->all(FLERR, "fix servo/radial: the wall radius would become <= 0; lower 'vmax' or the time step");
  if (factor != 1.0) {
    double ***node = node_access_->get_nodes();
    const int nall = mesh_->sizeLocal() + mesh_->sizeGhost();
    for (int i = 0; i < nall; i++)
      for (int j = 0; j < 3; j++) scale_node_xy(node[i][j], x0_, y0_, factor);
    // centres, bounding radii and the global bounding box (collective)
    mesh_->updateCenterRbound(0, nall);
    refresh_surface_geometry(false);
    radius_ *= factor;
  }
  set_wall_velocity(v_r_);
}

/* ----------------------------------------------------------------------
   the element forces of this step are complete (reverse-communicated in
   fix mesh/surface's final_integrate): measure and set the next velocity
------------------------------------------------------------------------- */

void FixServoRadial::end_of_step()
{
  measure(false);
  v_r_ = servo_radial_velocity(sigma_r_, target_, gain_, vmax_);
}

/* ---------------------------------------------------------------------- */

double FixServoRadial::compute_vector(int n)
{
  if (n == 0) return radius_;
  if (n == 1) return sigma_r_;
  if (n == 2) return v_r_;
  return 0.0;
}

/* ---------------------------------------------------------------------- */

double FixServoRadial::sample_height()
{
  if (height_var_.empty()) return height_const_;
  modify->clearstep_compute();
  const double h = input->variable->compute_equal(height_ivar_);
  modify->addstep_compute(update->ntimestep + 1);
  if (!(h > 0.0) || !std::isfinite(h)) {
    char buf[64];
    snprintf(buf, sizeof(buf), "%g", h);
    error->all(FLERR, ("fix servo/radial: variable '" + height_var_ + "' given to keyword 'height' "
                       "is " + buf + "; the sample height must be > 0").c_str());
  }
  return h;
}

/* ----------------------------------------------------------------------
   radius, mid-height and radial stress of the wall
   include_ghosts: add the forces held by ghost elements (at setup only,
   before any reverse communication); geometry is from owned elements
------------------------------------------------------------------------- */

void FixServoRadial::measure(bool include_ghosts)
{
  VectorContainer<double, 3> *fc = mesh_->prop().getElementProperty<VectorContainer<double, 3> >("f");
  if (!fc)
    error->all(FLERR, ("fix servo/radial: mesh '" + mesh_id_ + "' has no element force 'f' "
                       "(fix mesh/surface/stress with stress on)").c_str());

  const int nown = mesh_->sizeLocal();
  const int nall = include_ghosts ? nown + mesh_->sizeGhost() : nown;

  // sums: F_r, area, sum of node distances, number of nodes
  double sums[4] = {0.0, 0.0, 0.0, 0.0};
  // maxima: z_max, -z_min
  double maxs[2] = {-1e300, -1e300};
  double p[3][3], n_out[3], c[3];

  for (int i = 0; i < nall; i++) {
    for (int j = 0; j < 3; j++) mesh_->node(i, j, p[j]);
    const double area = wall_triangle_geometry(p[0], p[1], p[2], x0_, y0_, n_out, c);
    sums[0] += element_radial_force((*fc)(i), n_out);
    if (i >= nown) continue;
    sums[1] += area;
    for (int j = 0; j < 3; j++) {
      sums[2] += radial_distance(p[j][0], p[j][1], x0_, y0_);
      sums[3] += 1.0;
      if (p[j][2] > maxs[0]) maxs[0] = p[j][2];
      if (-p[j][2] > maxs[1]) maxs[1] = -p[j][2];
    }
  }
  double sums_all[4], maxs_all[2];
  MPI_Allreduce(sums, sums_all, 4, MPI_DOUBLE, MPI_SUM, world);
  MPI_Allreduce(maxs, maxs_all, 2, MPI_DOUBLE, MPI_MAX, world);

  const double wall_height = maxs_all[0] + maxs_all[1];
  if (!(sums_all[3] > 0.0) || !(wall_height > 0.0) || !(sums_all[1] > 0.0))
    error->all(FLERR, ("fix servo/radial: mesh '" + mesh_id_ + "' has no height or no area").c_str());

  radius_ = sums_all[2] / sums_all[3];
  height_now_ = sample_height();
  double perimeter = wall_perimeter(sums_all[1], wall_height);
  if (sector_deg_ > 0.0) {
    // the grains fill a sector of the chamber: the loaded wall is its arc
    const double arc = sector_arc_length(sector_deg_, radius_);
    if (arc > 1.01 * perimeter) {
      char buf[160];
      snprintf(buf, sizeof(buf), "%g degrees (arc %g m) is wider than mesh '%s' (perimeter %g m)",
               sector_deg_, arc, mesh_id_.c_str(), perimeter);
      error->all(FLERR, ("fix servo/radial: keyword 'sector': " + arg_text(buf) +
                         "; the mesh must span at least the sector").c_str());
    }
    perimeter = arc;
  }
  sigma_r_ = radial_stress(sums_all[0], perimeter, height_now_);
}
