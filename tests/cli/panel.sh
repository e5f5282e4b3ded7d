#!/usr/bin/env bash
# The window's panel and keys under Xvfb: Tab draws the panel (a box of
# text lines over the frame's top left corner, the rest of the frame
# untouched: tests/tools/xwdpanel.py), a second Tab takes it away, and M
# (shading) changes the setting that the next frame is rendered with: the
# window then shows lanray-render's --shading diffuse picture; a still
# frame that refines the lights gives way to a key that changes the view;
# U shows a frame rendered at a render scale in blocks, and smooth again;
# X shows a denoised server's frames raw (lanray-render's --denoise off
# picture) and denoised again (its --denoise on one); a path-traced view
# converges to 32x32 by itself, and N steps it on past 4x4 to 16x16, each
# converged frame lanray-render's.
# Keys go in through XTEST (xdotool), as a user's would.
set -u
BIN=${BIN:-bin}
source tests/tools/xvfb-lib.sh
window_test_begin Xvfb xwd xdotool

W=480 H=360
"$BIN/lanray-render" --width $W --height $H --aa 1 -o "$dir/phong.ppm" --quiet >/dev/null || fail "reference render"
"$BIN/lanray-render" --width $W --height $H --aa 1 --shading diffuse -o "$dir/diffuse.ppm" --quiet >/dev/null ||
    fail "diffuse reference"
! cmp -s "$dir/phong.ppm" "$dir/diffuse.ppm" || fail "the two shadings give one picture: the test cannot tell them apart"
start_xvfb 800x600x24
window_server server --width $W --height $H
at=$(appears "$dir/phong.ppm") || fail "the frame never showed"
read -r x y <<<"$(sed 's/found at \([0-9]*\),\([0-9]*\)/\1 \2/' <<<"$at")"
echo "the frame shows at $x,$y"
# the pointer over the window: without a window manager the keys go where it is
xdotool mousemove $((x + W / 2)) $((y + H / 2))
xdotool key Tab
ok=
for _ in $(seq 30); do
    sleep 0.2
    screenshot
    out=$(python3 tests/tools/xwdpanel.py "$dir/screen.xwd" "$dir/phong.ppm" "$x" "$y") && { ok=1; break; }
done
[ -n "$ok" ] || fail "Tab drew no panel of text: $out"
echo "Tab: $out"
[ -n "${PANEL_SHOT:-}" ] && cp "$dir/screen.xwd" "$PANEL_SHOT"
xdotool key Tab
appears "$dir/phong.ppm" >/dev/null || fail "a second Tab left the panel on the frame"
echo "Tab again: the frame untouched"
xdotool key m
appears "$dir/diffuse.ppm" >/dev/null || fail "M: the next frames are not lanray-render's --shading diffuse picture"
echo "M: the next frame is lanray-render's --shading diffuse picture"
stop_window_server server
# a still frame gives way to a change: the still frames refine the lamp's
# points up to 64 x 64 (a minute of work); once rows of the lamp's own 3 x 3
# or of the 12 x 12 one show (a still frame shows in part as its segments
# come), a larger one is on its way (12, 48 and 64 after them), and M drops
# it rather than wait for it.  Either picture will do: the 3 x 3 one stays
# on the screen only while the 12 x 12 one renders (half a second here, 3 s
# under AddressSanitizer), and a CI run's screenshots, a few a second on
# loaded cores, once missed such a picture and waited for it for 2 minutes.
W=240 H=180
still_refs $W $H still
window_server still --width $W --height $H --still-aa adaptive:4 --still-light-samples 64
window_at
rows=
for _ in $(seq 300); do
    screenshot
    rows=$(python3 tests/tools/xwdrows.py "$dir/screen.xwd" "$X" "$Y" "$dir/still3.ppm" "$dir/still12.ppm") ||
        fail "cannot read the screen: $rows"
    read -r _ three _ twelve _ <<<"$rows"
    [ "$three" -gt 0 ] || [ "$twelve" -gt 0 ] && break
    rows=
    sleep 0.2
done
[ -n "$rows" ] || fail "neither the still frame of 3 x 3 light points nor that of 12 x 12 showed"
xdotool mousemove $((X + W / 2)) $((Y + H / 2))
xdotool key m
for _ in $(seq 100); do grep -q "gave way to a change" "$dir/still.err" && break; sleep 0.2; done
grep -q "^lanray-server: frame [0-9]* gave way to a change$" "$dir/still.err" ||
    fail "M during a refining still frame: the frame did not give way: $(tail -3 "$dir/still.err")"
echo "a refining still frame gave way to M (pressed with rows of 3 x 3 and 12 x 12 points on the screen: $three and $twelve): $(grep -o 'frame [0-9]* gave way' "$dir/still.err")"
stop_window_server still
# U: the knot turning (--rotate) at a target out of reach, every frame at
# render scale 8, brought up smooth (the default: most 8 x 8 blocks of the
# window hold more than one colour), then in blocks (each one colour)
W=240 H=176
window_server scaled --width $W --height $H --target-fps 1000 --rotate 40
# shows UP: waits until the window's frame is brought up that way
shows() {
    local out=
    for _ in $(seq 40); do
        screenshot
        out=$(python3 tests/tools/xwdblocks.py "$dir/screen.xwd" "$X" "$Y" $W $H 8) && [ "$(tail -1 <<<"$out")" = "$1" ] && return 0
        sleep 0.2
    done
    echo "$out"
    return 1
}
window_at
xdotool mousemove $((X + W / 2)) $((Y + H / 2))
out=$(shows smooth) || fail "frames at render scale 8 were not brought up smooth: $out"
xdotool key u
out=$(shows blocks) || fail "U: frames at render scale 8 not shown in blocks: $out"
echo "U: frames at render scale 8 shown in blocks"
xdotool key u
out=$(shows smooth) || fail "U again: frames at render scale 8 not smooth again: $out"
echo "U again: smooth"
stop_window_server scaled
# X: the path-traced Cornell box served --denoise, shown raw, then denoised again
W=160 H=120
sed 's/^settings \(.*\)/settings \1 integrator path/' models/cornell.scene >"$dir/path.scene"
"$BIN/lanray-render" "$dir/path.scene" --width $W --height $H --aa 1 --denoise on -o "$dir/dn.ppm" --quiet >/dev/null ||
    fail "denoised reference"
"$BIN/lanray-render" "$dir/path.scene" --width $W --height $H --aa 1 -o "$dir/raw.ppm" --quiet >/dev/null ||
    fail "raw reference"
window_server denoised "$dir/path.scene" --width $W --height $H --denoise --still-aa 1 # one sample, still or not
at=$(appears "$dir/dn.ppm") || fail "the denoised frame never showed"
read -r x y <<<"$(sed 's/found at \([0-9]*\),\([0-9]*\)/\1 \2/' <<<"$at")"
xdotool mousemove $((x + W / 2)) $((y + H / 2))
xdotool key x
appears "$dir/raw.ppm" >/dev/null || fail "X: the frame was not shown raw"
xdotool key x
appears "$dir/dn.ppm" >/dev/null || fail "X again: the frame was not shown denoised again"
echo "X: the denoised frame shown raw, and denoised again"
stop_window_server denoised
# a path-traced view in a window converges by itself to 32x32 (its still
# frames adding up to lanray-render's --aa 32 picture); N steps from there
# to off, 2x2, adaptive 4x4, 4x4 and on past it to 16x16 (five presses),
# lanray-render's --aa 16 picture
W=32 H=24
for a in 1 16 32; do
    "$BIN/lanray-render" "$dir/path.scene" --width $W --height $H --aa $a -o "$dir/p$a.ppm" --quiet >/dev/null ||
        fail "reference at $a x $a"
done
window_server stepped "$dir/path.scene" --width $W --height $H
at=$(appears "$dir/p32.ppm" 300) || fail "a path-traced view in a window did not converge to lanray-render's 32x32"
read -r x y <<<"$(sed 's/found at \([0-9]*\),\([0-9]*\)/\1 \2/' <<<"$at")"
echo "a path-traced view converges to 32x32 by itself"
xdotool mousemove $((x + W / 2)) $((y + H / 2))
for _ in 1 2 3 4 5; do xdotool key n; sleep 0.1; done
appears "$dir/p16.ppm" 300 >/dev/null || fail "N five times: a path-traced view did not converge to lanray-render's 16x16"
echo "N: a path-traced view steps on to 16x16, its still frames adding up to lanray-render's picture"
stop_window_server stepped
exit 0
