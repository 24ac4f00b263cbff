#!/usr/bin/env python3
"""A MatCap library made by another renderer (issue 36, item 4): spheres of Mitsuba
materials lit by HDR environments, the way MatCap libraries are made, to judge where
`fit --lit-sphere` puts their lights (do they pile up at one z?).

Each MatCap is a unit sphere seen by an orthographic camera from +z, filling a square
picture, lit only by an environment (no key light) turned by a random yaw and pitch, on
a flat grey,
rendered with Mitsuba's path tracer and written as an 8-bit sRGB PNG with its brightest
percent at 90% white. OUT/matcaps.json records material, environment and rotation.

`--hdri sky` lights them instead by a uniform sky over a dark ground (1 above the horizon,
0.02 below), written as OUT/env/sky.exr: the truth a diffuse sphere's light should be read as is
then the sky's up, turned by the pitch.

Usage (DRJIT_LIBLLVM_PATH pointing at libLLVM 19, see README.md):
    python render_matcaps.py --hdri ../shared/data/hdri|sky --out DIR [--per-env 10] [--seed 1]
"""

import argparse
import json
from pathlib import Path

import numpy as np
import mitsuba as mi

mi.set_variant("llvm_ad_rgb")


def rgb(r, g, b):
    return {"type": "rgb", "value": [r, g, b]}


MATERIALS = [
    ("clay", {"type": "diffuse", "reflectance": rgb(0.6, 0.45, 0.35)}),
    ("plastic-red", {"type": "roughplastic", "distribution": "ggx", "alpha": 0.1, "diffuse_reflectance": rgb(0.6, 0.08, 0.05)}),
    ("plastic-blue", {"type": "roughplastic", "distribution": "beckmann", "alpha": 0.3, "diffuse_reflectance": rgb(0.1, 0.2, 0.6)}),
    ("gold", {"type": "roughconductor", "material": "Au", "distribution": "ggx", "alpha": 0.2}),
    ("aluminium", {"type": "roughconductor", "material": "Al", "distribution": "ggx", "alpha": 0.35}),
    ("copper", {"type": "roughconductor", "material": "Cu", "distribution": "beckmann", "alpha": 0.12}),
    ("sheen", {"type": "principled", "base_color": rgb(0.45, 0.12, 0.3), "roughness": 0.8, "sheen": 1.0}),
    ("clearcoat", {"type": "principled", "base_color": rgb(0.15, 0.3, 0.6), "roughness": 0.6, "clearcoat": 1.0, "clearcoat_gloss": 0.9}),
    ("jade", {"type": "roughplastic", "distribution": "ggx", "alpha": 0.05, "diffuse_reflectance": rgb(0.2, 0.55, 0.3)}),
    ("chalk", {"type": "diffuse", "reflectance": rgb(0.85, 0.85, 0.8)}),
]


def render(bsdf, env, yaw, pitch, size, spp):
    rotate = mi.ScalarTransform4f().rotate([0, 1, 0], yaw) @ mi.ScalarTransform4f().rotate([1, 0, 0], pitch)
    scene = mi.load_dict({
        "type": "scene",
        "integrator": {"type": "path", "max_depth": 3},
        "sensor": {
            "type": "orthographic",
            "to_world": mi.ScalarTransform4f().look_at(origin=[0, 0, 5], target=[0, 0, 0], up=[0, 1, 0]),
            "film": {"type": "hdrfilm", "width": size, "height": size, "rfilter": {"type": "box"}},
            "sampler": {"type": "independent", "sample_count": spp},
        },
        "sphere": {"type": "sphere", "radius": 1.0, "bsdf": bsdf},
        "env": {"type": "envmap", "filename": str(env), "to_world": rotate},
    })
    return np.array(mi.render(scene))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--hdri", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--per-env", type=int, default=10)
    ap.add_argument("--size", type=int, default=192)
    ap.add_argument("--spp", type=int, default=256)
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args()
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(a.seed)
    if a.hdri == "sky":
        sky = np.full((128, 256, 3), 0.02, dtype=np.float32)
        sky[:64] = 1.0
        (out / "env").mkdir(exist_ok=True)
        mi.Bitmap(sky).write(str(out / "env" / "sky.exr"))
        envs = [out / "env" / "sky.exr"]
    else:
        envs = sorted(Path(a.hdri).glob("*.exr"))
    record = []
    for env in envs:
        for k in range(a.per_env):
            name, bsdf = MATERIALS[len(record) % len(MATERIALS)]
            yaw, pitch = float(rng.uniform(0, 360)), float(rng.uniform(-30, 30))
            img = render(bsdf, env, yaw, pitch, a.size, a.spp)
            c = np.clip(img[..., :3], 0, None)
            # Outside the sphere a flat grey, as MatCap corners are (the camera sees the sky there).
            x = (np.arange(a.size) + 0.5) / a.size * 2 - 1
            outside = (x[None, :] ** 2 + x[:, None] ** 2) > 1
            c = c / max(np.percentile(c[~outside], 99), 1e-6) * 0.9
            c[outside] = 0.05
            srgb = np.where(c <= 0.0031308, 12.92 * c, 1.055 * np.power(np.clip(c, 0, 1), 1 / 2.4) - 0.055)
            file = f"{env.stem}-{k:02d}-{name}.png"
            mi.util.write_bitmap(str(out / file), (np.clip(srgb, 0, 1) * 255 + 0.5).astype(np.uint8), write_async=False)
            record.append({"file": file, "material": name, "environment": env.name, "yaw": yaw, "pitch": pitch})
            print(file, flush=True)
    (out / "matcaps.json").write_text(json.dumps({"renderer": f"mitsuba {mi.__version__}", "matcaps": record}, indent=1))


if __name__ == "__main__":
    main()
