#!/usr/bin/env python3
"""VTK 9.1 peer of the calculator benchmark (verify/bench/calculator.sh): vtkArrayCalculator on
an N^3 image with the arrays of calculator_time.cpp, expressions `mag(V)*2 + P/3` and
`cross(V, kHat) * P` (VTK's spelling of the same).

  vtk_calculator.py [N [REPEAT]]    one JSON line per case (minimum of REPEAT)
"""
import json
import sys
import time

import numpy as np
import vtk
from vtk.util import numpy_support


def main():
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 256
    repeat = int(sys.argv[2]) if len(sys.argv) > 2 else 3
    img = vtk.vtkImageData()
    img.SetDimensions(n, n, n)
    np_ = n * n * n
    t = np.arange(np_, dtype=np.float64) * 1e-6
    v = np.empty((np_, 3), dtype=np.float32)
    v[:, 0], v[:, 1], v[:, 2] = np.sin(t), np.cos(t), t
    for name, a in (("V", v), ("P", (1 + t).astype(np.float32))):
        arr = numpy_support.numpy_to_vtk(a, deep=1)
        arr.SetName(name)
        img.GetPointData().AddArray(arr)
    for case, expression in (("scalar", "mag(V)*2 + P/3"), ("vector", "cross(V, kHat) * P")):
        best, value = 1e300, None
        for _ in range(repeat):
            c = vtk.vtkArrayCalculator()
            c.SetInputData(img)
            c.SetAttributeTypeToPointData()
            c.AddScalarVariable("P", "P", 0)
            c.AddVectorArrayName("V")
            c.SetFunction(expression)
            c.SetResultArrayName("r")
            c.SetResultArrayType(vtk.VTK_DOUBLE)
            t0 = time.perf_counter()
            c.Update()
            best = min(best, time.perf_counter() - t0)
            value = c.GetOutput().GetPointData().GetArray("r").GetComponent(np_ // 2, 0)
        print(json.dumps({"case": f"{case}/{np_}", "peer": "vtkArrayCalculator",
                          "threads": vtk.vtkSMPTools.GetEstimatedNumberOfThreads(),
                          "seconds": round(best, 4), "value_at_middle": value}), flush=True)


if __name__ == "__main__":
    main()
