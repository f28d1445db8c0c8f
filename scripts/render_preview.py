#!/usr/bin/env python3
"""Renders a binary STL to a shaded PNG (orthographic, z-buffer) for the docs.

usage: render_preview.py MESH.stl OUT.png [SIZE] [--edges]
--edges draws each triangle's sides (to show how a mesh is made, not only its shape).
Plain Python (no numpy on a bare machine): meant for meshes of up to ~100k triangles.
"""
import math
import struct
import sys
import zlib


def read_stl(path):
    with open(path, "rb") as f:
        data = f.read()
    (n,) = struct.unpack_from("<I", data, 80)
    tris = []
    for i in range(n):
        v = struct.unpack_from("<12f", data, 84 + 50 * i)
        tris.append((v[3:6], v[6:9], v[9:12]))
    return tris


def view_basis():
    # camera looking from (1, 0.7, 0.9) towards the origin
    d = (1.0, 0.7, 0.9)
    n = math.sqrt(sum(c * c for c in d))
    w = tuple(c / n for c in d)
    up = (0.0, 0.0, 1.0)
    u = (up[1] * w[2] - up[2] * w[1], up[2] * w[0] - up[0] * w[2], up[0] * w[1] - up[1] * w[0])
    un = math.sqrt(sum(c * c for c in u))
    u = tuple(c / un for c in u)
    v = (w[1] * u[2] - w[2] * u[1], w[2] * u[0] - w[0] * u[2], w[0] * u[1] - w[1] * u[0])
    return u, v, w


def render(tris, size, edges=False):
    u, v, w = view_basis()
    dot = lambda a, b: a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
    proj = [[(dot(p, u), dot(p, v), dot(p, w)) for p in t] for t in tris]
    xs = [p[0] for t in proj for p in t]
    ys = [p[1] for t in proj for p in t]
    scale = 0.9 * size / max(max(xs) - min(xs), max(ys) - min(ys))
    cx, cy = (max(xs) + min(xs)) / 2, (max(ys) + min(ys)) / 2
    depth = [[-1e30] * size for _ in range(size)]
    image = [[(255, 255, 255)] * size for _ in range(size)]
    light = (0.4, 0.3, 0.87)
    for t, q in zip(tris, proj):
        a, b, c = t
        e1 = (b[0] - a[0], b[1] - a[1], b[2] - a[2])
        e2 = (c[0] - a[0], c[1] - a[1], c[2] - a[2])
        nrm = (e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0])
        ln = math.sqrt(dot(nrm, nrm)) or 1.0
        facing = dot(nrm, w) / ln
        if facing <= 0:
            continue
        shade = 0.25 + 0.75 * max(0.0, dot(nrm, light) / ln)
        colour = (int(70 * shade + 20), int(130 * shade + 30), int(200 * shade + 40))
        pts = [((p[0] - cx) * scale + size / 2, size / 2 - (p[1] - cy) * scale, p[2]) for p in q]
        x0, x1 = max(0, int(min(p[0] for p in pts))), min(size - 1, int(max(p[0] for p in pts)) + 1)
        y0, y1 = max(0, int(min(p[1] for p in pts))), min(size - 1, int(max(p[1] for p in pts)) + 1)
        (ax, ay, az), (bx, by, bz), (qx, qy, qz) = pts
        den = (by - qy) * (ax - qx) + (qx - bx) * (ay - qy)
        if den == 0:
            continue
        # pixels from each side: barycentric weight times the height over that side
        side = [math.hypot(bx - qx, by - qy), math.hypot(qx - ax, qy - ay), math.hypot(ax - bx, ay - by)]
        height = [abs(den) / (s or 1.0) for s in side]
        dark = tuple(int(0.35 * c) for c in colour)
        for y in range(y0, y1 + 1):
            for x in range(x0, x1 + 1):
                l1 = ((by - qy) * (x - qx) + (qx - bx) * (y - qy)) / den
                l2 = ((qy - ay) * (x - qx) + (ax - qx) * (y - qy)) / den
                l3 = 1 - l1 - l2
                if l1 < 0 or l2 < 0 or l3 < 0:
                    continue
                z = l1 * az + l2 * bz + l3 * qz
                if z > depth[y][x]:
                    depth[y][x] = z
                    near_side = edges and min(l1 * height[0], l2 * height[1], l3 * height[2]) < 0.6
                    image[y][x] = dark if near_side else colour
    return image


def write_png(path, image):
    h, w = len(image), len(image[0])
    raw = b"".join(b"\x00" + bytes(c for px in row for c in px) for row in image)
    chunk = lambda tag, data: struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)
    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


if __name__ == "__main__":
    args = [a for a in sys.argv[1:] if a != "--edges"]
    size = int(args[2]) if len(args) > 2 else 480
    write_png(args[1], render(read_stl(args[0]), size, edges="--edges" in sys.argv))
