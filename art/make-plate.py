#!/usr/bin/env python3
"""Draws art/plates/hills.png: a small hand-drawn-looking landscape (paper-grain sky, two rows of
hills with wobbly ink outlines, hatched ground, a cottage and two trees) for the compositing scene
art/scenes/plate-cloud.json (McGuire & Fein 2006, Fig. 8d: the cloud composited into a hand-drawn
scene). Standard library only; the same bytes every run (integer hashes, no randomness, zlib level 9).
Usage: art/make-plate.py [OUT.png]"""
import math
import os
import struct
import sys
import zlib

W, H = 480, 360


def hash01(x, y, seed=0):
    """A deterministic value in [0, 1) per integer (x, y, seed)."""
    h = (x * 374761393 + y * 668265263 + seed * 2246822519) & 0xFFFFFFFF
    h = ((h ^ (h >> 13)) * 1274126177) & 0xFFFFFFFF
    return ((h ^ (h >> 16)) & 0xFFFF) / 65536.0


def mix(a, b, t):
    return tuple(a[i] + (b[i] - a[i]) * t for i in range(3))


def wobble(v, seed, amp=1.2):
    """A hand's tremor: slow sines, the same for the same v."""
    return amp * (math.sin(v * 0.11 + seed) + 0.5 * math.sin(v * 0.37 + 2.1 * seed))


def far_hill(x):
    return 238 + 22 * math.sin(x * 0.012 + 0.8) + 10 * math.sin(x * 0.031 + 2.0)


def near_hill(x):
    return 276 + 26 * math.sin(x * 0.009 + 2.6) + 8 * math.sin(x * 0.027 + 0.3)


INK = (0.16, 0.13, 0.12)
SKY_TOP, SKY_LOW = (0.62, 0.76, 0.90), (0.96, 0.92, 0.82)
FAR, NEAR = (0.60, 0.68, 0.74), (0.55, 0.70, 0.38)
HATCH = (0.40, 0.55, 0.28)


def ink_line(d, x, seed, width=1.3):
    """Coverage of an ink stroke at signed distance d: its width swells and thins along x."""
    w = width * (0.75 + 0.45 * math.sin(x * 0.05 + seed))
    return max(0.0, min(1.0, w + 0.5 - abs(d)))


def pixel(x, y):
    # Sky: a gradient on paper grain, with soft watercolour blotches.
    t = y / 250.0
    c = mix(SKY_TOP, SKY_LOW, min(1.0, t))
    blotch = 0.025 * math.sin(x * 0.021 + y * 0.013) * math.sin(y * 0.029 - x * 0.008)
    c = tuple(v + blotch for v in c)
    fh, nh = far_hill(x) + wobble(x, 1.0), near_hill(x) + wobble(x, 2.0)
    if y >= fh:
        c = FAR
    if y >= nh:
        c = NEAR
        # Hatching on the near hill: short diagonal strokes, some left out.
        if (x + y) % 7 == 0 and hash01((x + y) // 7, y // 9, 3) < 0.55 and y > nh + 6:
            c = HATCH
    # Ink on the hills' ridges, under what stands on them.
    c = mix(c, INK, ink_line(y - fh, x, 0.5, 1.0))
    c = mix(c, INK, ink_line(y - nh, x, 1.7))
    # The cottage on the near hill's shoulder, its walls and roof outlined.
    hx0, hx1, base = 322, 372, near_hill(347) + 10
    roof = base - 38
    apex = roof - 22
    if hx0 <= x <= hx1 and roof <= y <= base:
        c = (0.93, 0.86, 0.70)
        if 340 <= x <= 352 and y >= base - 18:
            c = (0.45, 0.30, 0.22)  # door
        for d in (x - hx0 - wobble(y, 4.0, 0.8), x - hx1 - wobble(y, 5.0, 0.8), y - base):
            c = mix(c, INK, ink_line(d, y, 3.0, 1.0))
    if hx0 - 6 <= x <= hx1 + 6 and apex <= y <= roof + 1:
        half = (y - apex) / 22.0 * (hx1 - hx0 + 12) / 2.0
        if abs(x - 347) <= half + 1.5:
            if abs(x - 347) <= half:
                c = (0.72, 0.28, 0.22)
            c = mix(c, INK, ink_line(abs(x - 347) - half, y, 4.0, 1.0))
            c = mix(c, INK, ink_line(y - roof - wobble(x, 6.0, 0.7), x, 2.0, 1.0))
    # Two lollipop trees on the left.
    for tx, ty, r in ((92, near_hill(92) - 24, 18), (128, near_hill(128) - 16, 13)):
        if abs(x - tx) <= 2 and ty < y < ty + r + 22:
            c = (0.36, 0.25, 0.18)
        d = math.hypot(x - tx, y - ty) - r - wobble(math.atan2(y - ty, x - tx) * 40, tx)
        if d < 0:
            c = (0.34, 0.52, 0.30)
        c = mix(c, INK, ink_line(d, math.atan2(y - ty, x - tx) * 30, tx))
    # Paper grain over everything.
    g = (hash01(x // 2, y // 2, 7) - 0.5) * 0.02
    return tuple(min(255, max(0, int(round((v + g) * 255.0)))) for v in c)


def write_png(path, rows):
    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)

    raw = b"".join(b"\x00" + bytes(v for p in row for v in p) for row in rows)
    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", W, H, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


if __name__ == "__main__":
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(os.path.abspath(__file__)), "plates", "hills.png")
    write_png(out, [[pixel(x, y) for x in range(W)] for y in range(H)])
