#!/usr/bin/env python3
"""Finds a PPM image, pixel for pixel, inside an X screen dump (xwd -root).

    xwdfind.py screen.xwd frame.ppm [other.ppm ...]

Prints 'found at X,Y' (with more than one image, 'found at X,Y: NAME',
the first found) and exits 0, or 'not found' and exits 1.
"""
import struct, sys


def read_xwd(path):
    d = open(path, "rb").read()
    f = struct.unpack(">25I", d[:100])
    header_size, fmt, depth, width, height = f[0], f[2], f[3], f[4], f[5]
    byte_order, bpp, bpl = f[7], f[11], f[12]
    red, green, blue, ncolors = f[14], f[15], f[16], f[19]
    if fmt != 2 or bpp not in (24, 32):
        sys.exit("unsupported xwd: format %d, %d bits per pixel" % (fmt, bpp))
    data = d[header_size + 12 * ncolors:]
    shift = lambda m: (m & -m).bit_length() - 1
    rs, gs, bs = shift(red), shift(green), shift(blue)
    step = bpp // 8
    rows = []
    # the usual screen: each channel a byte of the pixel: rows by slices
    # (the loop below took a second a dump under load, and the window tests
    # read dumps every 0.2 s)
    if all(m == 0xFF << s and s % 8 == 0 for m, s in ((red, rs), (green, gs), (blue, bs))):
        at = [s // 8 if byte_order == 0 else step - 1 - s // 8 for s in (rs, gs, bs)]
        for y in range(height):
            line = data[y * bpl:y * bpl + width * step]
            out = bytearray(width * 3)
            for c in range(3):
                out[c::3] = line[at[c]::step]
            rows.append(bytes(out))
        return width, height, rows
    for y in range(height):
        line = data[y * bpl:y * bpl + width * step]
        out = bytearray(width * 3)
        for x in range(width):
            px = line[x * step:(x + 1) * step]
            v = int.from_bytes(px, "little" if byte_order == 0 else "big")
            out[3 * x:3 * x + 3] = bytes(((v & red) >> rs, (v & green) >> gs, (v & blue) >> bs))
        rows.append(bytes(out))
    return width, height, rows


def read_ppm(path):
    d = open(path, "rb").read()
    # the header's four words, then one whitespace byte, then the pixels:
    # split(maxsplit=4) took pixel bytes that happen to be whitespace
    # (a first pixel of 10 or 13) for the header's end, and every row after
    # shifted (a dark sky's picture was "not found")
    words, at = [], 0
    while len(words) < 4:
        while d[at:at + 1].isspace():
            at += 1
        end = at
        while end < len(d) and not d[end:end + 1].isspace():
            end += 1
        words.append(d[at:end])
        at = end
    assert words[0] == b"P6" and words[3] == b"255"
    w, h = int(words[1]), int(words[2])
    pix = d[at + 1:]
    assert len(pix) >= w * h * 3, "%s: short of pixels" % path
    return w, h, [pix[y * w * 3:(y + 1) * w * 3] for y in range(h)]


def find(screen, img):
    """The top-left corner of img on the screen, or None."""
    w, h, rows = img
    for y in range(len(screen) - h + 1):
        start = 0
        while True:
            i = screen[y].find(rows[0], start)
            if i < 0:
                break
            if i % 3 == 0 and all(screen[y + k][i:i + 3 * w] == rows[k] for k in range(h)):
                return i // 3, y
            start = i + 1
    return None


def main():
    _, _, screen = read_xwd(sys.argv[1])
    names = sys.argv[2:]
    for name in names:
        at = find(screen, read_ppm(name))
        if at:
            print("found at %d,%d%s" % (at[0], at[1], ": " + name if len(names) > 1 else ""))
            return 0
    print("not found")
    return 1


if __name__ == "__main__":
    sys.exit(main())
