#!/usr/bin/env python3
"""The light each exemplar of a folder was drawn under (paint_exemplar.py), replayed from its
name: one `NAME x y z` line each, the unit direction towards the light (x right, y up, z
towards the viewer), to judge the light `brdfpaint fit --lit-sphere` estimates.

    python3 tools/mypaint/exemplar_lights.py OUT
"""

import os
import sys
import zlib

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from paint_exemplar import scene  # noqa: E402


def main():
    folder = sys.argv[1]
    for name in sorted(os.listdir(folder)):
        if not name.endswith(".jpg"):
            continue
        preset, layout, style, seed = name[:-4].split("-")
        key = f"{preset}-{layout}-{style}".encode()
        rng = np.random.default_rng([int(seed[1:]), zlib.crc32(key)])
        light = scene(rng, layout, style)[3]
        print(f"{name} {light[0]:.4f} {light[1]:.4f} {light[2]:.4f}")


if __name__ == "__main__":
    main()
