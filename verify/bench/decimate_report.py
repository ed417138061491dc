#!/usr/bin/env python3
"""The decimation benchmark's table (decimate.sh): joins OUT/runs.jsonl (one line per command:
the peer's own timing of the decimation alone, and the wall time of the whole command) with
OUT/metrics.jsonl (isoforge-verify distance --check of every output) and prints Markdown.

Ratios: time = isoforge-t1's seconds of decimation / the peer's (both single-threaded), and
the same for the commands' CPU time; error = isoforge-t1's / the best peer's, per
measure (Hausdorff, RMS); the best peer is chosen among those that reached the target within
1 %."""
import json
import os
import sys

out = sys.argv[1]


def load(name):
    path = os.path.join(out, name)
    return [json.loads(l) for l in open(path) if l.strip()] if os.path.exists(path) else []


runs, metrics = load("runs.jsonl"), load("metrics.jsonl")
by_mesh = {m["mesh"]: m for m in metrics}


def fmt_s(v):
    return "n/a" if v is None else (f"{v:.3g}" if v < 100 else f"{v:.0f}")


def fmt_e(v):
    return "n/a" if v is None else f"{v:.3e}"


groups = {}
for r in runs:
    groups.setdefault((r["case"], r["target"]), []).append(r)

lines = ["# Decimation: isoforge and its peers (same inputs, same targets, one metric)", "",
         "seconds: the decimation alone as the program times it (wall clock; n/a: the command does not report it); "
         "command s: the whole command (read, decimate, write), wall clock; command CPU s: its user + system time "
         "(steadier on a loaded machine; Python peers include starting the interpreter and importing VTK). Hausdorff and RMS: to the input, "
         "relative to its bounding-box diagonal (isoforge-verify distance). Self-intersections: exact "
         "face pairs. t1/t2: threads; refine: --refine. Best peer: among those within 1 % of the target.", ""]
summary = []
for (case, target), rs in groups.items():
    rows = []
    for r in rs:
        m = by_mesh.get(r["output"], {})
        rows.append({
            "peer": r["peer"],
            "achieved": m.get("triangles", r.get("output_triangles")),
            "seconds": r.get("seconds"),
            "command": r["command_seconds"] if r.get("status", 0) == 0 else None,
            "cpu": r.get("command_cpu_seconds") if r.get("status", 0) == 0 else None,
            "h": m.get("relative_hausdorff"),
            "rms": m.get("relative_rms"),
            "si": m.get("self_intersections"),
            "manifold": m.get("manifold"),
            "status": r.get("status", 0),
        })
    ours = next((x for x in rows if x["peer"] == "isoforge-t1" and x["h"] is not None), None)
    lib = next((x for x in rows if x["peer"] == "isoforge-t1" and x["seconds"] is not None), None)
    cli = next((x for x in rows if x["peer"] == "isoforge-t1" and x["command"] is not None), None)
    # Peers that stopped more than 1 % above the target are not comparable (fewer collapses, less
    # error): they are listed but left out of the best.
    peers = [x for x in rows if not x["peer"].startswith("isoforge") and x["h"] is not None
             and x["achieved"] is not None and x["achieved"] <= 1.01 * target]
    lines += [f"## {case}, target {target}", "",
              "| peer | target | achieved | seconds | command s | command CPU s | Hausdorff | RMS | self-intersections | manifold | isoforge / peer: seconds | command CPU s |",
              "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for x in rows:
        ratio, cpu_ratio = "n/a", "n/a"
        if not x["peer"].startswith("isoforge"):
            if lib and x["seconds"]:
                ratio = f"{lib['seconds'] / x['seconds']:.2f}"
            if cli and cli["cpu"] and x["cpu"]:
                cpu_ratio = f"{cli['cpu'] / x['cpu']:.2f}"
        failed = "" if x["status"] == 0 else f" (failed: status {x['status']})"
        manifold = "n/a" if x["manifold"] is None else ("yes" if x["manifold"] else "no")
        lines.append(f"| {x['peer']}{failed} | {target} | {x['achieved'] if x['achieved'] is not None else 'n/a'} | "
                     f"{fmt_s(x['seconds'])} | {fmt_s(x['command'])} | {fmt_s(x['cpu'])} | {fmt_e(x['h'])} | {fmt_e(x['rms'])} | "
                     f"{x['si'] if x['si'] is not None else 'n/a'} | {manifold} | {ratio} | {cpu_ratio} |")
    lines.append("")
    if peers:
        bh = min(peers, key=lambda x: x["h"])
        br = min(peers, key=lambda x: x["rms"])
        clean = [x for x in peers if x["si"] == 0 and x["manifold"]]
        text = (f"Best peer: Hausdorff {fmt_e(bh['h'])} ({bh['peer']}), RMS {fmt_e(br['rms'])} ({br['peer']})")
        if clean:
            ch = min(clean, key=lambda x: x["h"])
            cr = min(clean, key=lambda x: x["rms"])
            text += (f"; among outputs that are manifold without self-intersections: Hausdorff "
                     f"{fmt_e(ch['h'])} ({ch['peer']}), RMS {fmt_e(cr['rms'])} ({cr['peer']})")
        if ours:
            text += (f". isoforge / best peer: Hausdorff {ours['h'] / bh['h']:.2f}, "
                     f"RMS {ours['rms'] / br['rms']:.2f}")
        lines += [text + ".", ""]
print("\n".join(lines))
