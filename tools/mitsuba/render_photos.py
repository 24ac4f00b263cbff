#!/usr/bin/env python3
"""Renders photograph-like sets with Mitsuba 3 (issue 37): objects of materials outside
brdfpaint's lobe families under twelve calibrated directional lights, written in the
layout photometric-stereo data sets use (DiLiGenT's), so that `brdfpaint fit --photos DIR`
reads them as it reads real photographs:

    OUT/NAME/001.png ... 012.png   linear 16-bit RGB (codes = value x 65535), photon noise,
                                   clipped at the white level (highlights saturate a little)
    OUT/NAME/filenames.txt         the images, one a line
    OUT/NAME/light_directions.txt  one `x y z` per image, toward the light, view space
    OUT/NAME/light_intensities.txt one `r g b` per image: the light's irradiance on the
                                   codes' scale (image / intensity = BRDF x cos)
    OUT/NAME/mask.png              8-bit, white on the object
    OUT/NAME/normal.png            16-bit, (n + 1) / 2, black background
    OUT/NAME/set.json              what was rendered, exposure, noise, saturation

View space as DiLiGenT's: x right, y up, z toward the camera. The camera is orthographic,
looking down -z; the object fills `--fill` of the image height.

Each pixel is Mitsuba's own BSDF evaluated at the hit of the ray through the pixel centre
(bsdf.eval includes the cosine), times the light's irradiance, as in render_suite.py: the
objects are convex (no cast shadows, no interreflection). The normal map is the shading
normal Mitsuba used at that hit. Then the sensor: electrons = value / white x FULL_WELL,
Poisson, plus Gaussian read noise; codes = electrons / FULL_WELL x 65535, rounded, clipped.
The PNGs carry no gAMA or sRGB chunk, as DiLiGenT's do not: `fit --photos` reads them as
linear.

With --faults each set (written as NAME-faults) also has what a real capture's calibration
leaves: every light's true direction 1 degree off the one written (a random axis), its
true colour x intensity off the one written by 2% per channel (one standard deviation),
veiling glare of 0.3% of white over the object, and a normal map (and mask) read through
rays 0.4 px right and 0.3 px down of the pixel centres, at 0.5% larger scale (a sphere fit
a little off).

Usage (DRJIT_LIBLLVM_PATH pointing at libLLVM 19, see README.md):
    python render_photos.py --out DIR [--width 64 --height 64] [--only NAME ...] [--seed 37]
"""

import argparse
import json
import shutil
import struct
import zlib
from pathlib import Path

import numpy as np
import drjit as dr
import mitsuba as mi

mi.set_variant("llvm_ad_rgb")

# A pixel at white collects this many electrons; read noise in electrons (a CCD's order).
FULL_WELL = 20000.0
READ_NOISE = 4.0
# The white level: this share of lit object pixels, over all twelve images, is at or above
# it, so the brightest highlights saturate.
SATURATED_SHARE = 0.003

# --faults: light direction error (degrees), relative intensity error per channel (one
# standard deviation), glare (share of white), normal map offset (pixels) and scale.
DIRECTION_ERROR_DEG = 1.0
INTENSITY_ERROR = 0.02
GLARE = 0.003
NORMALS_OFFSET_PX = (0.4, 0.3)
NORMALS_SCALE = 1.005


def rgb(r, g, b):
    return {"type": "rgb", "value": [r, g, b]}


# (name, description, shape, BSDF)
SETS = [
    ("plastic-glossy", "glossy red plastic sphere: roughplastic, GGX alpha 0.08, IOR 1.5, internal scattering",
     "sphere", {"type": "roughplastic", "distribution": "ggx", "alpha": 0.08, "int_ior": 1.5,
                "nonlinear": True, "diffuse_reflectance": rgb(0.55, 0.10, 0.07)}),
    ("matte-gray", "matte gray sphere: principled, roughness 1, specular 0.3 (Disney diffuse: retro-reflection, flat at grazing)",
     "sphere", {"type": "principled", "base_color": rgb(0.45, 0.45, 0.45), "roughness": 1.0, "specular": 0.3}),
    ("gold-rough", "rough gold sphere: roughconductor, measured Au IOR, GGX alpha 0.3",
     "sphere", {"type": "roughconductor", "material": "Au", "distribution": "ggx", "alpha": 0.3}),
    ("principled-clearcoat", "principled, blue base roughness 0.5, clearcoat 1 gloss 0.9",
     "sphere", {"type": "principled", "base_color": rgb(0.12, 0.25, 0.55), "roughness": 0.5,
                "clearcoat": 1.0, "clearcoat_gloss": 0.9}),
    ("ellipsoid-plastic", "glossy green plastic ellipsoid (semi-axes 1, 0.7, 0.55, turned): roughplastic, GGX alpha 0.12",
     "ellipsoid", {"type": "roughplastic", "distribution": "ggx", "alpha": 0.12, "int_ior": 1.5,
                   "nonlinear": True, "diffuse_reflectance": rgb(0.10, 0.40, 0.15)}),
]


def lights():
    """Twelve directions toward the lights, view space: polar angles 20, 40 and 60 degrees in
    turn, 30 degrees apart in azimuth (brdfpaint's study fits 0, 4 and 8: one of each ring),
    and their irradiance, a little coloured as calibrated lamps are."""
    out = []
    for k in range(12):
        polar, azimuth = np.radians([20.0, 40.0, 60.0][k % 3]), np.radians(30.0 * k + 15.0)
        d = np.array([np.sin(polar) * np.cos(azimuth), np.sin(polar) * np.sin(azimuth), np.cos(polar)])
        t = k / 11.0
        out.append((d, np.array([1.0 + 0.15 * np.sin(3 * k), 0.95 + 0.05 * t, 1.05 - 0.15 * t])))
    return out


def ellipsoid_mesh(axes, rotation, segments=384, rings=192):
    """A UV ellipsoid with its exact normals at the vertices."""
    theta = np.linspace(0.0, np.pi, rings + 1)
    phi = np.linspace(0.0, 2.0 * np.pi, segments + 1)
    t, p = np.meshgrid(theta, phi, indexing="ij")
    unit = np.stack([np.sin(t) * np.cos(p), np.cos(t), np.sin(t) * np.sin(p)], axis=-1).reshape(-1, 3)
    pos = unit * axes
    nrm = unit / axes
    nrm /= np.linalg.norm(nrm, axis=1, keepdims=True)
    pos, nrm = pos @ rotation.T, nrm @ rotation.T
    faces = []
    for r in range(rings):
        for s in range(segments):
            a, b = r * (segments + 1) + s, (r + 1) * (segments + 1) + s
            faces += [[a, b, a + 1], [a + 1, b, b + 1]]
    return pos, nrm, np.array(faces, dtype=np.uint32)


def rotation(yaw, pitch):
    cy, sy, cp, sp = np.cos(yaw), np.sin(yaw), np.cos(pitch), np.sin(pitch)
    ry = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
    rx = np.array([[1, 0, 0], [0, cp, -sp], [0, sp, cp]])
    return rx @ ry


def scene_of(shape, bsdf):
    if shape == "sphere":
        return mi.load_dict({"type": "scene", "object": {"type": "sphere", "radius": 1.0, "bsdf": bsdf}})
    pos, nrm, faces = ellipsoid_mesh(np.array([1.0, 0.7, 0.55]), rotation(0.5, 0.35))
    props = mi.Properties()
    props["bsdf"] = mi.load_dict(bsdf)
    mesh = mi.Mesh("ellipsoid", len(pos), len(faces), props=props, has_vertex_normals=True)
    params = mi.traverse(mesh)
    params["vertex_positions"] = mi.Float(pos.astype(np.float32).ravel())
    params["vertex_normals"] = mi.Float(nrm.astype(np.float32).ravel())
    params["faces"] = mi.UInt32(faces.ravel())
    params.update()
    return mi.load_dict({"type": "scene", "object": mesh})


def hits(scene, width, height, fill, offset=(0.0, 0.0), scale=1.0):
    """The surface interactions of orthographic rays down -z through the pixel centres
    (moved by `offset` pixels, right and down, and scaled about the image centre); row 0 at
    the top. The object (radius 1) spans `fill` of the height. Also the hit mask and the
    view-space shading normals (zero where nothing is hit)."""
    half = 1.0 / fill
    j, i = np.meshgrid(np.arange(height), np.arange(width), indexing="ij")
    x = ((2.0 * (i + 0.5 + offset[0]) - width) / height * half / scale).ravel()
    y = ((height - 2.0 * (j + 0.5 + offset[1])) / height * half / scale).ravel()
    n = x.size
    ray = mi.Ray3f(mi.Point3f(mi.Float(x.astype(np.float32)), mi.Float(y.astype(np.float32)), mi.Float(np.full(n, 10.0, np.float32))),
                   mi.Vector3f(0.0, 0.0, -1.0))
    si = scene.ray_intersect(ray)
    hit = np.array(si.is_valid())
    sh = si.sh_frame.n
    normals = np.stack([np.array(sh.x), np.array(sh.y), np.array(sh.z)], axis=-1)
    normals[~hit] = 0.0
    return si, hit, normals


def turned(d, degrees, rng):
    """`d` turned by `degrees` about a random axis perpendicular to it."""
    axis = np.cross(d, rng.normal(size=3))
    axis /= np.linalg.norm(axis)
    a = np.radians(degrees)
    return d * np.cos(a) + np.cross(axis, d) * np.sin(a) + axis * axis.dot(d) * (1.0 - np.cos(a))


def render(shape, bsdf, width, height, fill, faults=None):
    """Per light the clean linear image (H, W, 3), and the view-space normals and hit mask
    the set gives (with `faults`, a random generator: the capture's errors, --faults)."""
    scene = scene_of(shape, bsdf)
    si, hit, normals = hits(scene, width, height, fill)
    truth = [(d, e) for d, e in lights()]
    if faults is not None:
        truth = [(turned(d, DIRECTION_ERROR_DEG, faults), e * (1.0 + INTENSITY_ERROR * faults.normal(size=3))) for d, e in truth]
    images = []
    for d, e in truth:
        wo = si.to_local(mi.Vector3f(*[float(c) for c in d]))
        value = si.bsdf().eval(mi.BSDFContext(), si, wo, si.is_valid())
        img = np.stack([np.array(value.x), np.array(value.y), np.array(value.z)], axis=-1) * e
        img = np.clip(np.nan_to_num(img, nan=0.0), 0.0, None)
        img[~hit] = 0.0
        images.append(img.reshape(height, width, 3))
    if faults is not None:
        # Glare relative to the brightest lit pixel (the white level follows from the images).
        glare = GLARE * max(float(np.quantile(img.reshape(-1, 3)[hit].max(axis=1), 1.0 - SATURATED_SHARE)) for img in images)
        images = [img + np.where(hit.reshape(height, width, 1), glare, 0.0) for img in images]
        _, hit, normals = hits(scene, width, height, fill, NORMALS_OFFSET_PX, NORMALS_SCALE)
    return images, normals.reshape(height, width, 3), hit.reshape(height, width)


def sensor(clean, white, rng):
    """Linear 16-bit codes of `clean` (values; `white` maps to 65535): photon and read noise,
    clipped."""
    electrons = rng.poisson(np.clip(clean / white, 0.0, 4.0) * FULL_WELL).astype(np.float64)
    electrons += rng.normal(0.0, READ_NOISE, clean.shape)
    return np.clip(np.round(electrons / FULL_WELL * 65535.0), 0, 65535).astype(np.uint16)


def write_png(path, pixels):
    """A PNG of uint8 (grey) or uint16 (RGB) pixels, no colour chunks."""
    h, w = pixels.shape[:2]
    channels = 1 if pixels.ndim == 2 else pixels.shape[2]
    depth = 8 if pixels.dtype == np.uint8 else 16
    kind = {1: 0, 3: 2}[channels]
    raw = pixels.astype(">u2" if depth == 16 else np.uint8).reshape(h, -1).tobytes()
    stride = w * channels * depth // 8
    rows = b"".join(b"\x00" + raw[r * stride:(r + 1) * stride] for r in range(h))

    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)

    ihdr = struct.pack(">IIBBBBB", w, h, depth, kind, 0, 0, 0)
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(rows, 9)) + chunk(b"IEND", b""))


def write_set(out, name, description, shape, bsdf, args, seed):
    faults = np.random.default_rng(seed + 1000) if args.faults else None
    images, normals, hit = render(shape, bsdf, args.width, args.height, args.fill, faults)
    ls = lights()
    lit = [img[hit & (np.einsum("hwc,c->hw", normals, d) > 0)].max(axis=1) for img, (d, _) in zip(images, ls)]
    white = float(np.quantile(np.concatenate(lit), 1.0 - SATURATED_SHARE))
    rng = np.random.default_rng(seed)
    folder = out / name
    folder.mkdir(parents=True)
    names, noise_num, noise_den, saturated, object_px = [], 0.0, 0.0, 0, 0
    for k, (img, (d, e)) in enumerate(zip(images, ls)):
        codes = sensor(img, white, rng)
        fname = f"{k + 1:03d}.png"
        write_png(folder / fname, codes)
        names.append(fname)
        # The noise's own relative RMS where a fit reads the image (lit, unclipped, not black).
        front = hit & (np.einsum("hwc,c->hw", normals, d) > 0)
        clean = img / white * 65535.0
        usable = front & (codes.max(axis=2) < 65535) & (codes.max(axis=2) > 0.002 * 65535)
        noise_num += float(((codes[usable] - clean[usable]) ** 2).sum())
        noise_den += float((clean[usable] ** 2).sum())
        saturated += int((front & (codes.max(axis=2) == 65535)).sum())
        object_px += int(front.sum())
    (folder / "filenames.txt").write_text("".join(f"{n}\n" for n in names))
    (folder / "light_directions.txt").write_text("".join(f"{d[0]:.8f} {d[1]:.8f} {d[2]:.8f}\n" for d, _ in ls))
    (folder / "light_intensities.txt").write_text("".join(f"{c[0] / white:.8f} {c[1] / white:.8f} {c[2] / white:.8f}\n" for _, c in ls))
    write_png(folder / "mask.png", np.where(hit, 255, 0).astype(np.uint8))
    codes = np.where(hit[..., None], np.round((normals + 1.0) / 2.0 * 65535.0), 0).astype(np.uint16)
    write_png(folder / "normal.png", codes)
    manifest = {
        "name": name,
        "description": description,
        "shape": shape,
        "bsdf": bsdf,
        "size": [args.width, args.height],
        "fill": args.fill,
        "camera": "orthographic, looking down -z, view space x right y up z toward the camera",
        "encoding": "linear 16-bit PNG: code = value / white x 65535",
        "white": white,
        "full_well_electrons": FULL_WELL,
        "read_noise_electrons": READ_NOISE,
        "seed": seed,
        "faults": None if faults is None else {
            "light_direction_deg": DIRECTION_ERROR_DEG, "intensity_sd": INTENSITY_ERROR, "glare": GLARE,
            "normals_offset_px": NORMALS_OFFSET_PX, "normals_scale": NORMALS_SCALE},
        "saturated_pixels": saturated,
        "lit_object_pixels": object_px,
        "noise_relative_rms": (noise_num / noise_den) ** 0.5,
        "renderer": f"Mitsuba {mi.__version__} ({mi.variant()}), Dr.Jit {dr.__version__}",
        "generator": "tools/mitsuba/render_photos.py",
    }
    (folder / "set.json").write_text(json.dumps(manifest, indent=1) + "\n")
    print(f"{name}: white {white:.4f}, {saturated} of {object_px} lit pixels saturated, noise {manifest['noise_relative_rms']:.4f}")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", required=True, type=Path, help="where the sets go (each NAME/ replaced)")
    ap.add_argument("--width", type=int, default=64)
    ap.add_argument("--height", type=int, default=64)
    ap.add_argument("--fill", type=float, default=0.9, help="share of the image height the object's extent of 2 spans")
    ap.add_argument("--only", nargs="*", help="these sets only")
    ap.add_argument("--seed", type=int, default=37)
    ap.add_argument("--faults", action="store_true", help="a real capture's calibration errors (NAME-faults)")
    args = ap.parse_args()
    for k, (name, description, shape, bsdf) in enumerate(SETS):
        if args.only and name not in args.only:
            continue
        name = f"{name}-faults" if args.faults else name
        if (args.out / name).exists():
            shutil.rmtree(args.out / name)
        write_set(args.out, name, description, shape, bsdf, args, args.seed + k)


if __name__ == "__main__":
    main()
