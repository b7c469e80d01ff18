// SPDX-License-Identifier: GPL-2.0-or-later
/* ----------------------------------------------------------------------
   fix crush/particle: restart files and the per-atom arrays. The per-atom
   strength and generation travel with their atoms (grow/copy/set_arrays,
   pack/unpack_exchange, called by Atom) and are kept in restart files
   (pack/unpack_restart); the global counters, the seed, the time and the
   Br bins are kept by write_restart / restart (called by LIGGGHTS'
   write_restart and read_restart). The layout is documented at
   write_restart below and in docs/fix_crush_particle.md "Restart, output".
   Exercised by tests/integration/test_crush_single_grain.py and
   test_crush_br.py (a run split by a restart file equals one long run),
   test_crush_in_prep.py, test_chamber_small.py.
------------------------------------------------------------------------- */

#include "fix_crush_particle.h"

#include <algorithm>
#include <cstdio>
#include <vector>

#include "atom.h"
#include "comm.h"
#include "crush_breakage_index_kernel.h"
#include "error.h"
#include "memory.h"

using namespace LAMMPS_NS;
using namespace FixConst;
using namespace CrushKernels;

namespace {

// restart: 9 counters, then (format 2) the Br settings and kBrBins values of
// J0 and of the fines (see write_restart)
const int kRestartGlobalSize = 9;
const int kRestartBrSettings = 5;
// list[5] of the restart record: 0 not initialised, 1 initialised (files
// written before the Br bins, no bins follow), 2 initialised with the bins
const double kRestartFormatBins = 2.0;

}  // namespace

/* ----------------------------------------------------------------------
   per-atom arrays
------------------------------------------------------------------------- */

double FixCrushParticle::memory_usage()
{
  return (double)atom->nmax * 2 * sizeof(double);
}

void FixCrushParticle::grow_arrays(int nmax)
{
  memory->grow(crush_, nmax, 2, "crush/particle:crush");
  array_atom = crush_;
}

void FixCrushParticle::copy_arrays(int i, int j, int)
{
  crush_[j][0] = crush_[i][0];
  crush_[j][1] = crush_[i][1];
}

void FixCrushParticle::set_arrays(int i)
{
  crush_[i][0] = -1.0;  // drawn from the tag at the next neighbor build
  crush_[i][1] = 0.0;
}

int FixCrushParticle::pack_exchange(int i, double *buf)
{
  buf[0] = crush_[i][0];
  buf[1] = crush_[i][1];
  return 2;
}

int FixCrushParticle::unpack_exchange(int nlocal, double *buf)
{
  crush_[nlocal][0] = buf[0];
  crush_[nlocal][1] = buf[1];
  return 2;
}

int FixCrushParticle::pack_restart(int i, double *buf)
{
  buf[0] = 3;
  buf[1] = crush_[i][0];
  buf[2] = crush_[i][1];
  return 3;
}

void FixCrushParticle::unpack_restart(int nlocal, int nth)
{
  double **extra = atom->extra;
  int m = 0;
  for (int i = 0; i < nth; i++) m += static_cast<int>(extra[nlocal][m]);
  m++;
  crush_[nlocal][0] = extra[nlocal][m++];
  crush_[nlocal][1] = extra[nlocal][m++];
}

int FixCrushParticle::maxsize_restart() { return 3; }
int FixCrushParticle::size_restart(int) { return 3; }

/* ----------------------------------------------------------------------
   global state in restart files
------------------------------------------------------------------------- */

// Layout: the 9 counters of the first format, then the Br settings the bins
// depend on (d_min, d_max, omega, fines_grading, number of bins), J0 and the
// fines' bin integrals (kBrBins each). list[5]: 0 not initialised, 1 the
// first format (no bins follow), 2 bins follow. Builds of the first format
// read a new file as before (they ignore what follows the counters).
void FixCrushParticle::write_restart(FILE *fp)
{
  const int off = kRestartGlobalSize + kRestartBrSettings;
  std::vector<double> list(off + 2 * kBrBins);
  const double head[kRestartGlobalSize + kRestartBrSettings] = {
      n_events_, n_created_, fines_mass_, mass0_, integral0_,
      initialized_ ? kRestartFormatBins : 0.0, (double)maxtag_ever_, (double)seed_, current_time(),
      d_min_, d_max_, omega_, fines_fractal_ ? 1.0 : 0.0, (double)kBrBins};
  std::copy(head, head + off, list.begin());
  std::copy(J0_.begin(), J0_.end(), list.begin() + off);
  std::copy(J_fines_.begin(), J_fines_.end(), list.begin() + off + kBrBins);
  if (comm->me == 0) {
    int size = (int)list.size() * sizeof(double);
    fwrite(&size, sizeof(int), 1, fp);
    fwrite(&list[0], sizeof(double), list.size(), fp);
  }
}

void FixCrushParticle::restart(char *buf)
{
  double *list = (double *)buf;
  n_events_ = list[0];
  n_created_ = list[1];
  fines_mass_ = list[2];
  mass0_ = list[3];
  integral0_ = list[4];
  initialized_ = list[5] > 0.5;
  if (initialized_ && list[5] != kRestartFormatBins)
    // The binned initial grading cannot be rebuilt from the old record.
    error->all(FLERR, "fix crush/particle: the restart file was written by a version without Br size "
                      "bins (before fines_grading); its initial grading per bin is missing, so Br cannot "
                      "be continued. Continue that run with the version that wrote it, or start from a "
                      "data file");
  if (list[5] == kRestartFormatBins) {
    const double *br = list + kRestartGlobalSize;
    // the stored bins hold only for the settings they were made with
    if (br[0] != d_min_ || br[1] != d_max_ || br[2] != omega_ || (br[3] > 0.5) != fines_fractal_ ||
        (int)br[4] != kBrBins) {
      char msg[512];
      snprintf(msg, sizeof(msg),
               "fix crush/particle: the Br settings differ from those in the restart file "
               "(d_min %g, d_max %g, omega %g, fines_grading %s); give the same 'd_min', 'd_max', "
               "'omega' and 'fines_grading' to continue the run",
               br[0], br[1], br[2], br[3] > 0.5 ? "fractal" : "d_min");
      error->all(FLERR, msg);
    }
    const int off = kRestartGlobalSize + kRestartBrSettings;
    J0_.assign(list + off, list + off + kBrBins);
    J_fines_.assign(list + off + kBrBins, list + off + 2 * kBrBins);
  }
  maxtag_ever_ = (int)list[6];
  // strengths of fragments made after the restart, and the fragments'
  // orientations, are drawn from the seed: another seed forks the run
  if (list[7] != 0.0 && (uint64_t)list[7] != seed_) {
    char msg[256];
    snprintf(msg, sizeof(msg),
             "fix crush/particle: 'seed' %llu differs from the seed %llu in the restart file; give "
             "the same 'seed' to continue the run (a new seed: start from a data file)",
             (unsigned long long)seed_, (unsigned long long)list[7]);
    error->all(FLERR, msg);
  }
  // LIGGGHTS 3.8 restarts its clock at 0: the offset is set at the next setup
  restart_time_ = list[8];
  restart_time_pending_ = true;
}
