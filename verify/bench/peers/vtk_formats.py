#!/usr/bin/env python3
"""Peer of verify/bench/io_formats.sh: VTK 9's readers, writers and pipelines as a user runs
them, one operation per process (the bench times the whole process, as it times the isoforge
command). Prints the seconds of the VTK call(s) alone (without Python's start-up and
`import vtk`) on the first stdout line, then a line "points P cells C arrays A,B,.." of the
dataset read or produced. Exits with 1 if VTK reports an error or reads/produces nothing.

  vtk_formats.py read FILE
      .vti .vtp (vtkXML*Reader), .vtk (vtkStructuredPointsReader / vtkPolyDataReader by the
      DATASET line, else vtkDataSetReader; all attributes read), .nrrd .nhdr (vtkNrrdReader, not
      the MPI vtkPNrrdReader the object factory would give),
      .mhd .mha (vtkMetaImageReader), .ply (vtkPLYReader), .glb (vtkGLTFReader: a multiblock
      of the meshes; counted over its leaves)
  vtk_formats.py write RAW OUT FORMAT [OPTION]
      read RAW (.vti/.vtp), write OUT; the call time is the Write() alone:
      FORMAT xml, OPTION none|zlib|lz4: vtkXML*Writer, appended raw, UInt64 headers, level 5
      FORMAT legacy: vtkStructuredPointsWriter / vtkPolyDataWriter, binary (VTK 9.1 writes
                     header version 5.1)
      FORMAT ply:    vtkPLYWriter, binary
      FORMAT mhd:    vtkMetaImageWriter, compression off (OUT.mhd + OUT.raw)
      FORMAT gltf:   vtkGLTFWriter (the polydata as one block), OUT.gltf + its .bin: VTK 9.1
                     writes no .glb
  vtk_formats.py pipeline NAME ARGS   (every writer with VTK's defaults: zlib level 5,
                                       appended data base64-encoded; the time is the whole pipeline)
      contour IN.vti OUT.vtp VALUE normals|nonormals
                     vtkXMLImageDataReader -> vtkFlyingEdges3D -> vtkXMLPolyDataWriter
      sample OUT.vti N
                     vtkSampleFunction (float, no normals) of union(torus R=0.6 r=0.2 about z,
                     sphere c=(0.3,0.2,0.1) r=0.5) on [-1,1]^3 -> vtkXMLImageDataWriter. VTK has
                     no distance torus: vtkSuperquadric (toroidal, round) and vtkSphere are
                     algebraic, so the zero set is the same as isoforge's, not the values.
      distance IN.ply OUT.vti N
                     vtkPLYReader -> vtkImplicitPolyDataDistance (signed, exact everywhere) ->
                     vtkSampleFunction (float, no normals) on [-1,1]^3 -> vtkXMLImageDataWriter
      convert IN OUT.vti|OUT.vtp
                     the reader of IN (as `read`; a .glb's blocks through
                     vtkCompositeDataGeometryFilter) -> vtkXMLImageDataWriter / vtkXMLPolyDataWriter
  vtk_formats.py compare A.vti B.vti
      the largest absolute difference of the active scalars (printed alone)
VTK's threads: vtkSMPTools.Initialize($VTK_THREADS) when that is set (else TBB's default)."""
import os
import sys
import time

import vtk


class Errors:
    """Collects VTK error events of the objects it watches (VTK prints and goes on)."""

    def __init__(self):
        self.messages = []

    def watch(self, obj):
        obj.AddObserver("ErrorEvent", self.on_error)
        return obj

    @vtk.calldata_type(vtk.VTK_STRING)
    def on_error(self, obj, event, message):
        self.messages.append("%s: %s" % (obj.GetClassName(), str(message).strip()))

    def check(self, what):
        if self.messages:
            raise SystemExit("VTK failed on %s: %s" % (what, "; ".join(self.messages)))


ERRORS = Errors()


def legacy_dataset_type(path):
    with open(path, "rb") as f:
        for _ in range(10):
            line = f.readline().strip().upper()
            if line.startswith(b"DATASET"):
                return line.split()[1].decode()
    return ""


def reader_for(path):
    ext = os.path.splitext(path)[1].lower()
    if ext == ".vti":
        r = vtk.vtkXMLImageDataReader()
    elif ext == ".vtp":
        r = vtk.vtkXMLPolyDataReader()
    elif ext == ".vtk":
        kind = legacy_dataset_type(path)
        r = {"STRUCTURED_POINTS": vtk.vtkStructuredPointsReader,
             "POLYDATA": vtk.vtkPolyDataReader}.get(kind, vtk.vtkDataSetReader)()
        for flag in ("Scalars", "Vectors", "Normals", "TCoords", "Tensors", "Fields"):
            getattr(r, "ReadAll%sOn" % flag)()
    elif ext in (".nrrd", ".nhdr"):
        # Debian's VTK overrides vtkNrrdReader with vtkPNrrdReader, which fails without MPI
        # ("No MPI Controller available"): ask for the serial reader itself.
        vtk.vtkObjectFactory.SetAllEnableFlags(0, "vtkNrrdReader")
        r = vtk.vtkNrrdReader()
    elif ext in (".mhd", ".mha"):
        r = vtk.vtkMetaImageReader()
    elif ext == ".ply":
        r = vtk.vtkPLYReader()
    elif ext == ".glb":
        r = vtk.vtkGLTFReader()
    else:
        raise SystemExit("unsupported file " + path)
    r.SetFileName(path)
    return ERRORS.watch(r)


def leaves(ds):
    """The datasets of a composite dataset (a multiblock from vtkGLTFReader), else [ds]."""
    if not ds.IsA("vtkCompositeDataSet"):
        return [ds]
    it = ds.NewIterator()
    it.InitTraversal()
    out = []
    while not it.IsDoneWithTraversal():
        out.append(it.GetCurrentDataObject())
        it.GoToNextItem()
    return out


def describe(ds):
    names = []
    parts = leaves(ds)
    if not parts:
        return "points 0 cells 0 arrays -"
    points = sum(p.GetNumberOfPoints() for p in parts)
    cells = sum(p.GetNumberOfCells() for p in parts)
    ds = parts[0]
    for attrs in (ds.GetPointData(), ds.GetCellData()):
        for i in range(attrs.GetNumberOfArrays()):
            names.append(attrs.GetArrayName(i) or "?")
    return "points %d cells %d arrays %s" % (points, cells, ",".join(names) or "-")


def checked_output(alg, what):
    ERRORS.check(what)
    out = alg.GetOutputDataObject(0)
    if out is None or sum(p.GetNumberOfPoints() for p in leaves(out)) == 0:
        raise SystemExit("VTK read/produced nothing: " + what)
    return out


def read(path):
    r = reader_for(path)
    t = time.perf_counter()
    r.Update()
    dt = time.perf_counter() - t
    return checked_output(r, path), dt


def xml_writer_for(path):
    ext = os.path.splitext(path)[1].lower()
    w = {".vti": vtk.vtkXMLImageDataWriter, ".vtp": vtk.vtkXMLPolyDataWriter}.get(ext)
    if w is None:
        raise SystemExit("no VTK XML writer for " + path)
    return ERRORS.watch(w())


def run_writer(w, out_path):
    w.SetFileName(out_path)
    t = time.perf_counter()
    ok = w.Write()
    dt = time.perf_counter() - t
    ERRORS.check(out_path)
    if ok not in (1, None):  # vtkImageWriter::Write() returns nothing
        raise SystemExit("VTK could not write " + out_path)
    if not os.path.exists(out_path):
        raise SystemExit("VTK could not write " + out_path)
    return dt


def write(raw, out, fmt, option):
    data, _ = read(raw)
    image = data.IsA("vtkImageData")
    if fmt == "xml":
        w = xml_writer_for(out)
        w.SetDataModeToAppended()
        w.EncodeAppendedDataOff()
        w.SetHeaderTypeToUInt64()
        {"none": w.SetCompressorTypeToNone, "zlib": w.SetCompressorTypeToZLib,
         "lz4": w.SetCompressorTypeToLZ4}[option]()
    elif fmt == "legacy":
        w = ERRORS.watch(vtk.vtkStructuredPointsWriter() if image else vtk.vtkPolyDataWriter())
        w.SetFileTypeToBinary()
    elif fmt == "ply":
        w = ERRORS.watch(vtk.vtkPLYWriter())
        w.SetFileTypeToBinary()
    elif fmt == "mhd":
        w = ERRORS.watch(vtk.vtkMetaImageWriter())
        w.SetCompression(False)
    elif fmt == "gltf":
        w = ERRORS.watch(vtk.vtkGLTFWriter())
        w.SetInlineData(False)
        blocks = vtk.vtkMultiBlockDataSet()
        blocks.SetBlock(0, data)
        data = blocks
    else:
        raise SystemExit("unknown format " + fmt)
    w.SetInputData(data)
    return run_writer(w, out), data


def torus_and_sphere():
    torus = vtk.vtkSuperquadric()  # about y; R + r = Size, r / R = Thickness
    torus.SetToroidal(1)
    torus.SetThetaRoundness(1)
    torus.SetPhiRoundness(1)
    torus.SetSize(0.6 + 0.2)
    torus.SetThickness(0.2 / 0.6)
    about_z = vtk.vtkTransform()
    about_z.RotateX(90)  # the function's y is the world's z
    torus.SetTransform(about_z)
    sphere = vtk.vtkSphere()
    sphere.SetCenter(0.3, 0.2, 0.1)
    sphere.SetRadius(0.5)
    union = vtk.vtkImplicitBoolean()
    union.SetOperationTypeToUnion()
    union.AddFunction(torus)
    union.AddFunction(sphere)
    return union, (torus, about_z, sphere)


def sampler(function, n):
    s = ERRORS.watch(vtk.vtkSampleFunction())
    s.SetImplicitFunction(function)
    s.SetModelBounds(-1, 1, -1, 1, -1, 1)
    s.SetSampleDimensions(n, n, n)
    s.SetOutputScalarTypeToFloat()
    s.ComputeNormalsOff()
    return s


def pipeline(name, args):
    keep = None
    t = time.perf_counter()
    if name == "contour":
        src, out, value, normals = args[0], args[1], float(args[2]), args[3] == "normals"
        r = reader_for(src)
        f = ERRORS.watch(vtk.vtkFlyingEdges3D())
        f.SetInputConnection(r.GetOutputPort())
        f.SetValue(0, value)
        f.SetComputeNormals(normals)  # VTK's default: on
        w = xml_writer_for(out)
        w.SetInputConnection(f.GetOutputPort())
        last = f
    elif name == "sample":
        out, n = args[0], int(args[1])
        function, keep = torus_and_sphere()
        last = sampler(function, n)
        w = xml_writer_for(out)
        w.SetInputConnection(last.GetOutputPort())
    elif name == "distance":
        src, out, n = args[0], args[1], int(args[2])
        r = reader_for(src)
        r.Update()
        d = vtk.vtkImplicitPolyDataDistance()
        d.SetInput(checked_output(r, src))
        last = sampler(d, n)
        keep = d
        w = xml_writer_for(out)
        w.SetInputConnection(last.GetOutputPort())
    elif name == "convert":
        src, out = args[0], args[1]
        last = reader_for(src)
        if src.lower().endswith(".glb"):
            flat = ERRORS.watch(vtk.vtkCompositeDataGeometryFilter())
            flat.SetInputConnection(last.GetOutputPort())
            last = flat
        w = xml_writer_for(out)
        w.SetInputConnection(last.GetOutputPort())
    else:
        raise SystemExit(__doc__)
    w.SetFileName(out)
    ok = w.Write()
    dt = time.perf_counter() - t
    ERRORS.check(out)
    if ok != 1:
        raise SystemExit("VTK could not write " + out)
    del keep
    return dt, checked_output(last, name)


def main():
    if len(sys.argv) < 3:
        raise SystemExit(__doc__)
    if os.environ.get("VTK_THREADS"):
        vtk.vtkSMPTools.Initialize(int(os.environ["VTK_THREADS"]))
    mode = sys.argv[1]
    if mode == "compare" and len(sys.argv) == 4:
        import numpy as np
        from vtk.util.numpy_support import vtk_to_numpy
        a, b = (vtk_to_numpy(read(p)[0].GetPointData().GetScalars()).astype(np.float64)
                for p in sys.argv[2:4])
        print("%.3g" % np.abs(a - b).max() if a.shape == b.shape else
              "shapes differ: %s, %s" % (a.shape, b.shape))
        return
    if mode == "read":
        data, dt = read(sys.argv[2])
    elif mode == "write" and len(sys.argv) >= 5:
        dt, data = write(sys.argv[2], sys.argv[3], sys.argv[4],
                         sys.argv[5] if len(sys.argv) > 5 else "")
    elif mode == "pipeline":
        dt, data = pipeline(sys.argv[2], sys.argv[3:])
    else:
        raise SystemExit(__doc__)
    print("%.4f" % dt)
    print(describe(data))


main()
