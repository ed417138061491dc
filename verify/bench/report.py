#!/usr/bin/env python3
"""Turns benchmark JSON (ours and the peers', same run) into markdown tables with ratios."""
import json
import os
import sys

out, section = sys.argv[1], sys.argv[2]


def load(name):
    path = os.path.join(out, name)
    return json.load(open(path)) if os.path.exists(path) else {}


def runs(doc, prefix):
    """The benchmarks of doc named prefix*: medians when repetitions were run, else the runs."""
    bs = [b for b in doc.get("benchmarks", []) if b["name"].startswith(prefix)]
    med = [b for b in bs if b.get("aggregate_name") == "median"]
    if med:
        return med
    return [b for b in bs if b.get("run_type", "iteration") == "iteration"]


def ms(v):
    """Milliseconds with 3 significant digits below 100, whole above."""
    return f"{v:.3g}" if v < 100 else f"{v:.0f}"


def write(title, lines):
    text = f"# {title}\n\n" + "\n".join(lines) + "\n"
    open(os.path.join(out, f"{section}.md"), "w").write(text)
    print(text)


if section == "io":
    ours, vtk = load("io_isoforge.json"), load("io_vtk.json")
    lines = ["| file | isoforge ms (median of 5) | VTK 9 ms (best of 5) | VTK / isoforge |", "|---|---|---|---|"]
    writes = ["", "Writing VTK XML from memory (the writer alone; whole commands against VTK: xml_io.sh)", "",
              "| dataset / compressor | isoforge ms (median of 5) | MB/s of the uncompressed file |", "|---|---|---|"]
    for b in ours.get("benchmarks", []):
        if b.get("aggregate_name") != "median":
            continue
        name = b["run_name"].split("/")[1]
        ms, peer = b["real_time"], vtk.get(name)
        if b["run_name"].startswith("write_xml"):
            writes.append(f"| {name} | {ms:.2f} | {b['bytes_per_second'] / 1e6:.0f} |")
        elif isinstance(peer, (int, float)):
            lines.append(f"| {name} | {ms:.2f} | {peer:.2f} | {peer / ms:.2f}x |")
        else:
            lines.append(f"| {name} | {ms:.2f} | {peer or 'n/a'} | n/a |")
    write("Reading real files: isoforge vs VTK 9 readers (same machine, same run)", lines + writes)
elif section == "implicit":
    ours, vtk = load("implicit_isoforge.json"), load("implicit_vtk.json")
    lines = ["## Dense sampling of the ice cream cone (float32 output)", "",
             "| grid | threads | isoforge ms | isoforge Mevals/s | per core | vtkSampleFunction ms | Mevals/s | per core | speed-up per core |",
             "|---|---|---|---|---|---|---|---|---|"]
    for b in runs(ours, "dense_icecream"):
        n = b["name"].split("/")[1]
        thr = int(b["threads"])
        peer = vtk.get(f"dense_icecream/{n}/{thr}")
        per_core = b["Mevals_per_s_per_core"]
        if peer:
            peer_core = peer["Mevals_per_s"] / thr
            lines.append(f"| {n}³ | {thr} | {b['real_time']:.1f} | {b['Mevals_per_s']:.1f} | {per_core:.1f} | "
                         f"{peer['ms']:.1f} | {peer['Mevals_per_s']:.1f} | {peer_core:.1f} | {per_core / peer_core:.1f}x |")
        else:
            lines.append(f"| {n}³ | {thr} | {b['real_time']:.1f} | {b['Mevals_per_s']:.1f} | {per_core:.1f} | n/a | n/a | n/a | n/a |")
    lines += ["", "Both sides ran with the same thread counts (vtkSMPTools.Initialize for VTK).", "",
              "## Sparse narrow band (half width 3 voxels) into OpenVDB", "",
              "| effective resolution | time ms | active voxels | tree MB | dense float volume MB | evaluated fraction | peak RSS MB |",
              "|---|---|---|---|---|---|---|"]
    for b in runs(ours, "sparse_icecream"):
        n = b["name"].split("/")[1]
        lines.append(f"| {n}³ | {b['real_time']:.0f} | {b['active_voxels']:.0f} | {b['tree_MB']:.1f} | "
                     f"{b['dense_MB']:.0f} | {b['evaluated_fraction']:.4f} | {b['peak_rss_MB']:.0f} |")
    write("Sampling implicit functions: isoforge vs vtkSampleFunction (same machine, same run)", lines)
elif section == "contour":
    ours, vtk = load("contour_isoforge.json"), load("contour_vtk.json")
    lines = ["| field | n³ | threads | isoforge Mvox/s | triangles | vtkFlyingEdges3D Mvox/s | triangles | speed-up vs FE | vtkMarchingCubes Mvox/s (1 thread) | speed-up vs MC |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for b in runs(ours, "contour_dense"):
        name, n, thr = b["label"].split("/")
        fe = vtk.get(f"flying_edges/{name}/{n}/{thr}") or (vtk.get(f"flying_edges/{name}/{n}/{int(b['threads'])}"))
        mc = vtk.get(f"marching_cubes/{name}/{n}/1")
        ours_rate = b["Mvoxels_per_s"]
        fe_s = f"{fe['Mvoxels_per_s']:.0f} | {fe['triangles']} | {ours_rate / fe['Mvoxels_per_s']:.2f}x" if fe else "n/a | n/a | n/a"
        mc_s = f"{mc['Mvoxels_per_s']:.0f} | {ours_rate / mc['Mvoxels_per_s']:.1f}x" if (mc and int(b['threads']) == 1) else "| "
        lines.append(f"| {name} | {n} | {int(b['threads'])} | {ours_rate:.0f} | {int(b['triangles'])} | {fe_s} | {mc_s} |")
    lines += ["", "## Peak memory of one contour (all threads), each case in its own process", "",
              "| field | n³ | input MB | output MB | peak beyond input + output MB | fraction of input + output |",
              "|---|---|---|---|---|---|"]
    for m in ("0_256", "1_256", "0_512", "1_512"):
        for b in load(f"contour_memory_{m}.json").get("benchmarks", []):
            name, n = b["label"].split("/")
            lines.append(f"| {name} | {n} | {b['input_MB']:.0f} | {b['output_MB']:.0f} | {b['extra_MB']:.1f} | "
                         f"{100 * b['extra_fraction']:.1f}% |")
    write("Marching cubes: isoforge vs vtkFlyingEdges3D and vtkMarchingCubes (same volumes, same run)", lines)
elif section == "model":
    ours, vtk = load("model_isoforge.json"), load("model_vtk.json")
    lines = ["## Implicit modeller vs vtkImplicitModeller (same settings, same run)", "",
             "| input | samples | threads | isoforge ms | strategy | vtkImplicitModeller ms | speed-up | max abs diff (all / band) | band samples equal |",
             "|---|---|---|---|---|---|---|---|---|"]
    for b in ours.get("benchmarks", []):
        if not b["name"].startswith("modeller"):
            continue
        case = b["label"]
        peer = vtk.get(case)
        thr = int(b["threads"])
        strat = "gather" if b.get("gather") else "scatter"
        if peer:
            diff = f"{peer['max_abs_diff']:.3g} / {peer['max_abs_diff_band']:.3g}" if "max_abs_diff" in peer else "n/a"
            same = f"{peer['identical_samples']}/{peer['samples']}" if "identical_samples" in peer else "n/a"
            lines.append(f"| {case} | {int(b['samples'])} | {thr} | {ms(b['real_time'])} | {strat} | {peer['ms']:.0f} | "
                         f"{peer['ms'] / b['real_time']:.0f}x | {diff} | {same} |")
        else:
            lines.append(f"| {case} | {int(b['samples'])} | {thr} | {ms(b['real_time'])} | {strat} | n/a | n/a | n/a | n/a |")
    variants = [(k, v) for k, v in vtk.items() if k.startswith("hello-")]
    if variants:
        lines += ["", "Other output scalar types (HELLO; VTK's OutputScalarType and ScaleToMaximumDistance):", "",
                  "| variant | types (VTK / isoforge) | identical samples | max abs diff |", "|---|---|---|---|"]
        for k, v in variants:
            if "identical_samples" in v:
                lines.append(f"| {k} | {v['types']} | {v['identical_samples']}/{v['samples']} | {v['max_abs_diff']:.3g} |")
            else:
                lines.append(f"| {k} | n/a | {v.get('compare_error', 'n/a')} | n/a |")
    lines += ["", "vtkImplicitModeller's own thread count is shown in model_vtk.json; it does not speed up with threads here.",
              "", "## Narrow band (half width 3 voxels, unsigned) of bunny.ply subdivided twice (1.1M triangles) vs openvdb::tools::meshToVolume",
              "", "| resolution | method | ms | active voxels | tree MB | peak RSS MB | peak above baseline MB |", "|---|---|---|---|---|---|---|"]
    for res in (512, 1024):
        for m in (0, 1):
            nb = load(f"model_nb_{res}_{m}.json")
            for b in nb.get("benchmarks", []):
                lines.append(f"| {res}^3 | {b['label'].split('/')[0]} | {b['real_time']:.0f} | {b['active_voxels']:.0f} | "
                             f"{b['tree_MB']:.1f} | {b['peak_rss_MB']:.0f} | {b['peak_extra_MB']:.0f} |")
    lines += ["", "## Dense Scatter (rows) vs Gather as reach volumes overlap: a helix of n segments, 128^3, maximum distance 0.1",
              "", "| segments | estimated kernel calls / band samples | Scatter (rows) ms | Gather ms |", "|---|---|---|---|"]
    cross = {}
    for b in load("model_crossover.json").get("benchmarks", []):
        strat, n = b["label"].split("/")
        cross.setdefault(int(n), {})[strat] = b
    for n in sorted(cross):
        c = cross[n]
        if "scatter" in c and "gather" in c:
            ratio = c["scatter"]["scatter_estimate"] / c["scatter"]["band_samples"]
            lines.append(f"| {n} | {ratio:.0f} | {c['scatter']['real_time']:.1f} | {c['gather']['real_time']:.1f} |")
    lines += ["", "## Lorenz attractor (Fig. 1.25): 10M RK4 steps into 200^3 + marching cubes at 50, one thread", ""]
    for b in ours.get("benchmarks", []):
        if b["name"].startswith("attractor"):
            lines.append(f"{b['real_time']:.0f} ms, {int(b['triangles'])} triangles, {int(b['discarded'])} states discarded")
    write("Implicit modeling: isoforge vs vtkImplicitModeller and OpenVDB meshToVolume (same machine, same run)", lines)
