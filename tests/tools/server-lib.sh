# server-lib.sh - helpers for the integration tests that run real servers
# and clients (sourced by tests/cli/*.sh).
# Provides: $dir (a scratch directory), pids (killed on exit), fail,
# server_done SECONDS WHAT, clients_until_done N THREADS, serve_flight NAME FRAMES, served_are NAME PICTURES,
# start_server NAME ARGS (sets $port and $server_pid), run_prog (how
# start_server runs the server; a test may redefine it), verify_distributed
# (one frame through a server and a client, checked against a reference),
# same_on_simd_paths and same_through_tmd (a picture on every SIMD path and
# from a model's .tmd).
BIN=${BIN:-bin}
# 1 where the build under test is a sanitizer's (make check-asan,
# check-tsan): its checks want every code path run, not again the long
# renders that measure accuracy (the same code, several times slower:
# the plain pass measures them)
sanitized=0
case "$BIN" in *asan* | *tsan*) sanitized=1 ;; esac
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
# server_done SECONDS WHAT: waits for the server started last to exit, at
# most SECONDS; one that still runs then (its clients gone: a client that
# died, its error in $dir/*.err, which fail shows) fails naming WHAT, at
# once rather than at the test's time limit
server_done() {
    local i
    for i in $(seq $(($1 * 20))); do kill -0 "$server_pid" 2>/dev/null || return 0; sleep 0.05; done
    fail "the server ($2) still runs after $1 s (its clients gone?)"
}
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
# clients_until_done N THREADS: N clients of THREADS threads (--once, their
# errors in $dir/c-until-K.err) join the server started last; waits for it
# to exit, and fails (showing every error file) where it still runs after
# 120 s (server_done), not at the test run's time limit
clients_until_done() {
    local c
    for c in $(seq "$1"); do
        "$BIN/lanray-client" "127.0.0.1:$port" --threads "$2" --once --quiet 2>"$dir/c-until-$c.err" &
        pids+=("$!")
    done
    server_done 120 "clients_until_done: $1 clients of $2 threads"
}
# serve_flight NAME FRAMES: two clients of one thread (--once, their errors
# in $dir/c-NAME-K.err) join the server started last, which must exit 0
# (within 120 s) having written FRAMES frames into $dir/NAME
serve_flight() {
    local name=$1 frames=$2 c
    for c in 1 2; do
        "$BIN/lanray-client" "127.0.0.1:$port" --threads 1 --once 2>"$dir/c-$name-$c.err" >/dev/null &
        pids+=("$!")
    done
    server_done 120 "$name"
    wait "$server_pid" || fail "the server ($name) exited $?"
    [ "$(ls "$dir/$name" | wc -l)" = "$frames" ] || fail "$frames frames ($name): $(ls "$dir/$name")"
}
# served_are NAME PICTURE...: frame k of the flight in $dir/NAME is
# $dir/PICTURE_k.png bit for bit (lanray-render's)
served_are() {
    local name=$1 k=1 f
    shift
    for f in "$@"; do
        cmp -s "$dir/$name/frame-$(printf %05d $k).png" "$dir/$f.png" || fail "served frame $k ($name) is not lanray-render's $f"
        k=$((k + 1))
    done
}
# verify_distributed NAME SCENE REF.png WHAT [OPTIONS]: a server with one client renders
# one frame of SCENE (64x64) and checks it against REF.png bit for bit; fails
# naming WHAT when it differs
verify_distributed() {
    local name=$1 scene=$2 ref=$3 what=$4
    shift 4 # the rest: more of the server's options
    start_server "$name" "$scene" --port 0 --width 64 --height 64 --frames 1 --wait-clients 1 --verify "$ref" --out "$dir/f-$name" "$@"
    "$BIN/lanray-client" "127.0.0.1:$port" --threads 2 --once --quiet 2>"$dir/c-$name.err" &
    pids+=("$!")
    server_done 120 "$name"
    wait "$server_pid" || fail "the distributed frame $what differs from lanray-render's (server exit $?): $(tail -3 "$dir/$name.err")"
}
# setting_travels NAME SET PLAIN WHAT OPTION...: scene SET, whose settings
# hold what OPTION gives scene PLAIN, through a server and a client is
# lanray-render's picture of it (64 x 64, one sample), and so is PLAIN
# served with OPTION (the setting travels with the view)
setting_travels() {
    local name=$1 set=$2 plain=$3 what=$4
    shift 4
    "$BIN/lanray-render" "$set" --width 64 --height 64 --aa 1 -o "$dir/$name-64.png" --quiet >/dev/null 2>&1 ||
        fail "lanray-render $set did not render"
    verify_distributed "$name-set" "$set" "$dir/$name-64.png" "with the scene's $what"
    verify_distributed "$name-opt" "$plain" "$dir/$name-64.png" "with $*" "$@"
}
# untouched_by WHAT OPTION...: path-traced scenes that OPTION must leave
# byte for byte, as nothing in them is met right after a diffuse bounce
# with a glossy lobe, a mirror or glass to change: the Cornell box's
# diffuse walls (its panel a plain emitter) with a see-through veil in it
# (ior 1: it bends nothing, no caustic; $dir/box.scene, left for the
# test), and a mirror and a glass ball alone under the sky of
# tests/data/cycles/caustics.scene (every path after the camera's a
# delta's); fails naming WHAT
untouched_by() {
    local what=$1 s cy=tests/data/cycles
    shift
    { grep -v "^light rect" models/cornell.scene | sed 's/^settings .*/settings integrator path depth 8/'
      printf 'material veil ior 1 transmit 0.5 0.5 0.5\nsphere centre 278 120 278 radius 120 material veil\n'; } \
        >"$dir/box.scene"
    sed -e "s|^texture sky sky.hdr|texture sky $PWD/$cy/sky.hdr|" -e '/gold\|floor/d' "$cy/caustics.scene" \
        >"$dir/delta.scene"
    for s in box delta; do
        "$BIN/lanray-render" "$dir/$s.scene" --width 48 --height 36 --aa 2 -o "$dir/$s-0.png" --quiet >/dev/null 2>&1 &&
            "$BIN/lanray-render" "$dir/$s.scene" --width 48 --height 36 --aa 2 "$@" -o "$dir/$s-1.png" --quiet \
                >/dev/null 2>&1 || fail "lanray-render $s.scene $* did not render"
        cmp -s "$dir/$s-0.png" "$dir/$s-1.png" || fail "$s.scene changed $what"
    done
}
# refused_setting LINE MESSAGE: a scene whose first line is LINE (its
# settings) is refused by lanray-render, exit 1, naming the file, line 1
# and MESSAGE, and leaves no picture
refused_setting() {
    printf '%s\nsphere centre 0 0 -3 radius 1\n' "$1" >"$dir/bad.scene"
    rm -f "$dir/bad.png"
    local out
    out=$("$BIN/lanray-render" "$dir/bad.scene" -o "$dir/bad.png" 2>&1)
    [ $? = 1 ] && grep -q "bad.scene:1: $2" <<<"$out" || fail "$1: $out"
    [ ! -e "$dir/bad.png" ] || fail "$1: the refused scene left its picture"
}
# same_on_simd_paths SCENE PNG W H WHAT: lanray-render of SCENE at W x H
# (--aa 1) on each SIMD path this CPU and build have gives PNG's bytes
same_on_simd_paths() {
    local scene=$1 png=$2 w=$3 h=$4 what=$5 p
    for p in scalar sse avx2 avx512; do
        "$BIN/lanray-render" "$scene" --width "$w" --height "$h" --aa 1 --simd "$p" -o "$dir/simd-$p.png" --quiet \
            >/dev/null 2>&1 || continue # a path this CPU or build lacks
        cmp -s "$png" "$dir/simd-$p.png" || fail "the $p path renders $what differently"
    done
}
# same_through_tmd MODEL SCENE PNG W H WHAT: SCENE, which names MODEL by its
# file name, renders (W x H, --aa 1) to PNG's bytes with MODEL converted to
# a .tmd: what the material says travels in the file
same_through_tmd() {
    local model=$1 scene=$2 png=$3 w=$4 h=$5 what=$6 base
    base=$(basename "$model")
    "$BIN/obj2tmd" "$model" "$dir/through.tmd" >"$dir/tmd.log" 2>&1 || fail "obj2tmd: $(cat "$dir/tmd.log")"
    sed "s/$base/through.tmd/" "$scene" >"$dir/through.scene"
    "$BIN/lanray-render" "$dir/through.scene" --width "$w" --height "$h" --aa 1 -o "$dir/through.png" --quiet \
        >/dev/null 2>&1 || fail "render the .tmd of $base"
    cmp -s "$png" "$dir/through.png" || fail "the .tmd's $what renders differently from $base's"
}
