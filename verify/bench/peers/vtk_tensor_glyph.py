#!/usr/bin/env python3
"""VTK 9.1 peer of the tensor glyph benchmark (verify/bench/tensor_glyph.sh): vtkTensorGlyph on
the Boussinesq stress field of vtkPointLoad (unit load, [-1, 1]^3, 47^3 points; the field
isoforge's point_load samples in tensor_glyph_time.cpp), ellipsoids from a
vtkSphereSource of 12 x 7 (62 points, 120 triangles), scale 0.05, colour by eigenvalue.

  vtk_tensor_glyph.py [REPEAT]    one JSON line (minimum of REPEAT)
"""
import json
import sys
import time

import vtk


def main():
    repeat = int(sys.argv[1]) if len(sys.argv) > 1 else 3
    n = 47
    load = vtk.vtkPointLoad()
    load.SetLoadValue(1.0)
    load.SetModelBounds(-1, 1, -1, 1, -1, 1)
    load.SetSampleDimensions(n, n, n)
    load.SetPoissonsRatio(0.3)
    load.ComputeEffectiveStressOff()
    load.Update()
    img = load.GetOutput()
    sphere = vtk.vtkSphereSource()
    sphere.SetThetaResolution(12)
    sphere.SetPhiResolution(7)
    sphere.Update()
    best, out = 1e300, None
    for _ in range(repeat):
        g = vtk.vtkTensorGlyph()
        g.SetInputData(img)
        g.SetSourceData(sphere.GetOutput())
        g.SetScaleFactor(0.05)
        g.ExtractEigenvaluesOn()
        g.ColorGlyphsOn()
        g.SetColorModeToEigenvalues()
        t0 = time.perf_counter()
        g.Update()
        best = min(best, time.perf_counter() - t0)
        out = g.GetOutput()
    print(json.dumps({"case": f"boussinesq/{n ** 3}", "peer": "vtkTensorGlyph",
                      "threads": vtk.vtkSMPTools.GetEstimatedNumberOfThreads(),
                      "seconds": round(best, 4), "triangles": out.GetNumberOfCells()}), flush=True)


if __name__ == "__main__":
    main()
