// SPDX-License-Identifier: GPL-2.0-or-later
/* ----------------------------------------------------------------------
   fix servo/radial, the mesh it moves: finding the fix mesh/surface/stress
   and checking that nothing else moves it (init), checking that it is a
   cylinder of vertical facets about the axis (setup), the nodal wall
   velocity and the surface properties derived from the moved nodes
   (initial_integrate). The rest of the fix (keywords, the hooks, the
   stress measurement) is fix_servo_radial.cpp; the formulas are
   crush_servo_kernel.h. Exercised by tests/integration/test_servo_radial.py.
------------------------------------------------------------------------- */

#include <cmath>
#include <cstdio>
#include <string>

#include "container.h"
#include "crush_args.h"
#include "crush_servo_kernel.h"
#include "error.h"
#include "fix_mesh_surface.h"
#include "fix_move_mesh.h"
#include "fix_servo_radial.h"
#include "mesh_mover.h"
#include "modify.h"
#include "tri_mesh.h"

using namespace LAMMPS_NS;
using namespace CrushKernels;

namespace {

// relative tolerances of the geometry check
const double kVerticalTol = 1e-4;  // |n_z| of a facet
const double kRadiusTol = 1e-3;    // spread of node distances from the axis

}  // namespace

/* ----------------------------------------------------------------------
   the mesh fix by ID; NULL (or an error if must_exist) when it is gone
------------------------------------------------------------------------- */

FixMeshSurface *FixServoRadial::find_mesh(bool must_exist)
{
  const int ifix = modify->find_fix(mesh_id_.c_str());
  if (ifix < 0) {
    if (must_exist)
      error->all(FLERR, ("fix servo/radial: no fix with ID '" + mesh_id_ +
                         "' given to keyword 'mesh' (define the fix mesh/surface/stress first)").c_str());
    return NULL;
  }
  FixMeshSurface *fm = dynamic_cast<FixMeshSurface *>(modify->fix[ifix]);
  if (!fm || !fm->trackStress())
    error->all(FLERR, ("fix servo/radial: fix '" + mesh_id_ + "' (" +
                       arg_text(modify->fix[ifix]->style) +
                       ") given to keyword 'mesh' is not a fix mesh/surface/stress with stress "
                       "tracking on; the servo reads the wall force from it").c_str());
  return fm;
}

/* ----------------------------------------------------------------------
   nothing else may move this mesh
------------------------------------------------------------------------- */

void FixServoRadial::check_mesh_compatible()
{
  if (fix_mesh_->get_module("servo"))
    error->all(FLERR, ("fix servo/radial: mesh '" + mesh_id_ + "' is a fix mesh/surface/stress/servo, "
                       "which moves the mesh itself; use fix mesh/surface/stress").c_str());
  if (fix_mesh_->surfaceVel())
    error->all(FLERR, ("fix servo/radial: mesh '" + mesh_id_ + "' has a surface velocity "
                       "(keywords velocity or angular_velocity), which sets the wall velocity the "
                       "servo needs to set").c_str());
  for (int i = 0; i < modify->nfix; i++) {
    Fix *f = modify->fix[i];
    if (!f || f == this) continue;
    FixMoveMesh *mv = dynamic_cast<FixMoveMesh *>(f);
    if (mv && mv->fixMeshCompare(fix_mesh_))
      error->all(FLERR, ("fix servo/radial: fix move/mesh '" + arg_text(f->id) +
                         "' also moves mesh '" +
                         mesh_id_ + "'; a servo-controlled wall cannot be moved by another fix").c_str());
  }
}

/* ----------------------------------------------------------------------
   the mesh must be vertical facets with every node on one circle about
   the axis
------------------------------------------------------------------------- */

void FixServoRadial::check_geometry()
{
  const int nown = mesh_->sizeLocal();
  double p[3][3], n_out[3], c[3];
  // maxima: |n_z|, r_max, -r_min
  double maxs[3] = {0.0, -1e300, -1e300};
  for (int i = 0; i < nown; i++) {
    for (int j = 0; j < 3; j++) mesh_->node(i, j, p[j]);
    wall_triangle_geometry(p[0], p[1], p[2], x0_, y0_, n_out, c);
    if (std::fabs(n_out[2]) > maxs[0]) maxs[0] = std::fabs(n_out[2]);
    for (int j = 0; j < 3; j++) {
      const double r = radial_distance(p[j][0], p[j][1], x0_, y0_);
      if (r > maxs[1]) maxs[1] = r;
      if (-r > maxs[2]) maxs[2] = -r;
    }
  }
  double all[3];
  MPI_Allreduce(maxs, all, 3, MPI_DOUBLE, MPI_MAX, world);
  const double rmax = all[1], rmin = -all[2];
  char buf[256];
  if (all[0] > kVerticalTol) {
    snprintf(buf, sizeof(buf), "a facet normal has a z component of %g", all[0]);
    error->all(FLERR, ("fix servo/radial: mesh '" + mesh_id_ + "' is not a cylinder of vertical "
                       "facets (" + buf + "); the lateral wall only, no caps").c_str());
  }
  if (!(rmin > 0.0) || rmax - rmin > kRadiusTol * rmax) {
    snprintf(buf, sizeof(buf), "node distances from the axis range from %g to %g m", rmin, rmax);
    error->all(FLERR, ("fix servo/radial: the nodes of mesh '" + mesh_id_ + "' are not on one "
                       "circle about the axis (x0, y0) of keyword 'axis' (" + buf + ")").c_str());
  }
}

/* ----------------------------------------------------------------------
   nodal wall velocity of owned and ghost elements: radial, v_r at the nodes
------------------------------------------------------------------------- */

void FixServoRadial::set_wall_velocity(double v_r)
{
  MultiVectorContainer<double, 3, 3> *vc =
      mesh_->prop().getElementProperty<MultiVectorContainer<double, 3, 3> >("v");
  if (!vc) return;
  double ***v = vc->begin();
  const int nall = mesh_->sizeLocal() + mesh_->sizeGhost();
  double node[3];
  for (int i = 0; i < nall; i++)
    for (int j = 0; j < 3; j++) {
      mesh_->node(i, j, node);
      radial_node_velocity(node, x0_, y0_, v_r, radius_, v[i][j]);
    }
}

/* ----------------------------------------------------------------------
   surface properties of all (owned and ghost) elements from their nodes,
   as SurfaceMesh::recalcLocalSurfProperties / recalcGhostSurfProperties
   compute them. check_only: compare with the stored values instead and
   return the largest difference (lengths and areas relative), collective.
------------------------------------------------------------------------- */

double FixServoRadial::refresh_surface_geometry(bool check_only)
{
  CustomValueTracker &prop = mesh_->prop();
  VectorContainer<double, 3> *edgeLen = prop.getElementProperty<VectorContainer<double, 3> >("edgeLen");
  MultiVectorContainer<double, 3, 3> *edgeVec =
      prop.getElementProperty<MultiVectorContainer<double, 3, 3> >("edgeVec");
  MultiVectorContainer<double, 3, 3> *edgeNorm =
      prop.getElementProperty<MultiVectorContainer<double, 3, 3> >("edgeNorm");
  VectorContainer<double, 3> *surfaceNorm = prop.getElementProperty<VectorContainer<double, 3> >("surfaceNorm");
  ScalarContainer<double> *area = prop.getElementProperty<ScalarContainer<double> >("area");
  ScalarContainer<double> *areaAcc = prop.getElementProperty<ScalarContainer<double> >("areaAcc");
  ScalarContainer<int> *obtuse = prop.getElementProperty<ScalarContainer<int> >("obtuseAngleIndex");
  ScalarContainer<double> *areaMesh = prop.getGlobalProperty<ScalarContainer<double> >("areaMesh");
  if (!edgeLen || !edgeVec || !edgeNorm || !surfaceNorm || !area || !areaAcc || !obtuse || !areaMesh)
    error->all(FLERR, ("fix servo/radial: mesh '" + mesh_id_ + "' lacks the surface properties of a "
                       "LIGGGHTS 3.8 surface mesh").c_str());

  const int nlocal = mesh_->sizeLocal();
  const int nall = nlocal + mesh_->sizeGhost();
  double ***node = node_access_->get_nodes();
  double dev = 0.0;
  double area_owned = 0.0, area_ghost = 0.0, acc = 0.0;
  TriangleGeometry g;

  for (int i = 0; i < nall; i++) {
    const double *const p[3] = {node[i][0], node[i][1], node[i][2]};
    if (!triangle_surface_geometry(p, g))
      error->one(FLERR, ("fix servo/radial: mesh '" + mesh_id_ + "' has a degenerate triangle").c_str());
    if (check_only) {
      const double L = (*edgeLen)(i)[0] + (*edgeLen)(i)[1] + (*edgeLen)(i)[2];
      for (int j = 0; j < 3; j++) {
        dev = std::fmax(dev, std::fabs(g.edge_len[j] - (*edgeLen)(i)[j]) / L);
        dev = std::fmax(dev, std::fabs(g.surf_norm[j] - (*surfaceNorm)(i)[j]));
        for (int k = 0; k < 3; k++) {
          dev = std::fmax(dev, std::fabs(g.edge_vec[j][k] - (*edgeVec)(i)[j][k]));
          dev = std::fmax(dev, std::fabs(g.edge_norm[j][k] - (*edgeNorm)(i)[j][k]));
        }
      }
      dev = std::fmax(dev, std::fabs(g.area - (*area)(i)) / (*area)(i));
      continue;
    }
    for (int j = 0; j < 3; j++) {
      (*edgeLen)(i)[j] = g.edge_len[j];
      (*surfaceNorm)(i)[j] = g.surf_norm[j];
      for (int k = 0; k < 3; k++) {
        (*edgeVec)(i)[j][k] = g.edge_vec[j][k];
        (*edgeNorm)(i)[j][k] = g.edge_norm[j][k];
      }
    }
    (*area)(i) = g.area;
    acc += g.area;
    (*areaAcc)(i) = acc;
    (*obtuse)(i) = g.obtuse;
    if (i < nlocal) area_owned += g.area;
    else area_ghost += g.area;
  }

  if (check_only) {
    double dev_all = 0.0;
    MPI_Allreduce(&dev, &dev_all, 1, MPI_DOUBLE, MPI_MAX, world);
    return dev_all;
  }
  double area_global = 0.0;
  MPI_Allreduce(&area_owned, &area_global, 1, MPI_DOUBLE, MPI_SUM, world);
  (*areaMesh)(0) = area_global;
  (*areaMesh)(1) = area_owned;
  (*areaMesh)(2) = area_ghost;
  return 0.0;
}
