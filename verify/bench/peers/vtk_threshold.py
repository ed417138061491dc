#!/usr/bin/env python3
"""Peers of bench_threshold: vtkThreshold, vtkGeometryFilter and vtkDataSetSurfaceFilter on the
inputs of `bench_threshold make DIR` (read once, then each filter timed around Update(), REPS
times with all threads and REPS times with one; the minimum is kept). Settings as ours:
threshold of the point scalars "s" in [-0.2, 0.5] with all points of a cell in the range
(AllScalars, vtkThreshold's default); surfaces with the original cell ids passed through (our
default "OriginalCellIds"). Prints JSON keyed like bench_threshold:
{"threshold/tets/2": {"ms": .., "cells": ..}, "surface_geometry/tets/2": .., ...}.

Usage: vtk_threshold.py DIR REPS [CASE]
       vtk_threshold.py cli threshold|surface IN OUT   (the whole command: read, filter, write
       with zlib like isoforge; threshold.sh times the process)"""
import json
import os
import sys
import time

import vtk

if sys.argv[1] == "cli":
    _, _, what, src, dst = sys.argv
    r = vtk.vtkXMLUnstructuredGridReader() if src.endswith(".vtu") else vtk.vtkXMLImageDataReader()
    r.SetFileName(src)
    if what == "threshold":
        f = vtk.vtkThreshold()
        f.SetInputConnection(r.GetOutputPort())
        f.SetInputArrayToProcess(0, 0, 0, vtk.vtkDataObject.FIELD_ASSOCIATION_POINTS, "s")
        f.SetLowerThreshold(-0.2)
        f.SetUpperThreshold(0.5)
        f.SetThresholdFunction(vtk.vtkThreshold.THRESHOLD_BETWEEN)
        w = vtk.vtkXMLUnstructuredGridWriter()
    else:
        f = vtk.vtkDataSetSurfaceFilter()
        f.SetInputConnection(r.GetOutputPort())
        f.PassThroughCellIdsOn()
        w = vtk.vtkXMLPolyDataWriter()
    w.SetInputConnection(f.GetOutputPort())
    w.SetFileName(dst)
    w.SetDataModeToAppended()
    w.EncodeAppendedDataOff()
    w.SetCompressorTypeToZLib()
    w.Write()
    sys.exit(0)

d = sys.argv[1]
reps = int(sys.argv[2]) if len(sys.argv) > 2 else 5
only = sys.argv[3] if len(sys.argv) > 3 else ""


def read(name):
    r = vtk.vtkXMLUnstructuredGridReader() if name.endswith(".vtu") else vtk.vtkXMLImageDataReader()
    r.SetFileName(os.path.join(d, name))
    r.Update()
    return r.GetOutput()


def threshold(ds):
    f = vtk.vtkThreshold()
    f.SetInputData(ds)
    f.SetInputArrayToProcess(0, 0, 0, vtk.vtkDataObject.FIELD_ASSOCIATION_POINTS, "s")
    f.SetLowerThreshold(-0.2)
    f.SetUpperThreshold(0.5)
    f.SetThresholdFunction(vtk.vtkThreshold.THRESHOLD_BETWEEN)
    f.AllScalarsOn()
    return f


def geometry(ds):
    f = vtk.vtkGeometryFilter()
    f.SetInputData(ds)
    f.PassThroughCellIdsOn()
    return f


def surface(ds):
    f = vtk.vtkDataSetSurfaceFilter()
    f.SetInputData(ds)
    f.PassThroughCellIdsOn()
    return f


inputs = {"tets": read("tets.vtu"), "image": read("image.vti")}
out = {}
for threads in (os.cpu_count() or 1, 1):
    vtk.vtkSMPTools.Initialize(threads)
    for name, ds in inputs.items():
        for label, make in (("threshold", threshold), ("surface_geometry", geometry),
                            ("surface_dataset", surface)):
            key = f"{label}/{name}/{threads}"
            if only not in key:
                continue
            best, cells = float("inf"), 0
            for _ in range(reps):
                f = make(ds)
                t0 = time.perf_counter()
                f.Update()
                best = min(best, time.perf_counter() - t0)
                cells = f.GetOutput().GetNumberOfCells()
                del f
            out[key] = {"ms": round(best * 1e3, 2), "cells": cells}
print(json.dumps(out))
