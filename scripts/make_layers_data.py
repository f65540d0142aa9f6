#!/usr/bin/env python3
"""Makes the layers demo's inputs in data/ (docs/layers.md): standard library only.

  data/bottle.ply  a lathe-turned bottle, y up, 1 unit tall, with green
                   glass-like vertex colours (the base "mesh" of the demo)
  data/label.png   a 1024 x 256 RGBA label: cream with red stripes and a
                   dark band, its corners and a border of 12 px transparent
                   with a soft (2 px) edge

Run once; the outputs are committed (python3 scripts/make_layers_data.py).
"""
import math
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "..", "data")


def radius(y):
    """The bottle's profile: body, shoulder, neck, lip."""
    if y < 0.04:  # rounded base
        return 0.27 + 0.03 * math.sin(y / 0.04 * math.pi / 2)
    if y < 0.62:
        return 0.30
    if y < 0.80:  # shoulder: a half cosine from 0.30 down to 0.11
        t = (y - 0.62) / 0.18
        return 0.11 + 0.19 * (0.5 + 0.5 * math.cos(t * math.pi))
    if y < 0.97:
        return 0.11
    return 0.125  # lip


def bottle(rings=120, segments=96):
    verts, cols, faces = [], [], []
    for j in range(rings + 1):
        y = j / rings
        r = radius(y)
        shade = 0.55 + 0.45 * y
        for i in range(segments):
            a = 2 * math.pi * i / segments
            verts.append((r * math.cos(a), y, -r * math.sin(a)))
            cols.append((round(30 * shade), round(120 * shade), round(60 * shade)))
    for j in range(rings):
        for i in range(segments):
            a = j * segments + i
            b = j * segments + (i + 1) % segments
            c = a + segments
            d = b + segments
            faces.append((a, b, d))
            faces.append((a, d, c))
    # Bottom cap (facing -y) and top cap (facing +y), fans around centres.
    bottom = len(verts)
    verts.append((0.0, 0.0, 0.0))
    cols.append((20, 70, 35))
    for i in range(segments):
        faces.append((bottom, (i + 1) % segments, i))
    top = len(verts)
    verts.append((0.0, 1.0, 0.0))
    cols.append((30, 120, 60))
    base = rings * segments
    for i in range(segments):
        faces.append((top, base + i, base + (i + 1) % segments))
    return verts, cols, faces


def write_ply(path, verts, cols, faces):
    with open(path, "w") as f:
        f.write("ply\nformat ascii 1.0\ncomment made by scripts/make_layers_data.py\n")
        f.write(f"element vertex {len(verts)}\n")
        f.write("property float x\nproperty float y\nproperty float z\n")
        f.write("property uchar red\nproperty uchar green\nproperty uchar blue\n")
        f.write(f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n")
        for (x, y, z), (r, g, b) in zip(verts, cols):
            f.write(f"{x:.6f} {y:.6f} {z:.6f} {r} {g} {b}\n")
        for a, b, c in faces:
            f.write(f"3 {a} {b} {c}\n")


def label(w=1024, h=256, border=12.0, soft=2.0):
    rows = []
    for y in range(h):
        row = bytearray([0])  # PNG filter: none
        for x in range(w):
            px, py = x + 0.5, y + 0.5
            # Distance inside the rounded rectangle (corner radius 40 px).
            rad = 40.0
            cx = min(max(px, border + rad), w - border - rad)
            cy = min(max(py, border + rad), h - border - rad)
            inside = rad - math.hypot(px - cx, py - cy)
            alpha = min(max(inside / soft, 0.0), 1.0)
            stripe = int(px // 64) % 2 == 0
            r, g, b = (0.95, 0.90, 0.78) if stripe else (0.80, 0.12, 0.10)
            if 0.42 * h < py < 0.58 * h:  # a dark band across
                r, g, b = 0.10, 0.10, 0.15
            row += bytes([round(255 * r), round(255 * g), round(255 * b), round(255 * alpha)])
        rows.append(bytes(row))
    raw = b"".join(rows)

    def chunk(kind, data):
        c = struct.pack(">I", len(data)) + kind + data
        return c + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    png = b"\x89PNG\r\n\x1a\n"
    png += chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 6, 0, 0, 0))  # 8-bit RGBA
    png += chunk(b"sRGB", b"\x00")
    png += chunk(b"IDAT", zlib.compress(raw, 9))
    png += chunk(b"IEND", b"")
    return png


if __name__ == "__main__":
    v, c, f = bottle()
    write_ply(os.path.join(DATA, "bottle.ply"), v, c, f)
    with open(os.path.join(DATA, "label.png"), "wb") as out:
        out.write(label())
