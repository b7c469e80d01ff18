// SPDX-License-Identifier: GPL-2.0-or-later
/* ----------------------------------------------------------------------
   The HDF5 file of one snapshot of fix snapshot/hdf5 (see
   snapshot_hdf5_writer.h): thin helpers over the serial HDF5 C API and the
   file's layout. Called on rank 0 by FixSnapshotHdf5::write_snapshot.
------------------------------------------------------------------------- */

#include "snapshot_hdf5_writer.h"

#include <hdf5.h>

#include <algorithm>
#include <cmath>

namespace {

// thin helpers over the serial HDF5 C API (rank 0 only)

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

// The contact point, force, normal force and overlap, which a grain-grain
// (PP_CP...) and a grain-wall (PW_CP...) table hold in the same order from
// column `cp` on: one writer for both groups of write_file.
bool h5_contact_forces(hid_t g, const SnapshotHdf5::Table &t, const std::vector<size_t> &order,
                       int cp)
{
  const hsize_t n = order.size();
  bool w = h5_doubles(g, "contact_point", column_block(t.data, t.ncols, order, cp, 3), n, 3);
  w &= h5_doubles(g, "force", column_block(t.data, t.ncols, order, cp + 3, 3), n, 3);
  w &= h5_doubles(g, "force_normal", column_block(t.data, t.ncols, order, cp + 6, 3), n, 3);
  w &= h5_doubles(g, "overlap", column_block(t.data, t.ncols, order, cp + 9, 1), n, 1);
  return w;
}
static_assert(SnapshotHdf5::PP_F == SnapshotHdf5::PP_CP + 3 &&
                  SnapshotHdf5::PP_FN == SnapshotHdf5::PP_CP + 6 &&
                  SnapshotHdf5::PP_DELTA == SnapshotHdf5::PP_CP + 9,
              "h5_contact_forces reads the grain-grain columns in this order");
static_assert(SnapshotHdf5::PW_F == SnapshotHdf5::PW_CP + 3 &&
                  SnapshotHdf5::PW_FN == SnapshotHdf5::PW_CP + 6 &&
                  SnapshotHdf5::PW_DELTA == SnapshotHdf5::PW_CP + 9,
              "h5_contact_forces reads the grain-wall columns in this order");

}  // namespace

namespace SnapshotHdf5 {

int write_file(const std::string &path, const Snapshot &s)
{
  const Table &parts = s.particles, &pp = s.pp, &pw = s.pw;
  const int np = parts.nrows, npp = pp.nrows, npw = pw.nrows;
  hid_t file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  int ok = file >= 0;
  if (ok) {
    bool w = true;
    w &= h5_attr_int64(file, "step", s.step);
    w &= h5_attr_double(file, "time", s.time);
    w &= h5_attr_double(file, "dt", s.dt);
    w &= h5_attr_string(file, "trigger", s.trigger);
    w &= h5_attr_double(file, "trigger_old", s.trigger_old);
    w &= h5_attr_double(file, "trigger_new", s.trigger_new);
    w &= h5_attr_int64(file, "snapshot", s.snapshot);
    w &= h5_attr_string(file, "fix", s.fix);
    w &= h5_attr_string(file, "group", s.group);

    // particles sorted by id
    hid_t g = H5Gcreate2(file, "particles", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    std::vector<size_t> order = sorted_rows(parts.data, parts.ncols, np, std::vector<int>(1, P_ID));
    w &= h5_attr_int64(g, "count", np);
    w &= h5_int64s(g, "id", int_column_block(parts.data, parts.ncols, order, P_ID, 1), np, 1);
    {
      std::vector<long long> t = int_column_block(parts.data, parts.ncols, order, P_TYPE, 1);
      std::vector<int> ti(t.begin(), t.end());
      w &= h5_write(g, "type", H5T_NATIVE_INT, H5T_STD_I32LE, ti.empty() ? NULL : &ti[0], np, 1);
    }
    w &= h5_doubles(g, "x", column_block(parts.data, parts.ncols, order, P_X, 3), np, 3);
    w &= h5_doubles(g, "v", column_block(parts.data, parts.ncols, order, P_V, 3), np, 3);
    w &= h5_doubles(g, "radius", column_block(parts.data, parts.ncols, order, P_R, 1), np, 1);
    if (!s.value_names.empty()) {
      hid_t gv = H5Gcreate2(g, "values", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
      int c0 = P_NBASE;
      for (size_t k = 0; k < s.value_names.size(); k++) {
        w &= h5_doubles(gv, s.value_names[k].c_str(), column_block(parts.data, parts.ncols, order, c0,
                                                                  s.value_cols[k]),
                        np, s.value_cols[k]);
        c0 += s.value_cols[k];
      }
      H5Gclose(gv);
    }
    H5Gclose(g);

    if (s.contacts) {
      hid_t gc = H5Gcreate2(file, "contacts", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
      hid_t g1 = H5Gcreate2(gc, "pp", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
      std::vector<int> k2;
      k2.push_back(PP_I);
      k2.push_back(PP_J);
      order = sorted_rows(pp.data, pp.ncols, npp, k2);
      w &= h5_attr_int64(g1, "count", npp);
      w &= h5_attr_string(g1, "compute", s.pp_compute);
      w &= h5_int64s(g1, "id", int_column_block(pp.data, pp.ncols, order, PP_I, 2), npp, 2);
      w &= h5_contact_forces(g1, pp, order, PP_CP);
      H5Gclose(g1);
      if (s.walls) {
        hid_t g2 = H5Gcreate2(gc, "pw", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
        std::vector<int> k3;
        k3.push_back(PW_ID);
        k3.push_back(PW_MESH);
        k3.push_back(PW_TRI);
        order = sorted_rows(pw.data, pw.ncols, npw, k3);
        w &= h5_attr_int64(g2, "count", npw);
        w &= h5_attr_string(g2, "compute", s.pw_compute);
        w &= h5_attr_string(g2, "wall_fix", s.wall_fix);
        w &= h5_attr_string(g2, "meshes", s.meshes);
        w &= h5_int64s(g2, "id", int_column_block(pw.data, pw.ncols, order, PW_ID, 1), npw, 1);
        {
          std::vector<long long> m = int_column_block(pw.data, pw.ncols, order, PW_MESH, 1);
          std::vector<int> mi(m.begin(), m.end());
          w &= h5_write(g2, "mesh", H5T_NATIVE_INT, H5T_STD_I32LE, mi.empty() ? NULL : &mi[0],
                        npw, 1);
        }
        w &= h5_int64s(g2, "triangle", int_column_block(pw.data, pw.ncols, order, PW_TRI, 1), npw, 1);
        w &= h5_contact_forces(g2, pw, order, PW_CP);
        H5Gclose(g2);
      }
      H5Gclose(gc);
    }
    if (H5Fclose(file) < 0) w = false;
    ok = w ? 1 : 2;
  }
  return ok;
}

}  // namespace SnapshotHdf5
