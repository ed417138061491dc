#!/usr/bin/env python3
"""Writes the benchmark volumes as raw little-endian float32 (x fastest) so isoforge and VTK
contour exactly the same bytes: OUT_DIR/{gyroid,blobs}_{N}.raw for each N given."""
import os
import sys

import numpy as np


def gyroid(n):
    t = np.linspace(0.0, 8 * np.pi, n, dtype=np.float64)
    z, y, x = np.meshgrid(t, t, t, indexing="ij")
    return (np.sin(x) * np.cos(y) + np.sin(y) * np.cos(z) + np.sin(z) * np.cos(x)).astype(np.float32)


def blobs(n):
    rng = np.random.default_rng(12345)
    centers = rng.uniform(0.15, 0.85, size=(24, 3))
    widths = rng.uniform(0.04, 0.12, size=24)
    t = np.linspace(0.0, 1.0, n, dtype=np.float64)
    out = np.zeros((n, n, n), dtype=np.float64)
    z, y, x = np.meshgrid(t, t, t, indexing="ij")
    for c, w in zip(centers, widths):
        out += np.exp(-((x - c[0]) ** 2 + (y - c[1]) ** 2 + (z - c[2]) ** 2) / (2 * w * w))
    out += 0.1 * np.sin(20 * x) * np.sin(20 * y)
    return out.astype(np.float32)


out_dir = sys.argv[1]
os.makedirs(out_dir, exist_ok=True)
for n in map(int, sys.argv[2:]):
    for name, fn in (("gyroid", gyroid), ("blobs", blobs)):
        path = os.path.join(out_dir, f"{name}_{n}.raw")
        if not os.path.exists(path):
            fn(n).tofile(path)
