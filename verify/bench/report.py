#!/usr/bin/env python3
"""Turns benchmark JSON (ours and the peers', same run) into markdown tables with ratios."""
import json
import os
import sys

out, section = sys.argv[1], sys.argv[2]


def load(name):
    path = os.path.join(out, name)
    return json.load(open(path)) if os.path.exists(path) else {}


def write(title, lines):
    text = f"# {title}\n\n" + "\n".join(lines) + "\n"
    open(os.path.join(out, f"{section}.md"), "w").write(text)
    print(text)


if section == "io":
    ours, vtk = load("io_isoforge.json"), load("io_vtk.json")
    lines = ["| file | isoforge ms (median of 5) | VTK 9 ms (best of 5) | VTK / isoforge |", "|---|---|---|---|"]
    for b in ours.get("benchmarks", []):
        if b.get("aggregate_name") != "median":
            continue
        name = b["run_name"].split("/", 1)[1]
        ms, peer = b["real_time"], vtk.get(name)
        lines.append(f"| {name} | {ms:.2f} | {peer:.2f} | {peer / ms:.2f}x |" if peer else f"| {name} | {ms:.2f} | n/a | n/a |")
    write("Reading real files: isoforge vs VTK 9 readers (same machine, same run)", lines)
elif section == "implicit":
    ours, vtk = load("implicit_isoforge.json"), load("implicit_vtk.json")
    lines = ["## Dense sampling of the ice cream cone (float32 output)", "",
             "| grid | threads | isoforge ms | isoforge Mevals/s | per core | vtkSampleFunction ms | Mevals/s | speed-up (per core) |",
             "|---|---|---|---|---|---|---|---|"]
    for b in ours.get("benchmarks", []):
        if not b["name"].startswith("dense_icecream"):
            continue
        n = b["name"].split("/")[1]
        peer = vtk.get(f"dense_icecream/{n}")
        thr = int(b["threads"])
        per_core = b["Mevals_per_s_per_core"]
        if peer:
            lines.append(f"| {n}³ | {thr} | {b['real_time']:.1f} | {b['Mevals_per_s']:.1f} | {per_core:.1f} | "
                         f"{peer['ms']:.1f} | {peer['Mevals_per_s']:.1f} | {per_core / peer['Mevals_per_s']:.1f}x |")
        else:
            lines.append(f"| {n}³ | {thr} | {b['real_time']:.1f} | {b['Mevals_per_s']:.1f} | {per_core:.1f} | n/a | n/a | n/a |")
    lines += ["", "VTK's per-core rate is its total rate (vtkSampleFunction ran single-threaded here); "
              "the speed-up compares per-core rates.", "",
              "## Sparse narrow band (half width 3 voxels) into OpenVDB", "",
              "| effective resolution | time ms | active voxels | tree MB | dense float volume MB | evaluated fraction | peak RSS MB |",
              "|---|---|---|---|---|---|---|"]
    for b in ours.get("benchmarks", []):
        if not b["name"].startswith("sparse_icecream"):
            continue
        n = b["name"].split("/")[1]
        lines.append(f"| {n}³ | {b['real_time']:.0f} | {b['active_voxels']:.0f} | {b['tree_MB']:.1f} | "
                     f"{b['dense_MB']:.0f} | {b['evaluated_fraction']:.4f} | {b['peak_rss_MB']:.0f} |")
    write("Sampling implicit functions: isoforge vs vtkSampleFunction (same machine, same run)", lines)
elif section == "contour":
    ours, vtk = load("contour_isoforge.json"), load("contour_vtk.json")
    lines = ["| field | n³ | threads | isoforge Mvox/s | triangles | vtkFlyingEdges3D Mvox/s | triangles | speed-up vs FE | vtkMarchingCubes Mvox/s (1 thread) | speed-up vs MC |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for b in ours.get("benchmarks", []):
        name, n, thr = b["label"].split("/")
        fe = vtk.get(f"flying_edges/{name}/{n}/{thr}") or (vtk.get(f"flying_edges/{name}/{n}/{int(b['threads'])}"))
        mc = vtk.get(f"marching_cubes/{name}/{n}/1")
        ours_rate = b["Mvoxels_per_s"]
        fe_s = f"{fe['Mvoxels_per_s']:.0f} | {fe['triangles']} | {ours_rate / fe['Mvoxels_per_s']:.2f}x" if fe else "n/a | n/a | n/a"
        mc_s = f"{mc['Mvoxels_per_s']:.0f} | {ours_rate / mc['Mvoxels_per_s']:.1f}x" if (mc and int(b['threads']) == 1) else "| "
        lines.append(f"| {name} | {n} | {int(b['threads'])} | {ours_rate:.0f} | {int(b['triangles'])} | {fe_s} | {mc_s} |")
    write("Marching cubes: isoforge vs vtkFlyingEdges3D and vtkMarchingCubes (same volumes, same run)", lines)
