#!/usr/bin/env python3
"""Peer of `isoforge decimate`: VTK 9's decimation filters (python3-vtk9), single-threaded
(both filters are serial), to a target triangle count.

Usage: vtk_decimate.py METHOD IN OUT TARGET
  METHOD: quadric        vtkQuadricDecimation, VolumePreservation off, other settings default
          pro            vtkDecimatePro, PreserveTopologyOff (splitting allowed, its default)
          pro-topology   vtkDecimatePro, PreserveTopologyOn, SplittingOff
  IN: .ply/.vtp/.vtk/.stl; OUT: .ply or .vtp.
Both filters take a reduction fraction, not a count: TargetReduction = 1 - TARGET / input
triangles, and the count achieved is reported (vtkQuadricDecimation lands within a few
triangles; vtkDecimatePro stops short when topology preservation or the feature settings
forbid further removal). BoundaryVertexDeletion keeps its default (on).
Prints one JSON line: {"peer", "input", "target", "output_triangles", "seconds" (Update() of the
filter alone), "total_seconds" (read + triangulate + decimate + write)}."""
import json
import os
import sys
import time

import vtk


def reader_for(path):
    ext = os.path.splitext(path)[1].lower()
    cls = {".ply": vtk.vtkPLYReader, ".vtp": vtk.vtkXMLPolyDataReader,
           ".vtk": vtk.vtkPolyDataReader, ".stl": vtk.vtkSTLReader}.get(ext)
    if cls is None:
        sys.exit(f"vtk_decimate.py: {path}: unsupported extension")
    r = cls()
    r.SetFileName(path)
    return r


def writer_for(path):
    ext = os.path.splitext(path)[1].lower()
    if ext == ".ply":
        w = vtk.vtkPLYWriter()
        w.SetFileTypeToBinary()
    elif ext == ".vtp":
        w = vtk.vtkXMLPolyDataWriter()
    else:
        sys.exit(f"vtk_decimate.py: {path}: write .ply or .vtp")
    w.SetFileName(path)
    return w


def main():
    if len(sys.argv) != 5 or sys.argv[1] not in ("quadric", "pro", "pro-topology"):
        sys.exit(__doc__)
    method, src, dst, target = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4])
    vtk.vtkSMPTools.Initialize(1)
    start = time.perf_counter()
    r = reader_for(src)
    tri = vtk.vtkTriangleFilter()  # polygons and strips to triangles, as every peer takes them
    tri.SetInputConnection(r.GetOutputPort())
    tri.PassVertsOff()
    tri.PassLinesOff()
    tri.Update()
    mesh = tri.GetOutput()
    n = mesh.GetNumberOfPolys()
    reduction = min(max(1.0 - target / n, 0.0), 1.0)
    if method == "quadric":
        f = vtk.vtkQuadricDecimation()
        f.VolumePreservationOff()
        peer = "vtk-quadric"
    else:
        f = vtk.vtkDecimatePro()
        if method == "pro-topology":
            f.PreserveTopologyOn()
            f.SplittingOff()
            peer = "vtk-pro-topology"
        else:
            f.PreserveTopologyOff()
            peer = "vtk-pro"
    f.SetTargetReduction(reduction)
    f.SetInputData(mesh)
    t0 = time.perf_counter()
    f.Update()
    seconds = time.perf_counter() - t0
    out = f.GetOutput()
    w = writer_for(dst)
    w.SetInputData(out)
    w.Write()
    print(json.dumps({"peer": peer, "input": src, "target": target,
                      "output_triangles": out.GetNumberOfPolys(), "seconds": seconds,
                      "total_seconds": time.perf_counter() - start}))


if __name__ == "__main__":
    main()
