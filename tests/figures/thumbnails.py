#!/usr/bin/env python3
"""The gallery's small pictures for the documentation: docs/figures/STEM.png, 400 x 300 (each
figure's 800 x 600 picture averaged over 2 x 2 pixels), from a directory `isoforge figures`
wrote. Usage: thumbnails.py FIGURES_DIR DEST_DIR [STEM...] (default: the four of docs/figures.md)
"""
import os
import sys

from check_figures import read_png, reduce, write_png

STEMS = ["fig_1_4a", "fig_1_4c", "fig_1_25", "fig_1_31", "fig_1_32", "fig_1_37"]


def main():
    src, dest, *stems = sys.argv[1:]
    os.makedirs(dest, exist_ok=True)
    for stem in stems or STEMS:
        w, h, rows = read_png(os.path.join(src, stem, stem + ".png"))
        out = os.path.join(dest, stem + ".png")
        write_png(out, 400, 300, reduce(w, h, rows, (400, 300)))
        print(f"wrote {out} ({os.path.getsize(out)} bytes)")


if __name__ == "__main__":
    main()
