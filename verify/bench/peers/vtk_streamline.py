#!/usr/bin/env python3
"""VTK 9.1 peer of the streamline benchmark (verify/bench/streamline.sh): vtkStreamTracer on the
ABC flow over an N^3 image (float vectors), the same seeds as streamline_time.cpp, RK4 with
0.5-cell steps and RK45 (error 1e-4), both directions, 500 steps at most, vorticity on.

  vtk_streamline.py [N [SEEDS [REPEAT [THREADS]]]]   one JSON line per case (minimum of
                                                     REPEAT); THREADS for vtkSMPTools (TBB)
  vtk_streamline.py files DIR [REPEAT [THREADS [SEEDS]]]
                                                     RK4 on DIR/stream_grid.vts and
                                                     DIR/stream_tets.vtu (written by
                                                     streamline_time --write), SEEDS seeds
                                                     (10000)
"""
import json
import math
import sys
import time

import numpy as np
import vtk
from vtk.util import numpy_support


def abc_field(n):
    h = 2 * math.pi / (n - 1)
    img = vtk.vtkImageData()
    img.SetDimensions(n, n, n)
    img.SetSpacing(h, h, h)
    g = np.arange(n) * h
    z, y, x = np.meshgrid(g, g, g, indexing="ij")  # x fastest in the flattened order
    a, b, c = math.sqrt(3), math.sqrt(2), 1.0
    v = np.empty((n * n * n, 3), dtype=np.float32)
    v[:, 0] = (a * np.sin(z) + c * np.cos(y)).ravel()
    v[:, 1] = (b * np.sin(x) + a * np.cos(z)).ravel()
    v[:, 2] = (c * np.sin(y) + b * np.cos(x)).ravel()
    arr = numpy_support.numpy_to_vtk(v, deep=1)
    arr.SetName("V")
    img.GetPointData().SetVectors(arr)
    return img


def seeds(s, L=2 * math.pi):
    alpha = (0.8191725133961645, 0.6710436067037893, 0.5497004779019703)
    pts = vtk.vtkPoints()
    for i in range(1, s + 1):
        pts.InsertNextPoint(*[L * (0.05 + 0.9 * math.fmod(0.5 + i * a, 1.0)) for a in alpha])
    out = vtk.vtkPolyData()
    out.SetPoints(pts)
    return out


def tracer(field, source, name):
    t = vtk.vtkStreamTracer()
    t.SetInputData(field)
    t.SetSourceData(source)
    t.SetIntegrationDirectionToBoth()
    if name == "rk4":
        t.SetIntegratorTypeToRungeKutta4()
    else:
        t.SetIntegratorTypeToRungeKutta45()
        t.SetMaximumError(1e-4)
        t.SetMinimumIntegrationStep(0.01)
        t.SetMaximumIntegrationStep(1.0)
    t.SetIntegrationStepUnit(vtk.vtkStreamTracer.CELL_LENGTH_UNIT)
    t.SetInitialIntegrationStep(0.5)
    t.SetMaximumNumberOfSteps(500)
    t.SetMaximumPropagation(1e9)
    t.SetTerminalSpeed(1e-12)
    t.SetComputeVorticity(True)
    return t


def files(d, repeat, threads, count):
    source = seeds(count, 1.0)
    for case, name in (("rk4/curvilinear100", "stream_grid.vts"), ("rk4/tets44", "stream_tets.vtu")):
        r = vtk.vtkXMLStructuredGridReader() if name.endswith(".vts") else vtk.vtkXMLUnstructuredGridReader()
        r.SetFileName(f"{d}/{name}")
        r.Update()
        field = r.GetOutput()
        field.GetPointData().SetActiveVectors("V")
        best, out = 1e300, None
        for _ in range(repeat):
            t = tracer(field, source, "rk4")
            t0 = time.perf_counter()
            t.Update()
            best = min(best, time.perf_counter() - t0)
            out = t.GetOutput()
        print(json.dumps({"case": case, "peer": "vtkStreamTracer", "threads": threads,
                          "seconds": round(best, 4), "lines": out.GetNumberOfLines(),
                          "points": out.GetNumberOfPoints()}), flush=True)


def main():
    if sys.argv[1:2] == ["files"]:
        repeat = int(sys.argv[3]) if len(sys.argv) > 3 else 3
        if len(sys.argv) > 4:
            vtk.vtkSMPTools.Initialize(int(sys.argv[4]))
        count = int(sys.argv[5]) if len(sys.argv) > 5 else 10000
        files(sys.argv[2], repeat, vtk.vtkSMPTools.GetEstimatedNumberOfThreads(), count)
        return
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 256
    s = int(sys.argv[2]) if len(sys.argv) > 2 else 10000
    repeat = int(sys.argv[3]) if len(sys.argv) > 3 else 3
    if len(sys.argv) > 4:
        vtk.vtkSMPTools.Initialize(int(sys.argv[4]))
    threads = vtk.vtkSMPTools.GetEstimatedNumberOfThreads()
    field, source = abc_field(n), seeds(s)
    for name in ("rk4", "rk45"):
        best, out = 1e300, None
        for _ in range(repeat):
            t = tracer(field, source, name)
            t0 = time.perf_counter()
            t.Update()
            best = min(best, time.perf_counter() - t0)
            out = t.GetOutput()
        print(json.dumps({"case": f"{name}/{n}", "peer": "vtkStreamTracer", "threads": threads,
                          "seconds": round(best, 4), "lines": out.GetNumberOfLines(),
                          "points": out.GetNumberOfPoints()}), flush=True)


if __name__ == "__main__":
    main()
