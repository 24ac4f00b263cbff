"""The floor of a faulted photograph-like set: what a perfect material would score on it.

`render_photos.py --faults` writes NAME-faults with a real capture's calibration errors; the
same command without `--faults` (same size, same seed) writes NAME, the truth's own
photographs under the lights as written. This script judges NAME's photographs, as a
prediction, against NAME-faults' on the lights `brdfpaint::study::photos` holds out, over
the pixels that study reads (on the mask eroded by one pixel, lit by the light as written
through the normal map, no channel clipped in either, largest channel above 0.2% of
white): the error a fit would score if it found the material exactly
and the normal map were right. The calibration errors of the held-out lights themselves
(each 1 degree and 2% per channel off, the glare) are in it: no fit of the other lights can
remove them.

    python tools/mitsuba/photo_floor.py ROOT NAME...    # ROOT holds NAME and NAME-faults
"""

import json
import sys

import numpy as np
import png  # pypng: Pillow reads 16-bit RGB PNGs as 8-bit
from scipy.ndimage import binary_erosion

# brdfpaint::study::photos::FIT_LIGHTS: fitted on these, judged on the other nine.
FIT_LIGHTS = (0, 4, 8)
# brdfpaint::sample::photo::NEAR_BLACK, of a PNG's white (its largest code).
NEAR_BLACK = 0.002
WHITE = 65535


def read(path):
    """A PNG's codes as floats, (height, width, channels), at the file's own depth."""
    width, height, rows, info = png.Reader(filename=path).asDirect()
    return np.vstack([np.asarray(r, dtype=float) for r in rows]).reshape(height, width, info["planes"])


def floor(clean, faulted):
    """The median relative RMS of `clean` as a prediction of `faulted` over the held-out
    lights; the same without the clean photographs' own noise, and its worst light."""
    mask = read(f"{faulted}/mask.png")[..., 0] > 0
    mask = binary_erosion(mask, structure=np.ones((3, 3)))
    i_clean = np.loadtxt(f"{clean}/light_intensities.txt")
    i_faulted = np.loadtxt(f"{faulted}/light_intensities.txt")
    names = open(f"{faulted}/filenames.txt").read().split()
    lights = np.loadtxt(f"{faulted}/light_directions.txt")
    normals = read(f"{faulted}/normal.png") / WHITE * 2.0 - 1.0
    errors = []
    for k, name in enumerate(names):
        if k in FIT_LIGHTS:
            continue
        truth = read(f"{faulted}/{name}")
        predicted = read(f"{clean}/{name}")
        lit = normals @ lights[k] > 0.0
        # A pixel clipped in the clean photograph predicts nothing: left out too.
        unclipped = np.maximum(truth, predicted).max(-1) < WHITE
        usable = mask & lit & unclipped & (truth.max(-1) > NEAR_BLACK * WHITE)
        predicted = predicted[usable] / i_clean[k]
        truth = truth[usable] / i_faulted[k]
        errors.append(np.sqrt(((predicted - truth) ** 2).sum() / (truth**2).sum()))
    # The clean photographs carry their own photon noise (set.json's relative RMS over the
    # pixels a fit reads), independent of the faulted ones': taken out in quadrature.
    noise = json.load(open(f"{clean}/set.json"))["noise_relative_rms"]
    exact = [np.sqrt(max(e * e - noise * noise, 0.0)) for e in errors]
    return float(np.median(errors)), float(np.median(exact)), max(exact)


def main():
    if len(sys.argv) < 3:
        sys.exit("usage: photo_floor.py ROOT NAME...")
    root = sys.argv[1]
    print(f"{'set':<28} {'as photographed':>15} {'floor':>7} {'worst':>7}")
    for name in sys.argv[2:]:
        raw, exact, worst = floor(f"{root}/{name}", f"{root}/{name}-faults")
        print(f"{name + '-faults':<28} {raw:15.4f} {exact:7.4f} {worst:7.4f}")


if __name__ == "__main__":
    main()
