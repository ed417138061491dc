#!/usr/bin/env bash
# The probe benchmark: isoforge against VTK 9.1's vtkProbeFilter (python3-vtk9) in one run, on
# the same inputs, and a Markdown table of the times and ratios (VTK / isoforge).
#   1. The filter alone on in-memory data: probe_time makes the inputs (a warped 100^3 grid, a
#      44^3-cube grid split into 511 104 tetrahedra), writes them, and times Prober + probe;
#      peers/vtk_probe.py reads the same files and times vtkProbeFilter::Update() (which builds
#      its locator). Both probe image data over the input's bounds: 200^3 and 100^3 points.
#   2. The whole command on a file: `isoforge probe IN --volume N -o OUT.vti` against a Python
#      script that reads IN, probes and writes OUT.vti with VTK.
# Every time is the minimum of REPEAT runs (default 3). Not part of ctest.
#
# Usage: probe.sh BUILD OUT [REPEAT]    (BUILD configured with -DISOFORGE_BUILD_BENCH=ON)
set -euo pipefail
build=$(cd "$1" && pwd) out=$2 repeat=${3:-3}
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$out"
out=$(cd "$out" && pwd)
python=/usr/bin/python3
iso=$build/src/isoforge

echo "== filter on in-memory data (min of $repeat) =="
"$build/verify/bench/probe_time" --write "$out" --repeat "$repeat" | tee "$out/filter.jsonl"
$python "$here/peers/vtk_probe.py" filter "$out" "$repeat" | tee -a "$out/filter.jsonl"

# best_of CMD...: the minimum wall time of $repeat runs, in seconds.
best_of() {
  local best="" t0 t1 t
  for _ in $(seq "$repeat"); do
    t0=$(date +%s.%N); "$@" > /dev/null 2>&1; t1=$(date +%s.%N)
    t=$(echo "$t1 - $t0" | bc -l)
    if [ -z "$best" ] || [ "$(echo "$t < $best" | bc -l)" = 1 ]; then best=$t; fi
  done
  printf '%.3f' "$best"
}

echo "== whole command on a file (min of $repeat) =="
: > "$out/cli.jsonl"
for c in "curvilinear grid.vts 200" "tets tets.vtu 100"; do
  set -- $c
  ours=$(best_of "$iso" -q probe "$out/$2" --volume "$3" -o "$out/ours_$1.vti")
  theirs=$(best_of $python "$here/peers/vtk_probe.py" cli "$out/$2" "$3" "$out/vtk_$1.vti")
  echo "{\"case\": \"$1\", \"isoforge\": $ours, \"vtk\": $theirs}" | tee -a "$out/cli.jsonl"
done

$python - "$out" <<'PY'
import json, sys
out = sys.argv[1]
rows = [json.loads(l) for l in open(f"{out}/filter.jsonl")]
cli = {r["case"]: r for r in map(json.loads, open(f"{out}/cli.jsonl"))}
names = {"curvilinear": "100³ curvilinear grid at 200³ points",
         "tets": "511 104 tetrahedra at 100³ points (incl. locator)"}
print("\n| case | VTK filter s (CPU s) | isoforge filter s (CPU s) | ratio | found VTK / isoforge | VTK command s | isoforge command s | ratio |")
print("|---|---|---|---|---|---|---|---|")
for case in ("curvilinear", "tets"):
    v = next(r for r in rows if r["case"] == case and r["peer"] == "vtk")
    o = next(r for r in rows if r["case"] == case and r["peer"] == "isoforge")
    c = cli[case]
    print(f"| {names[case]} | {v['seconds']:.3f} ({v['cpu_seconds']:.2f}) | {o['seconds']:.3f} ({o['cpu_seconds']:.2f})"
          f" | {v['seconds'] / o['seconds']:.1f}x"
          f" | {v['found']} / {o['found']} | {c['vtk']:.3f} | {c['isoforge']:.3f} | {c['vtk'] / c['isoforge']:.1f}x |")
PY
