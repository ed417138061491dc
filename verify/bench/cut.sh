#!/usr/bin/env bash
# Cutting and clipping against VTK 9.1 (python3-vtk9) in the same run: bench_cut and
# peers/vtk_cut.py on the same in-memory inputs (built with the same formulas), THREADS threads,
# the minimum over REPEATS runs. Each side runs twice: with glibc's default allocator settings,
# and with MALLOC_TRIM_THRESHOLD_/MALLOC_MMAP_THRESHOLD_ raised for both (freed memory reused
# instead of returned to the kernel, so page faults on fresh memory, very costly on a virtual
# machine, do not dominate). Then the whole `isoforge cut` command on the combustor files against
# the same pipeline in VTK. Writes OUT_DIR/cut.md.
# Usage: cut.sh BUILD_DIR OUT_DIR [THREADS [REPEATS]]
set -euo pipefail
build=$1 out=$2 threads=${3:-2} repeats=${4:-5}
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
mkdir -p "$out"
reuse=(env MALLOC_TRIM_THRESHOLD_=4000000000 MALLOC_MMAP_THRESHOLD_=4000000000)
"$build/verify/bench/bench_cut" "$threads" "$repeats" > "$out/cut_isoforge.json"
/usr/bin/python3 "$here/peers/vtk_cut.py" "$threads" "$repeats" > "$out/cut_vtk.json"
"${reuse[@]}" "$build/verify/bench/bench_cut" "$threads" "$repeats" > "$out/cut_isoforge_reuse.json"
"${reuse[@]}" /usr/bin/python3 "$here/peers/vtk_cut.py" "$threads" "$repeats" > "$out/cut_vtk_reuse.json"
# The whole command (process start, reading, cutting, writing), best of REPEATS.
best=1e9
for _ in $(seq "$repeats"); do
  t0=$(date +%s.%N)
  "$build/src/isoforge" --threads "$threads" cut "$root/data/combxyz.bin" --q "$root/data/combq.bin" \
    --plane 8.255 0 29.763 -0.287 0 0.9579 -o "$out/comb_cut.vtp" --quiet
  t1=$(date +%s.%N)
  best=$(python3 -c "print(min($best, ($t1 - $t0) * 1e3))")
done
echo "{\"pipeline/combustor\": {\"ms\": $best}}" > "$out/cut_cli.json"
/usr/bin/python3 "$here/peers/vtk_cut.py" pipeline "$root/data" "$out/comb_cut_vtk.vtp" "$repeats" > "$out/cut_cli_vtk.json"
# The VTK pipeline as a whole process too (python start-up and `import vtk` included).
best=1e9
for _ in $(seq "$repeats"); do
  t0=$(date +%s.%N)
  /usr/bin/python3 "$here/peers/vtk_cut.py" pipeline "$root/data" "$out/comb_cut_vtk.vtp" 1 > /dev/null
  t1=$(date +%s.%N)
  best=$(python3 -c "print(min($best, ($t1 - $t0) * 1e3))")
done
echo "{\"pipeline/combustor\": {\"ms\": $best}}" > "$out/cut_cli_vtk_process.json"
/usr/bin/python3 - "$out" "$threads" <<'PY'
import json, sys, os
out, threads = sys.argv[1], sys.argv[2]
load = lambda n: json.load(open(os.path.join(out, n)))
rows = [("plane cut, 256³ image", "plane_image/256", "plane_image/256", "vtkPlaneCutter"),
        ("plane cut, 384³ image", "plane_image/384", "plane_image/384", "vtkPlaneCutter"),
        ("plane cut, 100³ curvilinear grid", "plane_curvilinear/100", "plane_curvilinear/100/vtkCutter", "vtkCutter"),
        ("plane cut, 100³ curvilinear grid", "plane_curvilinear/100", "plane_curvilinear/100/vtkPlaneCutter", "vtkPlaneCutter"),
        ("clip of a 256³ image by a sphere", "clip_sphere_image/256", "clip_sphere_image/256", "vtkTableBasedClipDataSet")]
lines = [f"Threads: {threads}. Times in ms (minimum over the repeats); ratio = VTK / isoforge (> 1: isoforge faster).", "",
         "| case | peer | allocator | VTK ms | isoforge ms | ratio | VTK cells | isoforge cells |", "|---|---|---|---|---|---|---|---|"]
for suffix, label in (("", "default"), ("_reuse", "memory reused")):
    ours, vtk = load(f"cut_isoforge{suffix}.json"), load(f"cut_vtk{suffix}.json")
    for name, ok, vk, peer in rows:
        o, v = ours[ok], vtk[vk]
        lines.append(f"| {name} | {peer} | {label} | {v['ms']:.1f} | {o['ms']:.1f} | {v['ms'] / o['ms']:.2f} | {v['cells']} | {o['cells']} |")
cli, cv = load("cut_cli.json")["pipeline/combustor"]["ms"], load("cut_cli_vtk.json")["pipeline/combustor"]["ms"]
cp = load("cut_cli_vtk_process.json")["pipeline/combustor"]["ms"]
lines += ["", f"Whole command on data/combxyz.bin + combq.bin (read, cut through the centre, write .vtp): "
          f"`isoforge cut` {cli:.1f} ms as a process; VTK (vtkMultiBlockPLOT3DReader, vtkCutter, "
          f"vtkXMLPolyDataWriter) {cp:.1f} ms as a python process (ratio {cp / cli:.2f}), {cv:.1f} ms "
          f"inside python once started (ratio {cv / cli:.2f})."]
open(os.path.join(out, "cut.md"), "w").write("\n".join(lines) + "\n")
print("\n".join(lines))
PY
