#!/usr/bin/env python3
"""Peer: vtkSampleFunction on the ice cream cone built from VTK implicit functions (VTK's
IceCream example: cone ∩ two planes, ∪ big sphere − bite sphere), same bounds and resolutions
as bench_implicit, with 1 thread and with all threads (vtkSMPTools). Prints JSON
{"dense_icecream/N/THREADS": {"ms": best_ms, "Mevals_per_s": ...}}."""
import json
import os
import sys
import time

import vtk

def icecream():
    cone = vtk.vtkCone(); cone.SetAngle(20)
    vert = vtk.vtkPlane(); vert.SetOrigin(0.1, 0, 0); vert.SetNormal(-1, 0, 0)
    base = vtk.vtkPlane(); base.SetOrigin(1.2, 0, 0); base.SetNormal(1, 0, 0)
    cream = vtk.vtkSphere(); cream.SetCenter(1.333, 0, 0); cream.SetRadius(0.5)
    bite = vtk.vtkSphere(); bite.SetCenter(1.5, 0, 0.5); bite.SetRadius(0.25)
    the_cone = vtk.vtkImplicitBoolean(); the_cone.SetOperationTypeToIntersection()
    for f in (cone, vert, base): the_cone.AddFunction(f)
    the_cream = vtk.vtkImplicitBoolean(); the_cream.SetOperationTypeToDifference()
    the_cream.AddFunction(cream); the_cream.AddFunction(bite)
    ice = vtk.vtkImplicitBoolean(); ice.SetOperationTypeToUnion()
    ice.AddFunction(the_cone); ice.AddFunction(the_cream)
    return ice, (cone, vert, base, cream, bite, the_cone, the_cream)

sizes = [int(s) for s in sys.argv[1:]] or [256, 512]
all_threads = os.cpu_count() or 1
out = {}
for n in sizes:
    f, keep = icecream()
    for threads in (1, all_threads):
        vtk.vtkSMPTools.Initialize(threads)
        best = float("inf")
        for _ in range(3 if n <= 256 else 1):
            s = vtk.vtkSampleFunction()
            s.SetImplicitFunction(f)
            s.SetModelBounds(-0.1, 2.0, -0.7, 0.7, -0.7, 0.7)
            s.SetSampleDimensions(n, n, n)
            s.ComputeNormalsOff()
            s.SetOutputScalarTypeToFloat()
            t0 = time.perf_counter(); s.Update(); best = min(best, time.perf_counter() - t0)
            del s
        out[f"dense_icecream/{n}/{threads}"] = {"ms": best * 1e3, "threads": threads,
                                                "Mevals_per_s": n ** 3 / best / 1e6}
print(json.dumps(out))
