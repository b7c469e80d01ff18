# SPDX-License-Identifier: GPL-2.0-or-later
"""crushpost: post-processing of crushable-sand DEM runs (LIGGGHTS plugin).

Pure functions on numpy arrays; see each module for units and conventions.

* :mod:`crushpost.materials` - the calibrated constants (NE34, steel; docs/model.md
  §3) and the Rayleigh time, the Python side of inputs/materials_ne34.in.
* :mod:`crushpost.breakage` - PSD curves and the Einav breakage index Br.
* :mod:`crushpost.trend` - fit q_c(h) = a (1 - exp(-b h)); virgin penetration.
* :mod:`crushpost.pile` - the fix jack/pile series, the tip position, points
  (breakage events) relative to the tip.
* :mod:`crushpost.stress` - p, q, principal stresses, cylindrical components,
  particle / measurement-sphere stresses, ring volume averages.
* :mod:`crushpost.thermo` - thermo blocks of LIGGGHTS/LAMMPS logs.
* :mod:`crushpost.dump` - text dumps and the crush event log.
* :mod:`crushpost.snapshot` - HDF5 snapshots of ``fix snapshot/hdf5`` (h5py).
* :mod:`crushpost.spheres` - measurement-sphere deck blocks and their output.
* :mod:`crushpost.prep` - the prepared sample: core porosity, ring statistics
  of the stress, the decks' preparation report (docs/preparation.md).
* :mod:`crushpost.cli` - ``crushpost {br,fit-qc,thermo,pile,spheres,report}`` (also ``python -m crushpost``).
"""

from .breakage import (N_BINS, W_FRACTAL, Breakage, BreakFines, bin_integrals,
                       bounded_breakage_index, break_fines, breakage, breakage_index,
                       fractal_grading_integral, fractal_psd, grading_integral,
                       limit_bin_integrals, psd_curve, sphere_mass)
from .dump import CRUSH_LOG_COLUMNS, iter_dump, read_crush_log, read_dump
from .snapshot import (list_snapshots, read_snapshot, read_snapshots,
                       snapshot_particle_stress)
from .stress import (Invariants, cylindrical_basis, invariants, pair_contact_terms,
                     particle_stress, ring_average, ring_averages, sphere_ring_volume,
                     sphere_stress, to_cylindrical, to_cylindrical_tensor)
from .thermo import concat_blocks, parse_log, read_log, summarize
from .trend import QcFit, fit_qc_trend, qc_trend, virgin_mask
from .pile import inside_pile, read_jack, relative_to_tip, tip_z_at

__all__ = [
    "N_BINS", "W_FRACTAL", "Breakage", "BreakFines", "bin_integrals",
    "bounded_breakage_index", "break_fines", "breakage", "breakage_index",
    "fractal_grading_integral", "fractal_psd", "grading_integral", "limit_bin_integrals",
    "psd_curve", "sphere_mass",
    "CRUSH_LOG_COLUMNS", "iter_dump", "read_crush_log", "read_dump",
    "list_snapshots", "read_snapshot", "read_snapshots", "snapshot_particle_stress",
    "Invariants", "cylindrical_basis", "invariants", "pair_contact_terms",
    "particle_stress", "ring_average", "ring_averages", "sphere_ring_volume",
    "sphere_stress", "to_cylindrical", "to_cylindrical_tensor",
    "concat_blocks", "parse_log", "read_log", "summarize",
    "QcFit", "fit_qc_trend", "qc_trend", "virgin_mask",
    "inside_pile", "read_jack", "relative_to_tip", "tip_z_at",
]
