#!/usr/bin/env python3
"""Runs the Draco comparison of draco.sh and prints a Markdown table (see draco.sh)."""
import json
import re
import statistics
import subprocess
import sys

build, out, runs = sys.argv[1], sys.argv[2], int(sys.argv[3])
cases = sys.argv[4:]
iso = f"{build}/src/isoforge"
drc_error = f"{build}/verify/bench/drc_error"
drc_axes = f"{build}/verify/bench/drc_axes"


def run(cmd):
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        raise SystemExit(f"failed: {' '.join(cmd)}\n{r.stdout}{r.stderr}")
    return r.stdout + r.stderr


def measure(original, drc):
    return json.loads(run([drc_error, original, drc]))


def peer(src, dst, qp):
    """draco_encoder at -qp (default level 7): its encode time in ms."""
    text = run(["draco_encoder", "-i", src, "-o", dst, "-qp", str(qp), "-cl", "7"])
    return float(re.search(r"\((\d+) ms to encode\)", text).group(1))


def ours(src, dst, args):
    """isoforge convert: encode time and total (with the verifying decode) in ms."""
    text = run([iso, "convert", src, dst, *args])
    m = re.search(r"encoded in (\d+) ms; with the verifying decode and measurement (\d+) ms", text)
    return float(m.group(1)), float(m.group(2))


def size(path):
    import os
    return os.path.getsize(path)


rows = []
for case in cases:
    src = f"{out}/{case}.ply"
    diag = measure(src, src)["diagonal"]
    settings = [("bits", b) for b in (11, 14, 16)] + [("budget", r) for r in (1e-3, 1e-4, 1e-5)]
    for kind, value in settings:
        p_out, i_out = f"{out}/{case}-{kind}{value}-draco_encoder.drc", f"{out}/{case}-{kind}{value}-isoforge.drc"
        if kind == "bits":
            qp, args = value, ["--bits", str(value)]
        else:
            args = ["--max-error-rel", str(value)]
            qp = None
            for q in range(1, 31):  # the smallest -qp whose file meets the budget
                peer(src, p_out, q)
                if measure(src, p_out)["max_error"] <= value * diag:
                    qp = q
                    break
            if qp is None:
                raise SystemExit(f"{case}: no -qp meets {value}")
        p_ms, i_ms, i_total = [], [], []
        for _ in range(runs):  # interleaved, so both see the same machine load
            p_ms.append(peer(src, p_out, qp))
            e, t = ours(src, i_out, args)
            i_ms.append(e)
            i_total.append(t)
        rows.append(dict(case=case, kind=kind, value=value, qp=qp,
                         p_bytes=size(p_out), i_bytes=size(i_out),
                         p_ms=statistics.median(p_ms), i_ms=statistics.median(i_ms),
                         i_total=statistics.median(i_total),
                         p_err=measure(src, p_out)["max_error"] / diag,
                         i_err=measure(src, i_out)["max_error"] / diag))

print("| input | setting | draco_encoder bytes (-qp) | isoforge bytes | size ratio | "
      "draco_encoder encode ms | isoforge encode ms | time ratio | isoforge ms with verification | "
      "error/diag draco_encoder | error/diag isoforge |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
for r in rows:
    setting = f"{r['value']} bits" if r["kind"] == "bits" else f"budget {r['value']:g}"
    print(f"| {r['case']} | {setting} | {r['p_bytes']} ({r['qp']}) | {r['i_bytes']} | "
          f"{r['i_bytes'] / r['p_bytes']:.3f} | {r['p_ms']:.0f} | {r['i_ms']:.0f} | "
          f"{r['i_ms'] / r['p_ms']:.2f} | {r['i_total']:.0f} | {r['p_err']:.3g} | {r['i_err']:.3g} |")

print()
print("Cube grid against per-axis stretching (sequential and Edgebreaker bytes at the same budget):")
print()
print("| input | z scaled by | budget/diag | cube bytes (seq) | stretched bytes (seq) | cube bytes (Edgebreaker) | stretched bytes (Edgebreaker) | cube error/budget | stretched error/budget |")
print("|---|---|---|---|---|---|---|---|---|")
for case in cases:
    for flatten in ("1", "0.1"):
        for line in run([drc_axes, f"{out}/{case}.ply", flatten, "1e-3", "1e-4", "1e-5"]).splitlines():
            j = json.loads(line)
            print(f"| {case} | {j['flatten']} | {j['rel']:g} | {j['cube_bytes']} | {j['stretch_bytes']} | "
                  f"{j['cube_eb_bytes']} | {j['stretch_eb_bytes']} | {j['cube_error'] / j['budget']:.3f} | "
                  f"{j['stretch_error'] / j['budget']:.3f} |")
