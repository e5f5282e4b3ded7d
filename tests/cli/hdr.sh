#!/usr/bin/env bash
# High dynamic range output and exposure: lanray-render -o F.hdr writes a
# Radiance RGBE file (header, then 4 bytes a pixel) whose light, encoded
# as sRGB, is the PNG's pixels (within RGBE's 8-bit mantissas); the
# exposure scales the 8-bit path by 2^stops, from the command line or the
# scene file, also through a server and a client; a server's --hdr frames
# (RGBE from two clients, cut in segments that end inside lines) are
# lanray-render's .hdr byte for byte; refusals.
set -u
source tests/tools/server-lib.sh
W=96 H=72
scene="$dir/lit.scene"
cat >"$scene" <<'SCENE'
camera position 0 1 4 lookat 0 0.5 0 fov 50
ambient 0.05 0.05 0.05
settings aa 1
material floor diffuse 0.7 0.7 0.7
material hot diffuse 0.9 0.5 0.2 emit 6 3 1
plane point 0 0 0 normal 0 1 0 material floor
sphere centre 0 0.5 0 radius 0.5 material hot
light point position 2 4 3 intensity 2.5
SCENE
"$BIN/lanray-render" "$scene" -o "$dir/a.hdr" --width $W --height $H --quiet >/dev/null || fail ".hdr render failed"
"$BIN/lanray-render" "$scene" -o "$dir/a.png" --width $W --height $H --quiet >/dev/null || fail ".png render failed"
"$BIN/lanray-render" "$scene" -o "$dir/up.png" --width $W --height $H --exposure 1 --quiet >/dev/null || fail "--exposure failed"
"$BIN/lanray-render" "$scene" -o "$dir/down.png" --width $W --height $H --exposure -2 --quiet >/dev/null || fail "--exposure -2 failed"
python3 - "$dir" $W $H <<'PY' || fail "the .hdr and the exposures do not agree with the PNG"
import math, struct, sys, zlib
sys.path.insert(0, "tests/tools")
from pngpixel import read
def read_png(path):
    rows, ch = read(path)
    return len(rows[0]) // ch, len(rows), [row[i] for row in rows for i in range(len(row)) if i % ch < 3]
d, W, H = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
raw = open(d + "/a.hdr", "rb").read()
head, sep, body = raw.partition(b"\n\n")
assert head.startswith(b"#?RADIANCE") and b"FORMAT=32-bit_rle_rgbe" in head, head
size, _, px = body.partition(b"\n")
assert size == b"-Y %d +X %d" % (H, W), size
assert len(px) == W * H * 4, (len(px), W * H * 4)
def srgb(v):
    v = max(0.0, min(1.0, v))
    s = 12.92 * v if v <= 0.0031308 else 1.055 * v ** (1 / 2.4) - 0.055
    return int(s * 255 + 0.5)
def light(i):
    r, g, b, e = px[4 * i:4 * i + 4]
    if e == 0:
        return (0.0, 0.0, 0.0)
    f = math.ldexp(1.0, e - 136)  # (mantissa + 0.5) * 2^(e - 128 - 8)
    return ((r + 0.5) * f, (g + 0.5) * f, (b + 0.5) * f)
for name, gain in (("a.png", 1.0), ("up.png", 2.0), ("down.png", 0.25)):
    w, h, rgb = read_png(d + "/" + name)
    assert (w, h) == (W, H)
    worst, over = 0, 0
    for i in range(W * H):
        L = light(i)
        over += max(L) > 1.0
        for k in range(3):
            worst = max(worst, abs(srgb(L[k] * gain) - rgb[3 * i + k]))
    print("%s: largest difference from the .hdr's light %d codes" % (name, worst))
    assert worst <= 3, (name, worst)
assert over > 0, "the scene should hold light above 1 (the emissive sphere)"
# the exposure moves the picture: brighter up, darker down
a, u, dn = (sum(read_png(d + "/" + n)[2]) for n in ("a.png", "up.png", "down.png"))
assert dn < a < u, (dn, a, u)
PY
# the scene file's exposure equals the option's, locally and through a server
sed 's/^settings aa 1$/settings aa 1 exposure 1/' "$scene" >"$dir/exp.scene"
"$BIN/lanray-render" "$dir/exp.scene" -o "$dir/exp.png" --width $W --height $H --quiet >/dev/null || fail "exposure in the scene"
cmp -s "$dir/exp.png" "$dir/up.png" || fail "settings exposure 1 differs from --exposure 1"
"$BIN/lanray-render" "$dir/exp.scene" -o "$dir/exp64.png" --width 64 --height 64 --quiet >/dev/null || fail "exposure 64x64"
verify_distributed exposure "$dir/exp.scene" "$dir/exp64.png" "with an exposure"
# a server's high dynamic range frames: the same bytes as lanray-render's .hdr
# (the scene's exposure is for 8-bit pixels: it must change nothing here)
"$BIN/lanray-render" "$dir/exp.scene" -o "$dir/ref.hdr" --width 61 --height 37 --quiet >/dev/null || fail ".hdr 61x37"
start_server hdrsrv "$dir/exp.scene" --port 0 --width 61 --height 37 --frames 2 --wait-clients 2 --segment 3 --hdr \
    --out "$dir/hdrframes"
clients_until_done 2 2
wait "$server_pid" || fail "the --hdr server failed (exit $?)"
for f in 1 2; do
    cmp -s "$dir/hdrframes/frame-0000$f.hdr" "$dir/ref.hdr" || fail "the server's .hdr frame $f differs from lanray-render's"
done
[ -z "$(ls "$dir/hdrframes" | grep -v '^frame-0000[12]\.hdr$')" ] || fail "the --hdr server wrote other files: $(ls "$dir/hdrframes")"
# an 8-bit frame of the same scene still travels as RGB8 (the PNG of a server without --hdr)
"$BIN/lanray-render" "$dir/exp.scene" -o "$dir/ref8.png" --width 64 --height 64 --quiet >/dev/null || fail "8-bit reference"
verify_distributed rgb8 "$dir/exp.scene" "$dir/ref8.png" "after an hdr run"
# the server refuses --hdr with --linear or --verify (bad command line: 2)
"$BIN/lanray-server" --headless --hdr --linear --port 0 --frames 1 >/dev/null 2>"$dir/r1.txt"; [ $? -eq 2 ] ||
    fail "--hdr --linear should exit 2"
grep -q -- "--linear is for 8-bit frames" "$dir/r1.txt" || fail "--hdr --linear message: $(cat "$dir/r1.txt")"
"$BIN/lanray-server" --headless --hdr --verify "$dir/ref8.png" --port 0 --frames 1 >/dev/null 2>"$dir/r2.txt"; [ $? -eq 2 ] ||
    fail "--hdr --verify should exit 2"
grep -q -- "--verify compares 8-bit frames" "$dir/r2.txt" || fail "--hdr --verify message: $(cat "$dir/r2.txt")"
# refusals: --linear or --exposure with .hdr, an exposure out of range
"$BIN/lanray-render" "$scene" -o "$dir/b.hdr" --linear --quiet >/dev/null 2>&1; [ $? -eq 2 ] || fail "--linear with .hdr should exit 2"
[ ! -e "$dir/b.hdr" ] || fail "a refused .hdr left a file"
"$BIN/lanray-render" "$scene" -o "$dir/b.png" --exposure 40 --quiet >/dev/null 2>&1; [ $? -eq 2 ] || fail "--exposure 40 should exit 2"
printf 'settings exposure 33\n' >"$dir/bad.scene"
err=$("$BIN/lanray-render" "$dir/bad.scene" -o "$dir/b.png" 2>&1); [ $? -eq 1 ] || fail "exposure 33 in a scene should exit 1"
grep -q "bad.scene:1: 'exposure' of settings must be from -32 to 32" <<<"$err" || fail "exposure error: $err"
echo "hdr: .hdr light against the PNG, exposure from the option, the scene and a server; a server's .hdr frames equal lanray-render's"
exit 0
