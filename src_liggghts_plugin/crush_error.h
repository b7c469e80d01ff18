// SPDX-License-Identifier: GPL-2.0-or-later
/* ----------------------------------------------------------------------
   Crushable-grain package for LIGGGHTS 3.8.

   crush_error_all: stop the run with one clean error message.

   LIGGGHTS 3.8's Error::all prints the message, then in about one call in
   five a "special message" whose text is the c_str() of a std::string that
   has already been destroyed (error_special.h, generate_message): the line
   that follows the message then holds garbage bytes, followed by the file
   and line again. That is stock behaviour, left alone for stock messages
   (docs/liggghts-patches.md); the package's own messages that a user must be
   able to read and grep for use this function instead. It does what
   Error::all does with the message (every rank calls it; rank 0 prints
   "ERROR: <msg> (<file>:<line>)" once to the screen and once to the log
   file; the output (dumps, thermo) is closed, then MPI_Finalize and exit
   status 1), without the special message.
------------------------------------------------------------------------- */

#ifndef LMP_CRUSH_ERROR_H
#define LMP_CRUSH_ERROR_H

#include <mpi.h>
#include <cstdio>
#include <cstdlib>

#include "lammps.h"
#include "output.h"
#include "universe.h"

namespace LAMMPS_NS {

inline void crush_error_all(LAMMPS *lmp, const char *file, int line, const char *msg)
{
  MPI_Barrier(lmp->world);
  int me = 0;
  MPI_Comm_rank(lmp->world, &me);
  if (me == 0) {
    if (lmp->screen) {
      fprintf(lmp->screen, "ERROR: %s (%s:%d)\n", msg, file, line);
      fflush(lmp->screen);
    }
    if (lmp->logfile) {
      fprintf(lmp->logfile, "ERROR: %s (%s:%d)\n", msg, file, line);
      fflush(lmp->logfile);
    }
  }
  if (lmp->output) {
    delete lmp->output;
    lmp->output = NULL;
  }
  if (lmp->screen && lmp->screen != stdout) fclose(lmp->screen);
  lmp->screen = NULL;
  if (lmp->logfile) fclose(lmp->logfile);
  lmp->logfile = NULL;
  if (lmp->universe->nworlds > 1) MPI_Abort(lmp->universe->uworld, 1);
  MPI_Finalize();
  exit(1);
}

}  // namespace LAMMPS_NS

#endif
