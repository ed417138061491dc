#!/usr/bin/python3
"""The VTK 9.1 side of the glyph benchmark (glyph.sh), the counterpart of glyph_time: the same
inputs in memory (the same formulas, or the same files read before the clock starts), each
filter timed around Update() REPEAT times, the fastest printed as one JSON line.

Usage: vtk_glyph.py CASE [ARGS...]   (the cases and arguments of glyph_time)
       vtk_glyph.py command IN.vtp SOURCE.vtp OUT.vtp   the whole glyph command: read, glyph, write
       vtk_glyph.py cloud N OUT.vtp                      writes the point cloud as a file
"""
import json
import sys
import time

import numpy as np
import vtk
from vtk.util import numpy_support as ns


def point_cloud(n):
    side = int(np.ceil(np.cbrt(n)))
    i = np.arange(n, dtype=np.float64)
    x = np.mod(i, side)
    y = np.mod(np.floor(i / side), side)
    z = np.floor(i / (side * side))
    pts = np.stack([x + 0.25 * np.sin(1.3 * i), y, z], axis=1).astype(np.float32)
    vec = np.stack([np.sin(0.1 * y) + 0.2, np.cos(0.1 * z), np.sin(0.1 * x)], axis=1).astype(np.float32)
    pd = vtk.vtkPolyData()
    points = vtk.vtkPoints()
    points.SetData(ns.numpy_to_vtk(pts, deep=True))
    pd.SetPoints(points)
    v = ns.numpy_to_vtk(vec, deep=True)
    v.SetName("V")
    pd.GetPointData().SetVectors(v)
    return pd


def read(path):
    if path.endswith(".vtp"):
        r = vtk.vtkXMLPolyDataReader()
    elif path.endswith(".ply"):
        r = vtk.vtkPLYReader()
    else:
        r = vtk.vtkPolyDataReader()
    r.SetFileName(path)
    r.Update()
    return r.GetOutput()


def best_of(repeat, make):
    best, points = float("inf"), 0
    for _ in range(repeat):
        f = make()
        t0 = time.perf_counter()
        f.Update()
        best = min(best, time.perf_counter() - t0)
        points = f.GetOutput().GetNumberOfPoints()
    return best, points


def glyph3d(input, source):
    g = vtk.vtkGlyph3D()
    g.SetInputData(input)
    g.SetSourceData(source)
    g.SetVectorModeToUseVector()
    g.SetScaleModeToScaleByVector()
    g.SetScaleFactor(0.5)
    g.OrientOn()
    g.GeneratePointIdsOn()
    return g


def main():
    what = sys.argv[1]
    if what == "cloud":
        w = vtk.vtkXMLPolyDataWriter()
        w.SetInputData(point_cloud(int(sys.argv[2])))
        w.SetFileName(sys.argv[3])
        w.Write()
        return
    if what == "command":
        # The whole command: read the point cloud and the cone, glyph, write with the writer's
        # defaults (.vtp: zlib-compressed, appended, base64 as VTK writes by default; .vtk:
        # binary legacy).
        g = glyph3d(read(sys.argv[2]), read(sys.argv[3]))
        if sys.argv[4].endswith(".vtp"):
            w = vtk.vtkXMLPolyDataWriter()
        else:
            w = vtk.vtkPolyDataWriter()
            w.SetFileTypeToBinary()
        w.SetInputConnection(g.GetOutputPort())
        w.SetFileName(sys.argv[4])
        w.Write()
        return
    if what == "glyph":
        cloud, source, repeat = point_cloud(int(sys.argv[2])), read(sys.argv[3]), int(sys.argv[4])
        seconds, points = best_of(repeat, lambda: glyph3d(cloud, source))
    elif what == "hedgehog":
        cloud, repeat = point_cloud(int(sys.argv[2])), int(sys.argv[3])

        def make():
            h = vtk.vtkHedgeHog()
            h.SetInputData(cloud)
            h.SetScaleFactor(0.5)
            return h
        seconds, points = best_of(repeat, make)
    elif what == "normals":
        mesh, repeat = read(sys.argv[2]), int(sys.argv[3])

        def make():
            f = vtk.vtkPolyDataNormals()
            f.SetInputData(mesh)
            f.SetFeatureAngle(30)
            f.SplittingOn()
            f.ConsistencyOn()
            f.AutoOrientNormalsOn()
            f.ComputeCellNormalsOn()
            f.ComputePointNormalsOn()
            return f
        seconds, points = best_of(repeat, make)
    elif what == "tube":
        lines, radius, sides, repeat = read(sys.argv[2]), float(sys.argv[3]), int(sys.argv[4]), int(sys.argv[5])

        def make():
            t = vtk.vtkTubeFilter()
            t.SetInputData(lines)
            t.SetRadius(radius)
            t.SetNumberOfSides(sides)
            t.CappingOn()
            return t
        seconds, points = best_of(repeat, make)
    else:
        sys.exit(f"vtk_glyph.py: unknown case {what}")
    print(json.dumps({"case": what, "peer": "vtk", "seconds": round(seconds, 6), "output_points": points}))


if __name__ == "__main__":
    main()
