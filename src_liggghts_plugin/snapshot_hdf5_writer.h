// SPDX-License-Identifier: GPL-2.0-or-later
/* ----------------------------------------------------------------------
   The HDF5 file of one snapshot of fix snapshot/hdf5: file creation, the
   groups, data sets and attributes (layout: docs/fix_snapshot_hdf5.md).
   Serial HDF5 C API, called on rank 0 only by FixSnapshotHdf5::write_snapshot
   (fix_snapshot_hdf5_record.cpp) with the tables it gathered there. No
   LIGGGHTS dependency: what is recorded is decided by the fix, how it is
   stored here. Rows are written sorted by particle id (contacts by their
   ids, mesh and triangle), so files do not depend on the number of ranks.
   Exercised by tests/integration/test_snapshot_hdf5.py and, for the
   reader's side, tests/python/test_snapshot.py.
------------------------------------------------------------------------- */

#ifndef SNAPSHOT_HDF5_WRITER_H
#define SNAPSHOT_HDF5_WRITER_H

#include <string>
#include <vector>

namespace SnapshotHdf5 {

// columns of one gathered particle row: id type x(3) v(3) radius, then the
// requested per-atom values
enum { P_ID, P_TYPE, P_X, P_V = P_X + 3, P_R = P_V + 3, P_NBASE };
// columns of one packed particle-particle contact row
enum { PP_I, PP_J, PP_CP, PP_F = PP_CP + 3, PP_FN = PP_F + 3, PP_DELTA = PP_FN + 3, PP_NCOL };
// columns of one packed particle-wall contact row
enum { PW_ID, PW_MESH, PW_TRI, PW_CP, PW_F = PW_CP + 3, PW_FN = PW_F + 3,
       PW_DELTA = PW_FN + 3, PW_NCOL };

// a row-major table of ncols doubles per row (ids stored as exact doubles)
struct Table {
  std::vector<double> data;
  int ncols;
  int nrows;
  Table() : ncols(0), nrows(0) {}
};

// everything one file holds
struct Snapshot {
  long long step;
  double time, dt;
  std::string trigger;               // as written in the deck
  double trigger_old, trigger_new;
  long long snapshot;                // snapshots written so far, this one included
  std::string fix, group;
  Table particles;                   // P_* columns, then the values
  std::vector<std::string> value_names;
  std::vector<int> value_cols;
  bool contacts;                     // write /contacts/pp
  Table pp;                          // PP_* columns
  std::string pp_compute;
  bool walls;                        // write /contacts/pw too
  Table pw;                          // PW_* columns
  std::string pw_compute, wall_fix, meshes;
  Snapshot() : step(0), time(0), dt(0), trigger_old(0), trigger_new(0), snapshot(0),
               contacts(false), walls(false) {}
};

// Writes the file; returns 0 if it could not be created, 2 if a write
// failed, 1 on success.
int write_file(const std::string &path, const Snapshot &s);

}  // namespace SnapshotHdf5

#endif
