#!/usr/bin/python3
"""Paint a style exemplar, a sphere sitting on a table, with a real MyPaint brush preset.

The layout example-based stylization tools publish their exemplars in (issue 36, item 1): a
shaded sphere on a table with its cast shadow, a wall behind, the table's edge across the
picture; the sphere in the middle, cut by the picture's edge, or hidden at the bottom by a
box in front. The scene is drawn in closed form (its circle is known), then painted over the
whole picture by `paint_sphere.Painter`, stroke by stroke with MyPaint's brushes on scanned
paper, and saved as JPEG. A second generator beside `examples/disk_pictures.rs`, which the
disk finder was developed on: here the outline is a painter's, smeared by strokes that cross
it, and the grain is real paper's.

    /usr/bin/python3 paint_exemplar.py OUT.jpg --preset oil --seed 1 --layout middle --style lambert

Writes OUT.jpg and OUT.txt ("cx cy r" in pixels, pixel centres at +0.5, as truth.csv of
`disk_pictures` has them). Same arguments, same file.
"""

import argparse
import os
import sys
import zlib

import numpy as np
from PIL import Image

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from paint_sphere import PRESETS, Painter, paint  # noqa: E402

LAYOUTS = ("middle", "edge", "hidden")
STYLES = ("lambert", "toon")


def srgb(x):
    """Linear to the sRGB encoding."""
    x = np.clip(x, 0, 1)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * x ** (1 / 2.4) - 0.055)


def smooth(e0, e1, x):
    t = np.clip((x - e0) / (e1 - e0), 0, 1)
    return t * t * (3 - 2 * t)


def hue(rng, sat, val):
    """A colour of random hue at the given saturation and value (linear)."""
    h = rng.random()
    k = (np.array([5.0, 3.0, 1.0]) + 6 * h) % 6
    c = val * (1 - sat * np.clip(np.minimum(k, 4 - k), 0, 1))
    return c ** 2.2


def scene(rng, layout, style):
    """The truth (sRGB, H x W x 3), its circle (cx, cy, r), the y from which a box in front
    hides the sphere (None outside the hidden layout) and the unit direction towards the
    light (x right, y up, z towards the viewer)."""
    w, h = int(rng.integers(300, 381)), int(rng.integers(240, 301))
    r = rng.uniform(0.24, 0.34) * min(w, h)
    horizon = rng.uniform(0.42, 0.6) * h
    cx = rng.uniform(0.35, 0.65) * w
    cy = rng.uniform(horizon + 0.15 * r, max(0.95 * h, horizon + 0.3 * r)) - r
    hidden = None
    if layout == "edge":
        side = rng.integers(3)
        cx = [r * rng.uniform(0.75, 0.95), w - r * rng.uniform(0.75, 0.95), cx][side]
        cy = h - r * rng.uniform(0.75, 0.95) if side == 2 else cy
    elif layout == "hidden":
        hidden = cy + r * rng.uniform(0.45, 0.75)
    side = rng.choice([-1.0, 1.0])
    light = np.array([side * rng.uniform(0.3, 0.9), rng.uniform(0.3, 0.9), rng.uniform(0.4, 1.0)])
    light /= np.linalg.norm(light)
    y, x = np.mgrid[0:h, 0:w] + 0.5
    # The wall and the table: pale, unsaturated, each with a gradient (the light falls off).
    wall, table = hue(rng, 0.15, 0.85), hue(rng, 0.3, 0.65)
    up = np.clip((horizon - y) / horizon, 0, 1)[..., None]
    front = np.clip((y - horizon) / max(h - horizon, 1), 0, 1)[..., None]
    out = np.where((y < horizon)[..., None], wall * (0.8 + 0.25 * up), table * (1.0 - 0.3 * front))
    # The cast shadow: an ellipse on the table, away from the light, darkest at the contact.
    contact = np.array([cx, cy + r])
    away = -np.sign(light[0]) * r * (0.4 + 0.6 * np.hypot(light[0], light[1]) / max(light[2], 0.3))
    ex, ey = contact[0] + 0.5 * away, contact[1] - 0.05 * r
    d = np.hypot((x - ex) / (1.0 * r + 0.5 * abs(away)), (y - ey) / (0.22 * r))
    shadow = 0.6 * (1 - smooth(0.7, 1.1, d)) * (y > horizon)
    out *= (1 - shadow)[..., None]
    # The sphere.
    nx, ny = (x - cx) / r, -(y - cy) / r
    inside = nx * nx + ny * ny < 1
    nz = np.sqrt(np.clip(1 - nx * nx - ny * ny, 0, 1))
    n = np.stack([nx, ny, nz], -1)
    half = light + np.array([0.0, 0.0, 1.0])
    half /= np.linalg.norm(half)
    ndl, ndh = n @ light, n @ half
    albedo = hue(rng, rng.uniform(0.3, 0.7), rng.uniform(0.55, 0.85))
    if style == "toon":
        lit = np.where(ndl > 0.15, 1.0, 0.35)[..., None]
        spec = (ndh > 0.97).astype(float)[..., None] * 0.9
    else:
        lit = (0.12 + 0.88 * np.clip(ndl, 0, 1))[..., None]
        spec = 0.5 * np.clip(ndh, 0, 1)[..., None] ** 40
    ball = albedo * lit + spec
    out = np.where(inside[..., None], ball, out)
    if hidden is not None:
        box = hue(rng, 0.35, 0.5)
        out = np.where((y > hidden)[..., None], box * (1.0 - 0.2 * np.clip((y - hidden) / r, 0, 1))[..., None], out)
    return srgb(out), (cx, cy, r), hidden, light


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("out")
    ap.add_argument("--preset", choices=sorted(PRESETS), required=True)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--layout", choices=LAYOUTS, default="middle")
    ap.add_argument("--style", choices=STYLES, default="lambert")
    a = ap.parse_args()
    key = f"{a.preset}-{a.layout}-{a.style}".encode()
    rng = np.random.default_rng([a.seed, zlib.crc32(key)])
    truth, (cx, cy, r), hidden, _ = scene(rng, a.layout, a.style)
    p = PRESETS[a.preset]
    mask = np.ones(truth.shape[:2], bool)
    painter = Painter(truth, mask, p, rng, set())
    # Brush sizes and stroke lengths are in sphere radii, as for a sphere painted alone.
    painter.centre, painter.R = np.array([cx, cy]), r
    paint(painter)
    pixels = np.round(painter.picture() * 255).astype(np.uint8)
    quality = 70 + zlib.crc32(key + bytes([a.seed % 256])) % 21
    Image.fromarray(pixels).save(a.out, quality=int(quality))
    with open(os.path.splitext(a.out)[0] + ".txt", "w") as f:
        # The y from which something in front hides the sphere, in the hidden layout.
        front = f" {hidden:.3f}" if hidden is not None else ""
        f.write(f"{cx:.3f} {cy:.3f} {r:.3f}{front}\n")


if __name__ == "__main__":
    main()
