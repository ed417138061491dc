#!/usr/bin/env bash
# The glyph benchmark: isoforge's glyph, hedgehog, compute_normals and tube against VTK 9.1's
# vtkGlyph3D, vtkHedgeHog, vtkPolyDataNormals and vtkTubeFilter (python3-vtk9) in one run, on
# the same inputs in memory (filter time: the fastest of REPEAT runs, around Update() for VTK),
# then the whole glyph command (read a 1M-point .vtp, glyph, write .vtp with each writer's
# default zlib compression, or binary legacy .vtk) as wall time of each process. Prints a
# Markdown table with ratios (VTK time / isoforge time) to OUT/glyph.md. Run by hand; not part
# of ctest. See docs/algorithms/glyph.md.
#
# Usage: glyph.sh BUILD OUT
#   BUILD: a build with -DISOFORGE_BUILD_BENCH=ON (src/isoforge, verify/bench/glyph_time).
# Environment: GLYPH_POINTS (default 1000000), REPEAT (default 3), GLYPH_COMMAND=0 (leave out
# the whole-command rows), GLYPH_APPEND=1 (keep the earlier runs' records in OUT/glyph.jsonl:
# the table shows the fastest of all runs, for a machine shared with other work).
set -euo pipefail
build=$(cd "$1" && pwd) out=$2
mkdir -p "$out" && out=$(cd "$out" && pwd)
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
iso=$build/src/isoforge
timer=$build/verify/bench/glyph_time
vtkpy="/usr/bin/python3 $here/peers/vtk_glyph.py"
n=${GLYPH_POINTS:-1000000} repeat=${REPEAT:-3}
results=$out/glyph.jsonl
[ "${GLYPH_APPEND:-0}" = 1 ] || : > "$results"

# Inputs: the cone both glyph (isoforge's 6-sided cone with normals, 13 points, 10 triangles),
# a closed genus-1 surface of about a million triangles (as decimate.sh's "big"), isolines of the
# bunny's intensity (streamline-like polylines), the point cloud as a file.
[ -f "$out/cone.vtp" ] || "$timer" source "$out/cone.vtp"
if [ ! -f "$out/big.ply" ]; then
  "$iso" -q sample -f 'union(torus(R=0.6, r=0.2), sphere(center=[0.5,0.5,0.3], r=0.4), superquadric(center=[-0.5,-0.4,0], radii=[0.35,0.35,0.35], n=0.3, e=0.3))' \
    -b -1.2 1.2 -1.2 1.2 -1.2 1.2 -d 550 -o "$out/big.vdb"
  "$iso" -q contour "$out/big.vdb" -v 0 -o "$out/big.ply"
fi
[ -f "$out/isolines.vtp" ] ||
  "$iso" -q contour "$root/data/bunny.ply" -a intensity --range 0.01 0.49 49 -o "$out/isolines.vtp"
[ -f "$out/cloud.vtp" ] || $vtkpy cloud "$n" "$out/cloud.vtp"

# Filter times, both peers on the same inputs.
run() { "$@" | tee -a "$results"; }
run "$timer" glyph "$n" "$out/cone.vtp" "$repeat"
run $vtkpy glyph "$n" "$out/cone.vtp" "$repeat"
run "$timer" hedgehog "$n" "$repeat"
run $vtkpy hedgehog "$n" "$repeat"
run "$timer" normals "$out/big.ply" "$repeat"
run $vtkpy normals "$out/big.ply" "$repeat"
run "$timer" tube "$out/isolines.vtp" 0.0005 12 "$repeat"
run $vtkpy tube "$out/isolines.vtp" 0.0005 12 "$repeat"

# The whole command, wall time of the process (fastest of REPEAT).
wall() {  # wall PEER CASE COMMAND...
  local peer=$1 case=$2 best=999999 t0 t1 dt; shift 2
  for _ in $(seq "$repeat"); do
    t0=$(date +%s.%N); "$@" > /dev/null; t1=$(date +%s.%N)
    dt=$(echo "$t1 - $t0" | bc -l)
    best=$(echo "if ($dt < $best) $dt else $best" | bc -l)
  done
  printf '{"case": "%s", "peer": "%s", "seconds": %.3f, "output_points": %d}\n' "$case" "$peer" "$best" $((13 * n)) | tee -a "$results"
}
for ext in $([ "${GLYPH_COMMAND:-1}" = 0 ] || echo vtp vtk); do
  wall "isoforge" "command_$ext" "$iso" -q glyph "$out/cloud.vtp" -s "$out/cone.vtp" --scale-by vector -f 0.5 --no-point-data -o "$out/glyphs_isoforge.$ext"
  wall "vtk" "command_$ext" $vtkpy command "$out/cloud.vtp" "$out/cone.vtp" "$out/glyphs_vtk.$ext"
done
rm -f "$out"/glyphs_*.vt?

/usr/bin/python3 - "$results" "$n" > "$out/glyph.md" <<'PY'
import json, sys
rows = [json.loads(l) for l in open(sys.argv[1]) if l.strip()]
n = int(sys.argv[2])
t = {}
for r in rows:  # the fastest run of each case and peer
    best = t.setdefault(r["case"], {}).get(r["peer"])
    if best is None or r["seconds"] < best["seconds"]:
        t[r["case"]][r["peer"]] = r
names = {
    "glyph": f"glyph {n:,} points with cones (13 points, 10 triangles, normals, point ids) | vtkGlyph3D",
    "hedgehog": f"hedgehog {n:,} points (one line each) | vtkHedgeHog",
    "normals": "compute_normals, 1 052 680 triangles (split 30°, consistent, outward) | vtkPolyDataNormals",
    "tube": "tube, bunny isolines (49 values), 12 sides, capped | vtkTubeFilter",
    "command_vtp": f"whole command: read {n:,}-point .vtp, cones, write .vtp, zlib (wall) | python + VTK",
    "command_vtk": f"whole command: read {n:,}-point .vtp, cones, write binary legacy .vtk (wall) | python + VTK",
}
print("| case | peer | isoforge (s) | VTK 9.1 (s) | VTK / isoforge | output points (isoforge / VTK) |")
print("|---|---|---:|---:|---:|---|")
for case, label in names.items():
    if case not in t or len(t[case]) < 2:
        continue
    a, b = t[case]["isoforge"], t[case]["vtk"]
    print(f"| {label} | {a['seconds']:.3f} | {b['seconds']:.3f} | {b['seconds'] / a['seconds']:.1f}x | {a['output_points']:,} / {b['output_points']:,} |")
PY
cat "$out/glyph.md"
