# SPDX-License-Identifier: GPL-2.0-or-later
"""

The package (one module per family of analysis and figures):

* core: reads the run once and hands the parts a context (make_report,
  main_report for ``crushpost report``);
* inputs: the readers, each failure one line naming the file;
* common: settings, the collector of outputs, constants, drawing helpers;
* qc: tip resistance, its trend and the normalising q_c;
* log_numbers: mass balance, lost atoms, break counts from the log;
* states: the snapshots read once, ring fields and the per-state steps;
* stresses: ring fields and stress paths (contours, profiles, histories,
  measurement spheres);
* rotation: the rotation of the principal axes;
* bands: breakage (Br in bands, where grains break, utilisation);
* psd: the grading; increments: radial displacement increments;
* paraview: ParaView's picture; page: report.html; fields_h5: fields.h5
  (layout pinned in crushpost.formats).
"""

from .common import HEADLINE_NAMES, STATE_KINDS, ReportInputError, ReportOptions
from .core import main_report, make_report
from .inputs import read_reference

__all__ = ["ReportInputError", "ReportOptions", "make_report", "read_reference",
           "HEADLINE_NAMES", "STATE_KINDS", "main_report"]
