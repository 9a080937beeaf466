#!/usr/bin/env python3
"""Writes the same 8-bit grey PNG the ways other tools store it, as fuzzing seeds for the PNG
decoder's other paths: a gAMA chunk, RGB, RGBA, grey + alpha, a grey palette, Adam7 interlacing,
and 16-bit samples (refused). Usage: png_variants.py IN.png OUT_PREFIX (writes OUT_PREFIX_<kind>.png)."""
import struct
import sys
import zlib


def chunks(data):
    at, out = 8, []
    while at + 12 <= len(data):
        n = struct.unpack('>I', data[at:at + 4])[0]
        out.append((data[at + 4:at + 8], data[at + 8:at + 8 + n]))
        at += 12 + n
    return out


def grey_rows(path):
    cs = chunks(open(path, 'rb').read())
    w, h, depth, colour, _, _, interlace = struct.unpack('>IIBBBBB', [c for t, c in cs if t == b'IHDR'][0])
    if (depth, colour, interlace) != (8, 0, 0):
        sys.exit(f'{path}: expected a non-interlaced 8-bit grey PNG')
    raw = zlib.decompress(b''.join(c for t, c in cs if t == b'IDAT'))
    rows, prev, at = [], bytearray(w), 0
    for _ in range(h):
        kind, line = raw[at], bytearray(raw[at + 1:at + 1 + w])
        at += 1 + w
        for x in range(w):
            a = line[x - 1] if x else 0
            b = prev[x]
            c = prev[x - 1] if x else 0
            if kind == 1:
                line[x] = (line[x] + a) & 255
            elif kind == 2:
                line[x] = (line[x] + b) & 255
            elif kind == 3:
                line[x] = (line[x] + (a + b) // 2) & 255
            elif kind == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(bytes(line))
        prev = line
    return w, h, rows


def chunk(kind, data):
    return struct.pack('>I', len(data)) + kind + data + struct.pack('>I', zlib.crc32(kind + data) & 0xffffffff)


def png(w, h, depth, colour, rows, bpp, extra=b'', adam7=False):
    raw = b''
    passes = [(0, 0, 8, 8), (4, 0, 8, 8), (0, 4, 4, 8), (2, 0, 4, 4), (0, 2, 2, 4), (1, 0, 2, 2), (0, 1, 1, 2)] if adam7 else [(0, 0, 1, 1)]
    for x0, y0, dx, dy in passes:
        for y in range(y0, h, dy):
            if x0 < w:
                raw += b'\0' + b''.join(rows[y][x * bpp:(x + 1) * bpp] for x in range(x0, w, dx))
    ihdr = struct.pack('>IIBBBBB', w, h, depth, colour, 0, 0, 1 if adam7 else 0)
    return b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', ihdr) + extra + chunk(b'IDAT', zlib.compress(raw)) + chunk(b'IEND', b'')


def main():
    w, h, rows = grey_rows(sys.argv[1])
    expand = lambda f: [b''.join(f(v) for v in r) for r in rows]
    variants = {
        'gamma': png(w, h, 8, 0, rows, 1, chunk(b'gAMA', struct.pack('>I', 100000))),
        'rgb': png(w, h, 8, 2, expand(lambda v: bytes((v, v, v))), 3),
        'rgba': png(w, h, 8, 6, expand(lambda v: bytes((v, v, v, 255))), 4),
        'grey_alpha': png(w, h, 8, 4, expand(lambda v: bytes((v, 255))), 2),
        'palette': png(w, h, 8, 3, rows, 1, chunk(b'PLTE', bytes(c for i in range(256) for c in (i, i, i)))),
        'adam7': png(w, h, 8, 0, rows, 1, adam7=True),
        '16bit': png(w, h, 16, 0, expand(lambda v: bytes((v, v))), 2),
    }
    for kind, data in variants.items():
        open(f'{sys.argv[2]}_{kind}.png', 'wb').write(data)


if __name__ == '__main__':
    main()
