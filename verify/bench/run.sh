#!/usr/bin/env bash
# Runs the benchmarks and their peers in the same run and writes ratio tables.
# Usage: run.sh BENCH_BUILD_DIR OUT_DIR
set -euo pipefail
build=$1 out=$2
root=$(cd "$(dirname "$0")/../.." && pwd)
mkdir -p "$out"
"$build/verify/bench/bench_io" --benchmark_format=json --benchmark_repetitions=5 \
  --benchmark_report_aggregates_only=true > "$out/io_isoforge.json"
if python3 -c "import vtk" 2>/dev/null; then
  python3 "$root/verify/bench/peers/vtk_io.py" "$root/data" 5 > "$out/io_vtk.json"
else
  echo '{}' > "$out/io_vtk.json"; echo "python3-vtk9 missing: no peer timings"
fi
python3 - "$out" <<'PY'
import json, sys, os
out = sys.argv[1]
ours = json.load(open(os.path.join(out, "io_isoforge.json")))
vtk = json.load(open(os.path.join(out, "io_vtk.json")))
rows = {}
for b in ours["benchmarks"]:
    if b.get("aggregate_name") != "median":
        continue
    name = b["run_name"].split("/", 1)[1] if "/" in b["run_name"] else b["run_name"]
    rows[name] = b["real_time"]  # milliseconds
lines = ["| file | isoforge (ms, median) | VTK 9 (ms, best of 5) | VTK / isoforge |", "|---|---|---|---|"]
for name, ms in rows.items():
    peer = vtk.get(name)
    ratio = f"{peer / ms:.2f}x" if peer else "n/a"
    lines.append(f"| {name} | {ms:.2f} | {peer:.2f} | {ratio} |" if peer else f"| {name} | {ms:.2f} | n/a | n/a |")
table = "\n".join(lines)
open(os.path.join(out, "io.md"), "w").write("# Reading real files: isoforge vs VTK 9 (same machine, same run)\n\n" + table + "\n")
print(table)
PY
