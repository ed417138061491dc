#!/usr/bin/env python3
"""Peers: vtkFlyingEdges3D and vtkMarchingCubes on the raw volumes of make_fields.py, with 1
thread and with all threads. Isovalues: gyroid 0.0, blobs 0.5. Prints JSON keyed like
bench_contour's benchmarks: {"flying_edges/gyroid/256/1": {"ms": .., "triangles": ..}, ...}."""
import json
import os
import sys
import time

import numpy as np
import vtk
from vtk.util import numpy_support

field_dir = sys.argv[1]
sizes = [int(s) for s in sys.argv[2:]] or [256, 512]
iso = {"gyroid": 0.0, "blobs": 0.5}
all_threads = os.cpu_count() or 1


def image(name, n):
    a = np.fromfile(os.path.join(field_dir, f"{name}_{n}.raw"), dtype=np.float32)
    img = vtk.vtkImageData()
    img.SetDimensions(n, n, n)
    img.SetSpacing(1.0 / (n - 1), 1.0 / (n - 1), 1.0 / (n - 1))
    arr = numpy_support.numpy_to_vtk(a, deep=1)
    arr.SetName("s")
    img.GetPointData().SetScalars(arr)
    return img


out = {}
for n in sizes:
    for name in ("gyroid", "blobs"):
        img = image(name, n)
        for threads in (1, all_threads):
            vtk.vtkSMPTools.Initialize(threads)
            for label, cls in (("flying_edges", vtk.vtkFlyingEdges3D), ("marching_cubes", vtk.vtkMarchingCubes)):
                if label == "marching_cubes" and threads != 1:
                    continue  # vtkMarchingCubes is serial
                best, tris = float("inf"), 0
                for _ in range(3 if n <= 256 else 1):
                    f = cls()
                    f.SetInputData(img)
                    f.SetValue(0, iso[name])
                    f.ComputeNormalsOff()
                    f.ComputeGradientsOff()
                    f.ComputeScalarsOff()
                    t0 = time.perf_counter()
                    f.Update()
                    best = min(best, time.perf_counter() - t0)
                    tris = f.GetOutput().GetNumberOfPolys()
                out[f"{label}/{name}/{n}/{threads}"] = {"ms": best * 1e3, "triangles": tris,
                                                        "Mvoxels_per_s": n ** 3 / best / 1e6}
print(json.dumps(out))
