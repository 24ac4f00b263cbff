#!/usr/bin/python3
"""Paint a clean truth of the sphere stroke by stroke with a real MyPaint brush preset.

A painter's procedure, not a filter: look at the truth, pick a colour under the brush
(an eyedropper on the truth, blurred to the brush's size), lay a stroke along the
shading's level lines (or round the sphere's form where the shading is flat), repeat
where the canvas is still furthest from the truth, with smaller brushes each pass. The
texture is MyPaint's own: its dabs, grain, smudging and colour jitter; and the paper's,
a scanned sheet from mypaint-data-extras that shows through dry media and under paint.

    /usr/bin/python3 paint_sphere.py TRUTH.png OUT.png --preset charcoal --seed 1 [--faults [strays,tones,noise]]

TRUTH.png: 16-bit sRGB with alpha = the sphere (`cargo run --example truth_dump`).
--faults adds what real paintings get wrong, beyond a light a few degrees off (paint the
`-off` truth for that): strokes across the outline in wrong colours, a palette of a few
premixed tones (flat tones), and scanner noise; all three unless some are named.
Output: 8-bit sRGB RGBA; alpha 0 where nothing was painted (outside the sphere and its
stray paint). Same arguments, same file.
"""

import argparse
import colorsys
import os
import zlib

import numpy as np
import png

from engine import Brush, Canvas

BRUSHES = "/usr/share/mypaint-data/2.0/brushes"
PAPERS = "/usr/share/mypaint/backgrounds"

# Per preset: the brush; the paper and how it shows (`tooth`: dry pigment misses the
# paper's valleys, by `tooth` per standard deviation of its relief; `ground`: the paper is
# on the canvas under wet paint, which smudges into it); brush radius per pass (in sphere
# radii R) and strokes per pass (as coverage of what is still off); stroke length range
# (R); pressure range; how far a stroke's direction strays from the level line (radians);
# how much of the paper's relief shows through paint.
PRESETS = {
    "charcoal": dict(myb="tanda/charcoal-03", paper="ramon/HR_RoughPaper.png", ground="tooth", tooth=0.35,
                     radii=(0.07, 0.045, 0.03), cover=(3.0, 2.5, 2.0), length=(0.4, 0.9),
                     pressure=(0.5, 0.95), wander=0.25, relief=0.6),
    "pencil": dict(myb="deevad/2B_pencil", paper="mrmamurk/mamurk_e_2.png", ground="tooth", tooth=0.25,
                   radii=(0.03, 0.022, 0.016), cover=(5.0, 4.0, 3.0), length=(0.25, 0.6),
                   pressure=(0.6, 1.0), wander=0.4, relief=0.5),
    "oil": dict(myb="tanda/oil-03-paint", paper="ramon/HR_Canvas 01.png", ground="ground",
                radii=(0.12, 0.07, 0.045), cover=(2.0, 1.5, 1.2), length=(0.3, 0.7),
                pressure=(0.5, 0.9), wander=0.2, relief=0.35),
    "acrylic": dict(myb="tanda/acrylic-04-paint", paper="ramon/HR_Canvas 02.png", ground="ground",
                    radii=(0.09, 0.055, 0.035), cover=(2.0, 1.5, 1.2), length=(0.3, 0.8),
                    pressure=(0.5, 0.9), wander=0.15, relief=0.3),
    "watercolour": dict(myb="deevad/watercolor_glazing", paper="ramon/HR_WaterColor.png", ground="ground",
                        radii=(0.12, 0.07, 0.045), cover=(3.0, 2.5, 2.0), length=(0.4, 0.9),
                        pressure=(0.4, 0.8), wander=0.2, relief=0.5),
}

# The faults of --faults, as strong as the faults study's (src/study/faults.rs), made
# differently: stray strokes across the outline (their half-width and length ranges, in
# sphere radii), tones in the palette (its display levels), noise (sRGB standard deviation).
STRAYS, STRAY_WIDTH, STRAY_LENGTH, TONES, NOISE = 8, (0.02, 0.06), (0.2, 0.6), 6, 0.01
# Until the mean difference from the truth (sRGB) is below SATISFIED, up to EXTRA_PASSES more
# passes with the smallest brush.
SATISFIED, EXTRA_PASSES = 0.03, 4
# The last touches' coverage (of the area still off).
DETAILS = 0.5
# How strongly a painter corrects a mix by what the canvas shows (0: the truth's colour).
CORRECT = 0.5
# A hand's speed across the sphere, radii per second (MyPaint's speed inputs are px/s).
SPEED = 6.0


def read_png(path):
    """H x W x C floats in [0, 1], whatever the bit depth."""
    w, h, rows, info = png.Reader(filename=path).asDirect()
    a = np.array(list(rows), np.float64).reshape(h, w, info["planes"])
    return a / (2 ** info["bitdepth"] - 1)


def box(a, r, axis):
    """Box filter of radius r along an axis, edges clamped."""
    pad = [(0, 0)] * a.ndim
    pad[axis] = (r + 1, r)
    c = np.cumsum(np.pad(a, pad, mode="edge"), axis=axis)
    n = a.shape[axis]
    hi = np.take(c, np.arange(2 * r + 1, 2 * r + 1 + n), axis=axis)
    lo = np.take(c, np.arange(0, n), axis=axis)
    return (hi - lo) / (2 * r + 1)


def blur(a, sigma, mask=None):
    """About a Gaussian of `sigma` (three box passes); within `mask` when given."""
    r = max(1, int(round(np.sqrt(4 * sigma * sigma + 1) / 2)))

    def go(x):
        for axis in (0, 1):
            for _ in range(3):
                x = box(x, r, axis)
        return x

    if mask is None:
        return go(a)
    m = mask.astype(np.float64).reshape(mask.shape + (1,) * (a.ndim - 2))
    return go(a * m) / np.maximum(go(m + 0 * a), 1e-9)


class Painter:
    """A painter at work on one canvas: the truth it copies (sRGB) and its mask, a preset,
    its random numbers and which faults it makes."""

    def __init__(self, truth, mask, preset, rng, faults):
        self.t, self.mask, self.p, self.rng, self.faults = truth, mask, preset, rng, faults
        self.h, self.w = mask.shape
        ys, xs = np.nonzero(mask)
        self.centre = np.array([xs.mean(), ys.mean()])
        self.R = np.sqrt(mask.sum() / np.pi)
        self.paper = self._paper()
        self.relief = self.paper.mean(2, keepdims=True) / self.paper.mean()
        self.brush = Brush(open(os.path.join(BRUSHES, preset["myb"] + ".myb")).read())
        ground = np.zeros((self.h, self.w, 4))
        if preset["ground"] == "ground":
            ground[..., :3], ground[..., 3] = self.paper, 1.0
        self.canvas = Canvas(ground)
        self.footprint = np.zeros(mask.shape, bool)
        # The level lines of the shading the painter sees (luminance, blurred a little).
        lum = blur(truth @ np.array([0.2126, 0.7152, 0.0722]), 0.03 * self.R, mask)
        gy, gx = np.gradient(lum)
        self.level = np.stack([-gy, gx], -1)
        g = np.hypot(gx, gy)
        self.g0 = np.percentile(g[mask], 30) + 1e-6
        # A limited palette: TONES mixes, one per band of the truth's luminance, each the
        # truth's mean colour in its band (bands evenly spaced, so highlights get theirs).
        t = truth[mask]
        y = t @ np.array([0.2126, 0.7152, 0.0722])
        band = np.minimum((TONES * (y - y.min()) / max(y.max() - y.min(), 1e-9)).astype(int), TONES - 1)
        self.palette = np.array([t[band == k].mean(0) for k in range(TONES) if (band == k).any()])

    def _paper(self):
        """A crop of the scanned paper at a seeded offset (tiled if smaller)."""
        sheet = read_png(os.path.join(PAPERS, self.p["paper"]))[..., :3]
        reps = (-(-self.h // sheet.shape[0]) + 1, -(-self.w // sheet.shape[1]) + 1, 1)
        sheet = np.tile(sheet, reps)
        y, x = self.rng.integers(0, sheet.shape[0] - self.h), self.rng.integers(0, sheet.shape[1] - self.w)
        return sheet[y:y + self.h, x:x + self.w]

    def picture(self):
        """What the canvas looks like: paint over the paper, the paper's relief through it."""
        c = self.canvas.pixels()
        if self.p["ground"] == "tooth":
            # Dry pigment catches on the paper's peaks: cover falls in its valleys.
            z = (self.relief - 1.0) / max(self.relief.std(), 1e-6)
            a = c[..., 3:4] * np.clip(1.0 + self.p["tooth"] * z, 0.0, 1.0)
            rgb = c[..., :3] / np.maximum(c[..., 3:4], 1e-9)
            out = a * rgb + (1 - a) * self.paper
        else:
            out = c[..., :3]
        return np.clip(out * (1.0 + self.p["relief"] * (self.relief - 1.0)), 0, 1)

    def direction(self, q, previous):
        """The stroke's way at q: along the level line where the shading changes, round the
        sphere's form where it is flat; kept pointing the way it went."""
        i, j = int(np.clip(q[1], 0, self.h - 1)), int(np.clip(q[0], 0, self.w - 1))
        d = self.level[i, j]
        g = np.hypot(*d)
        r = q - self.centre
        form = np.array([-r[1], r[0]]) / max(np.hypot(*r), 1e-6)
        wgt = g * g / (g * g + self.g0 * self.g0)
        d = wgt * d / max(g, 1e-12) + (1 - wgt) * form
        d /= max(np.hypot(*d), 1e-12)
        if previous is not None and d @ previous < 0:
            d = -d
        return d

    def trace(self, seed, length, step, turn):
        """A path through seed, each way along the field for half the length, turned by a
        constant angle (a hand's bias), ending at the outline."""
        c, s = np.cos(turn), np.sin(turn)
        rot = np.array([[c, -s], [s, c]])
        halves = []
        for sign in (1, -1):
            q, prev, pts = seed.copy(), None, []
            for _ in range(int(length / 2 / step)):
                d = rot @ self.direction(q, prev)
                d = d if prev is not None else sign * d
                q = q + step * d
                i, j = int(q[1]), int(q[0])
                if not (0 <= i < self.h and 0 <= j < self.w and self.mask[i, j]):
                    break
                pts.append(q.copy())
                prev = d
            halves.append(pts)
        return halves[1][::-1] + [seed] + halves[0]

    def colour(self, q, radius, seen):
        """The eyedropper: the truth averaged under the brush, mixed darker or lighter by
        how far the canvas (`seen`) is off there, as a painter corrects a mix; with --faults
        the nearest of the palette's few tones instead."""
        i, j = int(q[1]), int(q[0])
        r = max(1, int(radius))
        win = (slice(max(0, i - r), i + r + 1), slice(max(0, j - r), j + r + 1))
        m = self.mask[win]
        if not m.any():
            m = np.zeros_like(m)
            m[min(r, i), min(r, j)] = True
        c = self.t[win][m].mean(0)
        c = np.clip(c + CORRECT * (c - seen[win][m].mean(0)), 0, 1)
        if "tones" in self.faults:
            c = self.palette[np.argmin(((self.palette - c) ** 2).sum(1))]
        return c

    def stroke(self, pts, colour, radius, pressure, stray=False):
        """One stroke through pts: pen down, pressure swelling and easing off, pen up.
        A stray's paint outside the sphere is kept (the rest is masked off at the end)."""
        self.brush.set("radius_logarithmic", np.log(radius))
        h, s, v = colorsys.rgb_to_hsv(*np.clip(colour, 0, 1))
        for name, x in (("color_h", h), ("color_s", s), ("color_v", v)):
            self.brush.set(name, x)
        n = len(pts)
        step = np.hypot(*(pts[-1] - pts[0])) / max(n - 1, 1) if n > 1 else 1.0
        dt = max(step, 0.5) / (SPEED * self.R)
        events = [(pts[0][0], pts[0][1], 0.0, 0.5)]
        for k, q in enumerate(pts):
            t = k / max(n - 1, 1)
            events.append((q[0], q[1], pressure * np.sin(np.pi * (0.1 + 0.8 * t)) ** 0.5, dt))
        events.append((pts[-1][0], pts[-1][1], 0.0, dt))
        self.brush.stroke(self.canvas, events)
        for q in pts if stray else []:
            i, j, r = int(q[1]), int(q[0]), int(radius) + 1
            self.footprint[max(0, i - r):i + r + 1, max(0, j - r):j + r + 1] = True

    def error(self):
        """How far the canvas is from the truth, per pixel (sRGB, mean over channels)."""
        return np.abs(self.picture() - self.t).mean(2)

    def paint_pass(self, radius_r, cover, focus=1, lengths=None):
        """Strokes of one brush size where the canvas is off, more where it is further
        off (error to the power `focus`: 2 for the last touches on highlights and edges),
        of the preset's lengths unless given (in radii)."""
        p, R = self.p, self.R
        radius = radius_r * R
        lengths = lengths or p["length"]
        seen = self.picture()
        err = blur(np.abs(seen - self.t).mean(2), radius, self.mask)
        weight = np.where(self.mask, (err + 0.01) ** focus, 0.0)
        todo = np.minimum(1.0, err / 0.04)[self.mask].sum()
        mean_len = 0.5 * (lengths[0] + lengths[1]) * R
        count = int(cover * todo / (2 * radius * mean_len)) + 1
        flat = weight.ravel() / weight.sum()
        for k in self.rng.choice(flat.size, size=count, p=flat):
            seed = np.array([k % self.w + self.rng.random(), k // self.w + self.rng.random()])
            length = self.rng.uniform(*lengths) * R
            pts = self.trace(seed, length, max(1.0, radius / 2), self.rng.normal(0, p["wander"]))
            self.stroke(np.array(pts), self.colour(seed, radius, seen), radius, self.rng.uniform(*p["pressure"]))

    def strays(self):
        """Careless strokes across the outline: white, black and any colour in turn."""
        edge = self.mask & ~(np.roll(self.mask, 1, 0) & np.roll(self.mask, -1, 0) & np.roll(self.mask, 1, 1) & np.roll(self.mask, -1, 1))
        ys, xs = np.nonzero(edge)
        for n in range(STRAYS):
            k = self.rng.integers(len(xs))
            start = np.array([xs[k], ys[k]], float)
            a = self.rng.uniform(0, 2 * np.pi)
            d, bend = np.array([np.cos(a), np.sin(a)]), self.rng.uniform(-0.2, 0.2)
            length = self.rng.uniform(*STRAY_LENGTH) * self.R
            t = np.linspace(-0.5, 0.5, max(3, int(length)))[:, None]
            pts = start + length * t * d + length * bend * (0.25 - t * t) * np.array([-d[1], d[0]])
            colour = [np.full(3, 0.95), np.zeros(3), self.rng.random(3) ** 2][n % 3]
            self.stroke(pts, colour, self.rng.uniform(*STRAY_WIDTH) * self.R, 0.9, stray=True)


def paint(painter):
    """The painter's passes: each preset brush size in turn, more with the smallest while
    the canvas is visibly off, then the last touches."""
    p = painter.p
    for radius, cover in zip(p["radii"], p["cover"]):
        painter.paint_pass(radius, cover)
    # The painter goes on with the smallest brush while the canvas is visibly off.
    for _ in range(EXTRA_PASSES):
        if painter.error()[painter.mask].mean() < SATISFIED:
            break
        painter.paint_pass(p["radii"][-1], p["cover"][-1])
    # Last touches with a brush half the size, short dabs: highlights, accents.
    small = p["radii"][-1] / 2
    painter.paint_pass(small, DETAILS, focus=2, lengths=(small, 4 * small))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("truth")
    ap.add_argument("out")
    ap.add_argument("--preset", choices=sorted(PRESETS), required=True)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--faults", nargs="?", const="strays,tones,noise", default="",
                    type=lambda s: set(s.split(",")) - {""}, help="some of strays,tones,noise (default: all)")
    ap.add_argument("--shrink", type=int, default=1, help="box-filter the result by this factor (a coarser scan)")
    ap.add_argument("--bare", action="store_true", help="black, not paper, where alpha is 0 (smaller files)")
    a = ap.parse_args()
    rgba = read_png(a.truth)
    truth, mask = rgba[..., :3], rgba[..., 3] > 0.5
    rng = np.random.default_rng([a.seed, zlib.crc32(a.preset.encode()), int(bool(a.faults))])
    p = PRESETS[a.preset]
    painter = Painter(truth, mask, p, rng, a.faults)
    paint(painter)
    if "strays" in a.faults:
        painter.strays()
    out = painter.picture()
    if "noise" in a.faults:
        out = np.clip(out + NOISE * rng.standard_normal(out.shape), 0, 1)
    # The sphere, as if masked while painting, and the strays' paint beyond it; paper elsewhere.
    keep = mask | painter.footprint
    out = np.where(keep[..., None], out, 0.0 if a.bare else painter.paper)
    alpha = keep.astype(np.float64)
    if a.shrink > 1:
        f = a.shrink
        h, w = (out.shape[0] // f) * f, (out.shape[1] // f) * f
        out = out[:h, :w].reshape(h // f, f, w // f, f, 3).mean((1, 3))
        alpha = alpha[:h, :w].reshape(h // f, f, w // f, f).max((1, 3))
    rgba = np.concatenate([out, alpha[..., None]], 2)
    rows = np.round(rgba * 255).astype(np.uint8).reshape(rgba.shape[0], -1)
    png.from_array(rows, "RGBA").save(a.out)


if __name__ == "__main__":
    main()
