#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-or-later
# Wall-clock rates of the chamber slice of bench/icount (117,170 grains, the
# paper chamber's radius) at 1 to 16 ranks, balanced by balance/grains and
# not, on a machine with at least 16 free cores (docs/studies/performance.md
# "Wall-clock rates at 16 ranks"). The instruction counts of the same scene
# bound the efficiency; this measures what the cores deliver.
#
# Usage, from the repository root of a checkout on that machine:
#   bash bench/device/scaling_wall.sh BUNDLE.tar.xz OUT_DIR
# BUNDLE.tar.xz from bench/device/make_bundle.sh (LIGGGHTS and Open MPI with
# their libraries). Writes OUT_DIR/log.txt and OUT_DIR/results.tgz (one JSON
# per run of bench/icount/run.py, the machine's description), refreshed
# after every run so that a run cut short still returns what it measured.
#
# Each invocation of run.py builds the scene once and runs it at every rank
# count of RANKS (default 16 1 8 4 2); the balanced invocation
# (`balance/grains` after read_data, grid `8 1 2` at 16 ranks, `8 1 1` at 8,
# `* * 1` otherwise) and the default one (`* * 1`, no balancing) alternate,
# PASSES times (default 2), since wall time on a shared machine drifts.
# Every run has the same 115,200-grain target (7,200 per rank at 16 ranks),
# so every run is the same scene.
set -uo pipefail
bundle_tar=$(realpath "${1:?usage: scaling_wall.sh BUNDLE.tar.xz OUT_DIR}")
out=$(realpath -m "${2:?usage: scaling_wall.sh BUNDLE.tar.xz OUT_DIR}")
work=${TMPDIR:-/tmp}/crush_scaling_wall
rm -rf "$work"
mkdir -p "$work/json" "$out"
exec > >(tee "$out/log.txt") 2>&1
tar xf "$bundle_tar" -C "$work"
export CRUSH_BUNDLE="$work/bundle" PATH="$work/bundle/bin:$PATH"
export LIGGGHTS_BIN="$work/bundle/bin/liggghts" PYTHONUNBUFFERED=1
py=${PYTHON:-python3}
total=${GRAINS_TOTAL:-115200}   # smaller only for a smoke test
{ date -u; nproc; lscpu 2>/dev/null | head -25; free -g 2>/dev/null; } > "$work/json/machine.txt"

# 100 timed steps: the lattice stays static (no neighbour-list build, no
# break) for about 120 steps; over 2,000 it relaxes, rebuilds every 4-6
# steps and breaks grains, which is not the jacking phase's work.
# PASSES and RANKS (environment) change the number of passes and the rank
# counts of each invocation (e.g. PASSES=3 RANKS="16 16 16 1" for repeats).
# EXTRA adds run.py options to every run (e.g. EXTRA="--rebuild-every 20").
read -r -a ranks <<< "${RANKS:-16 1 8 4 2}"
read -r -a extra <<< "${EXTRA:-}"
max_rank=$(printf '%s\n' "${ranks[@]}" | sort -n | tail -1)

one() {  # one() NAME [run.py options...]
  local name=$1
  shift
  echo "== $name: ranks ${ranks[*]}, $* ($(date -u +%T))"
  "$py" bench/icount/run.py scaling --wall --steps 100 --ranks "${ranks[@]}" \
    --grains-per-rank $((total / max_rank)) --out "$work/runs" \
    --results "$work/json/$name.json" "$@" "${extra[@]}" || echo "!! $name failed"
  rm -rf "$work/runs"
  tar czf "$out/results.tgz" -C "$work" json
}

for pass in $(seq "${PASSES:-2}"); do
  one "balanced_$pass" --proc-grid "8=8 1 1" "16=8 1 2" --balance "balance/grains"
  one "default_grid_$pass"
done
echo "== done ($(date -u +%T))"
