# server-lib.sh - helpers for the integration tests that run real servers
# and clients (sourced by tests/cli/distributed.sh and faults.sh).
# Provides: $dir (a scratch directory), pids (killed on exit), fail,
# start_server NAME ARGS (sets $port and $server_pid), run_prog (how
# start_server runs the server; a test may redefine it).
BIN=${BIN:-bin}
dir=$(mktemp -d)
pids=()
lib_cleanup() {
    for p in "${pids[@]}"; do kill -CONT "$p" 2>/dev/null; kill -9 "$p" 2>/dev/null; done
    wait 2>/dev/null
    rm -rf "$dir"
}
trap lib_cleanup EXIT
# the precision of the build under test, for tests/tools/fakeclient.py's handshake
case "$("$BIN/lanray-server" --version)" in *double*) export LANRAY_REAL_SIZE=8 ;; *) export LANRAY_REAL_SIZE=4 ;; esac
fail() { echo "FAIL: $*"; for f in "$dir"/*.log "$dir"/*.err; do [ -f "$f" ] && { echo "--- $f"; tail -20 "$f"; }; done; exit 1; }
# exec: in the background the function runs in a subshell, which becomes the program, so $! is its pid
run_prog() { exec "$@"; }
# start_server NAME ARGS...: runs lanray-server --headless in the background, sets $port
start_server() {
    local name=$1; shift
    run_prog "$BIN/lanray-server" --headless "$@" >"$dir/$name.log" 2>"$dir/$name.err" &
    server_pid=$!
    pids+=("$server_pid")
    for _ in $(seq 100); do
        port=$(sed -n 's/.*listening on .*:\([0-9]*\) (.*/\1/p' "$dir/$name.log")
        [ -n "$port" ] && return 0
        sleep 0.05
    done
    fail "$name did not start"
}
