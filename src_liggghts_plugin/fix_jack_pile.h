// SPDX-License-Identifier: GPL-2.0-or-later
/* ----------------------------------------------------------------------
   fix jack/pile: jacking controller of a rigid pile made of two meshes
   (cone tip and shaft, each a fix mesh/surface/stress). It does not move the
   meshes: every step it computes the vertical pile velocity for the next
   step (monotonic push, or cyclic push / unload to zero head load / pause),
   exposed as f_ID[1] for stock `fix move/mesh ... linear/variable`, and
   reports depth, cone, shaft and head force, phase and cycle.
   The phase logic is crush_jack_kernel.h.
   Doc: docs/fix_jack_pile.md
------------------------------------------------------------------------- */

#ifdef FIX_CLASS

FixStyle(jack/pile,FixJackPile)

#else

#ifndef LMP_FIX_JACK_PILE_H
#define LMP_FIX_JACK_PILE_H

#include <cstdio>

#include "crush_jack_kernel.h"
#include "fix.h"

namespace LAMMPS_NS {

class FixJackPile : public Fix {
 public:
  FixJackPile(class LAMMPS *, int, char **);
  ~FixJackPile();
  int setmask();
  void init();
  void setup(int);
  void end_of_step();
  double compute_vector(int);

  void write_restart(FILE *);
  void restart(char *);

 private:
  CrushKernels::JackParams params_;
  CrushKernels::JackState state_;

  char *cone_id_, *shaft_id_;
  class FixMeshSurface *cone_, *shaft_;
  class MeshModuleStress *cone_stress_, *shaft_stress_;

  bool have_surface_;
  double surface_z_;
  bool check_motion_;
  double sector_deg_;  // simulated sector of the chamber (degrees)
  char *file_name_;
  FILE *fp_;
  int every_;
  bool reference_written_;  // the file's header has z_ref and the column names

  bool started_;      // the reference and the first stroke are set
  double z_ref_;      // depth = z_ref_ - tip z
  double v_cmd_;      // velocity commanded for the next step (f_ID[1])
  double dt_cmd_;     // timestep it was computed for
  double depth_;      // tip depth at the end of the last step
  double f_cone_, f_shaft_, f_head_;
  double z_tip_prev_, z_shaft_prev_;
  double time_offset_;   // LIGGGHTS 3.8 restarts its clock at 0 after read_restart
  double restart_time_;
  bool restart_time_pending_;

  void parse_args(int narg, char **arg);
  class FixMeshSurface *find_mesh(const char *key, const char *mesh_id,
                                  class MeshModuleStress **stress);
  double mesh_min_z(class FixMeshSurface *mesh);
  void check_motion(double z_tip, double z_shaft);
  void write_line(bool force);
  void write_reference(const char *source);
  double current_time() const;
};

}

#endif
#endif
