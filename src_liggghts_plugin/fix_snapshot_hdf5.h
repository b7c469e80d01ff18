// SPDX-License-Identifier: GPL-2.0-or-later
/* ----------------------------------------------------------------------
   fix snapshot/hdf5: event-triggered HDF5 snapshots of particles and
   contacts. Every step it evaluates one global scalar (the trigger, e.g. the
   phase f_JACK[6] of fix jack/pile); on the steps where the value changes,
   and the value it leaves is in the 'leaving' list, rank 0 writes
   PREFIX_<step>.h5 with the particles of the group (id, type, x, v, radius,
   requested per-atom values) and, with contacts, the particle-particle and
   particle-mesh contacts from LIGGGHTS' compute pair/gran/local and
   wall/gran/local. Serial HDF5 C API; data gathered to rank 0 with MPI.
   Doc: docs/fix_snapshot_hdf5.md

   Where the code is:
     fix_snapshot_hdf5.cpp         keywords, trigger, the contact computes
     fix_snapshot_hdf5_record.cpp  what a snapshot records: particles, values,
                                   contacts, gathered to rank 0 (write_snapshot)
     snapshot_hdf5_writer.{h,cpp}  the HDF5 file: groups, data sets, attributes
                                   (no LIGGGHTS dependency)
------------------------------------------------------------------------- */

#ifdef FIX_CLASS

FixStyle(snapshot/hdf5,FixSnapshotHdf5)

#else

#ifndef LMP_FIX_SNAPSHOT_HDF5_H
#define LMP_FIX_SNAPSHOT_HDF5_H

#include <string>
#include <vector>

#include "fix.h"

namespace LAMMPS_NS {

class FixSnapshotHdf5 : public Fix {
 public:
  FixSnapshotHdf5(class LAMMPS *, int, char **);
  ~FixSnapshotHdf5();
  int setmask();
  void post_create();
  void pre_delete(bool unfixflag);
  void init();
  void setup(int);
  void end_of_step();
  double compute_scalar();

 private:
  // a global scalar, vector element or equal-style variable (the trigger)
  // or a per-atom quantity (values); 'which' is 'c', 'f' or 'v'
  struct Ref {
    std::string text;   // as written in the deck, e.g. f_jack[6]
    char which;
    std::string id;     // compute, fix or variable name
    int index;          // 0 = scalar / per-atom vector, n >= 1 = element or column n
  };

  std::string prefix_;
  Ref trigger_;
  std::vector<double> leaving_;   // empty: any change triggers
  std::vector<Ref> values_;
  bool contacts_;
  std::string pair_local_id_, wall_local_id_;  // deck computes, or created here
  bool own_pair_local_, own_wall_local_;
  bool have_wall_local_;

  int itrigger_;                  // index of the trigger fix/compute/variable
  std::vector<int> ivalue_;
  class ComputePairGranLocal *pair_local_, *wall_local_;

  bool have_prev_;
  double prev_;
  int nsnap_;                     // snapshots written (f_ID)

  void parse_args(int narg, char **arg);
  Ref parse_ref(const char *key, const char *text, bool peratom);
  double eval_trigger();
  bool leaves_listed(double old_value) const;
  void check_local_compute(const char *key, const std::string &cid, bool wall,
                           class ComputePairGranLocal **out);
  int value_columns(const Ref &r, int ivalue) const;
  void fill_value(const Ref &r, int ivalue, int col, std::vector<double> &buf,
                  int stride, int offset);
  void write_snapshot(double old_value, double new_value);
  int gather(const std::vector<double> &local, int ncols, std::vector<double> &all);
  void gather_contacts(class ComputePairGranLocal *c, bool wall, int &ncols,
                       std::vector<double> &all, int &nrows);
};

}

#endif
#endif
