#!/usr/bin/env python3
"""Which of two pictures each row of a window on an X screen dump shows.

    xwdrows.py screen.xwd X Y old.ppm new.ppm

The window's frame is the PPMs' size at X,Y on the screen (xwd -root).
Prints 'old N new M both K neither L': rows equal to old.ppm's alone, to
new.ppm's alone, to both (where the two pictures agree) and to neither.
"""
import sys

from xwdfind import read_ppm, read_xwd


def main():
    if len(sys.argv) != 6:
        sys.exit(__doc__)
    _, _, screen = read_xwd(sys.argv[1])
    x, y = int(sys.argv[2]), int(sys.argv[3])
    w, h, old = read_ppm(sys.argv[4])
    w2, h2, new = read_ppm(sys.argv[5])
    if (w, h) != (w2, h2):
        sys.exit("the two pictures differ in size: %dx%d and %dx%d" % (w, h, w2, h2))
    if y + h > len(screen) or 3 * (x + w) > len(screen[0]):
        sys.exit("a %dx%d frame at %d,%d is not all on the screen" % (w, h, x, y))
    counts = {"old": 0, "new": 0, "both": 0, "neither": 0}
    for r in range(h):
        row = screen[y + r][3 * x:3 * (x + w)]
        is_old, is_new = row == old[r], row == new[r]
        counts["both" if is_old and is_new else "old" if is_old else "new" if is_new else "neither"] += 1
    print("old %(old)d new %(new)d both %(both)d neither %(neither)d" % counts)


main()
