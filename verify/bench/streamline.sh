#!/usr/bin/env bash
# Streamlines against VTK 9.1's vtkStreamTracer (python3-vtk9) in the same run: the ABC flow on
# an N³ image, SEEDS seeds, RK4 and RK45, both directions (streamline_time.cpp and
# peers/vtk_streamline.py build the same field and seeds); then RK4 with SEEDS seeds on a warped
# 100³ curvilinear grid and 511 104 tetrahedra carrying the same flow. Prints JSON lines and writes
# OUT/streamline.md with the ratios (VTK / isoforge), both sides with 1 and with 2 threads
# (VTK's vtkSMPTools on TBB).
# Usage: streamline.sh BUILD OUT [N [SEEDS [REPEAT]]]   (BUILD with -DISOFORGE_BUILD_BENCH=ON)
set -euo pipefail
build=$1 out=$2 n=${3:-256} seeds=${4:-10000} repeat=${5:-3}
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$out"
"$build/verify/bench/streamline_time" --n "$n" --seeds "$seeds" --repeat "$repeat" --write "$out" --file-seeds "$seeds" | tee "$out/streamline.jsonl"
for t in 1 2; do
  /usr/bin/python3 "$here/peers/vtk_streamline.py" "$n" "$seeds" "$repeat" "$t" | tee -a "$out/streamline.jsonl"
  /usr/bin/python3 "$here/peers/vtk_streamline.py" files "$out" "$repeat" "$t" "$seeds" | tee -a "$out/streamline.jsonl"
done
/usr/bin/python3 - "$out/streamline.jsonl" > "$out/streamline.md" <<'PY'
import json, sys
rows = [json.loads(l) for l in open(sys.argv[1])]
vtk = {(r["case"], r["threads"]): r for r in rows if r["peer"] != "isoforge"}
print("| case | threads | isoforge s | VTK s | ratio | isoforge points | VTK points |")
print("|---|---|---|---|---|---|---|")
for r in rows:
    if r["peer"] != "isoforge":
        continue
    v = vtk[(r["case"], r["threads"])]
    print(f"| {r['case']} | {r['threads']} | {r['seconds']:.3f} | {v['seconds']:.3f} | "
          f"{v['seconds'] / r['seconds']:.2f} | {r['points']} | {v['points']} |")
PY
cat "$out/streamline.md"
