# xvfb-lib.sh - sourced by the window tests: an X server of their own and
# a look at its screen.  Needs $dir, the pids array and fail() from the test.

# start_xvfb WxHxD: Xvfb on a free display (it picks it: -displayfd), DISPLAY set
start_xvfb() {
    Xvfb -displayfd 3 -screen 0 "$1" -nolisten tcp 3>"$dir/display" 2>"$dir/xvfb.err" &
    pids+=($!)
    for _ in $(seq 100); do [ -s "$dir/display" ] && break; sleep 0.05; done
    [ -s "$dir/display" ] || fail "Xvfb did not start"
    export DISPLAY=":$(head -1 "$dir/display")"
}

# appears REF.ppm [TRIES]: waits (0.2 s a try, 60 tries) until REF is on
# the screen, pixel for pixel; prints 'found at X,Y', or what xwdfind said
# and returns 1.  The last screen stays in $dir/screen.xwd.
appears() {
    local out=
    for _ in $(seq "${2:-60}"); do
        xwd -root -silent >"$dir/screen.xwd" 2>/dev/null
        out=$(python3 tests/tools/xwdfind.py "$dir/screen.xwd" "$1") && { echo "$out"; return 0; }
        sleep 0.2
    done
    echo "$out"
    return 1
}
