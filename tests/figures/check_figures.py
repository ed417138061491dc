#!/usr/bin/env python3
"""isoforge figures on a few quick figures: the files, the summary lines and the pictures.

Usage: check_figures.py ISOFORGE DATA_DIR OUT_DIR [--regenerate]

Runs `isoforge figures --only 1.4c 1.23a 1.24a 1.24b 1.31` into OUT_DIR and checks
- every figure's datasets, .glb, figures.json and index.html exist and index.html names them;
- each summary line says ok and carries the exact counts (1.24a's selected pixels and 1.24b's
  voxels are counted here independently from the chapter's formulas);
- with node and Chromium present: each PNG is 800 x 600, not a single colour, and its middle
  (where the fixed camera puts the model) differs from the viewer's background; and, for the
  three figures of REFERENCES, the picture reduced to 80 x 60 matches the committed reference
  tests/figures/reference/STEM.png (mean absolute difference of the channels below TOLERANCE,
  in 8-bit units). `--regenerate` rewrites those references from this run instead;
- with them too: every .glb passes the Khronos glTF validator, and the gallery served by
  `isoforge view OUT_DIR` in Chromium shows every picture and each viewer link opens its figure
  (viewer/test/gallery_test.mjs).
Without node or Chromium the picture checks are skipped (exit 77, ctest's SKIP).
"""
import os
import re
import shutil
import struct
import subprocess
import sys
import zlib

BACKGROUND = (0x1E, 0x21, 0x26)
FIGS = ["1.4c", "1.23a", "1.24a", "1.24b", "1.31"]
REFERENCES = ["fig_1_23a", "fig_1_24b", "fig_1_31"]
SMALL = (80, 60)
TOLERANCE = 3.0  # mean absolute difference, 8-bit units, over the 80 x 60 x 3 channels
HERE = os.path.dirname(os.path.abspath(__file__))

failures = []


def fail(what):
    print("FAIL:", what)
    failures.append(what)


def read_png(path):
    """8-bit RGB or RGBA, non-interlaced PNG -> (width, height, rows of (r, g, b) tuples)."""
    data = open(path, "rb").read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError(f"{path}: not a PNG")
    pos, idat, header = 8, b"", None
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos:pos + 4])
        kind = data[pos + 4:pos + 8]
        body = data[pos + 8:pos + 8 + length]
        pos += 12 + length
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        elif kind == b"IEND":
            break
    w, h, depth, color, _, _, interlace = header
    if depth != 8 or color not in (2, 6) or interlace:
        raise ValueError(f"{path}: only 8-bit RGB/RGBA non-interlaced PNGs are read here")
    bpp = 3 if color == 2 else 4
    raw = zlib.decompress(idat)
    stride = w * bpp
    prev = bytearray(stride)
    rows = []
    i = 0
    for _ in range(h):
        f = raw[i]
        line = bytearray(raw[i + 1:i + 1 + stride])
        i += 1 + stride
        for x in range(stride):
            a = line[x - bpp] if x >= bpp else 0
            b = prev[x]
            c = prev[x - bpp] if x >= bpp else 0
            if f == 1:
                line[x] = (line[x] + a) & 255
            elif f == 2:
                line[x] = (line[x] + b) & 255
            elif f == 3:
                line[x] = (line[x] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                pred = a if pa <= pb and pa <= pc else b if pb <= pc else c
                line[x] = (line[x] + pred) & 255
        rows.append([tuple(line[x * bpp:x * bpp + 3]) for x in range(w)])
        prev = line
    return w, h, rows


def write_png(path, w, h, rows):
    raw = b"".join(b"\x00" + bytes(v for px in row for v in px) for row in rows)

    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))

    png = (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)) +
           chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))
    open(path, "wb").write(png)


def reduce(w, h, rows, size):
    """Box-filter average down to size (w and h multiples of it)."""
    sw, sh = size
    fx, fy = w // sw, h // sh
    out = []
    for j in range(sh):
        row = []
        for i in range(sw):
            acc = [0, 0, 0]
            for y in range(j * fy, (j + 1) * fy):
                for px in rows[y][i * fx:(i + 1) * fx]:
                    acc[0] += px[0]
                    acc[1] += px[1]
                    acc[2] += px[2]
            n = fx * fy
            row.append(tuple(round(a / n) for a in acc))
        out.append(row)
    return out


def ellipse_pixels():
    n = 0
    for j in range(30):
        for i in range(40):
            ok = True
            for c in range(4):
                x = -1 + 0.05 * (i + (c & 1))
                y = -0.75 + 0.05 * (j + (c >> 1))
                ok = ok and x * x / 0.64 + y * y / 0.25 - 1 <= 0
            n += ok
    return n


def ellipsoid_voxels():
    def inside(p, s):
        return sum((p[k] / s[k]) ** 2 for k in range(3)) <= 1

    a, b = (0.83, 0.41, 0.41), (0.41, 0.83, 0.41)
    pt = [-1 + 0.1 * i for i in range(21)]
    n = 0
    for k in range(20):
        for j in range(20):
            for i in range(20):
                ok = True
                for c in range(8):
                    p = (pt[i + (c & 1)], pt[j + ((c >> 1) & 1)], pt[k + ((c >> 2) & 1)])
                    ok = ok and (inside(p, a) or inside(p, b))
                n += ok
    return n


def main():
    args = [a for a in sys.argv[1:] if a != "--regenerate"]
    regenerate = "--regenerate" in sys.argv
    isoforge, data, out = args
    shutil.rmtree(out, ignore_errors=True)
    # Usage errors: exit 2, one line naming the option and the problem.
    for bad, words in [(["--only", "1.99"], "--only: no figure '1.99'"),
                       ([], "--out: required"),
                       (["--out", out, "--no-render", "--chromium", "/x"], "--chromium"),
                       (["--out", out, "--data", os.path.join(out, "nowhere")], "not a directory")]:
        r = subprocess.run([isoforge, "figures", *bad], capture_output=True, text=True)
        if r.returncode != 2 or words not in r.stderr:
            fail(f"isoforge figures {' '.join(bad)}: exit {r.returncode}, '{r.stderr.strip()}'")
    r = subprocess.run([isoforge, "figures", "--list"], capture_output=True, text=True)
    listed = [l.split()[0] for l in r.stdout.splitlines() if l.strip()]
    if r.returncode != 0 or len(listed) != 20 or listed[0] != "1.4a" or listed[-1] != "1.37":
        fail(f"isoforge figures --list: {r.stdout}")
    have_browser = shutil.which("node") and os.access("/usr/bin/chromium", os.X_OK)
    cmd = [isoforge, "-q", "figures", "--out", out, "--data", data, "--only", *FIGS]
    if not have_browser:
        cmd.append("--no-render")
    r = subprocess.run(cmd, capture_output=True, text=True)
    print(r.stdout, r.stderr)
    if r.returncode != 0:
        fail(f"isoforge figures exited with {r.returncode}")
    lines = {l.split()[0]: l for l in r.stdout.splitlines() if l and l.split()[0] in FIGS}
    for fig in FIGS:
        if fig not in lines:
            fail(f"no summary line for {fig}")
        elif not re.search(r"\s+ok\s+", lines[fig]):
            fail(f"summary line of {fig} does not say ok: {lines[fig]}")
    # Exact counts, computed here from the chapter's formulas.
    want = {"1.24a": f"{ellipse_pixels()} of 1200 pixels selected",
            "1.24b": f"{ellipsoid_voxels()} of 8000 voxels, {6 * ellipsoid_voxels()} faces",
            "1.23a": "1681 samples, 3 lines", "1.31": "polygons",
            "1.4c": "216 ellipsoids"}
    for fig, text in want.items():
        if fig in lines and text not in lines[fig]:
            fail(f"summary line of {fig} lacks '{text}': {lines[fig]}")
    files = {"fig_1_4c": ["point_load.vti", "ellipsoids.vtp"],
             "fig_1_23a": ["sampled_plane.vti", "contour_lines.vtp"],
             "fig_1_24a": ["image.vti", "selected_pixels.vtu", "ellipse.vtp"],
             "fig_1_24b": ["selected_voxels.vtu", "shrunk_voxels.vtu"],
             "fig_1_31": ["cut_plane.vtp", "grid_k9.vts"]}
    index = open(os.path.join(out, "index.html")).read() if os.path.exists(os.path.join(out, "index.html")) else ""
    if not index:
        fail("no index.html")
    if not os.path.exists(os.path.join(out, "viewer", "index.html")):
        fail("the viewer was not copied beside the figures")
    for stem, names in files.items():
        glb = os.path.join(out, stem, stem + ".glb")
        if not os.path.exists(glb) or open(glb, "rb").read(4) != b"glTF":
            fail(f"{glb}: missing or not a binary glTF")
        for n in names:
            p = os.path.join(out, stem, n)
            if not os.path.exists(p) or b"<VTKFile" not in open(p, "rb").read(200):
                fail(f"{p}: missing or not VTK XML")
        if f'id="{stem}"' not in index or f"{stem}/{stem}.glb" not in index:
            fail(f"index.html does not show {stem}")
    if not have_browser:
        print("SKIP: the picture checks need node and /usr/bin/chromium (make deps)")
        return 77 if not failures else 1
    for stem in files:
        png = os.path.join(out, stem, stem + ".png")
        if not os.path.exists(png):
            fail(f"{png}: no picture")
            continue
        if f'src="{stem}/{stem}.png"' not in index:
            fail(f"index.html does not show {png}")
        w, h, rows = read_png(png)
        if (w, h) != (800, 600):
            fail(f"{png}: {w} x {h}, expected 800 x 600")
            continue
        colors = {px for row in rows[::4] for px in row[::4]}
        mid = [px for row in rows[150:450] for px in row[200:600]]
        drawn = sum(1 for px in mid if sum(abs(px[k] - BACKGROUND[k]) for k in range(3)) > 24)
        print(f"{stem}: {len(colors)} colours, {100 * drawn / len(mid):.1f}% of the middle drawn")
        if len(colors) < 8:
            fail(f"{png}: {len(colors)} colours: blank")
        if drawn < 0.05 * len(mid):
            fail(f"{png}: the middle is background ({drawn} of {len(mid)} pixels drawn)")
        if stem in REFERENCES:
            small = reduce(w, h, rows, SMALL)
            ref = os.path.join(HERE, "reference", stem + ".png")
            if regenerate:
                os.makedirs(os.path.dirname(ref), exist_ok=True)
                write_png(ref, *SMALL, small)
                print(f"wrote {ref}")
                continue
            if not os.path.exists(ref):
                fail(f"{ref}: no reference (regenerate: see docs/figures.md)")
                continue
            rw, rh, rrows = read_png(ref)
            diff = sum(abs(a[k] - b[k]) for ra, rb in zip(small, rrows) for a, b in zip(ra, rb)
                       for k in range(3)) / (SMALL[0] * SMALL[1] * 3)
            print(f"{stem}: mean difference from the reference {diff:.2f} (tolerance {TOLERANCE})")
            if (rw, rh) != SMALL or diff > TOLERANCE:
                fail(f"{png}: differs from {ref} by {diff:.2f} on average (tolerance {TOLERANCE})")
    # Every .glb through the Khronos glTF validator (npm gltf-validator).
    glbs = [os.path.join(out, stem, stem + ".glb") for stem in files]
    r = subprocess.run(["node", os.path.join(HERE, "..", "..", "viewer", "test", "validate.mjs"), *glbs],
                       capture_output=True, text=True)
    if r.returncode != 0 or r.stdout.count(": 0 errors") != len(glbs):
        fail(f"glTF validator: {r.stdout} {r.stderr}")
    # The gallery through `isoforge view DIR` in the browser: pictures load, viewer links open.
    if not regenerate:
        script = os.path.join(HERE, "..", "..", "viewer", "test", "gallery_test.mjs")
        r = subprocess.run(["node", script, isoforge, out], capture_output=True, text=True)
        print(r.stdout, r.stderr)
        if r.returncode != 0 or f"gallery test passed: {len(FIGS)} pictures, {len(FIGS)} viewer links opened" not in r.stdout:
            fail("the gallery in the browser (viewer/test/gallery_test.mjs)")
    if failures:
        print(f"{len(failures)} check(s) failed")
        return 1
    print("figures test passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
