#!/usr/bin/env python3
"""Checks that a PNG screenshot is not blank: decodes it with the standard
library alone (zlib and the PNG row filters) and counts its distinct pixel
colours; exits 1 when there are fewer than --min (default 16) or when fewer
than --min-ink percent (default 1) of the pixels differ from the most
frequent colour, 2 when the file cannot be decoded.

    ci/png-colours.py SHOT.png [--min N] [--min-ink PERCENT]

Prints "SHOT.png: WIDTHxHEIGHT, N distinct colours, M% of pixels not the
background" (the background being the most frequent colour).
"""

import struct
import sys
import zlib

CHANNELS = {0: 1, 2: 3, 3: 1, 4: 2, 6: 4}


def chunks(data):
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError("not a PNG file (bad signature)")
    at = 8
    while at + 12 <= len(data):
        (length,) = struct.unpack(">I", data[at : at + 4])
        kind = data[at + 4 : at + 8]
        body = data[at + 8 : at + 8 + length]
        if len(body) != length:
            raise ValueError("truncated chunk %r" % kind)
        yield kind, body
        at += 12 + length


def paeth(a, b, c):
    p = a + b - c
    pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
    if pa <= pb and pa <= pc:
        return a
    return b if pb <= pc else c


def decode(data):
    """(width, height, rows of pixel tuples)."""
    header, idat, palette = None, [], None
    for kind, body in chunks(data):
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"PLTE":
            palette = [tuple(body[i : i + 3]) for i in range(0, len(body), 3)]
        elif kind == b"IDAT":
            idat.append(body)
        elif kind == b"IEND":
            break
    if header is None:
        raise ValueError("no IHDR chunk")
    width, height, depth, colour, _, _, interlace = header
    if colour not in CHANNELS or depth not in (8, 16) or interlace != 0:
        raise ValueError(
            "unsupported PNG: colour type %d, depth %d, interlace %d" % (colour, depth, interlace)
        )
    if colour == 3 and (palette is None or depth != 8):
        raise ValueError("palette PNG without PLTE or not 8-bit")
    bpp = CHANNELS[colour] * depth // 8
    stride = width * bpp
    raw = zlib.decompress(b"".join(idat))
    if len(raw) < height * (stride + 1):
        raise ValueError("image data too short")
    rows, prev = [], bytearray(stride)
    for y in range(height):
        start = y * (stride + 1)
        kind = raw[start]
        line = bytearray(raw[start + 1 : start + 1 + stride])
        if kind == 1:
            for i in range(bpp, stride):
                line[i] = (line[i] + line[i - bpp]) & 255
        elif kind == 2:
            for i in range(stride):
                line[i] = (line[i] + prev[i]) & 255
        elif kind == 3:
            for i in range(stride):
                left = line[i - bpp] if i >= bpp else 0
                line[i] = (line[i] + ((left + prev[i]) >> 1)) & 255
        elif kind == 4:
            for i in range(stride):
                left = line[i - bpp] if i >= bpp else 0
                up_left = prev[i - bpp] if i >= bpp else 0
                line[i] = (line[i] + paeth(left, prev[i], up_left)) & 255
        elif kind != 0:
            raise ValueError("bad filter type %d in row %d" % (kind, y))
        pixels = [bytes(line[i : i + bpp]) for i in range(0, stride, bpp)]
        if colour == 3:
            pixels = [palette[p[0]] for p in pixels]
        rows.append(pixels)
        prev = line
    return width, height, rows


def main(argv):
    args = argv[1:]
    minimum, min_ink = 16, 1.0
    for flag in ("--min", "--min-ink"):
        if flag in args:
            i = args.index(flag)
            if i + 1 >= len(args):
                print(__doc__, file=sys.stderr)
                return 2
            if flag == "--min":
                minimum = int(args[i + 1])
            else:
                min_ink = float(args[i + 1])
            del args[i : i + 2]
    if len(args) != 1:
        print(__doc__, file=sys.stderr)
        return 2
    path = args[0]
    try:
        with open(path, "rb") as f:
            width, height, rows = decode(f.read())
    except (OSError, ValueError, zlib.error) as e:
        print("%s: cannot decode: %s" % (path, e), file=sys.stderr)
        return 2
    counts = {}
    for row in rows:
        for p in row:
            counts[p] = counts.get(p, 0) + 1
    total = max(1, width * height)
    background = max(counts.values()) if counts else 0
    ink = 100.0 * (total - background) / total
    print(
        "%s: %dx%d, %d distinct colours, %.1f%% of pixels not the background"
        % (path, width, height, len(counts), ink)
    )
    if len(counts) < minimum or ink < min_ink:
        print(
            "%s: blank or nearly blank screenshot: %d distinct colours (at least %d wanted), "
            "%.2f%% of pixels drawn (at least %.2f%% wanted)"
            % (path, len(counts), minimum, ink, min_ink),
            file=sys.stderr,
        )
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
