#!/usr/bin/env bash
# The real SDL window under Xvfb: the server opens its window, a client
# renders, and the frame captured from the X screen equals lanray-render's.
set -u
BIN=${BIN:-bin}
dir=$(mktemp -d)
pids=()
cleanup() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null; done; wait 2>/dev/null; rm -rf "$dir"; }
trap cleanup EXIT
fail() { echo "FAIL: $*"; tail -5 "$dir"/*.err 2>/dev/null; exit 1; }
command -v Xvfb >/dev/null && command -v xwd >/dev/null || fail "Xvfb and xwd are needed (make deps installs them)"

W=240 H=160
"$BIN/lanray-render" --width $W --height $H --aa 1 -o "$dir/ref.ppm" --quiet >/dev/null || fail "reference render"
# -displayfd: Xvfb picks a free display number and tells us
Xvfb -displayfd 3 -screen 0 640x480x24 -nolisten tcp 3>"$dir/display" 2>"$dir/xvfb.err" &
pids+=($!)
for _ in $(seq 100); do [ -s "$dir/display" ] && break; sleep 0.05; done
[ -s "$dir/display" ] || fail "Xvfb did not start"
export DISPLAY=":$(head -1 "$dir/display")"
"$BIN/lanray-server" --port 0 --width $W --height $H --frames 0 >"$dir/server.log" 2>"$dir/server.err" &
pids+=($!)
for _ in $(seq 100); do port=$(sed -n 's/.*listening on .*:\([0-9]*\) (.*/\1/p' "$dir/server.log"); [ -n "$port" ] && break; sleep 0.05; done
[ -n "$port" ] || fail "server did not start"
grep -q "no display\|cannot open a window" "$dir/server.err" && fail "the server did not open a window"
"$BIN/lanray-client" "127.0.0.1:$port" --threads 2 2>"$dir/client.err" &
pids+=($!)
for _ in $(seq 50); do
    xwd -root -silent >"$dir/screen.xwd" 2>/dev/null
    if out=$(python3 tests/tools/xwdfind.py "$dir/screen.xwd" "$dir/ref.ppm"); then
        echo "window shows the rendered frame: $out"
        exit 0
    fi
    sleep 0.2
done
fail "the rendered frame never appeared on the X screen ($out)"
