#!/usr/bin/env python3
"""VTK's side of plot3d.sh: vtkMultiBlockPLOT3DReader on the grid and solution plot3d_make
writes (big-endian float32, no byte counts, no IBLANK), asked for velocity (200) and pressure
(110) as isoforge derives them.

  vtk_plot3d.py info XYZ Q          read, then every point array's range (what `isoforge info` prints)
  vtk_plot3d.py convert XYZ Q OUT   read, then write OUT (.vts, uncompressed raw appended data)

Prints the seconds of the reader's Update() (and of the writer's Write()) to stderr."""
import sys
import time

import vtk


def read(xyz, q):
    r = vtk.vtkMultiBlockPLOT3DReader()
    r.SetXYZFileName(xyz)
    r.SetQFileName(q)
    r.SetBinaryFile(1)
    r.SetMultiGrid(0)
    r.SetHasByteCount(0)
    r.SetIBlanking(0)
    r.SetTwoDimensionalGeometry(0)
    r.SetForceRead(1)
    r.SetByteOrderToBigEndian()
    r.AddFunction(110)
    r.AddFunction(200)
    t = time.perf_counter()
    r.Update()
    print(f"update {time.perf_counter() - t:.3f}", file=sys.stderr)
    return r.GetOutput().GetBlock(0)


def main():
    mode, xyz, q = sys.argv[1], sys.argv[2], sys.argv[3]
    grid = read(xyz, q)
    if mode == "info":
        pd = grid.GetPointData()
        for i in range(pd.GetNumberOfArrays()):
            a = pd.GetArray(i)
            for c in range(a.GetNumberOfComponents()):
                a.GetRange(c)
        grid.GetBounds()
    elif mode == "convert":
        w = vtk.vtkXMLStructuredGridWriter()
        w.SetInputData(grid)
        w.SetFileName(sys.argv[4])
        w.SetDataModeToAppended()
        w.EncodeAppendedDataOff()
        w.SetCompressorTypeToNone()
        t = time.perf_counter()
        w.Write()
        print(f"write {time.perf_counter() - t:.3f}", file=sys.stderr)
    else:
        sys.exit(f"unknown mode {mode}")


main()
