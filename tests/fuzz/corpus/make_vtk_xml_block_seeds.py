#!/usr/bin/env python3
"""Writes the seed corpus of fuzz_vtk_xml_block (see tests/fuzz/fuzz_vtk_xml_block.cpp for the
input layout): DataArray payloads as VTK writes them, in every encoding the decoder reads.
Run from this directory: python3 make_vtk_xml_block_seeds.py"""
import base64
import os
import lzma
import struct
import zlib

data = struct.pack("<12f", *[0.5 * i for i in range(12)])  # 4 tuples of 3 float32 = 48 bytes
unit = 12


def prefix(b64, compressed, header64, big, expected, codec=0):
    flags = b64 | compressed << 1 | header64 << 2 | big << 3 | (expected is not None) << 4 | codec << 5
    return bytes([flags, unit - 1]) + struct.pack("<I", expected or 0)


def word(v, header64, big):
    return struct.pack((">" if big else "<") + ("Q" if header64 else "I"), v)


def lz4_literals(raw):
    """An LZ4 block holding `raw` as one run of literals (token, length bytes, the bytes)."""
    n = len(raw)
    if n < 15:
        return bytes([n << 4]) + raw
    out = bytes([0xF0])
    rest = n - 15
    while rest >= 255:
        out += b"\xff"
        rest -= 255
    return out + bytes([rest]) + raw


def seeds():
    for header64 in (0, 1):
        for big in (0, 1):
            # One byte-count header and the data.
            raw = word(len(data), header64, big) + data
            yield prefix(0, 0, header64, big, len(data)), raw
            # VTK's inline base64 encodes the header and the data as one stream.
            yield prefix(1, 0, header64, big, None), base64.b64encode(raw)
            # Compressed: two blocks of 32 bytes (the last one 16), header then blocks.
            blocks = [zlib.compress(data[:32]), zlib.compress(data[32:])]
            header = b"".join(word(v, header64, big) for v in [2, 32, 16] + [len(b) for b in blocks])
            yield prefix(0, 1, header64, big, len(data)), header + b"".join(blocks)
            # VTK encodes the compression header and the blocks as separate base64 streams.
            yield prefix(1, 1, header64, big, None), base64.b64encode(header) + base64.b64encode(
                b"".join(blocks))
            # The same blocks as LZ4 (literals only: a valid LZ4 block any decoder reads) and as
            # .xz streams (vtkLZMADataCompressor).
            for codec, blocks in ((1, [lz4_literals(data[:32]), lz4_literals(data[32:])]),
                                  (2, [lzma.compress(data[:32], check=lzma.CHECK_CRC32),
                                       lzma.compress(data[32:], check=lzma.CHECK_CRC32)])):
                header = b"".join(word(v, header64, big)
                                  for v in [2, 32, 16] + [len(b) for b in blocks])
                yield prefix(0, 1, header64, big, len(data), codec), header + b"".join(blocks)


for i, (head, payload) in enumerate(seeds()):
    with open(os.path.join("vtk_xml_block", "seed_%02d" % i), "wb") as f:
        f.write(head + payload)
