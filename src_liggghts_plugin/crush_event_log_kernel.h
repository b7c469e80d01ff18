// SPDX-License-Identifier: GPL-2.0-or-later
/* Columns of the breakage event log of fix crush/particle (keyword events
   FILE): the one definition of the file's header line and of the number of
   values each event carries. A stateless kernel with no LIGGGHTS
   dependency, unit-tested in tests/unit/test_event_log_kernel.cpp.

   The log's second line is "# " followed by the columns, space separated;
   the energy columns follow only with keyword energy. Python readers of the
   log (scripts/crushpost) pin the same list. Adding a column means adding
   it here, to the record break_particles builds and to the format of
   FixCrushParticle::write_event_line (a static_assert there ties the
   counts), and to the readers. */

#ifndef CRUSH_EVENT_LOG_KERNEL_H
#define CRUSH_EVENT_LOG_KERNEL_H

#include <string>

namespace CrushKernels {

// one line per breakage event: the step and time of the break, the parent
// grain (tag, diameter, centre), the contact that broke it (normal force,
// its limit, partner "particle" or "wall") and the parent's generation
const char *const kEventColumns[] = {"step", "time", "parent_tag", "parent_diameter", "x", "y", "z",
                                     "F_n", "F_lim", "partner", "generation"};
const int kEventRecord = sizeof(kEventColumns) / sizeof(kEventColumns[0]);

// then, with keyword energy: elastic energy before and after the break,
// kinetic energy of the parent and of its fragments as made, the kinetic
// energy the fragments gained over the window, their largest speed and the
// steps watched
const char *const kEventEnergyColumns[] = {"E_el_before", "E_el_after", "KE_before", "KE_frag0",
                                           "KE_gain", "v_max", "n_steps"};
const int kEventLineEnergy = sizeof(kEventEnergyColumns) / sizeof(kEventEnergyColumns[0]);
// of which the first four are known when the break happens: they travel in
// the event's record (break_particles); the rest when its window is over
const int kEventEnergy = 4;

// The column names of the log, space separated (its header line less "# ").
// Called by FixCrushParticle::open_event_log.
inline std::string event_log_columns(bool energy)
{
  std::string s;
  for (int k = 0; k < kEventRecord; k++) s += (k ? " " : "") + std::string(kEventColumns[k]);
  if (energy)
    for (int k = 0; k < kEventLineEnergy; k++) s += " " + std::string(kEventEnergyColumns[k]);
  return s;
}

}  // namespace CrushKernels

#endif
