# SPDX-License-Identifier: GPL-2.0-or-later
"""The file formats crushpost reads and writes, each defined once:

* the breakage event log ``breakage_events.txt`` of fix crush/particle
  (its header and columns; the C++ side writes them in
  src_liggghts_plugin/fix_crush_particle.cpp);
* the top-level keys of the chamber driver's ``summary.json``
  (examples/cpt_demo/run.py; README.md's table);
* the layout of the report's ``fields.h5`` (groups, data sets, attributes;
  docs/report.md).

Readers and writers take the names from here; tests check the files the
C++ side, the driver and the report write against these definitions.
"""

import re
import types

# ---------------------------------------------------------------------------
# (a) the event log of fix crush/particle
# ---------------------------------------------------------------------------

#: The first header line starts so: ``# fix crush/particle <fix id>: one
#: line per breakage event``.
EVENT_LOG_TITLE = re.compile(r"^# fix crush/particle (\S+): one line per breakage event$")
#: Columns of the event log, in file order.
EVENT_LOG_COLUMNS = ("step", "time", "parent_tag", "parent_diameter", "x", "y", "z",
                     "F_n", "F_lim", "partner", "generation")
#: Columns that follow with the fix's ``energy yes`` (docs/fix_crush_particle.md,
#: "Energy accounting"), in file order.
EVENT_LOG_ENERGY_COLUMNS = ("E_el_before", "E_el_after", "KE_before", "KE_frag0", "KE_gain",
                            "v_max", "n_steps")
#: Integer columns (the rest are floats, but ``partner``, a word).
EVENT_LOG_INT_COLUMNS = frozenset({"step", "parent_tag", "generation", "n_steps"})
#: The words of the ``partner`` column.
EVENT_LOG_PARTNERS = ("particle", "wall")


def event_log_columns(n_words):
    """The columns of an event log whose lines have ``n_words`` words:
    EVENT_LOG_COLUMNS, with EVENT_LOG_ENERGY_COLUMNS after them when the
    count says so."""
    if n_words == len(EVENT_LOG_COLUMNS) + len(EVENT_LOG_ENERGY_COLUMNS):
        return EVENT_LOG_COLUMNS + EVENT_LOG_ENERGY_COLUMNS
    return EVENT_LOG_COLUMNS


def event_log_header(lines):
    """The (fix id, column names) of an event log's two header lines (an
    iterable of lines); ValueError when they are not the fix's header."""
    it = iter(lines)
    title, names = next(it, "").rstrip("\n"), next(it, "").rstrip("\n")
    m = EVENT_LOG_TITLE.match(title)
    if not m:
        raise ValueError("first line %r is not the fix crush/particle title" % title)
    if not names.startswith("# "):
        raise ValueError("second line %r is not a '# column ...' line" % names)
    return m.group(1), tuple(names[2:].split())


# ---------------------------------------------------------------------------
# (b) summary.json of the chamber driver
# ---------------------------------------------------------------------------

#: Top-level keys of summary.json that examples/cpt_demo/run.py writes for
#: a jacked run (README.md's table has a row for each).
SUMMARY_KEYS = (
    "qc_steady_MPa", "qc_fit_b", "qc_fit_a_err_MPa", "qc_fit_b_err", "qc_levelled_off",
    "n_break_events", "fines_mass_fraction", "mass_balance_rel_error", "n_particles_initial",
    "n_particles_final", "n_break_events_prep", "crush_in_prep", "n_particles_jacking_start",
    "n_particles_expected", "n_grains_outside", "n_events_inside_pile", "qc_fit_points",
    "qc_fit_excluded_repush_points", "sand_surface_z_m", "final_depth_m", "cycles",
    "wall_time_s", "mpi_ranks", "core_s", "mode", "grains", "N", "R_pile_m", "R_chamber_m",
    "H_chamber_m", "sector_deg", "plots", "crush_reading", "break_zones", "snapshots",
    "spheres", "parts", "prep", "failed_checks")
#: Keys only a prepared-only run (run.py --prep-only) writes.
SUMMARY_PREP_ONLY_KEYS = ("packing_seed",)
#: The keys as attributes (``SUMMARY.R_pile_m == "R_pile_m"``): a reader
#: that names a key not defined here fails at once.
SUMMARY = types.SimpleNamespace(**{k: k for k in SUMMARY_KEYS + SUMMARY_PREP_ONLY_KEYS})

# ---------------------------------------------------------------------------
# (c) fields.h5 of crushpost report
# ---------------------------------------------------------------------------

#: Attributes of the file's root.
FIELDS_H5_ROOT_ATTRS = ("run_dir", "R", "z_ref", "units", "problems")
#: The group of the headline numbers (its attributes; names in
#: crushpost.report.HEADLINE_NAMES and the patterns FIELDS_H5_HEADLINE_PATTERNS).
FIELDS_H5_HEADLINE = "headline"
FIELDS_H5_HEADLINE_PATTERNS = ("Br_band_{}_{}", "utilisation_{}_{}")
_RING_FIELDS = ("sigma_r", "sigma_theta", "sigma_z", "tau_rz", "p", "q", "sigma_1", "sigma_2",
                "sigma_3", "psi", "psi_unwrapped", "rotation", "porosity", "n_grains", "n_equiv",
                "low_count")
#: group (``{}``: a name part, e.g. ``increments/{}`` for increments/00)
#: -> (data sets, attributes); a run writes the groups its inputs allow.
FIELDS_H5_GROUPS = {
    "states": (("step", "time", "kind", "file", "qc_norm", "depth", "z_tip", "cycle"), ()),
    "rings": (("r_edges", "z_edges", "r_mid", "z_mid", "r_over_R", "h_over_R") + _RING_FIELDS,
              ("sector", "ring_width", "ring_height", "min_grains", "z_ref", "R")),
    "qc": (("step", "time", "depth", "qc", "phase", "virgin", "fit_h", "fit_qc", "fit_qc_std",
            "fit_cov", "band_bottom", "band_mean", "band_count"),
           ("a", "b", "a_err", "b_err", "levelled_off", "R", "model", "band_height",
            "run_scatter_rel", "run_scatter", "uncertainty_dominated_by")),
    "profiles": (("h_over_R", "r_over_R", "values"), ("layout",)),
    "histories/r_over_R_{}": (("state", "h_over_R", "sigma_r", "sigma_theta", "sigma_z"),
                              ("r_over_R",)),
    "breakage/events": (("step", "h_over_R", "r_over_R", "tip_depth", "inside_pile",
                         "parent_diameter", "generation"), ()),
    "breakage/density": (("r_edges_over_R", "h_edges_over_R", "count", "density_per_R3"),
                         ("definition",)),
    "breakage/bands": (("band_edges_over_R", "z_edges", "Br", "Br_band", "Br_band_penetrated"),
                       ("definition",)),
    "breakage/zones": (("n_events", "prep", "switch_on", "entry", "penetration", "in_zone",
                        "along_shaft", "beyond_5R_below", "elsewhere", "fraction_in_zone"), ()),
    "utilisation": (("step", "{}_n", "{}_median", "{}_p90", "{}_max"), ()),
    "psd": (("sizes", "F", "F_limit"), ("d_min", "d_max", "N", "fines")),
    "increments/{}": (("dr_mean", "count"),
                      ("from_step", "to_step", "from_kind", "to_kind", "n_matched", "n_gone",
                       "n_new")),
    "spheres": (("step", "centres", "p", "q", "q_over_p", "h_over_R"), ("radius",)),
}


def _pattern(name):
    return re.compile("^" + "[^/]+".join(re.escape(p) for p in name.split("{}")) + "$")


_GROUP_RE = [(_pattern(g), g) for g in FIELDS_H5_GROUPS]


def fields_h5_group(group):
    """The layout key of the group ``group`` (e.g. ``increments/{}`` for
    ``increments/03``), or None when the layout has no such group."""
    if group in FIELDS_H5_GROUPS:
        return group
    for rx, key in _GROUP_RE:
        if rx.match(group):
            return key
    return None


def _known(name, names):
    return name in names or any(_pattern(n).match(name) for n in names if "{}" in n)


def fields_h5_check(group, names, kind="datasets"):
    """Raise KeyError unless the layout has the group ``group`` and in it the
    data sets (``kind`` "datasets") or attributes ("attrs") ``names``."""
    key = fields_h5_group(group)
    if key is None:
        raise KeyError("fields.h5 layout (crushpost.formats) has no group %r" % group)
    allowed = FIELDS_H5_GROUPS[key][0 if kind == "datasets" else 1]
    bad = [n for n in names if not _known(n, allowed)]
    if bad:
        raise KeyError("fields.h5 layout (crushpost.formats) has no %s %s in group %r"
                       % ("data set" if kind == "datasets" else "attribute", bad, group))


def fields_h5_path(group, name):
    """``group/name`` of a data set the layout has (KeyError if not)."""
    fields_h5_check(group, (name,))
    return "%s/%s" % (group, name)
