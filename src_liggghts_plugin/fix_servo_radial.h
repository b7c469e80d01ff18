// SPDX-License-Identifier: GPL-2.0-or-later
/* ----------------------------------------------------------------------
   fix servo/radial: servo-controls the radius of a cylindrical mesh wall
   (fix mesh/surface/stress, vertical facets around an axis parallel to z)
   to a target radial stress (docs/model.md §4.4, the calibration
   chamber's lateral wall). The wall's nodes are scaled in x and y about
   the axis (its height stays); unfix it to hold the radius.
   Doc: docs/fix_servo_radial.md
------------------------------------------------------------------------- */

#ifdef FIX_CLASS

FixStyle(servo/radial,FixServoRadial)

#else

#ifndef LMP_FIX_SERVO_RADIAL_H
#define LMP_FIX_SERVO_RADIAL_H

#include <string>

#include "fix.h"

namespace LAMMPS_NS {

class FixServoRadial : public Fix {
 public:
  FixServoRadial(class LAMMPS *, int, char **);
  ~FixServoRadial();
  void post_create();
  void pre_delete(bool unfixflag);
  int setmask();
  void init();
  void setup(int);
  void initial_integrate(int);
  void end_of_step();
  double compute_vector(int);

 private:
  std::string mesh_id_;
  double target_, gain_, vmax_;
  double height_const_;      // > 0 when 'height' is a number
  std::string height_var_;   // name after v_ when 'height' is a variable
  int height_ivar_;
  double x0_, y0_;
  double sector_deg_;        // > 0: the grains fill this sector (degrees)

  class FixMeshSurface *fix_mesh_;
  class TriMesh *mesh_;
  class MeshMover *node_access_;  // the mesh's node array (mesh movers' access)
  bool registered_;

  // state: measured at setup and at the end of every step, used by the
  // next initial_integrate
  double radius_;     // mean distance of the wall's nodes from the axis
  double sigma_r_;    // measured radial stress
  double v_r_;        // radial wall velocity for the next step
  double height_now_; // sample height used for sigma_r_

  void parse_args(int narg, char **arg);
  class FixMeshSurface *find_mesh(bool must_exist);
  void check_mesh_compatible();
  void check_geometry();
  void measure(bool include_ghosts);
  double sample_height();
  void set_wall_velocity(double v_r);
  double refresh_surface_geometry(bool check_only);
};

}

#endif
#endif
