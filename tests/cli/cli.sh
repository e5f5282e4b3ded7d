#!/usr/bin/env bash
# What a user meets on the command line, tool by tool (issue 13): --help and
# --version on standard output with exit 0, every option with its range and
# default, errors that say the allowed range, exit statuses that mean what
# the help says, checks made before the work, progress on a terminal only.
set -u
source tests/tools/server-lib.sh
root=$(pwd)
tools="lanray-render lanray-server lanray-client obj2tmd lanray-imgdiff schedsim"
# --help with each option's wrapped lines joined into one
help_of() { "$BIN/$1" --help | sed -e ':a' -e 'N' -e '$!ba' -e 's/\n \{26\}/ /g'; }

# 1. --help and --version: standard output, exit 0, nothing on standard error
for t in $tools; do
    out=$("$BIN/$t" --help 2>"$dir/err") || fail "$t --help exited $?"
    [ -s "$dir/err" ] && fail "$t --help wrote to standard error: $(cat "$dir/err")"
    grep -q "^usage: $t " <<<"$out" || fail "$t --help has no usage line"
    grep -q -- "--version" <<<"$out" || fail "$t --help does not list --version"
    grep -q "^exit status:" <<<"$out" || fail "$t --help does not document its exit statuses"
    # every option the help lists is one the tool takes (help must not promise what the parser lacks;
    # the parser's tables, the same under the sanitizers, where 150 starts took a quarter minute)
    [ $sanitized = 1 ] ||
    for o in $(grep -o '^  \(-[a-z], \)\?--[a-z-]*' <<<"$out" | sed 's/.*--/--/' | sort -u); do
        case $o in --help | --version) continue ;; esac
        "$BIN/$t" "$o" --help >/dev/null 2>&1 || fail "$t rejects $o, which its help lists"
    done
    v=$("$BIN/$t" --version) || fail "$t --version exited $?"
    grep -q "^$t [0-9]" <<<"$v" || fail "$t --version: $v"
done
# ranges and defaults are shown, taken from the real values
h=$(help_of lanray-render)
grep -q -- "--width W .*1\.\.65536 (default the scene's, else 1024)" <<<"$h" || fail "lanray-render --help lacks the width range"
grep -q -- "--threads T .*0 = one per core" <<<"$h" || fail "lanray-render --help: --threads 0"
grep -q -- "--repeat N" <<<"$h" || fail "lanray-render has no --repeat"
h=$(help_of lanray-server)
grep -q -- "--frames N .*stop after N frames, 0 = run until stopped" <<<"$h" || fail "lanray-server --frames help"
grep -q -- "--port P .*0\.\.65535 (default 7878)" <<<"$h" || fail "lanray-server --port default"
# --frames means frames to render and write, wherever it exists: lanray-render's repeats are --repeat
"$BIN/lanray-render" --frames 2 2>&1 | grep -q "unknown option '--frames'" || fail "lanray-render still takes --frames"

# 2. errors name the option and its range, exit 2
err=$("$BIN/lanray-render" --width 0 2>&1); [ $? -eq 2 ] || fail "--width 0 should exit 2"
grep -q "^lanray-render: --width wants 1\.\.65536, got '0'$" <<<"$err" || fail "width message: $err"
err=$("$BIN/lanray-server" --width 20000 2>&1); [ $? -eq 2 ] || fail "server --width 20000 should exit 2"
grep -q "\-\-width wants 1\.\.16384, got '20000'" <<<"$err" || fail "server width message: $err"
err=$("$BIN/lanray-render" --shading flat 2>&1); [ $? -eq 2 ] || fail "--shading flat should exit 2"
grep -q "\-\-shading wants phong or diffuse, got 'flat'" <<<"$err" || fail "choice message: $err"
err=$("$BIN/obj2tmd" --leaf 999 a.obj b.tmd 2>&1); [ $? -eq 2 ] || fail "--leaf 999 should exit 2"
grep -q "\-\-leaf wants 1\.\.255, got '999'" <<<"$err" || fail "leaf message: $err"
err=$("$BIN/lanray-client" --threads 2>&1); [ $? -eq 2 ] || fail "a missing value should exit 2"
grep -q "\-\-threads needs a value (0\.\.1024)" <<<"$err" || fail "missing value message: $err"
"$BIN/lanray-render" --width=48 --height=32 --threads=0 --aa 1 -o "$dir/eq.png" --quiet >/dev/null || fail "--opt=value and --threads 0"
[ "$(python3 -c 'import struct,sys; d=open(sys.argv[1],"rb").read(); print(*struct.unpack(">II", d[16:24]))' "$dir/eq.png")" = "48 32" ] ||
    fail "--width=48 --height=32 not honoured"

# 3. lanray-client --once with no server: the reason first, exit 1, no statistics
err=$("$BIN/lanray-client" 127.0.0.1:1 --once 2>&1); rc=$?
[ $rc -eq 1 ] || fail "a client that never connected exited $rc"
[ "$(head -1 <<<"$err")" = "lanray-client: cannot connect to 127.0.0.1 port 1: Connection refused" ] || fail "client message: $err"
grep -q "rendered" <<<"$err" && fail "statistics for a client that never connected: $err"

# 4. a server stopped before its --frames exits 4; one with no count asked exits 0 on SIGTERM
start_server early --port 0 --width 64 --height 48 --frames 100000 --out "$dir/early"
"$BIN/lanray-client" "127.0.0.1:$port" --threads 1 --quiet 2>/dev/null & pids+=($!)
for _ in $(seq 100); do [ -e "$dir/early/frame-00002.png" ] && break; sleep 0.05; done
kill -TERM "$server_pid"; wait "$server_pid"; rc=$?
[ $rc -eq 4 ] || fail "a server stopped before its frames were done exited $rc"
grep -q "stopped after [0-9]* of 100000 frames" "$dir/early.err" || fail "no word of the frames left undone"
start_server open --port 0 --width 64 --height 48 --out "$dir/open"
kill -TERM "$server_pid"; wait "$server_pid"; rc=$?
[ $rc -eq 0 ] || fail "a server with no --frames stopped by SIGTERM exited $rc"

# 5. lanray-render checks the output before rendering: a frame that would take minutes fails at once
# (an image format lanray does not write is a bad command line, 2; a
# directory that is not there is an error of the run, 1)
for o in "$dir/out.jpg" "$dir/missing/dir/out.png"; do
    t0=$(date +%s%N)
    err=$("$BIN/lanray-render" --width 8000 --height 8000 --aa 16 -o "$o" 2>&1); rc=$?
    ms=$((($(date +%s%N) - t0) / 1000000))
    case $o in *.jpg) want=2 ;; *) want=1 ;; esac
    [ $rc -eq $want ] || fail "-o $o exited $rc, not $want"
    grep -q "Mrays/s" <<<"$err" && fail "-o $o rendered before failing: $err"
    [ $ms -lt 20000 ] || fail "-o $o took $ms ms to fail"
done
grep -q "unknown image format" <<<"$("$BIN/lanray-render" -o "$dir/out.jpg" 2>&1)" || fail "jpg message"
grep -q "the directory $dir/missing/dir does not exist" <<<"$("$BIN/lanray-render" -o "$dir/missing/dir/o.png" 2>&1)" ||
    fail "missing directory message"
ls "$dir"/missing 2>/dev/null && fail "a directory was created for -o"

# 6. obj2tmd refuses an output that is its input, by file, not by name
cp models/cube.obj models/cube.mtl "$dir/"
sum=$(md5sum <"$dir/cube.obj")
ln -s cube.obj "$dir/link.obj"
for o in "$dir/cube.obj" "$dir/link.obj" "$dir/./cube.obj"; do
    err=$("$BIN/obj2tmd" "$dir/cube.obj" "$o" 2>&1); rc=$?
    [ $rc -eq 1 ] || fail "obj2tmd with output $o (the input) exited $rc"
    grep -q "is the input file" <<<"$err" || fail "same-file message: $err"
done
[ "$(md5sum <"$dir/cube.obj")" = "$sum" ] || fail "obj2tmd changed its input"
# an output that is not a .tmd: a command-line error, nothing written
err=$("$BIN/obj2tmd" "$dir/cube.obj" "$dir/out.xyz" 2>&1); rc=$?
[ $rc -eq 2 ] && grep -q "out.xyz: the output is a .tmd file" <<<"$err" || fail "obj2tmd to out.xyz: exit $rc, $err"
[ -e "$dir/out.xyz" ] && fail "obj2tmd wrote out.xyz"

# 7. frames too large for memory: a server refuses with what it needs; lanray-render renders in bands
# (address-space limits are the test's lever; the sanitizers reserve terabytes of it, so not there)
sanitized=0
case "$BIN" in *asan* | *tsan*) sanitized=1 ;; esac
if [ $sanitized = 0 ]; then
    err=$(ulimit -v 600000; "$BIN/lanray-server" --headless --port 0 --width 16384 --height 16384 --frames 1 2>&1); rc=$?
    [ $rc -eq 1 ] || fail "a server frame larger than memory exited $rc"
    grep -q "the frame needs 805 MB of memory; this machine has [0-9]* MB available" <<<"$err" || fail "memory message: $err"
fi
"$BIN/lanray-render" --width 300 --height 200 --aa adaptive -o "$dir/whole.png" --quiet >/dev/null || fail "whole frame"
"$BIN/lanray-render" --width 300 --height 200 --aa adaptive --band 7 --repeat 2 -o "$dir/bands.png" --quiet >/dev/null || fail "bands"
grep -q "^max difference 0," <<<"$("$BIN/lanray-imgdiff" "$dir/whole.png" "$dir/bands.png")" || fail "bands differ from the whole frame"
# lanray-imgdiff reads what lanray writes besides PNG: the same frame as a PPM compares equal
"$BIN/lanray-render" --width 300 --height 200 --aa adaptive -o "$dir/whole.ppm" --quiet >/dev/null || fail "whole frame as PPM"
grep -q "^max difference 0," <<<"$("$BIN/lanray-imgdiff" "$dir/whole.png" "$dir/whole.ppm" 2>&1)" || fail "imgdiff PNG against PPM"
if [ $sanitized = 0 ]; then
    # a 113 MB frame under a 90 MB limit: refused whole, written in bands of 16 lines
    printf 'camera position 0 0 5 lookat 0 0 0\nsettings aa 1\nlight point position 0 5 5\nsphere centre 0 0 0 radius 0.1\n' >"$dir/tiny.scene"
    err=$(ulimit -v 90000; "$BIN/lanray-render" "$dir/tiny.scene" --width 6144 --height 6144 -o "$dir/big.ppm" 2>&1); rc=$?
    [ $rc -eq 1 ] || fail "a whole frame larger than memory exited $rc"
    grep -q "the frame needs 113 MB of memory" <<<"$err" || fail "lanray-render memory message: $err"
    (ulimit -v 90000; "$BIN/lanray-render" "$dir/tiny.scene" --width 6144 --height 6144 --band 16 -o "$dir/big.ppm" \
        --threads 2 --quiet >/dev/null 2>"$dir/big.err") || fail "a 113 MB frame in bands under a 90 MB limit"
    [ "$(stat -c %s "$dir/big.ppm")" -eq $((6144 * 6144 * 3 + 17)) ] || fail "banded PPM size $(stat -c %s "$dir/big.ppm")"
    rm -f "$dir/big.ppm"
fi

# interrupted (SIGINT, SIGTERM, SIGHUP) while it writes, lanray-render
# leaves no temporary file behind, and ends by the signal
for sig in INT TERM HUP; do
    mkdir -p "$dir/sig"
    "$BIN/lanray-render" --width 6000 --height 6000 --threads 1 -o "$dir/sig/big.png" --quiet >/dev/null 2>&1 &
    p=$!
    for _ in $(seq 100); do ls "$dir"/sig/big.png.tmp.* >/dev/null 2>&1 && break; sleep 0.05; done
    ls "$dir"/sig/big.png.tmp.* >/dev/null 2>&1 || fail "no temporary file while rendering"
    kill -$sig $p
    wait $p 2>/dev/null; rc=$?
    [ -z "$(ls -A "$dir/sig")" ] || fail "SIG$sig left $(ls "$dir/sig")"
    [ $rc -gt 128 ] || fail "lanray-render ended with $rc after SIG$sig"
done

# 8. --out creates its directories; --listen localhost is loopback; IPv6
start_server nested --port 0 --width 32 --height 24 --frames 1 --out "$dir/a/b/c"
"$BIN/lanray-client" "127.0.0.1:$port" --threads 1 --once --quiet 2>/dev/null
wait "$server_pid" || fail "nested --out run failed"
[ -e "$dir/a/b/c/frame-00001.png" ] || fail "--out a/b/c was not created"
start_server localhost --port 0 --listen localhost --width 32 --height 24 --frames 1 --out "$dir/lh"
"$BIN/lanray-client" "localhost:$port" --threads 1 --once --quiet 2>/dev/null
wait "$server_pid" || fail "--listen localhost without a token should be loopback and serve"
if python3 -c 'import socket; s=socket.socket(socket.AF_INET6); s.bind(("::1", 0))' 2>/dev/null; then
    start_server v6 --port 0 --listen ::1 --width 32 --height 24 --frames 1 --out "$dir/v6"
    grep -q "listening on \[::1\]:$port" "$dir/v6.log" || fail "IPv6 listening line: $(cat "$dir/v6.log")"
    "$BIN/lanray-client" "[::1]:$port" --threads 1 --once 2>"$dir/v6c.err" || fail "IPv6 client: $(cat "$dir/v6c.err")"
    grep -q "connected to \[::1\]:$port with 1 threads" "$dir/v6c.err" || fail "IPv6 client's line: $(cat "$dir/v6c.err")"
    wait "$server_pid" || fail "IPv6 server"
    [ -e "$dir/v6/frame-00001.png" ] || fail "no frame over IPv6"
else
    echo "cli: no IPv6 loopback here; IPv6 not tested"
fi

# a client's back-off starts again at 0.1 s after a session that worked:
# a server for one frame, a gap while its port is closed (0.1, 0.2, 0.4
# ... s), a second server for one frame on the same port, then 0.1 s again
start_server one --port 0 --width 32 --height 24 --frames 1 --out "$dir/b1"
"$BIN/lanray-client" "127.0.0.1:$port" --threads 1 2>"$dir/backoff.err" & bc=$!
pids+=($bc)
wait "$server_pid"
sleep 1.6
start_server two --port "$port" --width 32 --height 24 --frames 1 --out "$dir/b2"
wait "$server_pid"
for _ in $(seq 40); do [ "$(grep -c "reconnecting in 0.1 s" "$dir/backoff.err")" -ge 2 ] && break; sleep 0.05; done
kill $bc 2>/dev/null; wait $bc 2>/dev/null
[ "$(grep -c "connected to 127.0.0.1:$port" "$dir/backoff.err")" -eq 2 ] || fail "back-off: two sessions: $(cat "$dir/backoff.err")"
[ "$(grep -c "reconnecting in 0.1 s" "$dir/backoff.err")" -ge 2 ] || fail "back-off not reset after a session: $(cat "$dir/backoff.err")"
# a server that cannot listen (its port taken) leaves no --out directory
start_server taken --port 0 --width 32 --height 24 --out "$dir/taken"
err=$("$BIN/lanray-server" --headless --port "$port" --width 32 --height 24 --frames 1 --out "$dir/never" 2>&1); rc=$?
[ $rc -eq 1 ] || fail "a server on a taken port exited $rc: $err"
[ -e "$dir/never" ] && fail "a server that could not listen created its --out directory"
kill "$server_pid"; wait "$server_pid" 2>/dev/null
# --verify against a reference made with lanray-render's defaults says why it may differ
"$BIN/lanray-render" --width 32 --height 24 -o "$dir/vref.png" --quiet >/dev/null 2>&1 || fail "verify reference"
start_server vfy --port 0 --width 32 --height 24 --frames 1 --verify "$dir/vref.png" --out "$dir/vf"
"$BIN/lanray-client" "127.0.0.1:$port" --threads 1 --once --quiet 2>/dev/null
wait "$server_pid"; rc=$?
[ $rc -eq 3 ] && grep -q "pixels differ from $dir/vref.png (is it the server's picture? it renders --aa 1, and lanray-render adaptive:4" \
    "$dir/vfy.err" || fail "--verify hint (exit $rc): $(cat "$dir/vfy.err")"
# a client killed mid-run: the summary says how many were there at the most and at the end
start_server gone --port 0 --width 320 --height 240 --frames 6 --wait-clients 2 --out "$dir/gone"
"$BIN/lanray-client" "127.0.0.1:$port" --threads 1 --once --quiet 2>/dev/null & keep=$!
"$BIN/lanray-client" "127.0.0.1:$port" --threads 1 --quiet 2>/dev/null & victim=$!
pids+=($keep $victim)
for _ in $(seq 200); do [ -e "$dir/gone/frame-00002.png" ] && break; sleep 0.05; done
kill -9 $victim
wait "$server_pid" || fail "server with a killed client: $(cat "$dir/gone.err")"
grep -q "^6 frames in [0-9.]* s: [0-9.]* fps with up to 2 clients, 1 at the end, 1 gone" "$dir/gone.log" ||
    fail "summary after a client was killed: $(cat "$dir/gone.log")"

# 9. progress: on a terminal only, off with --quiet; the headless server says at most a line a second
# (a render of the default scene long on any machine, 1024x768 at 4x4
# samples on one thread: the first progress line comes after a second,
# and the render is stopped there, or after 2.5 s where none may come)
render=("$BIN/lanray-render" --width 1024 --height 768 --aa 4 --threads 1 -o "$dir/p.png")
out=$(python3 tests/tools/ptyrun.py --for 60 --until "Mrays/s, .* left" "${render[@]}")
grep -q "lanray-render: [0-9]* of 768 lines ([0-9]*%), [0-9.]* Mrays/s, .* left" <<<"$out" || fail "no progress on a terminal: $out"
out=$(python3 tests/tools/ptyrun.py --for 2.5 "${render[@]}" --quiet)
grep -q " lines (" <<<"$out" && fail "progress despite --quiet"
out=$(timeout 2.5 "${render[@]}" 2>&1)
grep -q " lines (" <<<"$out" && fail "progress on a pipe"
python3 -c "
import math
n = $([ $sanitized = 1 ] && echo 250 || echo 500)  # 500k triangles (125k sanitized): the MST takes over a second (the progress line waits one)
with open('$dir/grid.obj', 'w') as f:
    for j in range(n + 1):
        for i in range(n + 1):
            f.write('v %g %g %g\n' % (i / n, 0.1 * math.sin(i * 0.3) * math.cos(j * 0.2), j / n))
    for j in range(n):
        for i in range(n):
            a = j * (n + 1) + i + 1
            f.write('f %d %d %d %d\n' % (a, a + 1, a + n + 2, a + n + 1))
"
out=$(python3 tests/tools/ptyrun.py --for 120 --until "grid.obj \([0-9]+ s\)" "$BIN/obj2tmd" --bvh mst "$dir/grid.obj" "$dir/grid.tmd")
grep -q "obj2tmd: building the MST tree of .*grid.obj ([0-9]* s)" <<<"$out" || fail "no obj2tmd progress: $out"
start_server status --port 0 --width 32 --height 24 --out "$dir/st"
"$BIN/lanray-client" "127.0.0.1:$port" --threads 1 --quiet 2>/dev/null & pids+=($!)
sleep 3.5
kill -TERM "$server_pid"; wait "$server_pid"
n=$(grep -c " frames, [0-9.]* fps, 1 client" "$dir/status.err")
[ "$n" -ge 2 ] && [ "$n" -le 4 ] || fail "$n status lines in 3.5 s: $(cat "$dir/status.err")"
# 10. a plain make without the libraries: one line that says to run make deps, no compiler errors
out=$(env -u MAKEFLAGS -u MAKELEVEL make --no-print-directory LIB_HEADERS=/nonexistent/SDL2/SDL.h 2>&1); rc=$?
[ $rc -ne 0 ] || fail "make without the libraries succeeded"
[ "$(wc -l <<<"$out")" -eq 1 ] || fail "make without the libraries printed more than one line: $out"
grep -q "run 'make deps' first" <<<"$out" || fail "make without the libraries: $out"
# 12. defaults: a still image is anti-aliased (adaptive) unless the scene or the user says; a
# server stays at one sample; a scene without light is warned about; the scene may set the size
printf 'camera position 0 0 4 lookat 0 0 0\nsphere centre 0 0 0 radius 1\n' >"$dir/dark.scene"
out=$("$BIN/lanray-render" "$dir/dark.scene" --width 32 --height 24 -o "$dir/dark.png" 2>&1) || fail "dark scene: $out"
grep -q "32x24 aa 4 adaptive" <<<"$out" || fail "lanray-render is not adaptive by default: $out"
grep -q "warning: the scene has no light" <<<"$out" || fail "no warning for a scene without light: $out"
printf 'settings aa 2 width 40 height 30\ncamera position 0 0 4 lookat 0 0 0\nsphere centre 0 0 0 radius 1\nlight point position 0 5 5\n' >"$dir/sized.scene"
out=$("$BIN/lanray-render" "$dir/sized.scene" -o "$dir/sized.png" 2>&1) || fail "sized scene: $out"
grep -q "^40x30 aa 2 phong" <<<"$out" || fail "the scene's size and samples were not used: $out"
grep -q "warning" <<<"$out" && fail "a warning for a scene with a light: $out"
start_server sized "$dir/sized.scene" --port 0 --frames 1 --out "$dir/sz"
"$BIN/lanray-client" "127.0.0.1:$port" --threads 1 --once --quiet 2>/dev/null
wait "$server_pid" || fail "sized server"
grep -q "listening on .* (40x30," "$dir/sized.log" || fail "the server did not take the scene's size: $(cat "$dir/sized.log")"
grep -q "^max difference 0," <<<"$("$BIN/lanray-imgdiff" "$dir/sized.png" "$dir/sz/frame-00001.png")" || fail "server frame differs"
start_server plain --port 0 --width 48 --height 32 --frames 1 --out "$dir/pl"
"$BIN/lanray-client" "127.0.0.1:$port" --threads 1 --once --quiet 2>/dev/null
wait "$server_pid" || fail "plain server"
"$BIN/lanray-render" --width 48 --height 32 --aa 1 -o "$dir/pl1.png" --quiet >/dev/null
grep -q "^max difference 0," <<<"$("$BIN/lanray-imgdiff" "$dir/pl1.png" "$dir/pl/frame-00001.png")" ||
    fail "a server's default is not one sample per pixel"
# a model alone: a preview with the camera framed on it (all of it in the frame, filling a good part)
# foreground PPM: the share of an 80x60 preview's pixels that are not the
# background, and the box they span: "share x0 x1 y0 y1"
foreground() {
    python3 - "$1" <<'PY'
import sys
d = open(sys.argv[1], "rb").read()
w, h = 80, 60
px = d[len(d) - w * h * 3:]
bg = px[0:3]
fg = [(i % w, i // w) for i in range(w * h) if px[3 * i:3 * i + 3] != bg]
xs, ys = [x for x, _ in fg], [y for _, y in fg]
print("%.3f %d %d %d %d" % (len(fg) / (w * h), min(xs), max(xs), min(ys), max(ys)))
PY
}
out=$("$BIN/lanray-render" models/cube.obj --width 80 --height 60 --aa 1 -o "$dir/cube.ppm" 2>&1) || fail "preview: $out"
read -r share x0 x1 y0 y1 <<<"$(foreground "$dir/cube.ppm")"
echo "preview covers $(python3 -c "print(round(100 * $share))")%, x $x0..$x1, y $y0..$y1"
python3 -c "import sys; sys.exit(0 if 0.1 < $share < 0.8 else 1)" && [ "$x0" -gt 0 ] && [ "$x1" -lt 79 ] && [ "$y0" -gt 0 ] &&
    [ "$y1" -lt 59 ] || fail "the preview does not frame the model"

# a model longer along z than x is previewed from its side: its picture is wider than tall
python3 -c "
v = [(x, y, z) for z in (-2, 2) for y in (0, 1) for x in (-0.5, 0.5)]
f = [(1,2,4,3),(5,7,8,6),(1,5,6,2),(3,4,8,7),(1,3,7,5),(2,6,8,4)]
open('$dir/long.obj', 'w').write(''.join('v %g %g %g\\n' % p for p in v) + ''.join('f %d %d %d %d\\n' % q for q in f))"
"$BIN/lanray-render" "$dir/long.obj" --width 80 --height 60 --aa 1 -o "$dir/long.ppm" --quiet >/dev/null 2>&1 || fail "long preview"
read -r share x0 x1 y0 y1 <<<"$(foreground "$dir/long.ppm")"
[ $((2 * (x1 - x0))) -gt $((3 * (y1 - y0))) ] || fail "a long model is not previewed from its side: x $x0..$x1, y $y0..$y1"
printf 'v -0.5 0 -2\nv 0.5 0 -2\nv 0.5 1 -2\n' >"$dir/tri.obj"
printf 'f 1 2 3\n' >>"$dir/tri.obj"
"$BIN/obj2tmd" "$dir/tri.obj" "$dir/tri.tmd" | grep -q "bounds x -0.5..0.5, y 0..1, z -2..-2 (size 1 x 1 x 0)" ||
    fail "obj2tmd prints no bounds: $("$BIN/obj2tmd" "$dir/tri.obj" "$dir/tri.tmd")"

# 13. the demo's log reads in order: the listening line before the first join, the table at the end;
# it flies its path and ends on the converged frame (STILL_LIGHTS 0: the lamp's own points, no frames that
# refine them, which cost a third of a minute at the demo's 12 x 12 and more under the sanitizers; path.sh
# checks those frames)
# (under the sanitizers at 320x240: the 1024x768 frames took a third of a minute there)
demo_size=
[ $sanitized = 1 ] && demo_size=320x240
out=$(DISPLAY= WAYLAND_DISPLAY= FRAMES=2 STILL_LIGHTS=0 SIZE=$demo_size OUT="$dir/demo" BIN="$BIN" bash tools/demo 2>&1) ||
    fail "demo: $out"
l=$(grep -n "listening on" <<<"$out" | head -1 | cut -d: -f1)
j=$(grep -n " joined with 1 thread$" <<<"$out" | head -1 | cut -d: -f1)
t=$(grep -n "frames started" <<<"$out" | head -1 | cut -d: -f1)
[ -n "$l" ] && [ -n "$j" ] && [ -n "$t" ] && [ "$l" -lt "$j" ] && [ "$j" -lt "$t" ] || fail "demo log out of order: $out"
grep -q "^  client address  *threads  *segments  *lines/s  *dup px  *bytes in  *bytes out$" <<<"$out" || fail "no statistics table: $out"
# FRAMES=2 is raised to 3: the flight's start and its end, which is its start again (frame 2 is already a
# still one), and the converged frame
grep -q "^3 frames in [0-9.]* s: [0-9.]* fps with 2 clients" <<<"$out" || fail "no summary line: $out"
grep -q "^path: frames 1 to 2 in [0-9.]* s, [0-9.]* fps while moving$" <<<"$out" || fail "no frame rate held: $out"
grep -q "^path: converged frame 3, " <<<"$out" || fail "the demo did not end converged: $out"
[ "$(ls "$dir/demo" | wc -l)" = 3 ] || fail "the demo wrote $(ls "$dir/demo" | wc -l) frames, not 3"

# 11. no header of ours has the name of one that the system headers we use include: with -Iserver, a
# server/sched.h was taken for <sched.h> inside <pthread.h>, and gcc -MMD then left every header
# reached from it out of the dependency files, so changing them rebuilt nothing
used=$(gcc -std=c17 -M -D_POSIX_C_SOURCE=200809L -Icommon -Iserver -Iclient common/*/*.c server/*.c client/*.c tools/*.c tests/*.c \
    2>/dev/null | tr ' \\' '\n\n' | grep '^/' | sort -u)
[ -n "$used" ] || fail "gcc -M listed no system headers"
sys=$(grep -hoE '^\s*#\s*include\s*<[^>]+>' $used | sed -E 's/.*<([^>]+)>.*/\1/' | sort -u)
# (common's headers are included as FOLDER/NAME.h, -Icommon: that is the name to compare)
for h in common/*/*.h server/*.h client/*.h; do
    name=$(basename "$h")
    case "$h" in common/*) name=${h#common/} ;; esac
    grep -qx "$name" <<<"$sys" && fail "$h has the name of a system header that system headers include"
done
grep -q "common/net/conn.h" build/float/client/client.d 2>/dev/null || [ ! -e build/float/client/client.d ] ||
    fail "build/float/client/client.d lacks common/net/conn.h: header changes would not rebuild the client"

echo "cli: help, version, ranges, exit statuses, early checks, bands, addresses and progress as documented"
