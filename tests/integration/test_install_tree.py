# SPDX-License-Identifier: GPL-2.0-or-later
"""The install path a LIGGGHTS user takes (issue 43 item 6; docs/install.md,
"Building into your own LIGGGHTS"): this repository built with CMake against
a separate, unpacked LIGGGHTS-PUBLIC 3.8 tree,

    cmake -S <repo> -B <build> -DLIGGGHTS_SOURCE_DIR=<tree> \\
          -DCRUSH_BUILD_TESTS=OFF -DCRUSH_PYTHON_VENV=OFF -DCMAKE_BUILD_TYPE=Release
    cmake --build <build> --target liggghts -j 2

1. The tree is a copy, at another path, of the one the main build uses
   (LIGGGHTS_SOURCE_DIR, which tests/CMakeLists.txt passes to the test),
   made read-only (chmod -R a-w) with a checksum of every name, mode and
   file content taken before. After the configure step and the build the
   checksum is the same (the build copies and patches the sources into
   <build>/liggghts_src; it never writes into the user's tree; as root the
   chmod does not stop a write, the checksum still sees it), and the build's
   copy says it came from the tree given.
2. `liggghts -h` of the new binary lists every style of src_liggghts_plugin/
   in its section, and one small deck per style runs with it and gives the
   independent answer the style's own deck test checks (those tests'
   functions are called here, with LIGGGHTS_BIN pointing at the new binary):
   fix crush/particle breaks one grain pressed by a platen at the analytic
   F_lim (1e-6), compute crush/atom reads 0.5 for a grain held at half its
   limit force (1e-9), compute stress/grain is the Hertz plate forces' stress
   (1e-9), fix damp/local the exact damped velocity Verlet (1e-9), fix
   jack/pile the exact kinematics of an empty push, fix servo/radial the
   control law on an empty chamber (the wall closes at -gain * target),
   fix snapshot/hdf5 writes the snapshot of one grain, fix check/stability
   stops a pair inserted overlapping, balance/grains evens the grains per
   rank at 2 ranks. A stock LIGGGHTS tutorial deck (none of our styles)
   prints the same thermo output as Debian's stock binary.
3. A LIGGGHTS_SOURCE_DIR without src/lammps.cpp stops the configure step
   with the message of CMakeLists.txt.
The build is made once and removed at the end (with the copy); the smoke
decks take about a second each: 550 s in all on 2 cores shared with two
long simulations.
"""

import hashlib
import os
import re
import shutil
import stat
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import harness  # noqa: E402
from harness import REPO  # noqa: E402
import test_balance as bg  # noqa: E402
import test_crush_readings as cr  # noqa: E402
import test_crush_single_grain as sg  # noqa: E402
import test_damp_local as dl  # noqa: E402
import test_jack_pile as jp  # noqa: E402
import test_servo_radial as sr  # noqa: E402
import test_snapshot_hdf5 as sh  # noqa: E402
import test_stability as st  # noqa: E402
import test_stock_tutorials as sto  # noqa: E402
import test_stress_grain as ts  # noqa: E402

from crushpost.meshes import cylinder_triangles, write_stl  # noqa: E402

CONFIGURE_TIMEOUT = 600
BUILD_TIMEOUT = 2700           # s: the whole of LIGGGHTS at -j2 on a loaded machine
CTEST_TIMEOUT = 4200   # ctest's budget: configure (600 s), build (2700 s), the smoke decks (300 s each at most, a few seconds in fact)

SOURCE = Path(os.environ.get("LIGGGHTS_SOURCE_DIR",
                             REPO / "deps" / "LIGGGHTS-PUBLIC-3.8.0")).resolve()
PLUGIN = REPO / "src_liggghts_plugin"
MISSING_MESSAGE = ("LIGGGHTS source not found at LIGGGHTS_SOURCE_DIR={} (expected "
                   "src/lammps.cpp). Run scripts/setup, or pass "
                   "-DLIGGGHTS_SOURCE_DIR=/path/to/LIGGGHTS-PUBLIC.")


# --------------------------------------------------------------------------
# the tree and the build
# --------------------------------------------------------------------------

def tree_checksum(root):
    """sha256 over every entry below `root`: names, types, permission bits,
    file contents and link targets (a file added, changed or removed, or a
    chmod, changes it)."""
    h = hashlib.sha256()
    root = Path(root)
    for dirpath, dirnames, filenames in os.walk(root):
        dirnames.sort()
        for name in sorted(dirnames) + sorted(filenames):
            p = Path(dirpath) / name
            st_ = os.lstat(p)
            rel = str(p.relative_to(root))
            if stat.S_ISLNK(st_.st_mode):
                h.update(b"L %s -> %s\n" % (rel.encode(), os.readlink(p).encode()))
            elif stat.S_ISDIR(st_.st_mode):
                h.update(b"D %s %o\n" % (rel.encode(), stat.S_IMODE(st_.st_mode)))
            else:
                h.update(b"F %s %o " % (rel.encode(), stat.S_IMODE(st_.st_mode)))
                with open(p, "rb") as f:
                    for block in iter(lambda: f.read(1 << 20), b""):
                        h.update(block)
                h.update(b"\n")
    return h.hexdigest()


def _chmod_tree(root, writable):
    for dirpath, dirnames, filenames in os.walk(root):
        for p in [Path(dirpath)] + [Path(dirpath) / n for n in filenames]:
            if p.is_symlink():
                continue
            mode = stat.S_IMODE(os.lstat(p).st_mode)
            os.chmod(p, (mode | stat.S_IWUSR) if writable else (mode & ~0o222))


def _tail(text, n=60):
    return "\n".join(text.splitlines()[-n:])


def configure_cmd(source_dir, build_dir):
    cmd = ["cmake", "-S", str(REPO), "-B", str(build_dir),
           "-DLIGGGHTS_SOURCE_DIR=%s" % source_dir,
           "-DCRUSH_BUILD_TESTS=OFF", "-DCRUSH_PYTHON_VENV=OFF", "-DCMAKE_BUILD_TYPE=Release"]
    if shutil.which("ccache"):
        cmd.append("-DCMAKE_CXX_COMPILER_LAUNCHER=ccache")
    return cmd


class Build:
    """The copied tree, its checksums and the new binary."""
    base = tree = build = binary = None
    checksum_before = checksum_after = None


@pytest.fixture(scope="module")
def new_build():
    """Copy the tree, make it read-only, configure and build `liggghts`; the
    module's deck runs use the new binary (LIGGGHTS_BIN). Everything is
    removed afterwards."""
    if not (SOURCE / "src" / "lammps.cpp").is_file():
        pytest.fail("LIGGGHTS source not found at %s (LIGGGHTS_SOURCE_DIR): run scripts/setup"
                    % SOURCE)
    b = Build()
    b.base = Path(tempfile.mkdtemp(prefix="crush_install_tree_"))
    mp = pytest.MonkeyPatch()
    try:
        b.tree = b.base / "elsewhere" / "LIGGGHTS-PUBLIC"
        shutil.copytree(SOURCE, b.tree, symlinks=True)
        _chmod_tree(b.tree, writable=False)
        b.checksum_before = tree_checksum(b.tree)
        b.build = b.base / "build"
        env = dict(os.environ)
        res = subprocess.run(configure_cmd(b.tree, b.build), env=env, stdin=subprocess.DEVNULL,
                             stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                             universal_newlines=True, timeout=CONFIGURE_TIMEOUT)
        assert res.returncode == 0, "configure failed:\n" + _tail(res.stdout)
        log = b.base / "build.log"
        with open(log, "w") as out:
            rc = subprocess.run(["cmake", "--build", str(b.build), "--target", "liggghts",
                                 "-j", "2"], env=env, stdin=subprocess.DEVNULL, stdout=out,
                                stderr=subprocess.STDOUT, timeout=BUILD_TIMEOUT).returncode
        assert rc == 0, "build failed:\n" + _tail(log.read_text(errors="replace"))
        b.checksum_after = tree_checksum(b.tree)
        b.binary = b.build / "liggghts"
        assert b.binary.is_file() and os.access(str(b.binary), os.X_OK), b.binary
        mp.setenv("LIGGGHTS_BIN", str(b.binary))
        yield b
    finally:
        mp.undo()
        if b.tree is not None and b.tree.exists():
            _chmod_tree(b.tree, writable=True)
        shutil.rmtree(b.base, ignore_errors=True)


# --------------------------------------------------------------------------
# the package's styles and one smoke deck each
# --------------------------------------------------------------------------

_STYLE_RE = re.compile(r"^\s*(Fix|Compute|Command|Pair|Atom|Region|Dump|Integrate|Minimize)"
                       r"Style\(\s*([^,\s]+)\s*,", re.M)


def package_styles():
    """(kind, name) of every style registered in src_liggghts_plugin/*.h."""
    out = set()
    for h in sorted(PLUGIN.glob("*.h")):
        for kind, name in _STYLE_RE.findall(h.read_text(errors="replace")):
            out.add((kind.lower(), name))
    return out


def servo_empty_chamber(tmp_path, tmp_path_factory):
    """fix servo/radial on a chamber with no grain touching it (one grain on
    the axis, held still): the radial stress is 0, so the wall moves in at
    v_r = clip(gain (0 - target), -vmax, vmax) = -gain target every step."""
    gain, target, vmax, dt, nsteps = 1e-6, 76e3, 1.0, 1e-6, 100
    write_stl(str(tmp_path / "chamber.stl"),
              cylinder_triangles(sr.R0, -0.1 * sr.H, 1.1 * sr.H, sr.N_SEG, center=sr.AXIS),
              "chamber")
    deck = (sr.ERR_HEAD.format(inputs=REPO / "inputs", boundary="f f f") + sr.WALL + f"""\
fix s all servo/radial mesh chamber target {target!r} gain {gain!r} vmax {vmax!r} height 0.04 &
    axis {sr.AXIS[0]!r} {sr.AXIS[1]!r}
thermo_style custom step f_s[1] f_s[2] f_s[3]
thermo_modify format float %.17g lost error
thermo 10
run {nsteps}
""")
    assert "timestep 1e-6\n" in deck and dt == 1e-6
    res = harness.run_deck(deck, tmp_path, timeout=120, check=True)
    blk = res.thermo[-1]
    step, R, sigma, v_r = blk["Step"], blk["f_s[1]"], blk["f_s[2]"], blk["f_s[3]"]
    assert step[-1] == nsteps
    v = float(sr.control_law(0.0, target, gain, vmax))
    assert v == pytest.approx(-gain * target)
    np.testing.assert_array_equal(sigma, 0.0)
    np.testing.assert_allclose(v_r, v, rtol=1e-12)
    assert R[0] == pytest.approx(sr.R0, rel=1e-12)
    np.testing.assert_allclose(R - R[0], v * dt * step, rtol=1e-6, atol=1e-15)


def stress_grain_between_plates(tmp_path, tmp_path_factory):
    ts.test_stack_between_plates(ts.run_stack(tmp_path, [ts.R1]))


STOCK_TUTORIAL = "cohesion/in.noCohesion"

# (kind, name) -> a check(tmp_path, tmp_path_factory) with the current LIGGGHTS_BIN
SMOKE = {
    ("fix", "crush/particle"): lambda tp, tpf: sg.test_single_grain_breaks_at_limit(
        tpf, "n1_mesh", 1),
    ("compute", "crush/atom"): lambda tp, tpf: cr.test_utilisation_of_a_grain_at_half_its_limit(
        tp, "", 1.0),
    ("compute", "stress/grain"): stress_grain_between_plates,
    ("fix", "damp/local"): lambda tp, tpf: dl.test_constant_force_from_rest(tpf, 0.05, 1),
    ("fix", "jack/pile"): lambda tp, tpf: jp.test_empty_monotonic_exact(tp, 1),
    ("fix", "servo/radial"): servo_empty_chamber,
    ("fix", "snapshot/hdf5"): lambda tp, tpf: sh.test_no_contacts_and_unfix(tp),
    ("fix", "check/stability"): lambda tp, tpf: st.test_grain_inserted_deep_stops_at_setup(tp, 1),
    ("command", "balance/grains"): lambda tp, tpf: bg.test_counts_within_10_percent(tp, "x_2"),
}


# --------------------------------------------------------------------------
# tests (cheap ones first)
# --------------------------------------------------------------------------

def test_every_style_has_a_smoke_deck():
    styles = package_styles()
    assert len(styles) >= 9, styles
    assert styles == set(SMOKE), ("styles without a smoke deck here: %s; smoke decks of styles "
                                  "that do not exist: %s" % (sorted(styles - set(SMOKE)),
                                                             sorted(set(SMOKE) - styles)))
    for kind, name in styles:        # each has its reference page (a command's without "command_")
        page = (name if kind == "command" else kind + "_" + name).replace("/", "_") + ".md"
        assert (REPO / "docs" / page).is_file(), (kind, name, page)


def test_source_without_lammps_cpp_is_refused(tmp_path):
    bogus = tmp_path / "not-liggghts"
    (bogus / "src").mkdir(parents=True)
    (bogus / "src" / "README").write_text("not LIGGGHTS\n")
    before = tree_checksum(bogus)
    res = subprocess.run(configure_cmd(bogus, tmp_path / "build"), stdin=subprocess.DEVNULL,
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                         universal_newlines=True, timeout=CONFIGURE_TIMEOUT)
    assert res.returncode != 0, res.stdout
    text = " ".join(res.stdout.split())          # CMake wraps the message
    assert "CMake Error" in text and MISSING_MESSAGE.format(bogus) in text, res.stdout
    assert tree_checksum(bogus) == before


def test_tree_is_not_written(new_build):
    assert new_build.checksum_after == new_build.checksum_before
    # the build compiled the copy it was given, in its own folder
    copied_from = (new_build.build / "liggghts_src" / ".copied_from").read_text()
    assert Path(copied_from) == new_build.tree / "src"
    assert (new_build.build / "liggghts_src" / "lammps.cpp").is_file()


def test_help_lists_every_style(new_build):
    res = subprocess.run([str(new_build.binary), "-h"], stdin=subprocess.DEVNULL,
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                         universal_newlines=True, timeout=120, env=harness._child_env())
    sections = {}
    current = None
    for line in res.stdout.splitlines():
        m = re.match(r"^\* (\w+) styles", line)
        if m:
            current = sections.setdefault(m.group(1).lower(), set())
        elif line.startswith("*"):
            current = None
        elif current is not None:
            current.update(line.split())
    assert "LIGGGHTS-PUBLIC 3.8.0, with the crushable-grain package" in res.stdout, \
        _tail(res.stdout)
    for kind, name in sorted(package_styles()):
        assert name in sections.get(kind, ()), (kind, name, sorted(sections))


@pytest.mark.parametrize("style", sorted(SMOKE), ids=lambda s: "%s_%s" % s)
def test_style_smoke_deck(new_build, style, tmp_path, tmp_path_factory):
    assert harness.liggghts_bin() == new_build.binary.resolve()
    SMOKE[style](tmp_path, tmp_path_factory)


def test_stock_tutorial_as_with_stock_liggghts(new_build, tmp_path, monkeypatch):
    """A LIGGGHTS tutorial deck from the user's tree, none of our styles:
    the same thermo output as Debian's stock binary (test_stock_tutorials)."""
    monkeypatch.setattr(sto, "TUTORIALS", SOURCE / "examples" / "LIGGGHTS" / "Tutorials_public")
    assert harness.liggghts_bin() == new_build.binary.resolve()
    sto.test_tutorial_runs_as_with_stock_liggghts(sto.BY_PATH[STOCK_TUTORIAL], "error", tmp_path)
