#!/usr/bin/env bash
# Integration: a real server and real clients on loopback.
#  - distributed frames are bit-identical to lanray-render's;
#  - a client killed with SIGKILL, one stopped with SIGSTOP, one sending random
#    bytes, one lying about a packet size, one sending pixels for a segment
#    it was not given, one sending coded pixels that do not decode and one
#    coded pixels as large as raw ones do not stop the frames from completing, the server's
#    memory stays within 20 MB of what it was before, and its log names each
#    cause;
#  - a wrong token or protocol version is refused with a clear message;
#  - clients survive a server restart.
set -u
source tests/tools/server-lib.sh

client() { "$BIN/lanray-client" "127.0.0.1:$port" --threads 1 "$@" & pids+=($!); last_pid=$!; }
wait_for() { for _ in $(seq "$2"); do [ -e "$1" ] && return 0; sleep 0.1; done; fail "timed out waiting for $1"; }
wait_exit() { # wait_exit PID SECONDS
    for _ in $(seq $(($2 * 10))); do kill -0 "$1" 2>/dev/null || { wait "$1"; return $?; }; sleep 0.1; done
    fail "process $1 still running after $2 s"
}
same_as_reference() { # same_as_reference FRAME REFERENCE
    out=$("$BIN/lanray-imgdiff" "$2" "$1") || fail "imgdiff: $out"
    grep -q "^max difference 0," <<<"$out" || fail "$1 differs from the reference: $out"
}

W=320 H=200
"$BIN/lanray-render" --width $W --height $H --aa 2 -o "$dir/ref.png" --quiet >/dev/null || fail "reference render"

# 1. faults while the server renders frame after frame
start_server faults --port 0 --width $W --height $H --aa 2 --segment 4 --frames 0 --stall-timeout 2 --out "$dir/f"
client 2>"$dir/c1.err"; client 2>"$dir/c2.err"
client 2>/dev/null; victim_kill=$last_pid
client 2>/dev/null; victim_stop=$last_pid
# all four must have joined before the faults, or a slow start (sanitizers) hides them
for _ in $(seq 300); do [ "$(grep -c ' joined ' "$dir/faults.err")" -ge 4 ] && break; sleep 0.1; done
[ "$(grep -c ' joined ' "$dir/faults.err")" -ge 4 ] || fail "the four clients did not all join"
wait_for "$dir/f/frame-00001.png" 300
rss_before=$(awk '/VmRSS/ {print $2}' "/proc/$server_pid/status")
kill -9 "$victim_kill"; wait "$victim_kill" 2>/dev/null
kill -STOP "$victim_stop"
garbage=$(python3 tests/tools/fakeclient.py "$port" garbage)
liar=$(python3 tests/tools/fakeclient.py "$port" lie-size)
forger=$(python3 tests/tools/fakeclient.py "$port" forge-data)
badcoded=$(python3 tests/tools/fakeclient.py "$port" bad-coded)
overclaim=$(python3 tests/tools/fakeclient.py "$port" overclaim)
# past the stall timeout, frames still complete
for _ in $(seq 100); do grep -q "stalled: no result in time" "$dir/faults.err" && break; sleep 0.1; done
grep -q "stalled: no result in time" "$dir/faults.err" || fail "the stopped client was not reported as stalled"
n=$(ls "$dir/f" | grep -c '^frame-.*png$')
wait_for "$dir/f/frame-$(printf %05d $((n + 3))).png" 300
# memory stays bounded: what the faulty clients sent (a 4 GiB claim included) left nothing behind
# (under AddressSanitizer freed memory waits in its quarantine: a looser bound)
rss_after=$(awk '/VmRSS/ {print $2}' "/proc/$server_pid/status")
rss_slack=20480
case "$BIN" in *asan*) rss_slack=65536 ;; esac
[ "$rss_after" -lt $((rss_before + rss_slack)) ] || fail "server RSS grew from $rss_before kB to $rss_after kB over the faults"
kill -TERM "$server_pid"
wait_exit "$server_pid" 20 || fail "server exited with an error"
frames=0
for f in "$dir"/f/frame-*.png; do same_as_reference "$f" "$dir/ref.png"; frames=$((frames + 1)); done
[ "$frames" -ge 4 ] || fail "only $frames frames"
grep -q "unknown type\|claims" <<<"$garbage" || fail "garbage client got: $garbage"
grep -q "DATA packet claims 4294967295 bytes" <<<"$liar" || fail "lying client got: $liar"
grep -q "which it was not given" <<<"$forger" || fail "forging client got: $forger"
grep -q "DATA packet for segment .*: pixels: a zstd frame of" <<<"$badcoded" || fail "bad coded pixels got: $badcoded"
grep -q "DATA packet of [0-9]* coded pixel bytes for a segment of" <<<"$overclaim" || fail "overclaiming client got: $overclaim"
# a killed process's socket closes with FIN, or with RST when data it had not read was still queued
grep -q "connection closed by peer\|Connection reset by peer" "$dir/faults.err" || fail "the killed client was not reported"
grep -q "claims 4294967295 bytes" "$dir/faults.err" || fail "the lying client was not logged"
grep -q "frames started" "$dir/faults.log" || fail "no statistics at exit"
kill -CONT "$victim_stop"
echo "faults: $frames frames bit-identical to lanray-render's; server RSS $rss_before kB before the faults, $rss_after kB after"

# 2. authentication and versions
start_server auth --port 0 --width 64 --height 48 --frames 2 --token s3cret --out "$dir/a"
err=$("$BIN/lanray-client" "127.0.0.1:$port" --token wrong --threads 1 2>&1); [ $? -eq 1 ] || fail "wrong token should exit 1"
grep -q "authentication failed" <<<"$err" || fail "wrong token message: $err"
err=$(LANRAY_TOKEN= "$BIN/lanray-client" "127.0.0.1:$port" --threads 1 2>&1); [ $? -eq 1 ] || fail "missing token should exit 1"
grep -q "authentication failed" <<<"$err" || fail "missing token message: $err"
version=$(python3 tests/tools/fakeclient.py "$port" version s3cret)
proto=$(sed -n 's/^#define PROTO_VERSION \([0-9]*\)u.*/\1/p' common/net/msg.h)
grep -q "protocol version 99, the server speaks version $proto" <<<"$version" || fail "version message: $version"
LANRAY_TOKEN=s3cret client 2>/dev/null
wait_exit "$server_pid" 60 || fail "authenticated frames did not complete"
[ -e "$dir/a/frame-00002.png" ] || fail "no frames with the right token"
err=$("$BIN/lanray-server" --headless --listen 0.0.0.0 --port 0 --frames 1 --out "$dir/x" 2>&1); [ $? -eq 1 ] || fail "LAN without token must refuse"
grep -q "needs --token (or LANRAY_TOKEN) or an explicit --insecure" <<<"$err" || fail "insecure message: $err"

# 3. clients survive a server restart
start_server first --port 0 --width 64 --height 48 --frames 0 --out "$dir/r1"
client 2>"$dir/restart.err"
wait_for "$dir/r1/frame-00002.png" 100
kill -TERM "$server_pid"
wait_exit "$server_pid" 10
start_server second --port "$port" --width 64 --height 48 --frames 3 --out "$dir/r2"
wait_exit "$server_pid" 60 || fail "restarted server did not finish"
[ -e "$dir/r2/frame-00003.png" ] || fail "the client did not come back after the restart"
grep -q "reconnecting" "$dir/restart.err" || fail "the client did not report reconnecting"
exit 0
