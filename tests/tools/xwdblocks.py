#!/usr/bin/env python3
"""xwdblocks.py screen.xwd X Y W H K: how a window's frame at render scale K
was brought up: 'blocks' where every K x K block from (X, Y) is one colour,
'smooth' where more than a tenth of the blocks are not."""
import sys
sys.path.insert(0, "tests/tools")
from xwdfind import read_xwd
_, _, rows = read_xwd(sys.argv[1])
x0, y0, w, h, k = map(int, sys.argv[2:7])
mixed = total = 0
for by in range(0, h - k + 1, k):
    for bx in range(0, w - k + 1, k):
        total += 1
        first = rows[y0 + by][3 * (x0 + bx):3 * (x0 + bx) + 3]
        if any(rows[y0 + by + j][3 * (x0 + bx):3 * (x0 + bx + k)] != first * k for j in range(k)):
            mixed += 1
print("%d of %d blocks of %dx%d mixed" % (mixed, total, k, k))
print("blocks" if mixed == 0 else "smooth" if mixed * 10 > total else "neither")
