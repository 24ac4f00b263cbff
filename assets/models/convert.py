#!/usr/bin/env python3
"""Reproduces the converted built-in models from the shared test data (standard library only).

    python3 assets/models/convert.py /path/to/shared/data/models

- teapot/teapot.glb: utah_teapot/teapot_npm_792v.obj as a GLB, POSITION + indices only
  (brdfpaint generates the smooth normals when it loads it). Vertex order and faces unchanged.
- apple/apple.glb: polyhaven_apple/food_apple_01_4k.gltf + .bin as one GLB, with the
  material, textures, images and samplers removed (geometry unchanged: POSITION, NORMAL,
  TEXCOORD_0, indices), so the 3.5 MB of 4k textures are not shipped.
- fox/fox.glb: khronos_fox/Fox.gltf + Fox.bin + Texture.png as one GLB (the texture moved into
  the binary chunk); nothing else changed.
"""
import json
import struct
import sys
from pathlib import Path


def glb(document, binary):
    """A GLB 2.0 container: JSON chunk padded with spaces, BIN chunk padded with zeros."""
    text = json.dumps(document, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    binary += b"\0" * (-len(binary) % 4)
    chunks = struct.pack("<I4s", len(text), b"JSON") + text + struct.pack("<I4s", len(binary), b"BIN\0") + binary
    return struct.pack("<4sII", b"glTF", 2, 12 + len(chunks)) + chunks


def teapot(src, dst):
    positions, faces = [], []
    for line in open(src):
        fields = line.split()
        if fields and fields[0] == "v":
            positions.append(tuple(float(x) for x in fields[1:4]))
        elif fields and fields[0] == "f":
            faces.append(tuple(int(x.split("/")[0]) - 1 for x in fields[1:4]))
    pos = b"".join(struct.pack("<3f", *p) for p in positions)
    idx = b"".join(struct.pack("<3H", *f) for f in faces)
    pad = b"\0" * (-len(idx) % 4)
    lo = [min(p[k] for p in positions) for k in range(3)]
    hi = [max(p[k] for p in positions) for k in range(3)]
    # min/max as stored in f32, so validators agree with the data.
    lo = list(struct.unpack("<3f", struct.pack("<3f", *lo)))
    hi = list(struct.unpack("<3f", struct.pack("<3f", *hi)))
    doc = {
        "asset": {"version": "2.0", "generator": "brdfpaint assets/models/convert.py"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"name": "teapot", "mesh": 0}],
        "meshes": [{"name": "teapot", "primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": len(positions), "type": "VEC3", "min": lo, "max": hi},
            {"bufferView": 1, "componentType": 5123, "count": 3 * len(faces), "type": "SCALAR"},
        ],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": len(pos), "target": 34962},
            {"buffer": 0, "byteOffset": len(pos), "byteLength": len(idx), "target": 34963},
        ],
        "buffers": [{"byteLength": len(pos) + len(idx) + len(pad)}],
    }
    Path(dst).write_bytes(glb(doc, pos + idx + pad))


def apple(src, dst):
    doc = json.loads(Path(src).read_text())
    binary = (Path(src).parent / doc["buffers"][0]["uri"]).read_bytes()
    for key in ("materials", "textures", "images", "samplers"):
        doc.pop(key, None)
    for mesh in doc["meshes"]:
        for primitive in mesh["primitives"]:
            primitive.pop("material", None)
    del doc["buffers"][0]["uri"]
    doc["asset"]["generator"] += " (textures removed by brdfpaint assets/models/convert.py)"
    Path(dst).write_bytes(glb(doc, binary))


def fox(src, dst):
    doc = json.loads(Path(src).read_text())
    binary = bytearray((Path(src).parent / doc["buffers"][0]["uri"]).read_bytes())
    binary += b"\0" * (-len(binary) % 4)
    for image in doc["images"]:
        data = (Path(src).parent / image.pop("uri")).read_bytes()
        doc["bufferViews"].append({"buffer": 0, "byteOffset": len(binary), "byteLength": len(data)})
        image["bufferView"] = len(doc["bufferViews"]) - 1
        image["mimeType"] = "image/png"
        binary += data + b"\0" * (-len(data) % 4)
    doc["buffers"] = [{"byteLength": len(binary)}]
    Path(dst).write_bytes(glb(doc, bytes(binary)))


if __name__ == "__main__":
    data = Path(sys.argv[1])
    here = Path(__file__).parent
    teapot(data / "utah_teapot/teapot_npm_792v.obj", here / "teapot/teapot.glb")
    apple(data / "polyhaven_apple/food_apple_01_4k.gltf", here / "apple/apple.glb")
    fox(data / "khronos_fox/Fox.gltf", here / "fox/fox.glb")
