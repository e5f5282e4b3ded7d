#!/usr/bin/env bash
# Fault injection: clients that connect and say nothing, a slow-loris client,
# 100 connections at once, and a full disk under the frames and under obj2tmd.
# Good clients keep rendering correct frames, the server's memory stays
# bounded, the log names each cause, and no partial file is left behind.
set -u
source tests/tools/server-lib.sh
mounted=""
trap '[ -n "$mounted" ] && umount "$mounted" 2>/dev/null; lib_cleanup' EXIT
W=160 H=120
"$BIN/lanray-render" --width $W --height $H --aa 1 -o "$dir/ref.png" --quiet >/dev/null || fail "reference"

# 1. silent, slow-loris and 100 connections at once, while two good clients render
start_server conn --port 0 --width $W --height $H --frames 0 --handshake-timeout 2 --out "$dir/f"
for _ in 1 2; do "$BIN/lanray-client" "127.0.0.1:$port" --threads 1 --quiet 2>/dev/null & pids+=($!); done
python3 tests/tools/fakeclient.py "$port" silent >"$dir/silent.out" &
silent_pid=$!
loris=$(python3 tests/tools/fakeclient.py "$port" slowloris)
storm=$(python3 tests/tools/fakeclient.py "$port" storm 100)
wait "$silent_pid"
grep -q "handshake not completed in time" "$dir/silent.out" || fail "silent client got: $(cat "$dir/silent.out")"
grep -q "handshake not completed in time" <<<"$loris" || fail "slow-loris client got: $loris"
grep -q "closed 100 of 100" <<<"$storm" || fail "storm: $storm"
[ "$(grep -c 'handshake not completed in time' "$dir/conn.err")" -ge 101 ] || fail "not every silent connection was logged"
rss=$(awk '/VmRSS/ {print $2}' "/proc/$server_pid/status")
[ "$rss" -lt 204800 ] || fail "server memory $rss kB after the storm"
n=$(ls "$dir/f" | grep -c png)
for _ in $(seq 100); do [ -e "$dir/f/frame-$(printf %05d $((n + 3))).png" ] && break; sleep 0.1; done
kill -TERM "$server_pid"; wait "$server_pid" 2>/dev/null
count=0
for f in "$dir"/f/frame-*.png; do
    out=$("$BIN/lanray-imgdiff" "$dir/ref.png" "$f") && grep -q "^max difference 0," <<<"$out" || fail "$f: $out"
    count=$((count + 1))
done
[ "$count" -ge 3 ] || fail "only $count frames"
echo "connections: 1 silent + 1 slow-loris + 100 at once dropped and logged; $count frames correct; server RSS ${rss} kB"

# 2. a full disk: frames and .tmd files fail with a clear error and leave no partial file
full="$dir/full"
mkdir -p "$full"
if mount -t tmpfs -o size=64k tmpfs "$full" 2>/dev/null; then
    mounted=$full
    how="a 64 KiB tmpfs"
else # no mount privilege: a file-size limit gives EFBIG instead of ENOSPC
    how="ulimit -f"
    run_prog() { ulimit -f 8; trap "" XFSZ; exec "$@"; }
fi
start_server disk --port 0 --width $W --height $H --frames 12 --out "$full"
"$BIN/lanray-client" "127.0.0.1:$port" --threads 1 --quiet 2>/dev/null & pids+=($!)
wait "$server_pid"; rc=$?
# it keeps serving, and ends with 1: not every requested frame was written
[ $rc -eq 1 ] || fail "a server whose frames could not all be written should exit 1, not $rc"
grep -q "frames could not be written" "$dir/disk.err" || fail "no count of the unwritten frames"
grep -q "write failed\|No space left\|File too large" "$dir/disk.err" || fail "no clear error for a full disk"
ls "$full" | grep -q '\.tmp\.' && fail "temporary frame left on the full disk"
for f in "$full"/*.png; do [ -e "$f" ] || continue; "$BIN/lanray-imgdiff" "$dir/ref.png" "$f" >/dev/null || fail "$f is not a whole PNG"; done
[ -n "$mounted" ] && rm -f "$full"/*.png
# a model whose .tmd (about 330 kB) cannot fit: 6400 triangles, made here so that no outside file is needed
python3 -c "
n = 40
with open('$dir/grid.obj', 'w') as f:
    for j in range(n + 1):
        for i in range(2 * n + 1):
            f.write('v %d %d %g\n' % (i, j, (i * j % 7) * 0.1))
    for j in range(n):
        for i in range(2 * n):
            a = j * (2 * n + 1) + i + 1
            f.write('f %d %d %d %d\n' % (a, a + 1, a + 2 * n + 2, a + 2 * n + 1))
"
err=$(run_prog "$BIN/obj2tmd" "$dir/grid.obj" "$full/grid.tmd" 2>&1 </dev/null) && fail "obj2tmd succeeded on a full disk: $err"
grep -q "write failed\|No space left\|File too large" <<<"$err" || fail "obj2tmd message: $err"
ls "$full" | grep -q 'tmd' && fail "partial .tmd left on the full disk: $(ls "$full")"
echo "full disk ($how): frames and obj2tmd fail cleanly, nothing partial left"
exit 0
