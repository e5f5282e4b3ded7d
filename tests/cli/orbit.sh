#!/usr/bin/env bash
# A view found in the window, kept: under Xvfb, a right drag orbits the
# camera round the middle of the view (the picture changes), a middle drag
# too, with Shift a right drag pans, and K prints the view as a scene's
# camera line (and puts it on the clipboard), which
# lanray-render --camera renders as the very picture the window shows,
# pixel for pixel.  A bad --camera is a bad command line (exit 2, the
# field named), for lanray-render and the server.
set -u
BIN=${BIN:-bin}
source tests/tools/xvfb-lib.sh
window_test_begin Xvfb xwd xdotool

W=240 H=180
start_xvfb 400x300x24
"$BIN/lanray-render" --width $W --height $H --aa 1 -o "$dir/home.ppm" --quiet >/dev/null || fail "the home view"
window_server orbit --width $W --height $H --aa 1 --frames 0
window_at
out=$(appears "$dir/home.ppm" 75) || fail "the window does not show the scene's view ($out)"

# view NAME N: K pressed; the N-th view line it prints, rendered by
# lanray-render --camera into $dir/NAME.ppm, must come on the screen
view() {
    xdotool key k
    local line=
    for _ in $(seq 50); do
        line=$(sed -n "s/^lanray-server: the view[^:]*: //p" "$dir/orbit.err" | sed -n "$2p")
        [ -n "$line" ] && break
        sleep 0.1
    done
    [ -n "$line" ] || fail "$1: K printed no view ($(tail -3 "$dir/orbit.err"))"
    "$BIN/lanray-render" --camera "$line" --width $W --height $H --aa 1 -o "$dir/$1.ppm" --quiet >/dev/null ||
        fail "$1: lanray-render --camera '$line'"
    cmp -s "$dir/$1.ppm" "$dir/home.ppm" && fail "$1: the view did not change ($line)"
    # ... and on the clipboard, to paste
    local pasted
    pasted=$(timeout 10 python3 tests/tools/xclipboard.py) || fail "$1: nothing to paste ($pasted)"
    [ "$pasted" = "$line" ] || fail "$1: the clipboard holds '$pasted', not the view"
    out=$(appears "$dir/$1.ppm" 75) || fail "$1: the window does not show lanray-render --camera '$line' ($out)"
    echo "$1: $line: the window's picture, pixel for pixel"
}

# drag BUTTON DX DY: the mouse dragged from the window's middle, in steps
drag() {
    xdotool mousemove $((X + W / 2)) $((Y + H / 2)) mousedown "$1"
    for _ in $(seq 10); do xdotool mousemove_relative -- $(($2 / 10)) $(($3 / 10)); sleep 0.02; done
    xdotool mouseup "$1"
}

drag 3 100 -30
view "right drag" 1
drag 2 -60 20
view "middle drag" 2
xdotool keydown shift
drag 3 50 40
xdotool keyup shift
view "Shift and a right drag (a pan)" 3
angles() { sed -n "s/^lanray-server: the view[^:]*: .*\( yaw .* pitch [^ ]*\).*/\1/p" "$dir/orbit.err" | sed -n "$1p"; }
[ "$(angles 3)" = "$(angles 2)" ] || fail "the pan turned the camera: '$(angles 2)' to '$(angles 3)'"
stop_window_server orbit

# a bad --camera: exit 2, the field named, nothing rendered
"$BIN/lanray-render" --camera "position 1 2 yaw 3" -o "$dir/bad.png" --quiet >/dev/null 2>"$dir/bad.err"
rc=$?
[ $rc -eq 2 ] || fail "lanray-render --camera with two numbers: exit $rc"
grep -q "'position' of camera expects 3 finite numbers" "$dir/bad.err" || fail "not said: $(cat "$dir/bad.err")"
[ -e "$dir/bad.png" ] && fail "lanray-render wrote a picture for a bad --camera"
"$BIN/lanray-server" --port 0 --headless --camera "position 0 0 0 lookat 0 0 0" --out "$dir/f" >/dev/null 2>"$dir/bads.err"
rc=$?
[ $rc -eq 2 ] || fail "lanray-server with a bad --camera: exit $rc"
grep -q "lookat' point equals its position" "$dir/bads.err" || fail "not said: $(cat "$dir/bads.err")"
echo "orbit: a bad --camera is refused with exit 2, the field named"
