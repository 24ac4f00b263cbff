#!/usr/bin/python3
"""A contact sheet of paintings: each shrunk by a whole factor to at most --size pixels,
what was painted (alpha above 0) on white, in rows of --cols.

    /usr/bin/python3 contact_sheet.py OUT.png A.png B.png ... [--cols 5] [--size 128]
"""

import argparse

import numpy as np
import png

from paint_sphere import read_png


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("out")
    ap.add_argument("paintings", nargs="+")
    ap.add_argument("--cols", type=int, default=5)
    ap.add_argument("--size", type=int, default=128)
    a = ap.parse_args()
    tiles = []
    for path in a.paintings:
        rgba = read_png(path)
        rgb = np.where(rgba[..., 3:] > 0, rgba[..., :3], 1.0)
        f = max(1, -(-rgb.shape[0] // a.size))
        h, w = rgb.shape[0] // f * f, rgb.shape[1] // f * f
        tiles.append(rgb[:h, :w].reshape(h // f, f, w // f, f, 3).mean((1, 3)))
    th, tw = max(t.shape[0] for t in tiles), max(t.shape[1] for t in tiles)
    rows = -(-len(tiles) // a.cols)
    sheet = np.ones((rows * th, min(a.cols, len(tiles)) * tw, 3))
    for k, t in enumerate(tiles):
        r, c = divmod(k, a.cols)
        sheet[r * th:r * th + t.shape[0], c * tw:c * tw + t.shape[1]] = t
    with open(a.out, "wb") as f:
        png.Writer(sheet.shape[1], sheet.shape[0], greyscale=False, compression=9).write(
            f, np.round(sheet * 255).astype(np.uint8).reshape(sheet.shape[0], -1))


if __name__ == "__main__":
    main()
