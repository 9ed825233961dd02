#!/usr/bin/env python3
"""Checks a screenshot of the example game at its default view (puff_game --width 960 --height 540):
the game's HUD and marker drawn after Puff, Puff's smoke (lit, with its ink outline) on both sides
of the game's pillar and nothing drawn over the pillar (the game's standard depth cut the smoke),
and with --fire bright orange fire over the fire pit and its light on the back wall. Pixel positions are the scene's (main.cpp),
x from the left, y from the top. Reads the PNG with the standard library only (zlib).
Usage: check_screenshot.py FILE.png [--fire]"""
import struct
import sys
import zlib


def read_png(path):
    """8-bit RGB or RGBA, not interlaced: (width, height, pixel(x, y) -> (r, g, b))."""
    data = open(path, 'rb').read()
    if data[:8] != b'\x89PNG\r\n\x1a\n':
        raise ValueError('not a PNG')
    pos, idat = 8, b''
    while pos < len(data):
        n, kind = struct.unpack('>I4s', data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        pos += 12 + n
        if kind == b'IHDR':
            w, h, depth, ctype, _, _, interlace = struct.unpack('>IIBBBBB', body)
            if depth != 8 or ctype not in (2, 6) or interlace:
                raise ValueError('expected 8-bit RGB(A), not interlaced')
        elif kind == b'IDAT':
            idat += body
    ch = 3 if ctype == 2 else 4
    raw, stride, rows, prev, i = zlib.decompress(idat), w * ch, [], bytearray(w * ch), 0
    for _ in range(h):  # undo each row's filter (PNG spec §9)
        f, line = raw[i], bytearray(raw[i + 1:i + 1 + stride])
        i += 1 + stride
        for x in range(stride):
            a = line[x - ch] if x >= ch else 0
            b = prev[x]
            c = prev[x - ch] if x >= ch else 0
            if f == 1:
                line[x] = (line[x] + a) & 255
            elif f == 2:
                line[x] = (line[x] + b) & 255
            elif f == 3:
                line[x] = (line[x] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(line)
        prev = line
    return w, h, lambda x, y: tuple(rows[y][x * ch:x * ch + 3])


def main():
    if len(sys.argv) not in (2, 3) or (len(sys.argv) == 3 and sys.argv[2] != '--fire'):
        print(__doc__.splitlines()[-1], file=sys.stderr)
        return 2
    path, fire = sys.argv[1], len(sys.argv) == 3
    try:
        w, h, px = read_png(path)
    except (OSError, ValueError, KeyError, zlib.error) as e:
        print(f'check_screenshot: {path}: {e}', file=sys.stderr)
        return 1
    if (w, h) != (960, 540):
        print(f'check_screenshot: {path} is {w} x {h}, expected 960 x 540', file=sys.stderr)
        return 1

    def count(xs, ys, test):
        return sum(1 for y in ys for x in xs if test(px(x, y)))

    failures = []

    def expect(what, ok, seen):
        print(f'check_screenshot: {what}: {seen} {"ok" if ok else "FAILED"}')
        if not ok:
            failures.append(what)

    # The HUD (display values, after Puff): the health bar's fill is (0.86, 0.20, 0.16) = (219, 51, 41).
    bar = px(100, 512)
    expect('HUD bar fill is (219, 51, 41) +- 2', all(abs(a - b) <= 2 for a, b in zip(bar, (219, 51, 41))), bar)
    cross = px(480, 270)
    expect('crosshair centre is white (> 230)', min(cross) > 230, cross)
    # The marker drawn after Puff with the game's camera block (binding 0, never rebound).
    yellow = count(range(525, 566), range(255, 306), lambda p: p[0] > 230 and p[1] > 190 and p[2] < 110)
    expect('yellow marker pixels near (545, 280) >= 400', yellow >= 400, yellow)
    # The pillar's front face is one flat colour: Puff drew nothing over it, though the smoke passes
    # behind it (lit smoke on both sides of it).
    band = {px(x, y) for y in range(160, 381) for x in range(385, 413)}
    expect('pillar face x 385-412, y 160-380 is one colour', len(band) == 1, sorted(band)[:3])
    white = lambda p: min(p) > 235
    left = count(range(300, 373), range(140, 251), white)
    right = count(range(425, 621), range(60, 201), white)
    expect('lit smoke pixels left of the pillar >= 100', left >= 100, left)
    expect('lit smoke pixels right of the pillar >= 100', right >= 100, right)
    ink = count(range(300, 621), range(60, 251), lambda p: max(p) < 50)
    expect("smoke's ink outline pixels (all channels < 50) >= 300", ink >= 300, ink)
    if fire:
        orange = count(range(540, 721), range(120, 346), lambda p: p[0] > 200 and 60 < p[1] < 215 and p[2] < 130
                       and p[0] - p[2] > 120)
        expect('bright orange fire pixels over the fire pit >= 100', orange >= 100, orange)
        # The explosion light on the game's back wall beside the fire: warmer and brighter than the
        # same wall far from it (unlit: (104, 100, 101)).
        lit, unlit = px(700, 240), px(200, 240)
        expect('back wall beside the fire lit: red +30 over the far wall, red > blue + 25',
               lit[0] >= unlit[0] + 30 and lit[0] > lit[2] + 25, (lit, unlit))
    if failures:
        print(f'check_screenshot: {path}: {len(failures)} check(s) failed', file=sys.stderr)
        return 1
    return 0


if __name__ == '__main__':
    sys.exit(main())
