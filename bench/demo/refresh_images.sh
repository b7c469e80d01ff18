#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-2.0-or-later
# Copies the demo's own pictures into docs/img/ after a demo run, for
# README.md ("What the demo shows") and docs/cpt.md:
#
#   results/demo/qc_depth.png          -> docs/img/demo_qc_depth.png
#   results/demo/breakage_map.png      -> docs/img/demo_breakage_map.png
#   results/demo/report/paraview.png   -> docs/img/demo_paraview.png
#
# The ParaView picture exists only for a run with VTK output
# (scripts/demo --vtk particles; the report draws it with scripts/pvbatch).
# Usage: bench/demo/refresh_images.sh [RUN_DIR]   (default results/demo)
# Copy results/demo/summary.json to bench/demo/summary.json with the
# pictures, so that the numbers README.md quotes and the pictures come from
# the same run (tests/python/doc_numbers.py checks the numbers).
set -euo pipefail
cd "$(dirname "$0")/../.."
run=${1:-results/demo}
missing=0
copy() {
    if [ -f "$run/$1" ]; then
        cp "$run/$1" "docs/img/$2"
        echo "refresh_images: $run/$1 -> docs/img/$2"
    else
        echo "refresh_images: $run/$1: no such file${3:+ ($3)}" >&2
        missing=1
    fi
}
copy qc_depth.png demo_qc_depth.png
copy breakage_map.png demo_breakage_map.png "a run without breakage events has none"
copy report/paraview.png demo_paraview.png "run scripts/demo --vtk particles"
exit "$missing"
