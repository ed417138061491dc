#!/usr/bin/env bash
# The array calculator against VTK 9.1's vtkArrayCalculator (python3-vtk9) in the same run: a
# scalar and a vector expression over the float arrays of an N³ image (16.7M points at 256).
# Writes OUT/calculator.jsonl and OUT/calculator.md with the ratios (VTK / isoforge).
# Usage: calculator.sh BUILD OUT [N [REPEAT]]   (BUILD with -DISOFORGE_BUILD_BENCH=ON)
set -euo pipefail
build=$1 out=$2 n=${3:-256} repeat=${4:-3}
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$out"
"$build/verify/bench/calculator_time" --n "$n" --repeat "$repeat" | tee "$out/calculator.jsonl"
/usr/bin/python3 "$here/peers/vtk_calculator.py" "$n" "$repeat" | tee -a "$out/calculator.jsonl"
/usr/bin/python3 - "$out/calculator.jsonl" > "$out/calculator.md" <<'PY'
import json, sys
rows = [json.loads(l) for l in open(sys.argv[1])]
vtk = {r["case"]: r for r in rows if r["peer"] != "isoforge"}
print("| case | isoforge threads | isoforge s | VTK s | ratio | value (isoforge / VTK) |")
print("|---|---|---|---|---|---|")
for r in rows:
    if r["peer"] != "isoforge":
        continue
    v = vtk[r["case"]]
    print(f"| {r['case']} | {r['threads']} | {r['seconds']:.3f} | {v['seconds']:.3f} | "
          f"{v['seconds'] / r['seconds']:.1f} | {r['value_at_middle']:.9g} / {v['value_at_middle']:.9g} |")
PY
cat "$out/calculator.md"
