#!/usr/bin/env python3
"""Peer timings: VTK 9's readers on the same files as bench_io (best of N runs, milliseconds).

Prints JSON {"name": ms, ...} with the names bench_io uses (a string instead of ms where VTK's
reader returns an empty dataset)."""
import json
import os
import sys
import time

import vtk

data = sys.argv[1]
repeats = int(sys.argv[2]) if len(sys.argv) > 2 else 5


def ply(p):
    r = vtk.vtkPLYReader(); r.SetFileName(p); return r

def vtp(p):
    r = vtk.vtkXMLPolyDataReader(); r.SetFileName(p); return r

def legacy(p):
    r = vtk.vtkDataSetReader(); r.SetFileName(p); r.ReadAllScalarsOn(); r.ReadAllVectorsOn()
    r.ReadAllFieldsOn(); r.ReadAllTCoordsOn(); r.ReadAllNormalsOn(); r.ReadAllTensorsOn(); return r

def plot3d(p, q):
    r = vtk.vtkMultiBlockPLOT3DReader(); r.SetXYZFileName(p); r.SetQFileName(q)
    r.SetBinaryFile(1); r.SetMultiGrid(0); r.SetHasByteCount(0); r.SetIBlanking(0)
    r.SetTwoDimensionalGeometry(0); r.SetForceRead(1); r.SetByteOrderToBigEndian()
    r.AddFunction(110); r.AddFunction(200); return r

def nrrd(p):
    r = vtk.vtkNrrdReader(); r.SetFileName(p); return r

cases = {
    "bunny_ply_ascii": lambda: ply(os.path.join(data, "bunny.ply")),
    "torso_vtp_zlib": lambda: vtp(os.path.join(data, "Torso.vtp")),
    "fran_cut_vtk_ascii": lambda: legacy(os.path.join(data, "fran_cut.vtk")),
    "post_vtk_binary": lambda: legacy(os.path.join(data, "post.vtk")),
    "ironprot_vtk_binary": lambda: legacy(os.path.join(data, "ironProt.vtk")),
    "combustor_plot3d": lambda: plot3d(os.path.join(data, "combxyz.bin"), os.path.join(data, "combq.bin")),
    "headsq_nrrd": lambda: nrrd(os.path.join(data, "headsq", "quarter.nhdr")),
}
out = {}
for name, make in cases.items():
    best = float("inf")
    for _ in range(repeats):
        r = make()  # a fresh reader each time: VTK caches otherwise
        t0 = time.perf_counter()
        r.Update()
        best = min(best, time.perf_counter() - t0)
    # A reader that returns nothing has not read the file (VTK's NRRD reader does not take the
    # "data file: NAME %d FIRST LAST STEP" list of the headsq volume): no time to compare with.
    points = r.GetOutputDataObject(0).GetNumberOfPoints()
    out[name] = best * 1000.0 if points > 0 else "VTK reads no points"
print(json.dumps(out))
