# SPDX-License-Identifier: GPL-2.0-or-later
"""Command line of crushpost: ``crushpost {br,fit-qc,thermo,pile,spheres,merge-parts,report} ...``."""

import argparse
import json
import os
import sys

import numpy as np

from .breakage import W_FRACTAL, break_fines, breakage
from .chamber import hole_gap, hole_radius, smallest_fragment_diameter
from .dump import read_crush_log, read_dump, true_mass
from .inputfile import InputFileError, read_checked
from .materials import D_MAX_BR, D_MIN_BR, RHO_GRAIN
from .meshes import write_pile_stl
from .spheres import chamber_sphere_centres, write_sphere_block
from .thermo import concat_blocks, read_log, summarize
from .pile import read_jack
from .trend import fit_qc_trend, mean_of_last_bands, qc_band_means, virgin_mask

# Calibrated NE34 limits at real size (docs/model.md §3) [m]; scaled by N.
D_MIN_REAL = D_MIN_BR
D_MAX_REAL = D_MAX_BR


def _read(path, reader, what):
    """``reader(path)`` with every failure one InputFileError naming the file."""
    return read_checked(path, what, lambda: reader(path))


def _is_empty(path):
    with open(path, "rb") as fh:
        return not fh.read(4096).strip()


def _read_dump(path):
    snaps = _read(path, read_dump, "a LAMMPS text dump")
    if not snaps:
        raise InputFileError("%s: no snapshot (an empty file, or not a LAMMPS text dump)" % path)
    return snaps


def _snapshot(snaps, index, path, option):
    try:
        return snaps[index]
    except IndexError:
        raise InputFileError("%s: no snapshot %d for %s (the dump has %d)"
                             % (path, index, option, len(snaps))) from None


def _grading(snap, density):
    atoms = snap["atoms"]
    if "radius" in atoms:
        d = 2.0 * atoms["radius"]
    elif "diameter" in atoms:
        d = atoms["diameter"]
    else:
        raise KeyError("dump at step %d has neither a radius nor a diameter column"
                       % snap["timestep"])
    # true mass: never the dump's `mass`, which density scaling raises
    return d, true_mass(atoms, density)


def _cmd_br(args):
    snaps = _read_dump(args.dump)
    now = _snapshot(snaps, args.snapshot, args.dump, "--snapshot")
    init_snaps = _read_dump(args.initial) if args.initial else snaps
    init = _snapshot(init_snaps, args.initial_snapshot, args.initial or args.dump,
                     "--initial-snapshot")
    d, m = _grading(now, args.density)
    d0, m0 = _grading(init, args.density)
    d_min = args.d_min if args.d_min is not None else D_MIN_REAL * args.N
    d_max = args.d_max if args.d_max is not None else D_MAX_REAL * args.N
    fines_events, m_fines = None, 0.0
    if args.events:
        if args.fines_mass is not None:
            raise ValueError("give either --events or --fines-mass, not both")
        # the breaks between the two snapshots (an event's step is the first
        # step its fragments exist)
        ev = _read(args.events, read_crush_log, "an event log of fix crush/particle")
        sel = (ev["step"] > init["timestep"]) & (ev["step"] <= now["timestep"])
        fines_events = break_fines(ev["parent_diameter"][sel], density=args.density,
                                   d_frag_min=args.d_frag_min)
        fines = fines_events.total
    else:
        if args.fines_mass is None:
            # Exact mass accounting: what the particles lost since the start is fines.
            fines = max(0.0, float(m0.sum()) + args.initial_fines_mass - float(m.sum()))
        else:
            fines = args.fines_mass
        if fines > 0.0 and args.fines_grading == "fractal":
            raise ValueError("fines_grading 'fractal' needs the sizes of the broken grains: "
                             "give the event log with --events, or use --fines-grading d_min")
        m_fines = fines
    res = breakage(d, m, d0, m0, d_min, d_max, m_fines=m_fines,
                   m_fines_initial=args.initial_fines_mass, w=args.w, fines=fines_events,
                   fines_grading=args.fines_grading)
    if args.json:
        print(json.dumps({"Br": res.Br, "Br_einav": res.Br_einav, "B_t": res.B_t,
                          "B_p": res.B_p, "fines_mass": fines, "fines_grading": args.fines_grading,
                          "d_min": d_min, "d_max": d_max,
                          "timestep": now["timestep"],
                          "initial_timestep": init["timestep"]}))
    else:
        print("%.10g" % res.Br)
    return 0


def _is_jack_series(path):
    with open(path) as fh:
        for line in fh:
            if not line.startswith("#"):
                return False
            if line.startswith("# fix jack/pile") or line.split()[1:4] == ["step", "time", "depth"]:
                return True
    return False


def _cmd_fit_qc(args):
    if not args.band_width > 0:
        raise ValueError("--band-width must be > 0 (the band height, in the units of h), got %g"
                         % args.band_width)
    if _read(args.file, _is_empty, "a text file"):
        raise InputFileError("%s: empty file; expected columns h and q_c, or a fix jack/pile "
                             "series" % args.file)
    if _read(args.file, _is_jack_series, "a text file"):
        # a fix jack/pile series: q_c = F_cone / (pi R^2) on virgin penetration
        # only (pushing, tip at its deepest so far, below the surface)
        if args.pile_radius is None or not args.pile_radius > 0:
            raise ValueError("%s is a fix jack/pile series: give --pile-radius R [m] "
                             "(q_c = F_cone / (pi R^2))" % args.file)
        jack = _read(args.file, read_jack, "a fix jack/pile series")
        mask = virgin_mask(jack["depth"], jack["phase"]) & (jack["depth"] > 0)
        h = jack["depth"][mask]
        q = jack["F_cone"][mask] / (np.pi * args.pile_radius ** 2)
        extra = {"n_points": int(mask.sum()),
                 "n_excluded": int(mask.size - mask.sum()),
                 "points": "virgin penetration"}
    else:
        data = _read(args.file, lambda p: np.loadtxt(p, ndmin=2), "a table of h and q_c")
        if data.shape[1] < 2:
            raise ValueError("%s: need two columns, h and q_c" % args.file)
        h, q = data[:, 0], data[:, 1]
        extra = {"n_points": int(h.size), "n_excluded": 0, "points": "all"}
    try:
        fit = fit_qc_trend(h, q)
    except (ValueError, RuntimeError) as exc:  # too few points, no convergence
        raise InputFileError("%s: cannot fit q_c(h) to the points of the file (%d: %s)"
                             % (args.file, h.size, exc)) from None
    bottom, mean, count = qc_band_means(h, q, args.band_width)
    extra.update(band_width=args.band_width, band_bottom=bottom.tolist(),
                 band_mean=[None if not np.isfinite(m) else float(m) for m in mean],
                 band_count=count.tolist())
    last3 = mean_of_last_bands(mean, count, 3)
    if last3 is not None:
        extra["mean_last3_bands"] = last3
    print(json.dumps(dict(fit._asdict(), **extra)))
    return 0


def _cmd_thermo(args):
    blocks = _read(args.log, read_log, "a LIGGGHTS log")
    if not blocks:
        raise InputFileError("%s: no thermo block found (%s)" % (
            args.log, "empty file" if _read(args.log, _is_empty, "a LIGGGHTS log")
            else "not a LIGGGHTS log, or no run printed thermo output"))
    groups = ([("all runs", concat_blocks(blocks))] if args.concat
              else [("run %d" % k, b) for k, b in enumerate(blocks)])
    for title, data in groups:
        n = len(next(iter(data.values()))) if data else 0
        print("# %s: %d rows" % (title, n))
        print("%-20s %8s %14s %14s %14s %14s" % ("column", "n", "first", "last", "min", "max"))
        for row in summarize(data):
            print("%-20s %8d %14.6g %14.6g %14.6g %14.6g" % row)
    return 0


def _cmd_pile(args):
    info = write_pile_stl(args.out, args.radius, args.shaft_length, tip_z=args.tip_z,
                          n_seg=args.segments, n_rings=args.shaft_rings,
                          cone_name=args.cone_name, shaft_name=args.shaft_name)
    # the top wall's hole for this pile (crushpost.chamber.hole_radius) and
    # the widest gap a grain could pass through
    r_hole = hole_radius(args.radius)
    lo, hi = hole_gap(args.radius, r_hole, args.segments, args.hole_segments)
    info["hole"] = {"radius": r_hole, "segments": args.hole_segments, "gap_min": lo,
                    "gap_max": hi}
    if args.N is not None:
        d_frag = smallest_fragment_diameter(args.N)
        info["hole"].update(N=args.N, smallest_fragment=d_frag, closed_to_fragments=hi < d_frag)
    print(json.dumps(info))
    return 0


def _cmd_spheres(args):
    centres = [list(c) for c in (args.centre or [])]
    if args.centres_file:
        rows = _read(args.centres_file, lambda p: np.loadtxt(p, comments="#", ndmin=2),
                     "a table of centres x y z")
        if rows.size == 0:
            raise InputFileError("%s: no centre (empty file); expected one line x y z per "
                                 "sphere" % args.centres_file)
        if rows.shape[1] != 3:
            raise InputFileError("%s: %d columns; expected three, x y z" % (args.centres_file,
                                                                            rows.shape[1]))
        centres += rows.tolist()
    if args.r_over_R or args.depth:
        if not (args.r_over_R and args.depth and args.pile_radius is not None
                and args.z_top is not None):
            raise ValueError("a grid needs --r-over-R, --depth, --pile-radius and --z-top")
        centres += chamber_sphere_centres(args.r_over_R, args.depth, args.pile_radius,
                                          args.z_top, azimuth_deg=args.azimuth).tolist()
    if not centres:
        raise ValueError("no sphere: give --centre, --centres-file or a --r-over-R/--depth grid")
    if not args.radius > 0.0:
        raise ValueError("--radius must be positive")
    if any(np.shape(c) != (3,) for c in centres):
        raise ValueError("every centre needs three coordinates")
    write_sphere_block(args.out, centres, args.radius, args.every, args.file,
                       group=args.group, prefix=args.prefix)
    print(json.dumps({"block": args.out, "output": args.file, "n_spheres": len(centres),
                      "radius": args.radius, "every": args.every, "centres": centres}))
    return 0


def _add_br(sub):
    """The ``br`` subcommand."""
    br = sub.add_parser("br", help="Einav breakage index Br of a dump snapshot")
    br.add_argument("dump", help="text dump with radius (or diameter) per particle")
    br.add_argument("--initial", help="dump holding the initial grading "
                    "(default: the same dump)")
    br.add_argument("--snapshot", type=int, default=-1,
                    help="index of the current snapshot (default -1, the last)")
    br.add_argument("--initial-snapshot", type=int, default=0,
                    help="index of the initial snapshot (default 0)")
    br.add_argument("--N", type=float, default=1.0,
                    help="particle up-scaling factor; scales the default d_min, d_max")
    br.add_argument("--d-min", type=float, help="d_min [m] (default 0.01 mm * N)")
    br.add_argument("--d-max", type=float, help="d_max [m] (default 0.27 mm * N)")
    br.add_argument("--w", type=float, default=W_FRACTAL,
                    help="fractal dimension of the limit grading (default 2.6)")
    br.add_argument("--density", type=float, default=RHO_GRAIN,
                    help="particle density [kg/m^3] for the grains' true mass when the dump "
                    "has no true-mass column (v_mass_true or c_crush_atom[3]; the mass column "
                    "is not used: density scaling raises it), "
                    "and of the broken grains of --events")
    br.add_argument("--events", help="event log of fix crush/particle (keyword 'events'): "
                    "the fines of each break get the size range of their parent")
    br.add_argument("--fines-grading", choices=("fractal", "d_min"), default="fractal",
                    help="how fines enter the grading, as the fix's keyword (default fractal, "
                    "needs --events when there are fines)")
    br.add_argument("--d-frag-min", type=float, default=0.0,
                    help="the fix's d_frag_min [m] (default 0), with --events")
    br.add_argument("--fines-mass", type=float,
                    help="without --events: fines mass now [kg], finer than d_min (default: "
                    "initial mass minus current particle mass, i.e. particles that left the "
                    "domain count as fines)")
    br.add_argument("--initial-fines-mass", type=float, default=0.0,
                    help="fines mass of the initial grading [kg] (default 0)")
    br.add_argument("--json", action="store_true",
                    help="print Br, Br_einav (unbounded), B_t, B_p, ... as JSON")
    br.set_defaults(func=_cmd_br)


def _add_fit_qc(sub):
    """The ``fit-qc`` subcommand."""
    fq = sub.add_parser("fit-qc", help="fit q_c(h) = a (1 - exp(-b h)); prints JSON "
                        "(a, b, their errors, the points used, the mean q_c of each depth band)")
    fq.add_argument("file", help="text file with columns h and q_c ('#' comments; every "
                    "point is fitted), or the time series of fix jack/pile (jack.txt: only "
                    "virgin penetration is fitted, i.e. pushing with the tip at its deepest "
                    "so far; re-pushes after an unload enter once past the deepest point)")
    fq.add_argument("--pile-radius", type=float,
                    help="pile radius R [m], for a jack/pile series: q_c = F_cone / (pi R^2)")
    fq.add_argument("--band-width", type=float, default=0.025,
                    help="height of the depth bands whose mean q_c is printed too (band_bottom, "
                    "band_mean, band_count, mean_last3_bands), in the units of h "
                    "(default 0.025: 25 mm for a jack/pile series)")
    fq.set_defaults(func=_cmd_fit_qc)


def _add_thermo(sub):
    """The ``thermo`` subcommand."""
    th = sub.add_parser("thermo", help="column summary of the thermo output of a log")
    th.add_argument("log")
    th.add_argument("--concat", action="store_true",
                    help="summarise all runs joined instead of run by run")
    th.set_defaults(func=_cmd_thermo)


def _add_pile(sub):
    """The ``pile`` subcommand."""
    pl = sub.add_parser("pile", help="cone tip (60 deg) and shaft of the pile as two ASCII "
                        "STL meshes; prints their geometry as JSON")
    pl.add_argument("--radius", type=float, required=True, help="pile radius R [m]")
    pl.add_argument("--shaft-length", type=float, required=True,
                    help="shaft length above the cone base [m]")
    pl.add_argument("--tip-z", type=float, default=0.0, help="z of the cone apex [m] (default 0)")
    pl.add_argument("--segments", type=int, default=24,
                    help="facets around the axis (default 24, at least 3)")
    pl.add_argument("--shaft-rings", type=int, default=None,
                    help="axial divisions of the shaft (default: facets no taller than 2 R)")
    pl.add_argument("--hole-segments", type=int, default=48,
                    help="segments of the top wall's hole polygon, for the reported gap "
                    "(default 48, the chamber's; a multiple of --segments keeps the gap "
                    "at R (1 - cos(pi / segments)))")
    pl.add_argument("--N", type=float, default=None,
                    help="particle up-scaling factor: also report the smallest fragment "
                    "(0.230093 d_comm, d_comm = 0.55 d50 = 0.55 * 0.21 mm * N) and whether "
                    "the hole's widest gap is below it")
    pl.add_argument("--out", required=True, help="output folder (created if missing)")
    pl.add_argument("--cone-name", default="cone.stl", help="file name of the cone (cone.stl)")
    pl.add_argument("--shaft-name", default="shaft.stl",
                    help="file name of the shaft (shaft.stl)")
    pl.set_defaults(func=_cmd_pile)


def _add_spheres(sub):
    """The ``spheres`` subcommand."""
    sp = sub.add_parser("spheres", help="deck block (stock LIGGGHTS commands) for measurement "
                        "spheres; `include` it after the walls; prints JSON")
    sp.add_argument("--radius", type=float, required=True, help="sphere radius [m]")
    sp.add_argument("--centre", type=float, nargs=3, action="append", metavar=("X", "Y", "Z"),
                    help="a sphere centre [m] (repeat for more spheres)")
    sp.add_argument("--centres-file", help="text file with one centre x y z per line")
    sp.add_argument("--r-over-R", type=float, nargs="+",
                    help="grid: distances from the pile axis in pile radii, e.g. 2 3 5 8")
    sp.add_argument("--depth", type=float, nargs="+",
                    help="grid: depths below --z-top [m], e.g. 0.2 0.5 0.8")
    sp.add_argument("--pile-radius", type=float, help="grid: pile radius R [m]")
    sp.add_argument("--z-top", type=float, help="grid: z of the sample top [m]")
    sp.add_argument("--azimuth", type=float, default=0.0,
                    help="grid: direction of the radii from +x [deg] (default 0)")
    sp.add_argument("--every", type=int, default=1000, help="output interval [steps] (default 1000)")
    sp.add_argument("--file", default="spheres.txt",
                    help="file the deck writes the stresses to (default spheres.txt)")
    sp.add_argument("--group", default="all", help="group of the grains (default all)")
    sp.add_argument("--prefix", default="ms", help="prefix of the IDs it defines (default ms)")
    sp.add_argument("--out", required=True, help="block file to write (e.g. spheres.in)")
    sp.set_defaults(func=_cmd_spheres)


def _add_merge_parts(sub):
    """The ``merge-parts`` subcommand."""
    mp = sub.add_parser("merge-parts", help="merge the parts of a chamber run that went on "
                        "from restart files into jack.txt, breakage_events.txt, spheres.txt and "
                        "log.liggghts (docs/cpt.md 'Restarting a run')")
    mp.add_argument("run_dir", help="the run's folder: restart/parts.json, or the parts' logs "
                    "log.part<k>.liggghts (their first thermo step is the restart step)")
    mp.set_defaults(func=_cmd_merge_parts)


def _add_report(sub):
    """The ``report`` subcommand."""
    rp = sub.add_parser("report", help="the analyses of a chamber run: figures (PNG), "
                        "fields.h5 and report.html (docs/report.md)")
    rp.add_argument("run_dir", help="the run's folder (examples/cpt_demo/run.py --out): "
                    "jack.txt, breakage_events.txt, snapshots/, spheres.in/.txt, "
                    "log.liggghts, summary.json")
    rp.add_argument("--out", default=None, help="output folder (default RUN_DIR/report)")
    rp.add_argument("--reference", default=None,
                    help="JSON or CSV of named values with their sources, shown beside the "
                    "run's headline numbers (docs/report.md lists the names)")
    rp.add_argument("--ring-width", type=float, default=None,
                    help="ring width [m] (default the pile radius R)")
    rp.add_argument("--ring-height", type=float, default=0.025,
                    help="ring height [m] (default 0.025)")
    rp.add_argument("--min-grains", type=int, default=65,
                    help="rings with fewer grains (centres) are flagged (default 65)")
    rp.add_argument("--profile-h", type=float, nargs="+", default=[-2.0, 0.0, 2.0, 5.0],
                    help="heights h/R above the apex of the radial profiles (default -2 0 2 5)")
    rp.add_argument("--history-r", type=float, nargs="+", default=[3.0, 5.0, 8.0],
                    help="r/R of the stress-history lines (default 3 5 8)")
    rp.add_argument("--band-width", type=float, default=1.0,
                    help="width of the radial bands of Br, in R (default 1: 1<r/R<2, ...)")
    rp.add_argument("--qc-norm", choices=("push", "steady"), default="push",
                    help="q_c that normalises the stresses: at the end of the last push "
                    "(default) or the steady q_c of the trend fit")
    rp.add_argument("--pile-radius", type=float, default=None,
                    help="pile radius R [m] (default summary.json's R_pile_m)")
    rp.add_argument("--N", type=float, default=None,
                    help="up-scaling factor N, for Br's d_min, d_max (default summary.json's)")
    rp.add_argument("--sector", type=int, default=None, choices=(360, 180, 90),
                    help="simulated sector [deg] (default summary.json's, else from the grains)")
    rp.add_argument("--quiet", action="store_true", help="print errors only")
    rp.set_defaults(func=_cmd_report)


def _add_compare(sub):
    """The ``compare`` subcommand."""
    cp = sub.add_parser("compare", help="two chamber runs side by side: the q_c ratio A/B and "
                        "the difference in crushing (events by zone, Br over the penetrated "
                        "layers), e.g. the demo with --grains unbreakable (A) and crushable (B)")
    cp.add_argument("run_a", help="run folder A (summary.json; report/fields.h5 if reported)")
    cp.add_argument("run_b", help="run folder B")
    cp.add_argument("--json", action="store_true", help="print JSON instead of a table")
    cp.set_defaults(func=_cmd_compare)


def build_parser():
    """The argparse parser with one subcommand per task (``br``, ``fit-qc``,
    ``thermo``, ``pile``, ``spheres``, ``merge-parts``, ``report``,
    ``compare``), each added by its ``_add_*`` function."""
    ap = argparse.ArgumentParser(prog="crushpost",
                                 description="Post-processing of crushable-sand DEM runs.")
    sub = ap.add_subparsers(dest="command", required=True)

    for add in (_add_br, _add_fit_qc, _add_thermo, _add_pile, _add_spheres, _add_merge_parts,
                _add_report, _add_compare):
        add(sub)
    return ap


def _cmd_compare(args):
    from .compare import compare, format_table, read_run

    try:
        run_a, run_b = read_run(args.run_a), read_run(args.run_b)
    except InputFileError as exc:
        print("crushpost compare: error: %s" % exc, file=sys.stderr)
        return 1
    rows, qc_ratio = compare(run_a, run_b)
    if args.json:
        print(json.dumps({"run_a": args.run_a, "run_b": args.run_b, "qc_ratio": qc_ratio,
                          "rows": {r[0]: {"a": r[1], "b": r[2], "ratio": r[3], "diff": r[4]}
                                   for r in rows}}, indent=2))
    else:
        print(format_table(rows, args.run_a, args.run_b))
    return 0


def _cmd_merge_parts(args):
    from . import restart as rs

    parts = rs.read_parts(args.run_dir)
    if not parts:
        parts = rs.infer_parts(args.run_dir)
        rs.write_parts(args.run_dir, parts)
    for name in rs.merge_parts(args.run_dir):
        print("crushpost merge-parts: wrote %s" % os.path.join(args.run_dir, name))
    return 0


def _cmd_report(args):
    from .report import main_report

    return main_report(args)


def main(argv=None):
    """Run the command line with ``argv`` (default ``sys.argv[1:]``); returns the exit code."""
    args = build_parser().parse_args(argv)
    try:
        return args.func(args)
    except OSError as exc:  # e.g. an output folder that does not exist
        where = exc.filename if exc.filename is not None else ""
        what = exc.strerror or str(exc)
        print("crushpost %s: error: %s%s" % (args.command, where and "%s: " % where, what),
              file=sys.stderr)
        return 1
    except (ValueError, KeyError, IndexError) as exc:
        print("crushpost %s: error: %s" % (args.command, exc), file=sys.stderr)
        return 1
