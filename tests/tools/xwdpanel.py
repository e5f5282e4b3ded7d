#!/usr/bin/env python3
"""Checks that the window's panel is drawn over a frame on an X screen dump.

    xwdpanel.py screen.xwd frame.ppm X Y

The frame (a PPM, as lanray-render wrote it) is shown at X,Y of the screen
(xwdfind.py found it there before the panel was shown).  Passes (exit 0)
when the pixels that differ from the frame make one box at the window's
top left corner, outside which the frame is untouched, darker than the
frame inside (its translucent background), and holding lines of text: light
glyph pixels where the frame has none, in at least MIN_LINES bands of rows
apart.  Prints what it measured.
"""
import sys

sys.path.insert(0, __import__("os").path.dirname(__file__))
from xwdfind import read_ppm, read_xwd  # noqa: E402

MIN_LINES = 8
MIN_GLYPH_PIXELS = 400


def main():
    _, _, screen = read_xwd(sys.argv[1])
    w, h, img = read_ppm(sys.argv[2])
    ox, oy = int(sys.argv[3]), int(sys.argv[4])
    x0 = y0 = 10 ** 9
    x1 = y1 = -1
    for y in range(h):
        row, ref = screen[oy + y][3 * ox:3 * (ox + w)], img[y]
        if row == ref:
            continue
        for x in range(w):
            if row[3 * x:3 * x + 3] != ref[3 * x:3 * x + 3]:
                x0, y0, x1, y1 = min(x0, x), min(y0, y), max(x1, x), max(y1, y)
    if x1 < 0:
        print("no panel: the window shows the frame untouched")
        return 1
    glyphs, darker, inside, text_rows = 0, 0, 0, []
    for y in range(y0, y1 + 1):
        row, ref = screen[oy + y], img[y]
        lit = False
        for x in range(x0, x1 + 1):
            s = row[3 * (ox + x):3 * (ox + x) + 3]
            r = ref[3 * x:3 * x + 3]
            inside += 1
            if min(s) >= 200 and max(r) < 200:
                glyphs += 1
                lit = True
            elif sum(s) < sum(r) or sum(r) == 0:
                darker += 1
        text_rows.append(lit)
    bands = sum(1 for i, lit in enumerate(text_rows) if lit and (i == 0 or not text_rows[i - 1]))
    print("panel box %d,%d to %d,%d; %d glyph pixels in %d lines of text; %.0f%% of the rest darker"
          % (x0, y0, x1, y1, glyphs, bands, 100.0 * darker / max(1, inside - glyphs)))
    ok = x0 <= 10 and y0 <= 10 and x1 > 100 and y1 > 100
    ok = ok and glyphs >= MIN_GLYPH_PIXELS and bands >= MIN_LINES and darker > 0.6 * (inside - glyphs)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
