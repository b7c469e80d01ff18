// SPDX-License-Identifier: GPL-2.0-or-later
/* ----------------------------------------------------------------------
   fix snapshot/hdf5: what a snapshot records. write_snapshot (called by
   FixSnapshotHdf5::end_of_step when the trigger leaves a listed value)
   gathers to rank 0 the particles of the group (id, type, x, v, radius and
   the requested per-atom values: value_columns, fill_value) and the
   particle-particle and particle-mesh contacts of compute pair/gran/local
   and wall/gran/local (gather_contacts), then hands them to the HDF5 writer
   (snapshot_hdf5_writer.{h,cpp}) and logs one line.
   Exercised by tests/integration/test_snapshot_hdf5.py.
------------------------------------------------------------------------- */

#include "fix_snapshot_hdf5.h"

#include <cstdio>
#include <string>
#include <vector>

#include "atom.h"
#include "comm.h"
#include "compute.h"
#include "compute_pair_gran_local.h"
#include "crush_args.h"
#include "error.h"
#include "fix_mesh_surface.h"
#include "fix_wall_gran.h"
#include "group.h"
#include "input.h"
#include "modify.h"
#include "snapshot_hdf5_writer.h"
#include "update.h"
#include "variable.h"

using namespace LAMMPS_NS;
using namespace SnapshotHdf5;

/* ---------------------------------------------------------------------- */

int FixSnapshotHdf5::value_columns(const Ref &r, int ivalue) const
{
  if (r.which == 'v' || r.index > 0) return 1;
  const int cols = r.which == 'c' ? modify->compute[ivalue]->size_peratom_cols
                                  : modify->fix[ivalue]->size_peratom_cols;
  return cols == 0 ? 1 : cols;
}

// per-atom value(s) of r for the owned atoms of the group, into buf at rows
// of 'stride' doubles starting at column 'offset'
void FixSnapshotHdf5::fill_value(const Ref &r, int ivalue, int ncol, std::vector<double> &buf,
                                 int stride, int offset)
{
  const int nlocal = atom->nlocal;
  const int *mask = atom->mask;
  double *vec = NULL;
  double **arr = NULL;
  std::vector<double> tmp;
  if (r.which == 'c') {
    Compute *c = modify->compute[ivalue];
    if (c->invoked_peratom != update->ntimestep) {
      modify->clearstep_compute();
      c->compute_peratom();
      modify->addstep_compute(update->ntimestep + 1);
    }
    if (c->size_peratom_cols == 0) vec = c->vector_atom;
    else arr = c->array_atom;
  } else if (r.which == 'f') {
    Fix *f = modify->fix[ivalue];
    if (f->size_peratom_cols == 0) vec = f->vector_atom;
    else arr = f->array_atom;
  } else {
    tmp.assign(nlocal > 0 ? nlocal : 1, 0.0);
    modify->clearstep_compute();
    input->variable->compute_atom(ivalue, igroup, &tmp[0], 1, 0);
    modify->addstep_compute(update->ntimestep + 1);
    vec = &tmp[0];
  }
  int row = 0;
  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    double *dst = &buf[(size_t)row * stride + offset];
    if (vec) dst[0] = vec[i];
    else if (r.index > 0) dst[0] = arr[i][r.index - 1];
    else for (int c = 0; c < ncol; c++) dst[c] = arr[i][c];
    row++;
  }
}

/* ----------------------------------------------------------------------
   gather a row-major table of ncols doubles per row to rank 0; returns the
   total number of rows (on rank 0; 0 elsewhere)
------------------------------------------------------------------------- */

int FixSnapshotHdf5::gather(const std::vector<double> &local, int ncols,
                            std::vector<double> &all)
{
  const int nprocs = comm->nprocs;
  int n = (int)local.size();
  std::vector<int> counts(nprocs, 0), displs(nprocs, 0);
  MPI_Gather(&n, 1, MPI_INT, &counts[0], 1, MPI_INT, 0, world);
  long total = 0;
  if (comm->me == 0) {
    for (int p = 0; p < nprocs; p++) {
      displs[p] = (int)total;
      total += counts[p];
    }
    if (total > 2147483647L)
      error->one(FLERR, "fix snapshot/hdf5: snapshot too large to gather (more than 2^31 values)");
    all.assign(total, 0.0);
  }
  MPI_Gatherv(local.empty() ? NULL : const_cast<double *>(&local[0]), n, MPI_DOUBLE,
              all.empty() ? NULL : &all[0], &counts[0], &displs[0], MPI_DOUBLE, 0, world);
  return comm->me == 0 ? (int)(total / ncols) : 0;
}

/* ----------------------------------------------------------------------
   contacts of one compute pair/gran/local or wall/gran/local, packed into
   rows (PP_* or PW_* columns) and gathered to rank 0. Pairs are stored with
   id_i < id_j and the force on particle i (the compute gives the force on
   its first particle; a swap flips the sign).
------------------------------------------------------------------------- */

void FixSnapshotHdf5::gather_contacts(ComputePairGranLocal *c, bool wall, int &ncols,
                                      std::vector<double> &all, int &nrows)
{
  c->compute_local();
  const int rows = c->size_local_rows;
  double **a = c->array_local;
  const int ox = c->offset_x1(), oid = c->offset_id1(), of = c->offset_f(),
            ofn = c->offset_fn(), od = c->offset_delta();
  ncols = wall ? (int)PW_NCOL : (int)PP_NCOL;
  std::vector<double> local((size_t)rows * ncols);
  for (int r = 0; r < rows; r++) {
    double *row = &local[(size_t)r * ncols];
    const double *src = a[r];
    if (wall) {
      // wall/gran/local: id columns are (mesh index in the wall fix,
      // triangle id, particle id); pos starts with the contact point
      row[PW_ID] = src[oid + 2];
      row[PW_MESH] = src[oid];
      row[PW_TRI] = src[oid + 1];
      for (int d = 0; d < 3; d++) {
        row[PW_CP + d] = src[ox + d];
        row[PW_F + d] = src[of + d];
        row[PW_FN + d] = src[ofn + d];
      }
      row[PW_DELTA] = src[od];
    } else {
      const bool swap = src[oid] > src[oid + 1];
      const double sign = swap ? -1.0 : 1.0;
      row[PP_I] = swap ? src[oid + 1] : src[oid];
      row[PP_J] = swap ? src[oid] : src[oid + 1];
      const int ocp = c->offset_contact_point();
      for (int d = 0; d < 3; d++) {
        row[PP_CP + d] = src[ocp + d];
        row[PP_F + d] = sign * src[of + d];
        row[PP_FN + d] = sign * src[ofn + d];
      }
      row[PP_DELTA] = src[od];
    }
  }
  nrows = gather(local, ncols, all);
}

/* ---------------------------------------------------------------------- */

void FixSnapshotHdf5::write_snapshot(double old_value, double new_value)
{
  const double t0 = MPI_Wtime();
  const int nlocal = atom->nlocal;
  const int *mask = atom->mask;
  const bigint step = update->ntimestep;

  // particles: id type x(3) v(3) radius, then the requested values
  std::vector<int> vcols(values_.size());
  int ncols = P_NBASE;
  for (size_t k = 0; k < values_.size(); k++) {
    vcols[k] = value_columns(values_[k], ivalue_[k]);
    ncols += vcols[k];
  }
  int nmine = 0;
  for (int i = 0; i < nlocal; i++)
    if (mask[i] & groupbit) nmine++;
  std::vector<double> local((size_t)nmine * ncols);
  int row = 0;
  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    double *dst = &local[(size_t)row * ncols];
    dst[P_ID] = (double)atom->tag[i];
    dst[P_TYPE] = (double)atom->type[i];
    for (int d = 0; d < 3; d++) {
      dst[P_X + d] = atom->x[i][d];
      dst[P_V + d] = atom->v[i][d];
    }
    dst[P_R] = atom->radius ? atom->radius[i] : 0.0;
    row++;
  }
  int off = P_NBASE;
  for (size_t k = 0; k < values_.size(); k++) {
    fill_value(values_[k], ivalue_[k], vcols[k], local, ncols, off);
    off += vcols[k];
  }
  std::vector<double> parts;
  const int np = gather(local, ncols, parts);

  std::vector<double> pp, pw;
  int pp_cols = PP_NCOL, pw_cols = PW_NCOL, npp = 0, npw = 0;
  if (pair_local_) gather_contacts(pair_local_, false, pp_cols, pp, npp);
  if (wall_local_) gather_contacts(wall_local_, true, pw_cols, pw, npw);

  nsnap_++;
  char name[64];
  snprintf(name, sizeof(name), "_" BIGINT_FORMAT ".h5", step);
  const std::string path = prefix_ + name;

  int ok = 1;
  if (comm->me == 0) {
    SnapshotHdf5::Snapshot s;
    s.step = (long long)step;
    s.time = update->get_cur_time();
    s.dt = update->dt;
    s.trigger = trigger_.text;
    s.trigger_old = old_value;
    s.trigger_new = new_value;
    s.snapshot = nsnap_;
    s.fix = id;
    s.group = group->names[igroup];
    s.particles.data.swap(parts);
    s.particles.ncols = ncols;
    s.particles.nrows = np;
    for (size_t k = 0; k < values_.size(); k++) s.value_names.push_back(values_[k].text);
    s.value_cols = vcols;
    s.contacts = contacts_;
    s.pp.data.swap(pp);
    s.pp.ncols = pp_cols;
    s.pp.nrows = npp;
    s.pp_compute = pair_local_id_;
    s.walls = wall_local_ != NULL;
    s.pw.data.swap(pw);
    s.pw.ncols = pw_cols;
    s.pw.nrows = npw;
    s.pw_compute = wall_local_id_;
    if (contacts_ && wall_local_) {
      // the meshes in the order of the 'mesh' index: those of the fix
      // wall/gran LIGGGHTS attaches wall/gran/local to (the last one with
      // mesh walls)
      for (int i = 0; i < modify->nfix; i++) {
        FixWallGran *fw = dynamic_cast<FixWallGran *>(modify->fix[i]);
        if (!fw || !fw->is_mesh_wall()) continue;
        s.wall_fix = fw->id;
        s.meshes.clear();
        for (int m = 0; m < fw->n_meshes(); m++)
          s.meshes += (m ? " " : "") + arg_text(fw->mesh_list()[m]->id);
      }
    }
    ok = SnapshotHdf5::write_file(path, s);
  }
  MPI_Bcast(&ok, 1, MPI_INT, 0, world);
  if (ok == 0)
    error->all(FLERR, ("fix snapshot/hdf5: cannot create file '" + path + "' (keyword 'file' "
                       "gives the prefix " + prefix_ + "; does its folder exist?)").c_str());
  if (ok == 2)
    error->all(FLERR, ("fix snapshot/hdf5: writing '" + path + "' failed (HDF5 error above; "
                       "disk full?)").c_str());
  if (comm->me == 0) {
    char line[512];
    snprintf(line, sizeof(line),
             "fix snapshot/hdf5 %s: step " BIGINT_FORMAT ", %s %.10g -> %.10g: wrote %s "
             "(%d particles, %d pair and %d wall contacts, %.3g s)\n",
             id, step, trigger_.text.c_str(), old_value, new_value, path.c_str(), np, npp, npw,
             MPI_Wtime() - t0);
    if (screen) fputs(line, screen);
    if (logfile) fputs(line, logfile);
  }
}
