#!/usr/bin/env bash
# The Draco benchmark: isoforge's .drc writer against Debian's draco_encoder (package `draco`)
# on the same geometry-only inputs in one run — at 11, 14 and 16 position bits, and at error
# budgets of 1e-3, 1e-4 and 1e-5 of the bounding-box diagonal (for draco_encoder: the smallest
# -qp whose file meets the budget). Every file is measured by one program (drc_error: the
# largest distance from an input point to the nearest decoded point); sizes, encode times
# (median of RUNS, each encoder's own count: draco_encoder's "ms to encode", isoforge's
# "encoded in") and errors are printed as a Markdown table with ratios, and the cube grid is
# compared with per-axis stretching (drc_axes). Run by hand; not part of ctest. See
# docs/algorithms/draco.md.
#
# Usage: draco.sh BUILD OUT
#   BUILD: a build with -DISOFORGE_BUILD_BENCH=ON (isoforge, drc_error, drc_axes);
#   OUT: a directory for inputs and outputs; the table goes to OUT/draco.md.
# Environment: RUNS (timed runs per encoder and setting, default 5).
set -euo pipefail
build=$(cd "$1" && pwd) out=$2
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
mkdir -p "$out"
out=$(cd "$out" && pwd)
iso=$build/src/isoforge
command -v draco_encoder > /dev/null || { echo "draco_encoder is missing (apt-get install draco)"; exit 1; }

# Inputs: positions and triangles only (through OFF, which holds nothing else), as PLY, which
# both encoders read.
"$iso" -q convert "$root/data/bunny.ply" "$out/bunny.off"
"$iso" -q convert "$out/bunny.off" "$out/bunny.ply"
"$iso" -q contour "$root/data/headsq/quarter.nhdr" -v 1150 --flip --normals none -o "$out/headsq.off"
"$iso" -q convert "$out/headsq.off" "$out/headsq.ply"

python3 "$here/draco_bench.py" "$build" "$out" "${RUNS:-5}" bunny headsq | tee "$out/draco.md"
