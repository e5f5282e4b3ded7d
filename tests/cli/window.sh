#!/usr/bin/env bash
# The real SDL window under Xvfb: the server opens its window, a client
# renders, and the frame captured from the X screen equals lanray-render's;
# with --hdr, the sRGB codes of lanray-render's .hdr (through ACES's curve
# with --tonemap aces); a still frame shows
# as its segments come, over the frame before; P saves an idle window's
# picture at once.
set -u
BIN=${BIN:-bin}
source tests/tools/xvfb-lib.sh
window_test_begin Xvfb xwd xdotool

W=240 H=160
"$BIN/lanray-render" --width $W --height $H --aa 1 -o "$dir/ref.ppm" --quiet >/dev/null || fail "reference render"
start_xvfb 640x480x24
# shown NAME REF.ppm SERVER-ARGS...: a server with a window and one client;
# passes when REF appears on the X screen
shown() {
    local name=$1 ref=$2 out=; shift 2
    window_server "$name" --width $W --height $H --frames 0 "$@"
    out=$(appears "$ref" 50) || fail "$name: the rendered frame never appeared on the X screen ($out)"
    echo "$name: window shows the rendered frame: $out"
    stop_window_server "$name"
}
shown rgb8 "$dir/ref.ppm"
# a high dynamic range frame (--hdr: RGBE from the client) is shown as the
# sRGB codes of its light: lanray-render's .hdr, decoded as Radiance reads it
"$BIN/lanray-render" --width $W --height $H --aa 1 -o "$dir/ref.hdr" --quiet >/dev/null || fail "reference .hdr"
python3 - "$dir/ref.hdr" "$dir/hdr.ppm" <<'PY' || fail "cannot decode the reference .hdr"
import math, sys
head, _, body = open(sys.argv[1], "rb").read().partition(b"\n\n")
size, _, px = body.partition(b"\n")
h, w = int(size.split()[1]), int(size.split()[3])
def srgb(v):
    v = max(0.0, min(1.0, v))
    s = 12.92 * v if v <= 0.0031308 else 1.055 * v ** (1 / 2.4) - 0.055
    return int(s * 255 + 0.5)
out = bytearray()
for i in range(w * h):
    r, g, b, e = px[4 * i:4 * i + 4]
    f = math.ldexp(1.0, e - 136) if e else 0.0
    out += bytes(srgb((c + 0.5) * f) for c in (r, g, b))
open(sys.argv[2], "wb").write(b"P6\n%d %d\n255\n" % (w, h) + bytes(out))
PY
# (RGBE's mantissas move some codes: else the check would not tell the paths apart)
! cmp -s "$dir/ref.ppm" "$dir/hdr.ppm" || fail "the .hdr's codes equal the PNG's: the test cannot tell them apart"
shown hdr "$dir/hdr.ppm" --hdr
# with --tonemap aces the frames keep the light and the window shows it
# through the curve, as an 8-bit frame would: the .hdr's light in the
# build's reals through Narkowicz's fit, each step rounded as the build
# rounds it, coded by its sRGB thresholds (common/base/srgb_tables.c)
case "$("$BIN/lanray-server" --version)" in *double*) real=d ;; *) real=f ;; esac
python3 - "$dir/ref.hdr" "$dir/aces.ppm" "$real" <<'PY' || fail "cannot make the tone-mapped reference"
import math, re, struct, sys
head, _, body = open(sys.argv[1], "rb").read().partition(b"\n\n")
size, _, px = body.partition(b"\n")
h, w = int(size.split()[1]), int(size.split()[3])
single = sys.argv[3] == "f"
r = (lambda x: struct.unpack("f", struct.pack("f", x))[0]) if single else (lambda x: x)
tables = open("common/base/srgb_tables.c").read()
name = "srgb_threshold_f" if single else "srgb_threshold"
body_t = re.search(name + r"\[255\] = \{([^}]*)\}", tables).group(1)
thr = [r(float(t.rstrip("f"))) for t in body_t.replace("\n", " ").split(",") if t.strip()]
def aces(x):
    if not x > 0:
        return 0.0
    return r(r(x * r(r(r(2.51) * x) + r(0.03))) / r(r(x * r(r(r(2.43) * x) + r(0.59))) + r(0.14)))
def code(v):
    return sum(1 for t in thr if v >= t)
out = bytearray()
for i in range(w * h):
    cr, cg, cb, e = px[4 * i:4 * i + 4]
    f = math.ldexp(1.0, e - 136) if e else 0.0
    out += bytes(code(aces(r((c + 0.5) * f) if e else 0.0)) for c in (cr, cg, cb))
open(sys.argv[2], "wb").write(b"P6\n%d %d\n255\n" % (w, h) + bytes(out))
PY
! cmp -s "$dir/hdr.ppm" "$dir/aces.ppm" || fail "the curve changes no code: the test cannot tell"
shown hdr-aces "$dir/aces.ppm" --hdr --tonemap aces
# a window whose picture converged idles: with --still-aa 2 the second
# frame is lanray-render's --aa 2 picture, and no frame starts after it
# while nothing changes (the frames started, read twice a second apart)
"$BIN/lanray-render" --width $W --height $H --aa 2 -o "$dir/still.ppm" --quiet >/dev/null || fail "reference still"
mkdir "$dir/shots"
WINDOW_CWD=$dir/shots window_server idle --width $W --height $H --still-aa 2
appears "$dir/still.ppm" 50 >/dev/null || fail "idle: the converged picture never showed"
started() { kill -USR1 "$spid"; sleep 0.3; sed -n 's/^frames started \([0-9]*\);.*/\1/p' "$dir/idle.log" | tail -1; }
n1=$(started)
sleep 1
n2=$(started)
kill -0 "$spid" 2>/dev/null || fail "idle: the server died of a second SIGUSR1"
[ -n "$n1" ] && [ "$n1" = "$n2" ] || fail "idle: frames kept starting on a converged picture ($n1, then $n2)"
[ "$n1" -le 3 ] || fail "idle: $n1 frames for a picture that converged at the second"
echo "idle: the converged picture stays, $n1 frames started, none in the second after"
# the title names the scene and says the picture converged (no rate: no frame comes)
title=
for _ in $(seq 20); do
    title=$(timeout 5 xdotool getwindowname "$(timeout 5 xdotool search --name '^lanray')")
    [ "$title" = "lanray - built-in scene - converged - 1 client" ] && break
    sleep 0.2
done
[ "$title" = "lanray - built-in scene - converged - 1 client" ] || fail "idle: the title reads '$title'"
echo "idle: the title reads '$title'"
# P saves the picture shown, at once: an idle window gets no frame to save
# it with (P waited for the next frame, which never came)
window_at
xdotool mousemove $((X + W / 2)) $((Y + H / 2))
xdotool key p
for _ in $(seq 50); do compgen -G "$dir/shots/lanray-screenshot-*.png" >/dev/null && break; sleep 0.1; done
shot=$(compgen -G "$dir/shots/lanray-screenshot-*.png") || fail "P: no screenshot within 5 s of an idle window ($(cat "$dir/idle.err"))"
diff=$("$BIN/lanray-imgdiff" --csv "$shot" "$dir/still.ppm") || fail "P: cannot compare the screenshot"
[ "${diff%%,*}" = 0 ] || fail "P: the screenshot is not the picture shown ($diff)"
grep -q "saved lanray-screenshot-" "$dir/idle.err" || fail "P: the server did not say where it saved"
echo "P: an idle window's picture saved at once ($(basename "$shot")), lanray-render's --aa 2"
stop_window_server idle
# a still frame refines on the screen as its segments come, over the frame
# before: the round lamp's own 3 x 3 points a pixel, then 12 x 12; a
# path-traced view's 8 samples a pixel, then the last batch's 8 more.  The
# client renders in short spells (SIGCONT ... SIGSTOP) and each pause's
# screen is read: some rows must be the later picture's and others still
# the earlier one's, every row one of the two.
# in_part NAME OLD.ppm NEW.ppm SERVER-ARGS...
in_part() {
    local name=$1 old=$2 new=$3 seen= rows=
    shift 3
    window_server "$name" "$@" --segment 2
    kill -STOP "$cpid"
    window_at
    for _ in $(seq 400); do
        kill -CONT "$cpid"; sleep 0.02; kill -STOP "$cpid"; sleep 0.1
        screenshot
        rows=$(python3 tests/tools/xwdrows.py "$dir/screen.xwd" "$X" "$Y" "$old" "$new") ||
            fail "$name: cannot read the screen: $rows"
        read -r _ o _ n _ _ _ neither <<<"$rows"
        if [ "$neither" -eq 0 ] && [ "$o" -gt 0 ] && [ "$n" -gt 0 ]; then seen=$rows; break; fi
        [ "$neither" -eq 0 ] && [ "$o" -eq 0 ] && fail "$name: the last frame showed whole, never in part ($rows)"
    done
    kill -CONT "$cpid"
    [ -n "$seen" ] || fail "$name: the two frames never showed together ($rows)"
    echo "$name: the still frame showed in part over the one before: $seen"
    stop_window_server "$name"
}
W=120 H=80
still_refs $W $H lights
in_part lines "$dir/lights3.ppm" "$dir/lights12.ppm" --width $W --height $H --still-aa adaptive:4 \
    --still-light-samples 12
# the batch's part shown with the batches before, as its frame will be
for k in 4 5; do
    "$BIN/lanray-render" --width $W --height $H --integrator path --aa 4 --still-frame $k -o "$dir/batch$k.ppm" \
        --quiet >/dev/null || fail "reference of still frame $k"
done
in_part batches "$dir/batch4.ppm" "$dir/batch5.ppm" --width $W --height $H --integrator path --still-aa 4
exit 0
