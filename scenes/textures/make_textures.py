#!/usr/bin/env python3
"""Generate the procedural "paintings" used by scenes/artroom.nff.

Standard library only: the PNG writer below uses zlib + struct. The output is
deterministic, so rerunning the script reproduces the committed files:

    python3 scenes/textures/make_textures.py      # writes next to this script

Files (8-bit sRGB RGB PNG, small on purpose):
    fields.png    96x128  soft colour fields on a deep red ground (Rothko-like)
    circles.png   128x96  concentric rings and discs over a dusk gradient
    grid.png      96x96   black grid with primary-coloured cells (Mondrian-like)
"""

import math
import os
import struct
import zlib


def write_png(path, width, height, pixel):
    """pixel(x, y) -> (r, g, b) floats in [0, 1], sRGB-encoded already; y = 0 is the top row."""
    rows = []
    for y in range(height):
        row = bytearray()
        for x in range(width):
            r, g, b = pixel(x, y)
            row += bytes(max(0, min(255, int(round(c * 255)))) for c in (r, g, b))
        # Filter type 1 (Sub): store each byte minus the byte one pixel to the left.
        # Smooth gradients then compress to a few KB.
        filtered = bytearray(row[:3])
        for i in range(3, len(row)):
            filtered.append((row[i] - row[i - 3]) & 0xFF)
        rows.append(b"\x01" + bytes(filtered))
    raw = b"".join(rows)

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)

    png = b"\x89PNG\r\n\x1a\n"
    png += chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 9))
    png += chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


def mix(a, b, t):
    return tuple(x + (y - x) * t for x, y in zip(a, b))


def smoothstep(e0, e1, x):
    t = max(0.0, min(1.0, (x - e0) / (e1 - e0)))
    return t * t * (3 - 2 * t)


def quant(c, levels=48):
    # Fewer distinct values compress better and are invisible after bilinear filtering.
    return tuple(round(v * levels) / levels for v in c)


def fields(x, y, w=96, h=128):
    u, v = (x + 0.5) / w, (y + 0.5) / h
    ground = mix((0.45, 0.07, 0.06), (0.30, 0.04, 0.05), v)
    # Three soft-edged rectangles, each with its own vertical gradient.
    blocks = [
        (0.08, 0.30, (0.95, 0.62, 0.18), (0.85, 0.45, 0.12)),
        (0.36, 0.52, (0.16, 0.05, 0.12), (0.12, 0.04, 0.10)),
        (0.58, 0.92, (0.98, 0.80, 0.40), (0.90, 0.55, 0.20)),
    ]
    c = ground
    for top, bottom, c0, c1 in blocks:
        edge = 0.035
        inside = (smoothstep(0.08 - edge, 0.08 + edge, u) * (1 - smoothstep(0.92 - edge, 0.92 + edge, u))
                  * smoothstep(top - edge, top + edge, v) * (1 - smoothstep(bottom - edge, bottom + edge, v)))
        c = mix(c, mix(c0, c1, (v - top) / (bottom - top)), inside)
    return quant(c)


def circles(x, y, w=128, h=96):
    u, v = (x + 0.5) / w, (y + 0.5) / h
    sky = mix((0.10, 0.16, 0.42), (0.95, 0.55, 0.30), smoothstep(0.0, 1.0, v))
    c = sky
    # A large ringed sun, a blue disc and a small green one, painted back to front.
    shapes = [
        (0.34, 0.46, 0.30, [(0.98, 0.85, 0.30), (0.90, 0.30, 0.15), (0.98, 0.85, 0.30), (0.20, 0.10, 0.30)]),
        (0.74, 0.36, 0.17, [(0.15, 0.35, 0.80), (0.85, 0.90, 0.95)]),
        (0.62, 0.78, 0.09, [(0.20, 0.60, 0.35)]),
    ]
    for cx, cy, r, bands in shapes:
        d = math.hypot((u - cx) * w / h, v - cy) / r
        if d < 1.0:
            band = bands[min(len(bands) - 1, int(d * len(bands)))]
            aa = 1 - smoothstep(0.96, 1.0, d)
            c = mix(c, band, aa)
    # A thin diagonal line across the lower right.
    dist = abs((u - 0.5) * 0.6 - (v - 0.9) * 0.8)
    c = mix(c, (0.05, 0.05, 0.08), 1 - smoothstep(0.004, 0.012, dist))
    return quant(c)


def grid(x, y, w=96, h=96):
    # Cell boundaries in pixels; lines are 3 px wide.
    xs = [0, 30, 60, 78, 96]
    ys = [0, 22, 58, 80, 96]
    for b in xs:
        if abs(x - b) <= 1 or (b == 96 and x >= 94):
            return (0.06, 0.06, 0.07)
    for b in ys:
        if abs(y - b) <= 1 or (b == 96 and y >= 94):
            return (0.06, 0.06, 0.07)
    i = sum(1 for b in xs[1:-1] if x > b)
    j = sum(1 for b in ys[1:-1] if y > b)
    colours = {
        (0, 0): (0.85, 0.12, 0.10), (2, 1): (0.10, 0.22, 0.65), (3, 3): (0.95, 0.80, 0.10),
        (1, 2): (0.95, 0.80, 0.10), (3, 0): (0.10, 0.22, 0.65), (0, 3): (0.85, 0.12, 0.10),
    }
    return colours.get((i, j), (0.93, 0.92, 0.88))


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    write_png(os.path.join(here, "fields.png"), 96, 128, fields)
    write_png(os.path.join(here, "circles.png"), 128, 96, circles)
    write_png(os.path.join(here, "grid.png"), 96, 96, grid)


if __name__ == "__main__":
    main()
