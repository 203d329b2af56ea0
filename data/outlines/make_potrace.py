#!/usr/bin/env python3
"""Trace horse.png with potrace, for `metabezier score` (see PROVENANCE.md).

Writes horse.pbm: the pixels `metabezier fit` takes as the shape (luminance
Y = 0.2126 R + 0.7152 G + 0.0722 B composited over white with alpha, rounded
as crates/fit/src/outline/image.rs does; shape = the class at or below Otsu's threshold
when it is the smaller one), black in the PBM. The standard library only
(zlib, struct): the PNG is 8-bit RGBA, non-interlaced.

Usage: python3 make_potrace.py horse.png horse.pbm
then:  potrace -s -o horse-potrace.svg horse.pbm
"""
import struct
import sys
import zlib


def read_png(path):
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
    pos, idat, header = 8, b"", None
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos:pos + 4])
        kind = data[pos + 4:pos + 8]
        body = data[pos + 8:pos + 8 + length]
        pos += 12 + length
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
    w, h, depth, colour, _, _, interlace = header
    assert depth == 8 and colour == 6 and interlace == 0, "expected 8-bit RGBA"
    raw = zlib.decompress(idat)
    bpp, stride = 4, 4 * w
    rows, prev = [], bytearray(stride)
    for y in range(h):
        f = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b = prev[i]
            c = prev[i - bpp] if i >= bpp else 0
            if f == 1:
                line[i] = (line[i] + a) & 255
            elif f == 2:
                line[i] = (line[i] + b) & 255
            elif f == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                pred = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                line[i] = (line[i] + pred) & 255
        rows.append(line)
        prev = line
    return w, h, rows


def luminance(rows, w):
    out = []
    for line in rows:
        row = []
        for x in range(w):
            r, g, b, a = line[4 * x:4 * x + 4]
            y = (2126 * r + 7152 * g + 722 * b + 5000) // 10000
            row.append((y * a + 255 * (255 - a) + 127) // 255)
        out.append(row)
    return out


def otsu(grey):
    hist = [0] * 256
    for row in grey:
        for v in row:
            hist[v] += 1
    total = sum(hist)
    sum_all = sum(i * hist[i] for i in range(256))
    best, best_t, w0, sum0 = -1.0, 0, 0, 0
    for t in range(256):
        w0 += hist[t]
        sum0 += t * hist[t]
        w1 = total - w0
        if w0 == 0 or w1 == 0:
            continue
        m0, m1 = sum0 / w0, (sum_all - sum0) / w1
        between = w0 * w1 * (m0 - m1) ** 2
        if between > best:
            best, best_t = between, t
    return best_t


def main(src, dst):
    w, h, rows = read_png(src)
    grey = luminance(rows, w)
    t = otsu(grey)
    dark = sum(v <= t for row in grey for v in row)
    dark_is_shape = 2 * dark <= w * h
    with open(dst, "w") as f:
        f.write(f"P1\n{w} {h}\n")
        for row in grey:
            f.write(" ".join("1" if (v <= t) == dark_is_shape else "0" for v in row) + "\n")
    print(f"{dst}: {w}x{h}, threshold {t}, shape pixels "
          f"{sum(((v <= t) == dark_is_shape) for row in grey for v in row)}")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
