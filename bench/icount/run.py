#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-2.0-or-later
"""Instruction counts per rank, per component and per feature of the chamber
in its jacking phase (docs/studies/performance.md "Instruction counts").

    /usr/bin/python3 bench/icount/run.py scaling  [--grains-per-rank 7200] [--ranks 1 2 4 8]
    /usr/bin/python3 bench/icount/run.py features [--grains 3000]
    /usr/bin/python3 bench/icount/run.py meshes   [--grains 3000]   # each mesh of the wall fix
    /usr/bin/python3 bench/icount/run.py scaling --wall --ranks 8 16   # wall clock, no valgrind

A benchmark, not a test. Wall time on a shared 2-core machine says nothing,
so the script counts instructions with valgrind's callgrind (deterministic,
independent of the load): every MPI rank runs under
`valgrind --tool=callgrind --collect-atstart=no
--toggle-collect='LAMMPS_NS::Verlet::run(int)'`, so only the time loops
count (the deck's only timed loop is the jacking run; its `run 0` loop is
empty). The script parses each rank's callgrind file itself (call edges
with inclusive costs) and splits the loop into components.

Scene (bench/icount/in.icount): a horizontal slice of the paper chamber
(R_ch = 216 mm, full circle, NE34 at N = 39) with the cone pile's apex
half-way down, its height chosen for the requested number of grains. The
grains sit on a face-centred cubic lattice whose neighbours overlap by
0.15-0.45 % of d50 (bench/crush_overhead/run.py's construction, its rattler
rule included, so nothing breaks); sites inside or touching the pile are
left empty. All meshes (side, top, plug, bottom, cone, shaft) are in the
wall fix, the top servo and the jack move their meshes, the crushing fix
runs: the fix set of examples/cpt_paper/in.monotonic while jacking. The
packing is static over the few timed steps: no neighbour-list rebuild
happens in them (the script checks the count of neighbour builds).

Derived numbers (scaling): W_P(r) = instructions of rank r outside MPI
calls (the MPI library busy-waits, so its count depends on the timing; it
is reported separately as `mpi`), imbalance = max_r W_P / mean_r W_P,
replicated work = (sum_r W_P - W_1) / P per rank, efficiency bound
E_P <= W_1 / (P max_r W_P).

`--wall` runs the same decks natively and reports loop times and
particle-steps per core-second instead (for machines with 16 or more
cores; not meaningful on a shared 2-core machine). Keep the timed steps
at 100 or fewer: the compressed lattice stays static for about 120 steps,
then relaxes (a neighbour-list build every 4-6 steps, grains break), which
is not the work of a jacking step. bench/device/scaling_wall.sh runs the
16-core comparison.

`--balance "CMD"` puts the command line CMD right after read_data (e.g. a
static load-balancing command).
"""

import argparse
import json
import math
import os
import platform
import re
import shutil
import subprocess
import sys
import time
from collections import defaultdict

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
DECK = os.path.join(HERE, "in.icount")
sys.path.insert(0, os.path.join(REPO, "scripts"))

from crushpost.chamber import N_SEG_FULL, hole_radius  # noqa: E402
from crushpost.materials import D50, RHO_GRAIN  # noqa: E402
from crushpost.meshes import (annulus_triangles, cone_height, cylinder_triangles,  # noqa: E402
                              plate_triangles, write_pile_stl, write_stl)
from crushpost.packing import write_lammps_data  # noqa: E402

D50_REAL = D50
RHO = RHO_GRAIN
SEED = 15485863

# ---------------------------------------------------------------------------
# scene


def _overhead_module():
    """bench/crush_overhead/run.py: the fix's strength factor and constants."""
    import importlib.util
    spec = importlib.util.spec_from_file_location(
        "crush_overhead_run", os.path.join(REPO, "bench", "crush_overhead", "run.py"))
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def lattice_scene(out, n_target, N=39.0, R_ch=0.216, R_pile=0.018, compress=0.003,
                  perturb=0.0015, safety=3.0, packing_seed=20240611, mesh_refine=1):
    """Write grains.data and the meshes of a chamber slice holding about
    n_target grains on an FCC lattice, the pile's apex at mid-height.
    mesh_refine multiplies the facet counts of the side and top walls and of
    the pile (the grain sites stay those of the coarsest side wall)."""
    overhead = _overhead_module()
    n_seg = N_SEG_FULL * mesh_refine
    os.makedirs(out, exist_ok=True)
    d50 = D50_REAL * N
    s = (1.0 - compress) * d50
    a = s * math.sqrt(2.0)
    r0 = 0.5 * d50
    h_cone = cone_height(R_pile)
    # sites per layer pair (two FCC layers a/2 apart) in the disc, less the pile
    area = math.pi * (R_ch - r0) ** 2 - math.pi * (R_pile + r0) ** 2 * 0.5
    per_layer = area / (a * a / 2.0)
    n_layers = max(4, int(math.ceil(n_target / per_layer)))
    nx = int(math.ceil(2 * R_ch / (a / 2))) + 2
    while True:
        I, J, K = np.meshgrid(np.arange(-nx, nx + 1), np.arange(-nx, nx + 1), np.arange(n_layers),
                              indexing="ij")
        on = (I + J + K) % 2 == 0
        x, y, k = I[on] * a / 2, J[on] * a / 2, K[on]
        z = s / 2 + k * a / 2
        H = s / 2 + (n_layers - 1) * a / 2 + s / 2
        z_tip = 0.5 * H
        rho = np.hypot(x, y)
        # the side wall is a polygon of N_SEG_FULL facets with its vertices on
        # R_ch: at most the lattice overlap against its flat facets
        inside = rho <= R_ch * math.cos(math.pi / N_SEG_FULL) - r0 * (1.0 - compress)
        # (the same sites for every mesh_refine: the coarsest polygon decides)
        # distance to the pile (cone from the apex, shaft above), in the (rho, z) half-plane
        sz = z - z_tip
        prof = np.where(sz < 0, -1.0, np.minimum(sz / h_cone, 1.0) * R_pile)
        t = np.clip((rho * R_pile + sz * h_cone) / (R_pile ** 2 + h_cone ** 2), 0.0, 1.0)
        d_cone = np.hypot(rho - t * R_pile, sz - t * h_cone)
        d_shaft = np.where(sz >= h_cone, np.abs(rho - R_pile), np.hypot(rho - R_pile, sz - h_cone))
        clear = (rho > prof) & (np.minimum(d_cone, d_shaft) > 1.2 * r0)
        keep = inside & clear
        if keep.sum() >= n_target or n_layers > 10000:
            break
        n_layers += 1
    pos = np.column_stack([x[keep], y[keep], z[keep]])
    n = pos.shape[0]
    rng = np.random.default_rng(packing_seed)
    d = d50 * (1.0 + rng.uniform(-perturb, perturb, n))
    # rattlers: grains too weak for the lattice overlap (bench/crush_overhead/run.py)
    Es = overhead.e_star_grain()
    f = np.array([overhead.strength_factor(SEED, t, overhead.VAR) for t in range(1, n + 1)])
    sigma = overhead.SIGMA_LIM0 * f * (d / (N * overhead.D0)) ** (-3.0 / overhead.M_WEIBULL)
    g2 = (3.0 * math.pi * sigma / (4.0 * Es)) ** 2
    r_star_min = d50 * (1.0 - perturb) / 4.0
    rattler = r_star_min * g2 < safety * d50 * (compress + perturb)
    d[rattler] = 0.99 * s
    L = 1.25 * R_ch
    shaft_len = (H - z_tip - h_cone) + 0.1 * H + 2 * d50
    pile = write_pile_stl(out, R_pile, shaft_length=shaft_len, tip_z=z_tip, n_seg=24 * mesh_refine)
    box = (-L, L, -L, L, -0.05 * H, pile["z_top"] + 0.02 * H)
    write_lammps_data(os.path.join(out, "grains.data"), pos, d, RHO, box, ntypes=4)
    r_hole = hole_radius(R_pile)
    write_stl(os.path.join(out, "side.stl"), cylinder_triangles(R_ch, -0.02 * H, 1.1 * H, n_seg), "side")
    write_stl(os.path.join(out, "bottom.stl"), plate_triangles(1.15 * R_ch), "bottom")
    write_stl(os.path.join(out, "top.stl"), annulus_triangles(r_hole, 1.15 * R_ch, H, n_seg), "top")
    write_stl(os.path.join(out, "plug.stl"), plate_triangles(1.4 * R_pile, 1.001 * H), "plug")
    scene = {"grains": int(n), "rattlers": int(rattler.sum()), "layers": n_layers, "H_ch": H,
             "z_tip": z_tip, "R_ch": R_ch, "R_pile": R_pile, "R_hole": r_hole, "N": N, "d50": d50,
             "spacing": s, "compress": compress, "perturb": perturb, "box": list(box),
             "mesh_refine": mesh_refine,
             "facets": {"cone": pile["cone_facets"], "shaft": pile["shaft_facets"],
                        "side": 2 * n_seg, "top": 2 * n_seg}}
    with open(os.path.join(out, "scene.json"), "w") as fh:
        json.dump(scene, fh, indent=2)
    return scene


# ---------------------------------------------------------------------------
# callgrind files

_NAMED = re.compile(r"^(ob|cob|fl|fi|fe|cfi|cfl|fn|cfn)=\((\d+)\)(?: (.*))?$")


def parse_callgrind(path):
    """Exclusive cost per function and inclusive cost per call edge.

    Returns {"total", "self": {fn: Ir}, "edges": {(caller, callee): Ir},
    "object": {fn: object file}}. Function names as valgrind demangles them.
    """
    names = {"ob": {}, "fl": {}, "fn": {}}
    kind_of = {"ob": "ob", "cob": "ob", "fl": "fl", "fi": "fl", "fe": "fl", "cfi": "fl",
               "cfl": "fl", "fn": "fn", "cfn": "fn"}
    self_cost = defaultdict(int)
    edges = defaultdict(int)
    ncalls = defaultdict(int)
    obj = {}
    fn = cfn = None
    ob = cob = None
    pending_call = False
    total = None
    with open(path) as fh:
        for line in fh:
            c = line[0]
            if c.isdigit() or c in "+-*":
                parts = line.split()
                cost = int(parts[1]) if len(parts) > 1 else 0
                if pending_call:
                    edges[(fn, cfn)] += cost
                    pending_call = False
                    cob = None                 # cob= names the object of one call only
                else:
                    self_cost[fn] += cost
                continue
            m = _NAMED.match(line.rstrip("\n"))
            if m:
                key, ident, name = m.group(1), m.group(2), m.group(3)
                table = names[kind_of[key]]
                if name is not None:
                    table[ident] = name
                value = table.get(ident, "?")
                if key == "fn":
                    fn = value
                    obj.setdefault(fn, ob)
                elif key == "cfn":
                    cfn = value
                    obj.setdefault(cfn, cob if cob is not None else ob)
                elif key == "ob":
                    ob = value
                    cob = None
                elif key == "cob":
                    cob = value
                continue
            if line.startswith("calls="):
                pending_call = True
                ncalls[(fn, cfn)] += int(line[6:].split()[0])
                continue
            if line.startswith("summary:") or line.startswith("totals:"):
                total = int(line.split()[1])
    return {"total": total if total is not None else sum(self_cost.values()),
            "self": dict(self_cost), "edges": dict(edges), "calls": dict(ncalls), "object": obj}


VERLET = "LAMMPS_NS::Verlet::run(int)"
_CLASS = re.compile(r"^(?:non-virtual thunk to )?(?:LAMMPS_NS|LIGGGHTS)::(?:[A-Za-z]+::)*?([A-Z][A-Za-z0-9_]*)::[~A-Za-z_]")

# components of the step: the class of a function called by Verlet::run or by
# Modify (the fix hooks) decides where its inclusive cost goes
COMPONENT_OF_CLASS = {
    "PairGran": "pair force", "PairGranProxy": "pair force",
    "Neighbor": "neighbour lists", "NeighList": "neighbour lists",
    "Comm": "communication", "CommBrick": "communication", "Irregular": "communication",
    "FixWallGran": "mesh walls", "FixMeshSurfaceStress": "mesh walls",
    "FixMeshSurface": "mesh walls", "FixMesh": "mesh walls",
    "FixNeighlistMesh": "mesh walls", "FixContactHistoryMesh": "mesh walls",
    "FixMoveMesh": "servo and jack (moving meshes, their variables)",
    "FixAveTime": "servo and jack (moving meshes, their variables)",
    "FixJackPile": "servo and jack (moving meshes, their variables)",
    "FixServoRadial": "servo and jack (moving meshes, their variables)",
    "FixCrushParticle": "crushing (fix crush/particle)",
    "FixDampLocal": "local damping", "FixNVE": "integration (nve)",
    "Output": "output (thermo, dumps)", "Thermo": "output (thermo, dumps)",
    "FixSnapshotHdf5": "output (thermo, dumps)",
}


def class_of(fn):
    m = _CLASS.match(fn or "")
    return m.group(1) if m else None


def is_mpi_object(ob):
    return ob is not None and ("libmpi" in ob or "openmpi" in ob or "libopen-" in ob or "mca_" in ob)


def components(cg):
    """Split the collected instructions (inside Verlet::run) into components.

    Returns {"total", "mpi", "work", "components": {name: Ir incl. MPI},
    "components_mpi": {name: Ir in MPI calls made by that component's
    classes}, "top_functions": [...]}. `work` = total - mpi.
    """
    edges, obj = cg["edges"], cg["object"]
    comp = defaultdict(int)
    comp["other"] += cg["self"].get(VERLET, 0)
    hooks = set()                              # Modify's fix hooks called by the loop
    for (a, b), cost in edges.items():
        if a == VERLET:
            cls = class_of(b)
            if cls == "Modify":
                hooks.add(b)                   # split below by fix class
                continue
            comp[COMPONENT_OF_CLASS.get(cls, "other")] += cost
    for (a, b), cost in edges.items():
        if a in hooks:
            cls = class_of(b)
            name = COMPONENT_OF_CLASS.get(cls)
            if name is None:
                name = "other fixes (%s)" % cls if cls and cls.startswith("Fix") else "other"
            comp[name] += cost
    for fn in hooks:
        comp["other"] += cg["self"].get(fn, 0)
    # MPI: instructions inside the MPI library (busy waiting included) under
    # each component, propagated up the call graph in proportion (gprof's
    # rule: a function's MPI share is the same for each of its callers)
    frac = mpi_fractions(cg)
    mpi = defaultdict(int)
    for (a, b), cost in edges.items():
        if a == VERLET and b not in hooks:
            mpi[COMPONENT_OF_CLASS.get(class_of(b), "other")] += cost * frac.get(b, 0.0)
        elif a in hooks:
            cls = class_of(b)
            name = COMPONENT_OF_CLASS.get(cls)
            if name is None:
                name = "other fixes (%s)" % cls if cls and cls.startswith("Fix") else "other"
            mpi[name] += cost * frac.get(b, 0.0)
    mpi = {k: int(round(v)) for k, v in mpi.items() if v > 0}
    total = cg["total"]
    mpi_total = sum(cost for (a, b), cost in edges.items()
                    if is_mpi_object(obj.get(b)) and not is_mpi_object(obj.get(a)))
    mpi_calls = defaultdict(int)                # calls into MPI, by the calling function
    for (a, b), n in cg["calls"].items():
        if is_mpi_object(obj.get(b)) and not is_mpi_object(obj.get(a)):
            mpi_calls["%s -> %s" % (a, b)] += n
    return {"total": total, "mpi": mpi_total, "work": total - mpi_total,
            "mpi_calls": dict(sorted(mpi_calls.items(), key=lambda kv: -kv[1])),
            "components": dict(sorted(comp.items(), key=lambda kv: -kv[1])),
            "components_mpi": dict(mpi),
            "unaccounted": total - sum(comp.values())}


def mpi_fractions(cg):
    """For each function, the fraction of its inclusive cost spent inside the
    MPI library (an MPI function: 1)."""
    edges, obj = cg["edges"], cg["object"]
    out_edges = defaultdict(list)
    incl = defaultdict(int)
    for (a, b), cost in edges.items():
        if a != b:
            out_edges[a].append((b, cost))
            incl[b] += cost
    memo = {}

    def frac(fn, stack):
        if fn in memo:
            return memo[fn]
        if is_mpi_object(obj.get(fn)):
            memo[fn] = 1.0
            return 1.0
        if fn in stack:                      # a cycle: count it as no MPI
            return 0.0
        stack.add(fn)
        m = sum(cost * frac(b, stack) for b, cost in out_edges.get(fn, ()))
        stack.discard(fn)
        total = max(incl.get(fn, 0), cg["self"].get(fn, 0) + sum(c for _, c in out_edges.get(fn, ())))
        memo[fn] = min(1.0, m / total) if total > 0 else 0.0
        return memo[fn]

    sys.setrecursionlimit(max(10000, sys.getrecursionlimit()))
    for fn in list(incl) + list(cg["self"]):
        frac(fn, set())
    return memo


def inclusive_of(cg, fn):
    """Inclusive cost of fn: the sum of the edges into it (0 if never called)."""
    return sum(c for (a, b), c in cg["edges"].items() if b == fn and a != fn)


# ---------------------------------------------------------------------------
# runs

def jack_args(scene_dir, scene, steps, dt, v=0.5):
    """fix jack/pile arguments whose push ends on the last timed step: the
    deck's depth reference is c_zmax + d50/2 (pile_jacking.in), the apex is
    at z_tip, the last step is shortened to land on the depth."""
    z = np.loadtxt(os.path.join(scene_dir, "grains.data"), skiprows=10, usecols=6)
    depth = float(z.max()) + 0.5 * scene["d50"] - scene["z_tip"] + v * dt * (steps - 0.5)
    return "mode monotonic v %g depth %.12g" % (v, depth)


def deck_vars(args, scene_dir, scene, extra=None):
    var = {"inputs": os.path.join(REPO, "inputs"), "R_ch": scene["R_ch"], "H_ch": scene["H_ch"],
           "R_pile": scene["R_pile"], "R_hole": scene["R_hole"], "N": scene["N"],
           "steps": args.steps, "dt": args.dt,
           "jack_args": jack_args(scene_dir, scene, args.steps, args.dt)}
    if args.balance:
        var["balance_cmd"] = args.balance
    if args.rebuild_every:
        var["rebuild_every"] = args.rebuild_every
    var.update(extra or {})
    return var


LOOP_RE = re.compile(r"^Loop time of (\S+) on (\d+) procs for (\d+) steps with (\d+) atoms")


def parse_log(path):
    """The timed run's loop line, neighbour builds and the ICOUNT line."""
    out = {"loops": [], "neighbor_builds": [], "icount": None}
    with open(path) as fh:
        for line in fh:
            m = LOOP_RE.match(line)
            if m:
                out["loops"].append({"loop_s": float(m.group(1)), "procs": int(m.group(2)),
                                     "steps": int(m.group(3)), "atoms": int(m.group(4))})
            elif line.startswith("Neighbor list builds ="):
                out["neighbor_builds"].append(int(line.split("=")[1]))
            elif line.startswith("ICOUNT"):
                w = line.split()
                out["icount"] = {w[i]: float(w[i + 1]) for i in range(1, len(w) - 1, 2)}
    return out


def run_deck(args, run_dir, scene_dir, np_, var, proc_grid=None, callgrind=True):
    """Run the deck at np_ ranks in run_dir (a copy of the scene's files);
    returns the log summary and, under callgrind, each rank's components."""
    if os.path.exists(run_dir):
        shutil.rmtree(run_dir)
    shutil.copytree(scene_dir, run_dir)
    cmd = ["mpirun", "--oversubscribe", "-np", str(np_)]
    if os.geteuid() == 0:
        cmd.insert(1, "--allow-run-as-root")
    if callgrind:
        cmd += ["valgrind", "--tool=callgrind", "--collect-atstart=no",
                "--toggle-collect=" + VERLET, "--callgrind-out-file=callgrind.out.%p"]
    var = dict(var)
    var["proc_grid"] = proc_grid or ("* * 1" if np_ > 1 else "1 1 1")
    cmd += [args.liggghts, "-in", DECK, "-log", "log.liggghts", "-echo", "none", "-screen", "none"]
    for k, v in var.items():
        cmd += ["-var", k, str(v)]
    t0 = time.time()
    res = subprocess.run(cmd, cwd=run_dir, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    wall = time.time() - t0
    if res.returncode != 0:
        sys.stderr.write(res.stdout[-3000:])
        raise RuntimeError("run failed in %s (see log.liggghts)" % run_dir)
    log = parse_log(os.path.join(run_dir, "log.liggghts"))
    timed = log["loops"][-1]
    if timed["steps"] != args.steps or len([lp for lp in log["loops"] if lp["steps"] > 0]) != 1:
        raise RuntimeError("%s: expected one timed run of %d steps, got %s"
                           % (run_dir, args.steps, log["loops"]))
    out = {"np": np_, "proc_grid": var["proc_grid"], "atoms": timed["atoms"], "steps": timed["steps"],
           "loop_s": timed["loop_s"], "neighbor_builds_timed_run": log["neighbor_builds"][-1],
           "n_break": log["icount"]["n_break"] if log["icount"] else None,
           "wall_s_incl_setup": wall, "vars": {k: v for k, v in var.items() if k != "inputs"}}
    if out["n_break"] or (out["neighbor_builds_timed_run"] and not args.rebuild_every):
        # the counts are meant for a static packing: say when it was not
        sys.stderr.write("warning: %s: %s breaks, %d neighbour-list builds in the timed run\n"
                         % (run_dir, out["n_break"], out["neighbor_builds_timed_run"]))
    if callgrind:
        ranks = []
        files = sorted((f for f in os.listdir(run_dir) if f.startswith("callgrind.out.")),
                       key=lambda f: int(f.rsplit(".", 1)[1]))
        for f in files:
            cg = parse_callgrind(os.path.join(run_dir, f))
            c = components(cg)
            c["file"] = f
            if c["unaccounted"] != 0:       # the components must add up to the loop
                sys.stderr.write("warning: %s: components miss %d instructions\n" % (f, c["unaccounted"]))
            ranks.append(c)
        # in pid order (mpirun on one node starts the ranks in order, usually)
        out["ranks"] = ranks
        if not args.keep:
            for f in files:
                os.remove(os.path.join(run_dir, f))
    return out


def summarise_scaling(runs):
    """Imbalance, replicated work and the efficiency bound from the counts."""
    by_np = {r["np"]: r for r in runs}
    base = by_np.get(1)
    W1 = base["ranks"][0]["work"] if base else None
    names = sorted({k for r in runs for rk in r["ranks"] for k in rk["components"]})
    out = []
    for r in runs:
        P = r["np"]
        steps = r["steps"]
        W = [rk["work"] for rk in r["ranks"]]
        mpi = [rk["mpi"] for rk in r["ranks"]]
        mean, mx = sum(W) / P, max(W)
        row = {"np": P, "grains": r["atoms"], "grains_per_rank": r["atoms"] / P, "steps": steps,
               "work_per_step_per_rank": [w / steps for w in W],
               "mpi_per_step_per_rank": [m / steps for m in mpi],
               "imbalance_max_over_mean": mx / mean}
        if W1 is not None:
            row["replicated_work_per_rank_per_step"] = (sum(W) - W1) / P / steps
            row["replicated_fraction_of_W1_over_P"] = (sum(W) - W1) / W1
            row["efficiency_bound"] = W1 / (P * mx)
        # per-component instructions per step, mean and max over ranks (MPI excluded)
        comp = {}
        for name in names:
            vals = [(rk["components"].get(name, 0) - rk["components_mpi"].get(name, 0)) / steps
                    for rk in r["ranks"]]
            comp[name] = {"mean": sum(vals) / P, "max": max(vals),
                          "share_of_mean_work": sum(vals) / P / (mean / steps)}
        row["components_per_step"] = comp
        out.append(row)
    # fit W_mean(P) = W1/P + c over the rank counts (least squares in c)
    if W1 is not None and len(runs) > 1:
        cs = [sum(rk["work"] for rk in r["ranks"]) / r["np"] - W1 / r["np"] for r in runs if r["np"] > 1]
        fit_c = sum(cs) / len(cs) / runs[0]["steps"]
        for row in out:
            row["fit_c_replicated_per_rank_per_step"] = fit_c
    return out


def machine():
    info = {"platform": platform.platform(), "python": platform.python_version(),
            "cpus": os.cpu_count()}
    try:
        info["valgrind"] = subprocess.run(["valgrind", "--version"], capture_output=True,
                                          text=True).stdout.strip()
    except OSError:
        info["valgrind"] = None
    return info


def cmd_scaling(args):
    n_total = int(args.grains_per_rank * max(args.ranks))
    scene_dir = os.path.join(args.out, "scene_scaling")
    scene = lattice_scene(scene_dir, n_total, N=args.N, R_ch=args.R_ch)
    print(json.dumps({"scene": scene}), flush=True)
    runs = []
    for P in args.ranks:
        grid = None
        if args.proc_grid:
            grid = dict(g.split("=") for g in args.proc_grid).get(str(P))
        var = deck_vars(args, scene_dir, scene)
        r = run_deck(args, os.path.join(args.out, "scaling_np%d" % P), scene_dir, P, var,
                     proc_grid=grid, callgrind=not args.wall)
        if not args.wall:
            r["work_per_step_per_rank"] = [rk["work"] / r["steps"] for rk in r["ranks"]]
        else:
            r["particle_steps_per_core_s"] = r["atoms"] * r["steps"] / (r["loop_s"] * P)
        print(json.dumps({k: r[k] for k in r if k != "ranks"}), flush=True)
        runs.append(r)
    result = {"what": "instruction counts per rank of the chamber slice (bench/icount/run.py scaling)",
              "command": " ".join(sys.argv), "date_utc": time.strftime("%Y-%m-%d %H:%M", time.gmtime()),
              "machine": machine(), "scene": scene, "steps": args.steps, "wall_clock": args.wall,
              "runs": runs}
    if not args.wall:
        result["summary"] = summarise_scaling(runs)
    return result


def feature_variants(args, scene_dir, scene):
    """(name, what, deck variables) of the feature table: a base deck with
    no optional feature, each feature alone, active (its output falls in the
    timed steps) and idle (its period is longer than the timed steps)."""
    from crushpost.spheres import write_sphere_block
    S = args.steps
    never = 10 * S + 1000                    # a period no timed step reaches
    # four spheres of radius d50 around the pile (2 and 3 pile radii, 2 depths)
    R = scene["R_pile"]
    cen = [(f * R, 0.0, z) for z in (scene["z_tip"], scene["z_tip"] - 2 * R) for f in (2.0, 2.5)]
    spheres = {}
    for tag, every in (("active", S), ("idle", never)):
        path = os.path.join(scene_dir, "spheres_%s.in" % tag)
        write_sphere_block(path, cen, scene["d50"], every, "spheres_%s.txt" % tag)
        spheres[tag] = path
    base = {"grain_model": "unbreakable", "damping": 0}
    idle_snap = "../bench/icount/snapshot_idle"
    return [
        ("base", "no optional feature: unbreakable grains, no damping, no output; the contact "
                 "computes and compute stress/grain defined (chamber_walls.in) but never evaluated", base),
        ("base, contact computes absent", "as base, with compute pgl, wgl, sigma_p uncomputed",
         dict(base, drop_contact_computes=1)),
        ("crushing", "fix crush/particle (crushable_ne34.in); nothing breaks",
         dict(base, grain_model="crushable_ne34")),
        ("local damping", "fix damp/local alpha 0.05 (integrate.in)", dict(base, damping=1)),
        ("measurement spheres, idle", "4 spheres (crushpost spheres block), period > timed steps",
         dict(base, spheres_file=spheres["idle"])),
        ("measurement spheres, one output", "the same, output on the last timed step",
         dict(base, spheres_file=spheres["active"])),
        ("VTK dumps, idle", "vtk_dumps.in, period > timed steps", dict(base, output_block="vtk_dumps",
                                                                       vtk_every=never)),
        ("VTK dumps, one output", "vtk_dumps.in, files written on the last timed step",
         dict(base, output_block="vtk_dumps", vtk_every=S)),
        ("HDF5 snapshots, idle", "fix snapshot/hdf5 as snapshots_hdf5.in, trigger never fires",
         dict(base, snapshot_block=idle_snap)),
        ("HDF5 snapshots, one output", "snapshots_hdf5.in: one snapshot when the push ends "
                                       "(the last timed step)", dict(base, snapshot_block="snapshots_hdf5")),
        ("per-particle stress, idle", "compute stress/grain read by a fix ave/time, period > timed steps",
         dict(base, stress_every=never)),
        ("per-particle stress, one evaluation", "the same, evaluated on the last timed step",
         dict(base, stress_every=S)),
        ("paper deck", "crushing and local damping on, outputs idle (as between outputs)",
         dict(base, grain_model="crushable_ne34", damping=1, output_block="vtk_dumps", vtk_every=never,
              snapshot_block=idle_snap, spheres_file=spheres["idle"])),
    ]


def cmd_features(args):
    scene_dir = os.path.join(args.out, "scene_features")
    scene = lattice_scene(scene_dir, args.grains, N=args.N, R_ch=args.R_ch_features)
    print(json.dumps({"scene": scene}), flush=True)
    rows = []
    base_ir = None
    variants = feature_variants(args, scene_dir, scene)
    if args.only:
        variants = [v for v in variants if v[0] in args.only or v[0] == "base"]
    for i, (name, what, var) in enumerate(variants):
        r = run_deck(args, os.path.join(args.out, "feature_%02d" % i), scene_dir, 1,
                     deck_vars(args, scene_dir, scene, var), callgrind=not args.wall)
        row = {"variant": name, "what": what, "vars": var, "atoms": r["atoms"], "steps": r["steps"],
               "n_break": r["n_break"], "neighbor_builds_timed_run": r["neighbor_builds_timed_run"]}
        if args.wall:
            row["loop_s"] = r["loop_s"]
            row["per_step"] = r["loop_s"] / r["steps"]
        else:
            rk = r["ranks"][0]
            row["instructions"] = rk["total"]
            row["per_step"] = rk["total"] / r["steps"]
            row["components_per_step"] = {k: v / r["steps"] for k, v in rk["components"].items()}
        if base_ir is None:
            base_ir = row["per_step"]
        row["extra_per_step"] = row["per_step"] - base_ir
        row["extra_percent"] = 100.0 * (row["per_step"] / base_ir - 1.0)
        print(json.dumps({k: row[k] for k in ("variant", "per_step", "extra_per_step", "extra_percent")}),
              flush=True)
        rows.append(row)
    if args.mesh_refine > 1:
        # the same grains and base deck with every wall and the pile
        # mesh_refine times finer: the cost against mesh size
        fine_dir = os.path.join(args.out, "scene_features_fine")
        fine = lattice_scene(fine_dir, args.grains, N=args.N, R_ch=args.R_ch_features,
                             mesh_refine=args.mesh_refine)
        var = variants[0][2]
        r = run_deck(args, os.path.join(args.out, "feature_fine"), fine_dir, 1,
                     deck_vars(args, fine_dir, fine, var), callgrind=not args.wall)
        row = {"variant": "base, meshes %dx finer" % args.mesh_refine,
               "what": "base deck; side, top, cone and shaft with %d times the facets (%s)"
                       % (args.mesh_refine, fine["facets"]),
               "vars": var, "atoms": r["atoms"], "steps": r["steps"], "n_break": r["n_break"],
               "neighbor_builds_timed_run": r["neighbor_builds_timed_run"], "facets": fine["facets"]}
        if args.wall:
            row["per_step"] = r["loop_s"] / r["steps"]
        else:
            rk = r["ranks"][0]
            row["instructions"] = rk["total"]
            row["per_step"] = rk["total"] / r["steps"]
            row["components_per_step"] = {k: v / r["steps"] for k, v in rk["components"].items()}
        row["extra_per_step"] = row["per_step"] - base_ir
        row["extra_percent"] = 100.0 * (row["per_step"] / base_ir - 1.0)
        print(json.dumps({k: row[k] for k in ("variant", "per_step", "extra_per_step", "extra_percent")}),
              flush=True)
        rows.append(row)
    return {"what": "instructions per step of each optional feature (bench/icount/run.py features)",
            "command": " ".join(sys.argv), "date_utc": time.strftime("%Y-%m-%d %H:%M", time.gmtime()),
            "machine": machine(), "scene": scene, "steps": args.steps, "wall_clock": args.wall,
            "unit": "seconds" if args.wall else "instructions (callgrind Ir) inside Verlet::run",
            "rows": rows}


MESH_SUBSETS = [("all six meshes", ["top", "plug", "bottom", "side", "cone", "shaft"]),
                ("without the side wall", ["top", "plug", "bottom", "cone", "shaft"]),
                ("without top wall and plug", ["bottom", "side", "cone", "shaft"]),
                ("without the bottom", ["top", "plug", "side", "cone", "shaft"]),
                ("without cone and shaft", ["top", "plug", "bottom", "side"])]


def cmd_meshes(args):
    """The cost of each mesh in the wall fix: the base deck of the feature
    table with the wall fix redefined on all meshes, then without each
    (the mesh fixes, their motion and the jack stay)."""
    scene_dir = os.path.join(args.out, "scene_meshes")
    scene = lattice_scene(scene_dir, args.grains, N=args.N, R_ch=args.R_ch_features)
    print(json.dumps({"scene": scene}), flush=True)
    rows = []
    for i, (name, meshes) in enumerate(MESH_SUBSETS):
        var = {"grain_model": "unbreakable", "damping": 0, "walls_subset": 1,
               "wall_meshes": " ".join(meshes), "n_wall_meshes": len(meshes)}
        r = run_deck(args, os.path.join(args.out, "meshes_%02d" % i), scene_dir, 1,
                     deck_vars(args, scene_dir, scene, var), callgrind=True)
        rk = r["ranks"][0]
        row = {"variant": name, "meshes": meshes, "atoms": r["atoms"], "steps": r["steps"],
               "n_break": r["n_break"], "neighbor_builds_timed_run": r["neighbor_builds_timed_run"],
               "per_step": rk["total"] / r["steps"],
               "components_per_step": {k: v / r["steps"] for k, v in rk["components"].items()}}
        rows.append(row)
    for row in rows:
        row["cost_of_the_missing_meshes_per_step"] = rows[0]["per_step"] - row["per_step"]
        row["percent_of_step"] = 100.0 * row["cost_of_the_missing_meshes_per_step"] / rows[0]["per_step"]
        print(json.dumps({k: row[k] for k in ("variant", "per_step", "cost_of_the_missing_meshes_per_step",
                                              "percent_of_step")}), flush=True)
    return {"what": "instructions per step of each mesh in the wall fix (bench/icount/run.py meshes)",
            "command": " ".join(sys.argv), "date_utc": time.strftime("%Y-%m-%d %H:%M", time.gmtime()),
            "machine": machine(), "scene": scene, "steps": args.steps,
            "unit": "instructions (callgrind Ir) inside Verlet::run", "rows": rows}


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("what", choices=["scaling", "features", "meshes"])
    p.add_argument("--grains-per-rank", type=float, default=7200,
                   help="scaling: grains per rank at the largest rank count (total = this x max ranks)")
    p.add_argument("--ranks", type=int, nargs="+", default=[1, 2, 4, 8])
    p.add_argument("--proc-grid", nargs="*", default=None, metavar="P=GRID",
                   help="processors grid per rank count, e.g. '8=4 2 1' (default '* * 1')")
    p.add_argument("--grains", type=int, default=3000, help="features: grains of the small scene")
    p.add_argument("--mesh-refine", type=int, default=1,
                   help="features: also run the base deck with meshes this many times finer (default 1: not)")
    p.add_argument("--only", nargs="*", default=None, help="features: run only these variants (and base)")
    p.add_argument("--steps", type=int, default=None,
                   help="timed steps (default 10 for scaling, 40 for features; 100 with --wall: the "
                        "lattice stays static for about 120 steps, then relaxes, rebuilds and breaks)")
    p.add_argument("--dt", type=float, default=1.5e-7)
    p.add_argument("--N", type=float, default=39.0)
    p.add_argument("--R-ch", type=float, default=0.216, help="scaling scene: chamber radius (m)")
    p.add_argument("--R-ch-features", type=float, default=0.054, help="features scene: chamber radius (m)")
    p.add_argument("--balance", default=None,
                   help="a command line put after read_data (e.g. a static load-balancing command)")
    p.add_argument("--rebuild-every", type=int, default=0,
                   help="rebuild the neighbour lists every so many steps (default 0: the packing "
                        "is static and needs no rebuild; the cost of a rebuild is the difference)")
    p.add_argument("--wall", action="store_true",
                   help="no valgrind: native runs, loop times (for machines with >= 16 free cores)")
    p.add_argument("--keep", action="store_true", help="keep the callgrind files")
    p.add_argument("--out", default=os.path.join(REPO, "results", "bench_icount"),
                   help="run directories (git-ignored)")
    p.add_argument("--results", default=None,
                   help="JSON output (default bench/icount/results_<what>[_wall].json)")
    p.add_argument("--liggghts", default=os.environ.get("LIGGGHTS_BIN", os.path.join(REPO, "build", "liggghts")))
    a = p.parse_args(argv)
    if a.steps is None:
        a.steps = 100 if a.wall else (10 if a.what == "scaling" else 40)
    os.makedirs(a.out, exist_ok=True)
    if a.what == "meshes" and a.wall:
        p.error("meshes counts instructions only")
    result = {"scaling": cmd_scaling, "features": cmd_features, "meshes": cmd_meshes}[a.what](a)
    result["liggghts"] = a.liggghts
    path = a.results or os.path.join(HERE, "results_%s%s.json" % (a.what, "_wall" if a.wall else ""))
    with open(path, "w") as fh:
        json.dump(result, fh, indent=1)
    if "summary" in result:
        print(json.dumps([{k: row[k] for k in row if k != "components_per_step"}
                          for row in result["summary"]], indent=1))
    print("wrote", path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
