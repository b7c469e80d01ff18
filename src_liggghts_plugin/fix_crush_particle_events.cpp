// SPDX-License-Identifier: GPL-2.0-or-later
/* ----------------------------------------------------------------------
   fix crush/particle: the breakage event log (keyword events FILE), one
   line per break in the order of the parents' tags. Its columns are
   defined once, in crush_event_log_kernel.h (header line and count).
   open_event_log: called by the constructor; write_events: by
   break_particles; write_event_line: by write_events, and with keyword
   energy by energy_write_closed once an event's window is over.
   Exercised by tests/integration/test_crush_single_grain.py,
   test_crush_br.py (Br recomputed from the log), test_energy.py (the
   energy columns), test_crush_parallel.py (the same lines at 1 and 2 ranks).
------------------------------------------------------------------------- */

#include "fix_crush_particle.h"

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "comm.h"
#include "crush_event_log_kernel.h"
#include "error.h"

using namespace LAMMPS_NS;
using namespace FixConst;
using namespace CrushKernels;

/* ---------------------------------------------------------------------- */

void FixCrushParticle::open_event_log()
{
  if (!events_file_) return;
  int ok = 1;
  if (comm->me == 0) {
    events_ = fopen(events_file_, events_append_ ? "a" : "w");
    ok = events_ ? 1 : 0;
    if (events_ && !events_append_) {
      fprintf(events_, "# fix crush/particle %s: one line per breakage event\n", id);
      fprintf(events_, "# %s\n", event_log_columns(energy_on_).c_str());
      fflush(events_);
    }
  }
  MPI_Bcast(&ok, 1, MPI_INT, 0, world);
  if (!ok)
    error->all(FLERR, ("fix crush/particle: cannot open file '" + std::string(events_file_) +
                       "' given to keyword 'events'").c_str());
}

/* ---------------------------------------------------------------------- */

void FixCrushParticle::write_events(const std::vector<double> &local_records, int nrec_local)
{
  if (!events_file_) return;
  const int rec = kEventRecord + (energy_on_ ? kEventEnergy : 0);
  const int nprocs = comm->nprocs;
  int n = nrec_local * rec;
  std::vector<int> counts(nprocs), displs(nprocs);
  MPI_Gather(&n, 1, MPI_INT, &counts[0], 1, MPI_INT, 0, world);
  int total = 0;
  if (comm->me == 0)
    for (int p = 0; p < nprocs; p++) { displs[p] = total; total += counts[p]; }
  std::vector<double> all(total + 1);
  std::vector<double> send(local_records);
  send.push_back(0.0);
  MPI_Gatherv(&send[0], n, MPI_DOUBLE, &all[0], &counts[0], &displs[0], MPI_DOUBLE, 0, world);
  if (comm->me != 0 || !events_) return;
  // lines in order of parent tag, as on one rank
  std::vector<std::pair<double, int> > order;
  for (int k = 0; k < total / rec; k++) order.push_back(std::make_pair(all[k * rec + 2], k));
  std::sort(order.begin(), order.end());
  for (size_t q = 0; q < order.size(); q++) {
    const double *e = &all[order[q].second * rec];
    // with energy, the line waits for the end of the event's window
    if (energy_on_) event_lines_.push_back(std::vector<double>(e, e + rec));
    else write_event_line(e, NULL);
  }
  fflush(events_);
}

// extra: with energy, E_el_before E_el_after KE_before KE_frag0 KE_gain v_max n_steps
void FixCrushParticle::write_event_line(const double *e, const double *extra)
{
  // the diameter in full precision: Br can be recomputed from this file
  static_assert(kEventRecord == 11 && kEventLineEnergy == 7,
                "write_event_line prints the columns of crush_event_log_kernel.h");
  fprintf(events_, "%.0f %.10g %.0f %.17g %.10g %.10g %.10g %.10g %.10g %s %.0f", e[0], e[1], e[2], e[3],
          e[4], e[5], e[6], e[7], e[8], e[9] == PARTNER_WALL ? "wall" : "particle", e[10]);
  if (extra)
    fprintf(events_, " %.10g %.10g %.10g %.10g %.10g %.10g %.0f", extra[0], extra[1], extra[2], extra[3], extra[4],
            extra[5], extra[6]);
  fputc('\n', events_);
}
