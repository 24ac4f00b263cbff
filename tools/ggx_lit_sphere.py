#!/usr/bin/env python3
"""Writes the synthetic GGX lit sphere of issue 38's target (tests/export.rs draws the same):
glTF base colour (0.8, 0.25, 0.1), roughness 0.5, F0 0.04, light towards (-0.4, 0.5, 0.77),
in the painter's convention (pixel = base colour x cos(theta_l) for the diffuse part, i.e.
pi x BRDF x cos), 16-bit sRGB PNG, the disk inscribed, transparent outside.
Usage: python3 tools/ggx_lit_sphere.py OUT.png [SIZE]"""
import math, struct, sys, zlib

BASE, ROUGH, F0 = (0.8, 0.25, 0.1), 0.5, 0.04
L = (-0.4, 0.5, 0.77)

def norm(v):
    n = math.sqrt(sum(x * x for x in v)); return tuple(x / n for x in v)

def shading(n, l, v):
    cl, cv = sum(a * b for a, b in zip(n, l)), sum(a * b for a, b in zip(n, v))
    if cl <= 0 or cv <= 0:
        return (0.0, 0.0, 0.0)
    h = norm(tuple(a + b for a, b in zip(l, v)))
    ch, cd = sum(a * b for a, b in zip(n, h)), sum(a * b for a, b in zip(l, h))
    a2 = (ROUGH * ROUGH) ** 2
    d = a2 / (math.pi * ((a2 - 1) * ch * ch + 1) ** 2)
    g1 = lambda c: 2 * c / (c + math.sqrt(a2 + (1 - a2) * c * c))
    f = F0 + (1 - F0) * (1 - cd) ** 5
    spec = d * f * g1(cl) * g1(cv) / (4 * cl * cv)
    return tuple(math.pi * (b / math.pi + spec) * cl for b in BASE)

def srgb(x):
    x = min(max(x, 0.0), 1.0)
    return 12.92 * x if x <= 0.0031308 else 1.055 * x ** (1 / 2.4) - 0.055

def main():
    out, size = sys.argv[1], int(sys.argv[2]) if len(sys.argv) > 2 else 256
    l = norm(L)
    rows = []
    for j in range(size):
        row = bytearray([0])
        for i in range(size):
            x, y = 2 * (i + 0.5) / size - 1, 1 - 2 * (j + 0.5) / size
            rr = x * x + y * y
            if rr >= 1:
                row += bytes(8); continue
            s = shading((x, y, math.sqrt(1 - rr)), l, (0.0, 0.0, 1.0))
            for c in s:
                row += struct.pack(">H", round(srgb(c) * 65535))
            row += struct.pack(">H", 65535)
        rows.append(bytes(row))
    chunk = lambda t, d: struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xFFFFFFFF)
    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", size, size, 16, 6, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(b"".join(rows), 9)) + chunk(b"IEND", b"")
    open(out, "wb").write(png)

main()
