#!/usr/bin/env python3
"""Peers of bench_cut (cut.sh): VTK 9.1 cutting and clipping the same in-memory inputs, timed
around Update(), minimum over REPEATS runs, with THREADS SMP threads.
Usage: vtk_cut.py THREADS REPEATS. Prints JSON keyed like bench_cut."""
import json
import sys
import time

import numpy as np
import vtk
from vtk.util import numpy_support

if len(sys.argv) > 1 and sys.argv[1] == "pipeline":
    # The whole command as VTK does it: read the combustor (PLOT3D), cut it by the plane through
    # its centre, write .vtp; timed inside python (the interpreter's start-up left out).
    # Usage: vtk_cut.py pipeline DATA_DIR OUT.vtp REPEATS
    import vtk as _vtk
    data, out_path, reps = sys.argv[2], sys.argv[3], int(sys.argv[4])
    best = float("inf")
    for _ in range(reps):
        t0 = time.perf_counter()
        r = _vtk.vtkMultiBlockPLOT3DReader()
        r.SetXYZFileName(data + "/combxyz.bin")
        r.SetQFileName(data + "/combq.bin")
        r.SetScalarFunctionNumber(100)
        r.SetVectorFunctionNumber(202)
        r.Update()
        grid = r.GetOutput().GetBlock(0)
        p = _vtk.vtkPlane()
        p.SetOrigin(grid.GetCenter())
        p.SetNormal(-0.287, 0, 0.9579)
        c = _vtk.vtkCutter()
        c.SetInputData(grid)
        c.SetCutFunction(p)
        w = _vtk.vtkXMLPolyDataWriter()
        w.SetInputConnection(c.GetOutputPort())
        w.SetFileName(out_path)
        w.Write()
        best = min(best, time.perf_counter() - t0)
    print(json.dumps({"pipeline/combustor": {"ms": best * 1e3}}))
    sys.exit(0)

threads = int(sys.argv[1]) if len(sys.argv) > 1 else 2
repeats = int(sys.argv[2]) if len(sys.argv) > 2 else 5
vtk.vtkSMPTools.Initialize(threads)
normal = (-0.287, 0.0, 0.9579)


def field(x, y, z):
    return (np.sin(x * 0.05) + np.cos(y * 0.07) + z * 0.01).astype(np.float32)


def image(n):
    img = vtk.vtkImageData()
    img.SetDimensions(n, n, n)
    k, j, i = np.meshgrid(np.arange(n), np.arange(n), np.arange(n), indexing="ij")
    s = numpy_support.numpy_to_vtk(field(i.ravel(), j.ravel(), k.ravel()), deep=1)
    s.SetName("s")
    img.GetPointData().SetScalars(s)
    return img


def curvilinear(n):
    k, j, i = np.meshgrid(np.arange(n), np.arange(n), np.arange(n), indexing="ij")
    x = (i + 0.3 * np.sin(j * 0.1)).ravel().astype(np.float32)
    y = (j + 0.3 * np.sin(k * 0.1)).ravel().astype(np.float32)
    z = k.ravel().astype(np.float32)
    pts = vtk.vtkPoints()
    pts.SetData(numpy_support.numpy_to_vtk(np.stack([x, y, z], axis=1), deep=1))
    sg = vtk.vtkStructuredGrid()
    sg.SetDimensions(n, n, n)
    sg.SetPoints(pts)
    s = numpy_support.numpy_to_vtk(field(x.astype(np.float64), y.astype(np.float64), z.astype(np.float64)), deep=1)
    s.SetName("s")
    sg.GetPointData().SetScalars(s)
    return sg


def cells_of(out):
    if isinstance(out, vtk.vtkCompositeDataSet):
        it = out.NewIterator()
        it.InitTraversal()
        total = 0
        while not it.IsDoneWithTraversal():
            total += it.GetCurrentDataObject().GetNumberOfCells()
            it.GoToNextItem()
        return total
    return out.GetNumberOfCells()


def timed(make, reps=repeats):
    best, cells = float("inf"), 0
    for _ in range(reps):
        f = make()
        t0 = time.perf_counter()
        f.Update()
        best = min(best, time.perf_counter() - t0)
        cells = cells_of(f.GetOutputDataObject(0))
    return best * 1e3, cells


out = {}
for n in (256, 384):
    img = image(n)
    h = (n - 1) / 2.0

    def plane_cutter():
        p = vtk.vtkPlane()
        p.SetOrigin(h, h, h)
        p.SetNormal(*normal)
        c = vtk.vtkPlaneCutter()
        c.SetInputData(img)
        c.SetPlane(p)
        return c
    ms, cells = timed(plane_cutter)
    out[f"plane_image/{n}"] = {"ms": ms, "cells": cells, "peer": "vtkPlaneCutter"}
    del img

sg = curvilinear(100)
for label, cls in (("vtkCutter", vtk.vtkCutter), ("vtkPlaneCutter", vtk.vtkPlaneCutter)):
    def make(cls=cls):
        p = vtk.vtkPlane()
        p.SetOrigin(49.5, 49.5, 49.5)
        p.SetNormal(*normal)
        c = cls()
        c.SetInputData(sg)
        if cls is vtk.vtkCutter:
            c.SetCutFunction(p)
        else:
            c.SetPlane(p)
        return c
    ms, cells = timed(make)
    out[f"plane_curvilinear/100/{label}"] = {"ms": ms, "cells": cells, "peer": label}

img = image(256)
h = 255 / 2.0


def clipper():
    s = vtk.vtkSphere()
    s.SetCenter(h, h, h)
    s.SetRadius(0.4 * 255)
    c = vtk.vtkTableBasedClipDataSet()
    c.SetInputData(img)
    c.SetClipFunction(s)
    c.InsideOutOn()
    return c
ms, cells = timed(clipper)
out["clip_sphere_image/256"] = {"ms": ms, "cells": cells, "peer": "vtkTableBasedClipDataSet"}
print(json.dumps(out))
