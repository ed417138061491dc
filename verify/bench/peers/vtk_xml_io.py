#!/usr/bin/env python3
"""Peer of verify/bench/xml_io.sh: VTK 9's XML readers and writers as a user runs them, one
operation per process (the bench times the whole process, as it times the isoforge command).

  vtk_xml_io.py read FILE                       read a .vti/.vtp (vtkXMLImageDataReader/...PolyData...)
  vtk_xml_io.py write IN OUT none|zlib|lz4 [L] [ids32]
                                                read IN, write OUT with that compressor (level L;
                                                ids32: cell ids as Int32: the cell arrays
                                                converted to 32-bit storage, timed with the
                                                write)

VTK's writers use blocks of 32 KiB, compression level 5 unless L is given, and Int64 cell ids
(VTK's default) unless ids32 is given; the size written is what the bench compares. Prints the seconds of the read/write call itself on stdout."""
import sys
import time

import vtk


def reader_for(path):
    if path.endswith(".vti"):
        return vtk.vtkXMLImageDataReader()
    if path.endswith(".vtp"):
        return vtk.vtkXMLPolyDataReader()
    raise SystemExit("unsupported file " + path)


def writer_for(path):
    if path.endswith(".vti"):
        return vtk.vtkXMLImageDataWriter()
    if path.endswith(".vtp"):
        return vtk.vtkXMLPolyDataWriter()
    raise SystemExit("unsupported file " + path)


def read(path):
    r = reader_for(path)
    r.SetFileName(path)
    t = time.perf_counter()
    r.Update()
    dt = time.perf_counter() - t
    out = r.GetOutput()
    if out.GetNumberOfPoints() == 0:
        raise SystemExit("VTK read nothing from " + path)
    return out, dt


def main():
    mode = sys.argv[1]
    if mode == "read":
        _, dt = read(sys.argv[2])
        print("%.4f" % dt)
        return
    if mode == "write":
        data, _ = read(sys.argv[2])
        w = writer_for(sys.argv[3])
        w.SetInputData(data)
        w.SetFileName(sys.argv[3])
        w.SetDataModeToAppended()
        w.EncodeAppendedDataOff()
        w.SetHeaderTypeToUInt64()
        comp = sys.argv[4]
        {"none": w.SetCompressorTypeToNone, "zlib": w.SetCompressorTypeToZLib,
         "lz4": w.SetCompressorTypeToLZ4}[comp]()
        ids32 = False
        for arg in sys.argv[5:]:
            if arg == "ids32":
                ids32 = True
            else:
                w.SetCompressionLevel(int(arg))
        t = time.perf_counter()
        if ids32:
            # VTK 9 writes a cell array's own storage type (SetIdType only converts
            # vtkIdTypeArrays): 32-bit storage is what makes Int32 connectivity and offsets.
            w.SetIdTypeToInt32()
            for cells in (data.GetVerts(), data.GetLines(), data.GetPolys(), data.GetStrips()):
                if not cells.ConvertTo32BitStorage():
                    raise SystemExit("VTK could not convert the cells to 32-bit ids")
        ok = w.Write()
        dt = time.perf_counter() - t
        if ok != 1:
            raise SystemExit("VTK could not write " + sys.argv[3])
        print("%.4f" % dt)
        return
    raise SystemExit(__doc__)


main()
