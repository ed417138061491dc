#!/usr/bin/env python3
"""Peer: vtkImplicitModeller on the inputs and settings of bench_model's `modeller` cases (HELLO
strokes 110x40x20 as VTK's Hello example; 500 random segments at 200^3 with VTK's defaults, from
the same splitmix64 sequence; bunny.ply at 64^3 and 128^3 with maximum distance 0.1 of the
diagonal). 128^3 takes a minute: it is timed once; the others best of `repeats`.
If FIELD_DIR holds isoforge's results (bench_model with ISOFORGE_BENCH_OUT), the values are
compared sample by sample (max abs difference over all samples, and over the band).
Usage: vtk_model.py DATA_DIR [FIELD_DIR] [CASES...]   (cases: hello segments500/200 bunny/64 bunny/128)
Prints JSON {"hello/0": {"ms": .., "threads": .., "max_abs_diff": .., ...}, ...}."""
import json
import os
import sys
import time

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy

data = sys.argv[1]
field_dir = sys.argv[2] if len(sys.argv) > 2 else ""
cases = sys.argv[3:] or ["hello/0", "segments500/200", "bunny/64", "bunny/128"]
MASK = (1 << 64) - 1


def splitmix(seed):
    s = seed
    while True:
        s = (s + 0x9E3779B97F4A7C15) & MASK
        z = s
        z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & MASK
        z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & MASK
        yield z ^ (z >> 31)


def segments(n):
    g = splitmix(12345)
    pts = vtk.vtkPoints()  # float32, as isoforge's default Points
    for _ in range(2 * n):
        pts.InsertNextPoint(*[(next(g) >> 11) * 2.0 ** -53 for _ in range(3)])
    lines = vtk.vtkCellArray()
    for i in range(n):
        lines.InsertNextCell(2)
        lines.InsertCellPoint(2 * i)
        lines.InsertCellPoint(2 * i + 1)
    pd = vtk.vtkPolyData()
    pd.SetPoints(pts)
    pd.SetLines(lines)
    return pd


def read(path):
    r = vtk.vtkPLYReader() if path.endswith(".ply") else vtk.vtkPolyDataReader()
    r.SetFileName(path)
    r.Update()
    return r.GetOutput()


def compare(m, path, band_limit=None):
    """Sample-by-sample comparison of VTK's output with isoforge's .vti at path; with band_limit,
    also over the samples VTK has below it (the band)."""
    x = vtk.vtkXMLImageDataReader()
    x.SetFileName(path)
    x.Update()
    a = vtk_to_numpy(m.GetOutput().GetPointData().GetScalars()).astype(np.float64)
    b = vtk_to_numpy(x.GetOutput().GetPointData().GetScalars()).astype(np.float64)
    if a.shape != b.shape:
        return {"compare_error": f"shapes differ: {a.shape} vs {b.shape}"}
    d = np.abs(a - b)
    r = {"max_abs_diff": float(d.max()), "identical_samples": int((a == b).sum()),
         "samples": int(a.size),
         "types": f"{m.GetOutput().GetPointData().GetScalars().GetDataTypeAsString()} / "
                  f"{x.GetOutput().GetPointData().GetScalars().GetDataTypeAsString()}"}
    if band_limit is not None:
        band = a < band_limit
        r["max_abs_diff_band"] = float(d[band].max()) if band.any() else 0.0
        r["band_samples"] = int(band.sum())
        r["same_band"] = bool((band == (b < band_limit)).all())
    return r


# Other output scalar types of the HELLO case: (isoforge file tag, VTK type, ScaleToMaximumDistance).
VARIANTS = [("uint8s", vtk.VTK_UNSIGNED_CHAR, 1), ("int16", vtk.VTK_SHORT, 0),
            ("uint16s", vtk.VTK_UNSIGNED_SHORT, 1), ("float64", vtk.VTK_DOUBLE, 0)]


def modeller(name, n):
    m = vtk.vtkImplicitModeller()
    if name == "hello":
        pd = read(os.path.join(data, "hello.vtk"))
        m.SetSampleDimensions(110, 40, 20)
        m.SetModelBounds(-1, 10, -1, 3, -1, 1)
        m.SetMaximumDistance(0.25)
    elif name == "bunny":
        pd = read(os.path.join(data, "bunny.ply"))
        b = pd.GetBounds()
        side = max(b[1] - b[0], b[3] - b[2], b[5] - b[4])
        diag = ((b[1] - b[0]) ** 2 + (b[3] - b[2]) ** 2 + (b[5] - b[4]) ** 2) ** 0.5
        m.SetSampleDimensions(n, n, n)
        m.SetMaximumDistance(0.1 * diag / side)
    else:
        pd = segments(500)
        m.SetSampleDimensions(n, n, n)
    m.SetInputData(pd)
    return m, pd


out = {}
for case in cases:
    name, n = case.split("/")
    n = int(n)
    repeats = 1 if (name == "bunny" and n >= 64) or name == "segments500" else 3
    best = float("inf")
    for _ in range(repeats):
        m, keep = modeller(name, n)
        t0 = time.perf_counter()
        m.Update()
        best = min(best, time.perf_counter() - t0)
    r = {"ms": best * 1e3, "threads": m.GetNumberOfThreads()}
    ours = os.path.join(field_dir, f"{name}_{n}.vti") if field_dir else ""
    if ours and os.path.exists(ours):
        r.update(compare(m, ours, band_limit=1e37))
    if name == "hello" and field_dir:
        for tag, vtype, scale in VARIANTS:
            path = os.path.join(field_dir, f"{name}_{tag}_{n}.vti")
            if os.path.exists(path):
                mv, keep = modeller(name, n)
                mv.SetOutputScalarType(vtype)
                mv.SetScaleToMaximumDistance(scale)
                mv.Update()
                out[f"{name}-{tag}/{n}"] = compare(mv, path)
                print(f"{name}-{tag}/{n}: {out[f'{name}-{tag}/{n}']}", file=sys.stderr)
    out[case] = r
    print(f"{case}: {r}", file=sys.stderr)
print(json.dumps(out))
