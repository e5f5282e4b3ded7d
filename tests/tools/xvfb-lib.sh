# xvfb-lib.sh - sourced by the window tests: their start (a folder, the
# processes to end, fail()), an X server of their own and a look at its
# screen.

# window_test_begin TOOL...: $dir (a temporary folder, removed at exit),
# the pids array (ended at exit), fail(); fails naming a TOOL missing
window_test_begin() {
    dir=$(mktemp -d)
    pids=()
    trap window_test_cleanup EXIT
    local t
    for t in "$@"; do command -v "$t" >/dev/null || fail "$t is needed (make deps installs it)"; done
}
window_test_cleanup() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null; done; wait 2>/dev/null; rm -rf "$dir"; }
fail() { echo "FAIL: $*"; tail -5 "$dir"/*.err 2>/dev/null; exit 1; }

# start_xvfb WxHxD: Xvfb on a free display (it picks it: -displayfd), DISPLAY set
start_xvfb() {
    Xvfb -displayfd 3 -screen 0 "$1" -nolisten tcp 3>"$dir/display" 2>"$dir/xvfb.err" &
    pids+=($!)
    for _ in $(seq 100); do [ -s "$dir/display" ] && break; sleep 0.05; done
    [ -s "$dir/display" ] || fail "Xvfb did not start"
    export DISPLAY=":$(head -1 "$dir/display")"
}

# screenshot: the whole screen into $dir/screen.xwd.  Every call to the X
# server is bounded (here and in window_at): a CI run once sat 85 minutes
# in this test's window steps until CI's own limit ended it, naming nothing.
screenshot() { timeout 10 xwd -root -silent >"$dir/screen.xwd" 2>/dev/null; }

# appears_any TRIES REF.ppm...: waits (0.2 s a try) until any of the REFs
# is on the screen, pixel for pixel; prints 'found at X,Y' (with more than
# one REF, 'found at X,Y: REF', the first found), or what xwdfind said and
# returns 1.  The last screen stays in $dir/screen.xwd.
appears_any() {
    local tries=$1 out=
    shift
    for _ in $(seq "$tries"); do
        screenshot
        out=$(python3 tests/tools/xwdfind.py "$dir/screen.xwd" "$@") && { echo "$out"; return 0; }
        sleep 0.2
    done
    echo "$out"
    return 1
}

# appears REF.ppm [TRIES]: appears_any of one REF, 60 tries unless told
appears() { appears_any "${2:-60}" "$1"; }

# window_server NAME SERVER-ARGS...: a server with a window on the X screen
# (its output in $dir/NAME.log and NAME.err) and one client of two threads
# (NAME-client.err); sets spid, cpid and port.  WINDOW_CWD: the folder the
# server runs in (where P saves), else this one.
window_server() {
    local name=$1 exe; shift
    exe=$(realpath "$BIN/lanray-server")
    # under AddressSanitizer (make check-asan) without leak detection: SDL
    # opens a D-Bus connection for a window and libdbus keeps a kilobyte of
    # it to the end (its own stack, and 112 bytes more that LeakSanitizer
    # cannot place); the headless tests check the server's own leaks
    (cd "${WINDOW_CWD:-.}" && ASAN_OPTIONS="detect_leaks=0${ASAN_OPTIONS:+:$ASAN_OPTIONS}" \
        exec "$exe" --port 0 "$@") >"$dir/$name.log" 2>"$dir/$name.err" &
    spid=$!
    pids+=($spid)
    port=
    for _ in $(seq 100); do port=$(sed -n 's/.*listening on .*:\([0-9]*\) (.*/\1/p' "$dir/$name.log"); [ -n "$port" ] && break; sleep 0.05; done
    [ -n "$port" ] || fail "$name: server did not start"
    grep -q "no display\|cannot open a window" "$dir/$name.err" && fail "$name: the server did not open a window"
    "$BIN/lanray-client" "127.0.0.1:$port" --threads 2 2>"$dir/$name-client.err" &
    cpid=$!
    pids+=($cpid)
}

# window_at: the geometry of the one window titled lanray... (X, Y, WIDTH,
# HEIGHT set), waiting up to 10 s for it; fails naming how many there were
window_at() {
    local ids=
    for _ in $(seq 50); do
        ids=$(timeout 5 xdotool search --name '^lanray' 2>/dev/null)
        [ "$(wc -w <<<"$ids")" -eq 1 ] && break
        sleep 0.2
    done
    [ "$(wc -w <<<"$ids")" -eq 1 ] || fail "not one lanray window on the screen but $(wc -w <<<"$ids")"
    eval "$(timeout 5 xdotool getwindowgeometry --shell "$ids")"
    [ -n "${X:-}" ] && [ -n "${Y:-}" ] || fail "the window's geometry could not be read"
}

# sized W H: waits (5 s) until the window is W x H (WIDTH, HEIGHT, X, Y
# set by WINDOW_AT, window_at unless the test names another)
sized() {
    for _ in $(seq 25); do
        ${WINDOW_AT:-window_at}
        [ "$WIDTH" -eq "$1" ] && [ "$HEIGHT" -eq "$2" ] && return 0
        sleep 0.2
    done
    fail "the window is ${WIDTH}x$HEIGHT, not $1x$2"
}

# stop_window_server NAME: SIGTERM to the server that window_server started
# and to its client; the server must end (exit 0, as its --help says) within
# 10 s and take its window with it
stop_window_server() {
    kill "$spid" "$cpid" 2>/dev/null
    for _ in $(seq 100); do kill -0 "$spid" 2>/dev/null || break; sleep 0.1; done
    kill -0 "$spid" 2>/dev/null && fail "$1: the server did not end within 10 s of SIGTERM"
    wait "$spid"; local rc=$?
    [ "$rc" -eq 0 ] || { tail -20 "$dir/$1.err"; fail "$1: the server ended with exit $rc on SIGTERM"; }
    wait "$cpid" 2>/dev/null
}

# still_refs W H NAME: lanray-render's still frames of the round lamp's own
# 3 x 3 and 12 x 12 points a pixel (adaptive 4x4; a server's first two still
# frames with --still-light-samples 12 or more) into $dir/NAME3.ppm and
# NAME12.ppm, which must differ (the tests tell them apart)
still_refs() {
    local n
    for n in 3 12; do
        "$BIN/lanray-render" --width "$1" --height "$2" --aa adaptive:4 --light-samples $n -o "$dir/$3$n.ppm" --quiet \
            >/dev/null || fail "$n x $n reference"
    done
    ! cmp -s "$dir/${3}3.ppm" "$dir/${3}12.ppm" || fail "3 x 3 and 12 x 12 points give one picture: no test"
}
