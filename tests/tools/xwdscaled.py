#!/usr/bin/env python3
"""xwdscaled.py SCREEN.xwd X Y W H REF.ppm: whether the window at X,Y of
W x H on the screen shows REF scaled to fit, its shape kept and centred,
with black bars beside it (the server's window, resized or opened smaller
than its frame: server/display.c).  The window's frame is compared with
REF averaged over each screen pixel's footprint; prints the mean
difference (0-255) there, and with REF's top-left corner unscaled (what a
window that crops would show), and the brightest bar pixel.  Exit 0 when
the scaled frame is within 6 levels on average, the cropped one is not,
and the bars are black."""
import sys

from xwdfind import read_ppm, read_xwd


def fit(ww, wh, fw, fh):
    """The frame's rectangle in the window (display.c frame_rect)."""
    if ww == fw and wh == fh:
        return 0, 0, fw, fh
    w, h = ww, ww * fh // fw
    if h > wh:
        w, h = wh * fw // fh, wh
    w, h = max(w, 1), max(h, 1)
    return (ww - w) // 2, (wh - h) // 2, w, h


def averaged(ref, w, h):
    """REF (rows of RGB bytes) averaged to w x h, each pixel over its footprint."""
    rw, rh, rows = ref
    out = []
    for y in range(h):
        y0, y1 = y * rh // h, max((y + 1) * rh // h, y * rh // h + 1)
        line = []
        for x in range(w):
            x0, x1 = x * rw // w, max((x + 1) * rw // w, x * rw // w + 1)
            acc = [0, 0, 0]
            for yy in range(y0, y1):
                r = rows[yy]
                for xx in range(x0, x1):
                    for c in range(3):
                        acc[c] += r[3 * xx + c]
            n = (y1 - y0) * (x1 - x0)
            line.append([a / n for a in acc])
        out.append(line)
    return out


def main():
    sw, sh, screen = read_xwd(sys.argv[1])
    X, Y, W, H = (int(v) for v in sys.argv[2:6])
    if X < 0 or Y < 0 or X + W > sw or Y + H > sh:
        print("the %dx%d window at %d,%d is not all on the %dx%d screen" % (W, H, X, Y, sw, sh))
        return 1
    ref = read_ppm(sys.argv[6])
    fx, fy, fw, fh = fit(W, H, ref[0], ref[1])
    want = averaged(ref, fw, fh)
    scaled = cropped = 0.0
    for y in range(fh):
        row = screen[Y + fy + y]
        for x in range(fw):
            px = row[3 * (X + fx + x):3 * (X + fx + x) + 3]
            scaled += sum(abs(px[c] - want[y][x][c]) for c in range(3))
            cropped += sum(abs(px[c] - ref[2][y][3 * x + c]) for c in range(3)) if y < ref[1] and x < ref[0] else 0
    n = 3 * fw * fh
    bar = 0
    for y in range(H):
        row = screen[Y + y]
        for x in range(W):
            if not (fx <= x < fx + fw and fy <= y < fy + fh):
                bar = max(bar, max(row[3 * (X + x):3 * (X + x) + 3]))
    print("frame %dx%d at %d,%d in the %dx%d window: %.2f levels from the scaled picture, %.2f from its corner unscaled; "
          "bars at most %d" % (fw, fh, fx, fy, W, H, scaled / n, cropped / n, bar))
    return 0 if scaled / n < 6 and cropped / n >= 6 and bar == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
