#!/usr/bin/env python3
"""Renders the other-renderer truth suite (issue 37) with Mitsuba 3.

Spheres of materials outside brdfpaint's seven analytic lobe families, each rendered in
the six scenes of `brdfpaint::study::rendered` (three painted views, three held out),
written as half-float linear EXR into OUT/MATERIAL/PRESET.exr, with OUT/suite.json saying
what was rendered and by what. See README.md beside this file.

The scenes come from brdfpaint itself (`cargo run --release --example mitsuba_suite --
scenes DIR`): camera, light and the very sphere mesh the G-buffer rasterizes are read from
those glTF files, so the framing cannot drift between the two renderers.

Each pixel is Mitsuba's own BSDF evaluated at the pixel centre's ray hit, times the
directional light's irradiance: pixel = f(wi, wo) cos(theta_o) E. That is the direct
illumination Mitsuba's `direct` integrator computes for a delta light, without its
shadow ray and without pixel jitter: brdfpaint's convention is one sample at each pixel
centre (DESIGN.md), and a convex sphere has no shadows, while a shadow ray from a flat
facet near the terminator would hit the facet behind it where the smooth normal still
faces the light. The result is deterministic: no sampling noise.

Usage (DRJIT_LIBLLVM_PATH pointing at libLLVM 19, see README.md):
    python render_suite.py --scenes DIR --out tests/data/mitsuba [--size 128]
"""

import argparse
import base64
import json
import os
import shutil
import struct
from pathlib import Path

import numpy as np
import drjit as dr
import mitsuba as mi

mi.set_variant("llvm_ad_rgb")

# The suite's scenes, in the order of brdfpaint::study::rendered::presets(): three painted,
# three held out with the light 38-63 degrees from the camera, four under side, rim and
# grazing light (90, 115, 140, 150 degrees).
PRESETS = ["front-left", "paint-2", "paint-3", "held-1", "held-2", "held-3",
           "side-90", "rim-115", "rim-140", "grazing-150"]

# The convention check: a Lambertian sphere, compared in Rust against brdfpaint's own
# Lambert shading of the same albedo (the analytic suite's Lambert).
CHECK = {"name": "lambert", "albedo": [0.70, 0.45, 0.20]}


def rgb(r, g, b):
    return {"type": "rgb", "value": [r, g, b]}


# Materials whose physics none of the lobe families has: measured complex IOR (coloured,
# angle-dependent Fresnel), internal scattering under a dielectric coat, clearcoat and
# sheen layers, and a blend of a diffuse and a conductor lobe.
MATERIALS = [
    ("gold-ggx-0.2", "rough conductor, measured Au IOR, GGX alpha 0.2",
     {"type": "roughconductor", "material": "Au", "distribution": "ggx", "alpha": 0.2}),
    ("copper-beckmann-0.15", "rough conductor, measured Cu IOR, Beckmann alpha 0.15",
     {"type": "roughconductor", "material": "Cu", "distribution": "beckmann", "alpha": 0.15}),
    ("aluminium-ggx-0.3", "rough conductor, measured Al IOR, GGX alpha 0.3",
     {"type": "roughconductor", "material": "Al", "distribution": "ggx", "alpha": 0.3}),
    ("plastic-red-ggx-0.1", "rough plastic, GGX alpha 0.1, IOR 1.5, internal scattering",
     {"type": "roughplastic", "distribution": "ggx", "alpha": 0.1, "int_ior": 1.5,
      "nonlinear": True, "diffuse_reflectance": rgb(0.6, 0.08, 0.05)}),
    ("plastic-blue-beckmann-0.3", "rough plastic, Beckmann alpha 0.3, IOR 1.5, internal scattering",
     {"type": "roughplastic", "distribution": "beckmann", "alpha": 0.3, "int_ior": 1.5,
      "nonlinear": True, "diffuse_reflectance": rgb(0.1, 0.2, 0.6)}),
    # A smooth coat's mirror highlight is a delta, never seen under a directional light:
    # what shows is the diffuse base seen through the coat's Fresnel, darker at grazing.
    ("plastic-smooth-orange", "smooth plastic (dielectric coat over diffuse), IOR 1.5, internal scattering",
     {"type": "plastic", "int_ior": 1.5, "nonlinear": True, "diffuse_reflectance": rgb(0.8, 0.35, 0.05)}),
    ("principled-clearcoat", "principled, blue base roughness 0.6, clearcoat 1 gloss 0.9",
     {"type": "principled", "base_color": rgb(0.15, 0.3, 0.6), "roughness": 0.6,
      "clearcoat": 1.0, "clearcoat_gloss": 0.9}),
    ("principled-sheen", "principled, plum base roughness 0.8, sheen 1 tint 0.3",
     {"type": "principled", "base_color": rgb(0.45, 0.12, 0.3), "roughness": 0.8,
      "sheen": 1.0, "sheen_tint": 0.3}),
    ("blend-diffuse-copper", "blend 0.5: diffuse blue and rough Cu (GGX alpha 0.1)",
     {"type": "blendbsdf", "weight": 0.5,
      "diffuse": {"type": "diffuse", "reflectance": rgb(0.15, 0.25, 0.55)},
      "copper": {"type": "roughconductor", "material": "Cu", "distribution": "ggx", "alpha": 0.1}}),
    # A sharp highlight, a metallic principled and a very rough conductor.
    ("plastic-grey-ggx-0.05", "rough plastic, GGX alpha 0.05, IOR 1.5, internal scattering",
     {"type": "roughplastic", "distribution": "ggx", "alpha": 0.05, "int_ior": 1.5,
      "nonlinear": True, "diffuse_reflectance": rgb(0.18, 0.2, 0.24)}),
    # Mitsuba's principled has one microfacet distribution (GGX): no Beckmann.
    ("principled-metallic", "principled, metallic 1, brass base, roughness 0.35",
     {"type": "principled", "base_color": rgb(0.8, 0.6, 0.3), "metallic": 1.0, "roughness": 0.35}),
    ("chromium-ggx-0.5", "rough conductor, measured Cr IOR, GGX alpha 0.5 (isotropic, very rough)",
     {"type": "roughconductor", "material": "Cr", "distribution": "ggx", "alpha": 0.5}),
]


def read_gltf(path):
    """Camera, light and world-space meshes of a glTF written by brdfpaint (embedded
    base64 buffer; node rotations, translations, scales or matrices; node hierarchy)."""
    doc = json.loads(Path(path).read_text())
    buffers = []
    for b in doc["buffers"]:
        head, data = b["uri"].split(",", 1)
        assert head.endswith(";base64"), f"{path}: only embedded base64 buffers are read"
        buffers.append(base64.b64decode(data))

    def accessor(k):
        a = doc["accessors"][k]
        view = doc["bufferViews"][a["bufferView"]]
        dtype = {5126: np.float32, 5125: np.uint32, 5123: np.uint16}[a["componentType"]]
        width = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}[a["type"]]
        start = view.get("byteOffset", 0) + a.get("byteOffset", 0)
        assert view.get("byteStride", 0) in (0, width * np.dtype(dtype).itemsize), "strided data"
        count = a["count"] * width
        return np.frombuffer(buffers[view["buffer"]], dtype, count, start).reshape(a["count"], width)

    def local(node):
        if "matrix" in node:
            return np.array(node["matrix"], dtype=np.float64).reshape(4, 4).T  # column-major
        x, y, z, w = node.get("rotation", [0, 0, 0, 1])
        r = np.array([
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ])
        m = np.eye(4)
        m[:3, :3] = r * np.array(node.get("scale", [1, 1, 1]))
        m[:3, 3] = node.get("translation", [0, 0, 0])
        return m

    camera, light, meshes = None, None, []

    def visit(k, parent):
        nonlocal camera, light
        node = doc["nodes"][k]
        world = parent @ local(node)
        if "camera" in node:
            camera = (doc["cameras"][node["camera"]], world)
        ext = node.get("extensions", {}).get("KHR_lights_punctual")
        if ext is not None:
            light = (doc["extensions"]["KHR_lights_punctual"]["lights"][ext["light"]], world)
        if "mesh" in node:
            normal_matrix = np.linalg.inv(world[:3, :3]).T
            for prim in doc["meshes"][node["mesh"]]["primitives"]:
                att = prim["attributes"]
                p = accessor(att["POSITION"]) @ world[:3, :3].T + world[:3, 3]
                n = accessor(att["NORMAL"]) @ normal_matrix.T
                n /= np.linalg.norm(n, axis=1, keepdims=True)
                uv = accessor(att["TEXCOORD_0"]) if "TEXCOORD_0" in att else None
                faces = accessor(prim["indices"]).reshape(-1, 3)
                meshes.append((p, n, uv, faces))
        for c in node.get("children", []):
            visit(c, world)

    for k in doc["scenes"][doc.get("scene", 0)]["nodes"]:
        visit(k, np.eye(4))
    assert camera and light and meshes, f"{path}: a camera, a light and a mesh are needed"
    return camera, light, meshes


def sensor_dict(camera, width, height):
    """Mitsuba's sensor for a glTF camera: it looks along its node's -Z with +Y up.
    Mitsuba's camera looks along its local +Z with +X to the left, so look_at is built
    from the glTF frame instead of reusing the matrix."""
    cam, world = camera
    eye, forward, up = world[:3, 3], -world[:3, 2], world[:3, 1]
    to_world = mi.ScalarTransform4f().look_at(origin=eye.tolist(), target=(eye + forward).tolist(), up=up.tolist())
    film = {"type": "hdrfilm", "width": width, "height": height, "rfilter": {"type": "box"}, "pixel_format": "rgb"}
    if cam["type"] == "perspective":
        p = cam["perspective"]
        return {"type": "perspective", "fov": float(np.degrees(p["yfov"])), "fov_axis": "y",
                "near_clip": p["znear"], "far_clip": p.get("zfar", 1e4), "to_world": to_world, "film": film}
    o = cam["orthographic"]
    # Mitsuba's orthographic view spans x in [-1, 1] and y in [-1/aspect, 1/aspect]
    # before to_world: a uniform scale by xmag gives glTF's +-xmag, +-ymag.
    return {"type": "orthographic", "near_clip": o["znear"], "far_clip": o["zfar"],
            "to_world": to_world @ mi.ScalarTransform4f().scale([o["xmag"], o["xmag"], 1.0]), "film": film}


def emitter_dict(light):
    """A glTF directional light: it travels along its node's -Z; colour x intensity is its
    irradiance on a surface facing it (brdfpaint divides exactly that out)."""
    spec, world = light
    assert spec["type"] == "directional", "the suite uses directional lights"
    direction = -world[:3, 2]
    e = np.array(spec.get("color", [1, 1, 1])) * spec.get("intensity", 1.0)
    return {"type": "directional", "direction": direction.tolist(), "irradiance": rgb(*e.tolist())}


def mitsuba_mesh(name, p, n, uv, faces, bsdf):
    props = mi.Properties()
    props["bsdf"] = mi.load_dict(bsdf)
    mesh = mi.Mesh(name, len(p), len(faces), props=props, has_vertex_normals=True, has_vertex_texcoords=uv is not None)
    params = mi.traverse(mesh)
    params["vertex_positions"] = mi.Float(p.astype(np.float32).ravel())
    params["vertex_normals"] = mi.Float(n.astype(np.float32).ravel())
    if uv is not None:
        params["vertex_texcoords"] = mi.Float(uv.astype(np.float32).ravel())
    params["faces"] = mi.UInt32(faces.astype(np.uint32).ravel())
    params.update()
    return mesh


def render(scene_path, bsdf, size):
    camera, light, meshes = read_gltf(scene_path)
    scene = {"type": "scene", "light": emitter_dict(light)}
    for k, (p, n, uv, faces) in enumerate(meshes):
        scene[f"mesh{k}"] = mitsuba_mesh(f"mesh{k}", p, n, uv, faces, bsdf)
    scene = mi.load_dict(scene)
    sensor = mi.load_dict(sensor_dict(camera, size, size))

    # One ray through each pixel centre; row 0 is the top row, as in brdfpaint.
    j, i = np.meshgrid(np.arange(size), np.arange(size), indexing="ij")
    pos = mi.Point2f(((i.ravel() + 0.5) / size).astype(np.float32), ((j.ravel() + 0.5) / size).astype(np.float32))
    ray, ray_weight = sensor.sample_ray(0.0, 0.5, pos, mi.Point2f(0.5))
    si = scene.ray_intersect(ray)
    hit = si.is_valid()
    ds, irradiance = scene.sample_emitter_direction(si, mi.Point2f(0.5), False, hit)
    bsdf = si.bsdf(ray)
    value = bsdf.eval(mi.BSDFContext(), si, si.to_local(ds.d), hit) * irradiance * ray_weight
    value = dr.select(hit, value, 0.0)
    img = np.stack([np.array(value.x), np.array(value.y), np.array(value.z)], axis=-1).reshape(size, size, 3)
    # A BSDF never returns negative values; NaN would come only from degenerate hits.
    return np.clip(np.nan_to_num(img, nan=0.0), 0.0, None)


def write_exr(path, img):
    path.parent.mkdir(parents=True, exist_ok=True)
    bitmap = mi.Bitmap(img.astype(np.float32), mi.Bitmap.PixelFormat.RGB)
    bitmap.convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float16, srgb_gamma=False).write(str(path))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scenes", required=True, type=Path, help="the scenes brdfpaint wrote (PRESET.gltf)")
    ap.add_argument("--out", required=True, type=Path, help="where the suite goes (replaced)")
    ap.add_argument("--size", type=int, default=128, help="square renders of SIZE pixels")
    args = ap.parse_args()

    if args.out.exists():
        shutil.rmtree(args.out)
    check = {"type": "diffuse", "reflectance": rgb(*CHECK["albedo"])}
    for name, _, bsdf in [(CHECK["name"], "", check)] + MATERIALS:
        for preset in PRESETS:
            write_exr(args.out / name / f"{preset}.exr", render(args.scenes / f"{preset}.gltf", bsdf, args.size))
        print(name)
    manifest = {
        "renderer": f"Mitsuba {mi.__version__} ({mi.variant()}), Dr.Jit {dr.__version__}",
        "generator": "tools/mitsuba/render_suite.py",
        "size": args.size,
        "presets": PRESETS,
        "check": CHECK,
        "materials": [{"name": n, "description": d, "bsdf": b} for n, d, b in MATERIALS],
    }
    (args.out / "suite.json").write_text(json.dumps(manifest, indent=1) + "\n")


if __name__ == "__main__":
    main()
