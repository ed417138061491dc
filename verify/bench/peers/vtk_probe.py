#!/usr/bin/env python3
"""VTK 9.1 peer of the probe benchmark (verify/bench/probe.sh).

  vtk_probe.py filter DIR [REPEAT]   time vtkProbeFilter::Update() on grid.vts (at a 200^3 image
                                     over its bounds) and tets.vtu (at 100^3), inputs read first
                                     and kept in memory; one JSON line per case, minimum of REPEAT
  vtk_probe.py cli IN DIMS OUT       the whole command: read IN, probe at a DIMS^3 image over its
                                     bounds, write OUT (.vti); timed from outside by probe.sh
"""
import json
import sys
import time

import vtk


def read(path):
    r = vtk.vtkXMLStructuredGridReader() if path.endswith(".vts") else vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(path)
    r.Update()
    return r.GetOutput()


def volume_over(ds, n):
    b = ds.GetBounds()
    img = vtk.vtkImageData()
    img.SetDimensions(n, n, n)
    img.SetOrigin(b[0], b[2], b[4])
    img.SetSpacing((b[1] - b[0]) / (n - 1), (b[3] - b[2]) / (n - 1), (b[5] - b[4]) / (n - 1))
    return img


def probe(source, probe_ds):
    f = vtk.vtkProbeFilter()
    f.SetSourceData(source)
    f.SetInputData(probe_ds)
    t0, c0 = time.perf_counter(), time.process_time()
    f.Update()
    return time.perf_counter() - t0, f.GetOutput(), time.process_time() - c0


def main():
    if sys.argv[1] == "filter":
        d = sys.argv[2]
        repeat = int(sys.argv[3]) if len(sys.argv) > 3 else 3
        for case, name, n in (("curvilinear", "grid.vts", 200), ("tets", "tets.vtu", 100)):
            src = read(f"{d}/{name}")
            img = volume_over(src, n)
            runs = [probe(src, img) for _ in range(repeat)]
            best, out, _ = min(runs, key=lambda r: r[0])
            cpu = min(r[2] for r in runs)
            mask = out.GetPointData().GetArray("vtkValidPointMask")
            found = sum(1 for i in range(0, mask.GetNumberOfTuples()) if mask.GetValue(i))
            print(json.dumps({"case": case, "peer": "vtk", "seconds": round(best, 4),
                              "cpu_seconds": round(cpu, 4),
                              "cells": src.GetNumberOfCells(),
                              "probe_points": img.GetNumberOfPoints(), "found": found}), flush=True)
    elif sys.argv[1] == "cli":
        src = read(sys.argv[2])
        _, out, _ = probe(src, volume_over(src, int(sys.argv[3])))
        w = vtk.vtkXMLImageDataWriter()
        w.SetFileName(sys.argv[4])
        w.SetInputData(out)
        w.Write()
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main()
