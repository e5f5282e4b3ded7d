#!/usr/bin/env bash
# The path tracer of the book (tools/bench/rtweekend, issue 31's baseline) and
# the reference scenes: a white furnace (a Lambertian sphere of albedo 1 under
# a sky of 1) comes out 1 at every pixel; the picture does not depend on the
# threads (its numbers come from the pixel and the sample); the benchmark
# scene it writes for lanray (104 spheres: the seed's 100, the ground, the
# book's three) and models/cornell.scene render with lanray-render, the
# Cornell box's walls red on the left and green on the right.
set -u
BIN=${BIN:-bin}
RTW=${RTWEEKEND:-${BUILD:-build/float}/tools/bench/rtweekend}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
[ -x "$RTW" ] || fail "$RTW not built"
"$RTW" --furnace --width 48 --height 32 --spp 16 -o "$dir/f.ppm" >/dev/null || fail "the furnace did not render"
python3 - "$dir/f.ppm" <<'PY' || fail "the white furnace is not white"
import sys
d = open(sys.argv[1], 'rb').read().split(b'\n', 3)[3]
assert len(d) == 48 * 32 * 3 and min(d) == 255, (len(d), min(d))
PY
"$RTW" --width 96 --height 54 --spp 4 --threads 1 -o "$dir/one.ppm" --write-scene "$dir/spheres.scene" >/dev/null &&
    "$RTW" --width 96 --height 54 --spp 4 --threads 2 -o "$dir/two.ppm" >/dev/null || fail "the benchmark scene did not render"
cmp -s "$dir/one.ppm" "$dir/two.ppm" || fail "1 and 2 threads give different pictures"
"$RTW" --width 96 --height 54 --spp 4 --threads 1 --seed 2 -o "$dir/seed2.ppm" >/dev/null
cmp -s "$dir/one.ppm" "$dir/seed2.ppm" && fail "another seed gave the same scene: the test cannot tell"
[ "$(grep -c '^sphere ' "$dir/spheres.scene")" = 104 ] || fail "the written scene does not hold 104 spheres"
"$BIN/lanray-render" "$dir/spheres.scene" --aa 1 -o "$dir/spheres.png" --quiet >/dev/null ||
    fail "lanray-render refused the written scene"
"$BIN/lanray-render" models/cornell.scene --aa 1 --width 64 --height 64 -o "$dir/cornell.png" --quiet >/dev/null ||
    fail "lanray-render refused models/cornell.scene"
python3 - "$dir/cornell.png" <<'PY' || fail "the Cornell box's walls are not red (left) and green (right)"
import sys, zlib, struct
raw = open(sys.argv[1], 'rb').read()
pos, idat, w = 8, b'', 0
while pos < len(raw):
    n, t = struct.unpack('>I4s', raw[pos:pos + 8])
    if t == b'IHDR':
        w, h, depth, ctype = struct.unpack('>IIBB', raw[pos + 8:pos + 18])
        assert depth == 8 and ctype == 2
    if t == b'IDAT':
        idat += raw[pos + 8:pos + 8 + n]
    pos += 12 + n
data = zlib.decompress(idat)
stride = 1 + 3 * w
rows = [bytearray(data[y * stride + 1:(y + 1) * stride]) for y in range(h)]
for y in range(h):  # undo the PNG filters
    f, prev = data[y * stride], rows[y - 1] if y else bytearray(3 * w)
    r = rows[y]
    for i in range(3 * w):
        a = r[i - 3] if i >= 3 else 0
        b, c = prev[i], prev[i - 3] if i >= 3 else 0
        p = a + b - c
        pr = a if abs(p - a) <= abs(p - b) and abs(p - a) <= abs(p - c) else b if abs(p - b) <= abs(p - c) else c
        r[i] = (r[i] + [0, a, b, (a + b) // 2, pr][f]) & 255
px = lambda x, y: rows[y][3 * x:3 * x + 3]
left, right = px(5, 32), px(58, 32)
assert left[0] > 3 * left[1] and right[1] > 1.5 * right[0] and right[1] > 1.5 * right[2], (left, right)
PY
echo "rtweekend: a white furnace comes out white; 1 and 2 threads give one picture; the benchmark scene (104 spheres) and the Cornell box render in lanray"
