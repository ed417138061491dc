#!/usr/bin/env bash
# Tensor glyphs against VTK 9.1's vtkTensorGlyph (python3-vtk9) in the same run: ellipsoids at
# the 103 823 points of a Boussinesq stress field (isoforge's point_load in
# tensor_glyph_time.cpp, vtkPointLoad in peers/vtk_tensor_glyph.py: the same field).
# Writes OUT/tensor_glyph.jsonl and a table.
# Usage: tensor_glyph.sh BUILD OUT [REPEAT]   (BUILD with -DISOFORGE_BUILD_BENCH=ON)
set -euo pipefail
build=$1 out=$2 repeat=${3:-3}
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$out"
"$build/verify/bench/tensor_glyph_time" --repeat "$repeat" | tee "$out/tensor_glyph.jsonl"
/usr/bin/python3 "$here/peers/vtk_tensor_glyph.py" "$repeat" | tee -a "$out/tensor_glyph.jsonl"
/usr/bin/python3 - "$out/tensor_glyph.jsonl" <<'PY' | tee "$out/tensor_glyph.md"
import json, sys
rows = [json.loads(l) for l in open(sys.argv[1])]
vtk = next(r for r in rows if r["peer"] != "isoforge")
print("| isoforge threads | isoforge s | VTK s | ratio | triangles (isoforge / VTK) |")
print("|---|---|---|---|---|")
for r in rows:
    if r["peer"] == "isoforge":
        print(f"| {r['threads']} | {r['seconds']:.3f} | {vtk['seconds']:.3f} | "
              f"{vtk['seconds'] / r['seconds']:.1f} | {r['triangles']} / {vtk['triangles']} |")
PY
