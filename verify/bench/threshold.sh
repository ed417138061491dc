#!/usr/bin/env bash
# The threshold and surface-extraction benchmark (docs/algorithms/threshold.md): isoforge and
# VTK 9.1 (python3-vtk9) in the same run, on the same inputs.
# - In memory: bench_threshold and peers/vtk_threshold.py read the inputs once, then time each
#   filter alone (REPS runs, minimum), with all threads and with one.
# - Whole command: `isoforge threshold|surface FILE -o OUT` against a python script that reads,
#   filters and writes the same way with VTK (peers/vtk_threshold.py cli), each process timed
#   from start to exit (REPS runs, minimum), both writing zlib-compressed appended XML.
# Inputs (made by `bench_threshold make`): a 100^3 hexahedral grid split into 5 000 000
# tetrahedra, and a 256^3 image; point field s = sin(2 pi x) sin(2 pi y) sin(2 pi z), threshold
# s in [-0.2, 0.5] with all points of a cell in the range.
#
# Usage: threshold.sh BUILD OUT [REPS]
#   BUILD: a build with -DISOFORGE_BUILD_BENCH=ON (isoforge, verify/bench/bench_threshold);
#   OUT: a directory for the inputs, outputs, JSON results and OUT/threshold.md.
set -euo pipefail
build=$(cd "$1" && pwd) out=$2 reps=${3:-5}
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$out"
out=$(cd "$out" && pwd)
python=/usr/bin/python3
bench=$build/verify/bench/bench_threshold
iso=$build/src/isoforge
[ -f "$out/tets.vtu" ] && [ -f "$out/image.vti" ] || "$bench" make "$out"

echo "in memory: isoforge"
"$bench" time "$out" "$reps" > "$out/threshold_isoforge.json"
echo "in memory: VTK"
$python "$here/peers/vtk_threshold.py" "$out" "$reps" > "$out/threshold_vtk.json"

# Whole commands: min wall time of REPS runs of each, as JSON {"name": ms}.
echo "whole commands"
$python - "$reps" "$out" "$iso" "$here/peers/vtk_threshold.py" > "$out/threshold_cli.json" <<'PY'
import json, subprocess, sys, time
reps, out, iso, peer = int(sys.argv[1]), sys.argv[2], sys.argv[3], sys.argv[4]
cmds = {}
for name, src in (("tets", f"{out}/tets.vtu"), ("image", f"{out}/image.vti")):
    cmds[f"threshold/{name}/isoforge"] = [iso, "--quiet", "threshold", src, "-a", "s", "--between", "-0.2", "0.5", "-o", f"{out}/iso_{name}.vtu"]
    cmds[f"threshold/{name}/vtk"] = ["/usr/bin/python3", peer, "cli", "threshold", src, f"{out}/vtk_{name}.vtu"]
    cmds[f"surface/{name}/isoforge"] = [iso, "--quiet", "surface", src, "-o", f"{out}/iso_{name}.vtp"]
    cmds[f"surface/{name}/vtk"] = ["/usr/bin/python3", peer, "cli", "surface", src, f"{out}/vtk_{name}.vtp"]
res = {}
for key, cmd in cmds.items():
    best = float("inf")
    for _ in range(reps):
        t0 = time.perf_counter()
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
        best = min(best, time.perf_counter() - t0)
    res[key] = round(best * 1e3, 1)
t0 = time.perf_counter()
subprocess.run(["/usr/bin/python3", "-c", "import vtk"], check=True)
res["python_import_vtk"] = round((time.perf_counter() - t0) * 1e3, 1)
print(json.dumps(res))
PY

$python - "$out" > "$out/threshold.md" <<'PY'
import json, os, sys
out = sys.argv[1]
ours = json.load(open(f"{out}/threshold_isoforge.json"))
vtk = json.load(open(f"{out}/threshold_vtk.json"))
cli = json.load(open(f"{out}/threshold_cli.json"))
threads = max(int(k.rsplit("/", 1)[1]) for k in ours)
print(f"In memory (filter alone, min of runs; {threads} threads and 1 thread):\n")
print("| filter | input | threads | isoforge ms | VTK ms (filter) | ratio VTK / isoforge | cells (both) |")
print("|---|---|---|---|---|---|---|")
for f, peers in (("threshold", ["threshold"]), ("surface", ["surface_dataset", "surface_geometry"])):
    for name in ("tets", "image"):
        for t in (threads, 1):
            o = ours.get(f"{f}/{name}/{t}")
            if not o:
                continue
            cands = [(p, vtk[f"{p}/{name}/{t}"]) for p in peers if f"{p}/{name}/{t}" in vtk]
            if not cands:
                continue
            p, best = min(cands, key=lambda c: c[1]["ms"])
            label = {"threshold": "vtkThreshold", "surface_dataset": "vtkDataSetSurfaceFilter",
                     "surface_geometry": "vtkGeometryFilter"}[p]
            others = ", ".join(f"{ {'surface_dataset': 'vtkDataSetSurfaceFilter', 'surface_geometry': 'vtkGeometryFilter'}[q]} {c['ms']:.0f}"
                               for q, c in cands if q != p)
            cells = "same" if best["cells"] == o["cells"] else f"{o['cells']} vs {best['cells']}"
            print(f"| {f} | {name} | {t} | {o['ms']:.1f} | {best['ms']:.1f} ({label}{'; ' + others if others else ''}) | "
                  f"{best['ms'] / o['ms']:.1f} | {o['cells']} {cells} |")
print(f"\nWhole command (process start to exit, min of runs; VTK's includes `import vtk`, "
      f"{cli['python_import_vtk']:.0f} ms alone):\n")
print("| command | input | isoforge ms | VTK (python) ms | ratio |")
print("|---|---|---|---|---|")
for f in ("threshold", "surface"):
    for name in ("tets", "image"):
        a, b = cli[f"{f}/{name}/isoforge"], cli[f"{f}/{name}/vtk"]
        print(f"| {f} | {name} | {a:.0f} | {b:.0f} | {b / a:.1f} |")
PY
cat "$out/threshold.md"
