#!/usr/bin/env python3
"""VTK 9.1 peer of the tensor glyph benchmark (verify/bench/tensor_glyph.sh): vtkTensorGlyph on
the Boussinesq stress field of tensor_glyph_time.cpp (47^3 points), ellipsoids from a
vtkSphereSource of 12 x 7 (62 points, 120 triangles), scale 0.05, colour by eigenvalue.

  vtk_tensor_glyph.py [REPEAT]    one JSON line (minimum of REPEAT)
"""
import json
import math
import sys
import time

import numpy as np
import vtk
from vtk.util import numpy_support


def main():
    repeat = int(sys.argv[1]) if len(sys.argv) > 1 else 3
    n = 47
    img = vtk.vtkImageData()
    img.SetDimensions(n, n, n)
    img.SetOrigin(-1, -1, -2)
    img.SetSpacing(2.0 / 46, 2.0 / 46, 1.9 / 46)
    k_, j_, i_ = np.meshgrid(np.arange(n), np.arange(n), np.arange(n), indexing="ij")
    x = (-1 + i_ * (2.0 / 46)).ravel()
    y = (-1 + j_ * (2.0 / 46)).ravel()
    z = -(-2 + k_ * (1.9 / 46)).ravel()
    P, nu = 1.0, 0.3
    rho = np.sqrt(x * x + y * y + z * z)
    rho3, rho5, rz = rho ** 3, rho ** 5, rho + z
    k = P / (2 * math.pi)
    sxx = k * (3 * x * x * z / rho5 + (1 - 2 * nu) * (z / rho3 - 1 / (rho * rz) + x * x * (2 * rho + z) / (rho3 * rz * rz)))
    syy = k * (3 * y * y * z / rho5 + (1 - 2 * nu) * (z / rho3 - 1 / (rho * rz) + y * y * (2 * rho + z) / (rho3 * rz * rz)))
    szz = k * 3 * z ** 3 / rho5
    sxy = k * (3 * x * y * z / rho5 - (1 - 2 * nu) * x * y * (2 * rho + z) / (rho3 * rz * rz))
    syz, sxz = k * 3 * y * z * z / rho5, k * 3 * x * z * z / rho5
    t = np.stack([sxx, sxy, sxz, sxy, syy, syz, sxz, syz, szz], axis=1).astype(np.float32)
    arr = numpy_support.numpy_to_vtk(t, deep=1)
    arr.SetName("stress")
    img.GetPointData().SetTensors(arr)
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
