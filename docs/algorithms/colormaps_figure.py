#!/usr/bin/env python3
"""Draws docs/algorithms/img/colormaps.png: one bar per colour map, each coloured by
`isoforge colormap` itself (a 256-point ramp 0..255 written as ASCII VTK and read back), plus a
bar in 8 bands. Usage: colormaps_figure.py ISOFORGE OUT.png (Python standard library only)."""
import os
import struct
import subprocess
import sys
import tempfile
import zlib

MAPS = ["viridis", "plasma", "inferno", "cool-warm", "rainbow", "grayscale", "black-body"]
WIDTH, BAR, GAP = 512, 28, 6


def colours(isoforge, workdir, name, *extra):
    ramp = os.path.join(workdir, "ramp.vtk")
    with open(ramp, "w") as f:
        f.write("# vtk DataFile Version 3.0\nramp\nASCII\nDATASET POLYDATA\nPOINTS 256 float\n")
        f.write("".join(f"{i} 0 0\n" for i in range(256)))
        f.write("POINT_DATA 256\nSCALARS s float\nLOOKUP_TABLE default\n")
        f.write("".join(f"{i}\n" for i in range(256)))
    coloured = os.path.join(workdir, "coloured.vtp")
    text = os.path.join(workdir, "coloured.vtk")
    subprocess.run([isoforge, "-q", "colormap", ramp, "-a", "s", "--colormap", name, *extra,
                    "-o", coloured], check=True)
    subprocess.run([isoforge, "-q", "convert", coloured, text, "--ascii"], check=True)
    words = open(text).read().split()
    start = words.index("Colors") + 4  # SCALARS Colors unsigned_char 3 LOOKUP_TABLE default
    while not words[start].isdigit():
        start += 1
    values = [int(w) for w in words[start:start + 3 * 256]]
    return [tuple(values[3 * i:3 * i + 3]) for i in range(256)]


def png(path, rows):
    raw = b"".join(b"\0" + bytes(v for px in row for v in px) for row in rows)
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
    header = struct.pack(">IIBBBBB", len(rows[0]), len(rows), 8, 2, 0, 0, 0)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(raw, 9))
                + chunk(b"IEND", b""))


def main():
    isoforge, out = sys.argv[1], sys.argv[2]
    with tempfile.TemporaryDirectory() as workdir:
        bars = [colours(isoforge, workdir, m) for m in MAPS]
        bars.append(colours(isoforge, workdir, "viridis", "--bands", "8"))
    rows = []
    for bar in bars:
        line = [bar[x * 256 // WIDTH] for x in range(WIDTH)]
        rows += [line] * BAR + [[(255, 255, 255)] * WIDTH] * GAP
    png(out, rows[:-GAP])


if __name__ == "__main__":
    main()
