#!/usr/bin/env bash
# tools/schedsim against answers that can be worked out by hand, on a
# synthetic profile: 100 lines of 100 us each (a 10 ms frame on one thread).
set -u
BIN=${BIN:-bin}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
for i in $(seq 0 99); do echo "$i,100"; done >"$dir/flat.csv"
sim() { "$BIN/schedsim" --profile "$dir/flat.csv" --width 10 --latency-us 0 --overhead-us 0 --frames 4 "$@" |
    sed -n 's/.*fps=\([0-9.]*\).*/\1/p'; }
near() { awk -v a="$1" -v b="$2" -v t="$3" 'BEGIN{exit !(a > b * (1 - t) && a < b * (1 + t))}'; }

# one client, no overhead: 100 FPS whatever the segment size
for seg in 1 10 50; do
    f=$(sim --clients 1 --segment "$seg" --tail static)
    near "$f" 100 0.01 || fail "1 client, $seg-line segments: $f FPS, expected 100"
done
# 4 clients on their own cores, 1-line segments: 4 times that
f=$(sim --clients 4 --segment 1 --tail static)
near "$f" 400 0.03 || fail "4 clients: $f FPS, expected 400"
# 4 clients sharing 2 cores: the cores are the limit
f=$(sim --clients 4 --cores 2 --segment 1 --tail static)
near "$f" 200 0.03 || fail "4 clients on 2 cores: $f FPS, expected 200"
# a per-segment overhead of 100 us doubles a 1-line segment's cost
f=$(sim --clients 1 --segment 1 --tail static --overhead-us 100)
near "$f" 50 0.02 || fail "1 client with 100 us overhead per line: $f FPS, expected 50"
# ... unless it is all waiting, which other clients fill with work
a=$(sim --clients 4 --cores 2 --segment 1 --tail static --overhead-us 100 --overhead-cpu 1)
b=$(sim --clients 4 --cores 2 --segment 1 --tail static --overhead-us 100 --overhead-cpu 0)
awk -v a="$a" -v b="$b" 'BEGIN{exit !(b > a * 1.3)}' || fail "overhead as waiting ($b FPS) should beat overhead as CPU ($a FPS) on shared cores"
# background CPU (packets in the server and network threads), 100 us per
# segment: on 2 shared cores the frame costs 10 ms of rendering and 100 x
# 0.1 ms of packets, 20 ms of CPU, 10 ms on 2 cores: 100 FPS ...
f=$(sim --clients 4 --cores 2 --segment 1 --tail static --bg-cpu-us 100)
near "$f" 100 0.05 || fail "4 clients on 2 cores, 100 us background per segment: $f FPS, expected 100"
# ... and each client's share runs on a core of its own: 4 clients on 4
# cores, 10 ms of rendering and 10 ms of packets on 4 cores is 5 ms, 200 FPS
# (not 100, as if all the packets took turns on one core)
f=$(sim --clients 4 --cores 4 --segment 1 --tail static --bg-cpu-us 100)
near "$f" 200 0.03 || fail "4 clients on 4 cores, 100 us background per segment: $f FPS, expected 200"
# ... and nothing when every client has its own machine
f=$(sim --clients 2 --segment 1 --tail static --bg-cpu-us 100)
near "$f" 200 0.03 || fail "2 clients on their own cores with background work: $f FPS, expected 200"
# a 10 ms turnaround between frames (scene out, decoded) on a 10 ms frame
# halves the frame rate; with 4 clients it is as long and the frame a
# quarter: 400 FPS becomes 1 / (2.5 + 10 ms) = 80
f=$(sim --clients 1 --segment 10 --tail static --turnaround-us 10000)
near "$f" 50 0.02 || fail "1 client, 10 ms turnaround: $f FPS, expected 50"
f=$(sim --clients 4 --segment 1 --tail static --turnaround-us 10000)
near "$f" 80 0.03 || fail "4 clients, 10 ms turnaround: $f FPS, expected 80"
# the server's one thread at 100 us per packet: one client keeps rendering
# while its result is handled (it holds two segments), but 2 clients with
# 1-line (100 us) segments send 2 packets per 100 us and the server takes
# one: the first line, then 100 packets one after another, 10.1 ms, 99 FPS
# instead of 200
f=$(sim --clients 1 --segment 1 --tail static --server-us 100)
near "$f" 100 0.02 || fail "1 client, 100 us per packet at the server: $f FPS, expected 100"
f=$(sim --clients 2 --segment 1 --tail static --server-us 100)
near "$f" 99 0.02 || fail "2 clients, 100 us per packet at the server: $f FPS, expected 99"
# a client link of 2.4192 Mbit/s (0.3024 bytes/us): the frame as one
# segment (3024 bytes of DATA) takes 10 ms to send and the 900-byte UPDATE
# 3 ms, so a frame takes 3 + 10 + 10 ms (43.5 FPS); with a 4 kB token
# bucket, as tc tbf gives, both pass at once, the bucket refilling while
# the client renders, and the frame is its 10 ms of rendering (100 FPS)
f=$(sim --clients 1 --segment 100 --tail static --client-mbit 2.4192)
near "$f" 43.5 0.01 || fail "1 client behind a 2.4 Mbit/s link: $f FPS, expected 43.5"
f=$(sim --clients 1 --segment 100 --tail static --client-mbit 2.4192 --client-burst-kb 4)
near "$f" 100 0.01 || fail "1 client behind a 2.4 Mbit/s link with a 4 kB bucket: $f FPS, expected 100"
# a woken client waits for a time slice on oversubscribed cores: slower frames
a=$(sim --clients 8 --cores 2 --segment 10 --tail static)
b=$(sim --clients 8 --cores 2 --segment 10 --tail static --slice-us 2000)
awk -v a="$a" -v b="$b" 'BEGIN{exit !(b < a * 0.95)}' || fail "time slices: $b FPS, not below $a"
# more clients than segments: the idle client is given the segment waiting
# in the other's queue, not a copy of the one in progress, so the two
# 50-line segments take 5 ms side by side (200 FPS; "oldest first" gave 100)
f=$(sim --clients 3 --segment 50 --tail static)
near "$f" 200 0.02 || fail "3 clients, 2 segments: $f FPS, expected 200"
# one client never duplicates anything
d=$("$BIN/schedsim" --profile "$dir/flat.csv" --width 10 --latency-us 0 --overhead-us 0 --frames 4 --clients 1 \
    --segment 50 --tail static | sed -n 's/.*dup_lines_per_frame=\([0-9.]*\).*/\1/p')
[ "$d" = 0.00 ] || fail "1 client: $d duplicated lines per frame"
# the machine probe measures something plausible (0.1 to 100 ms)
s=$("$BIN/schedsim" --probe-slice "$(nproc)" | sed -n 's/slice_us=\([0-9.]*\).*/\1/p')
awk -v s="$s" 'BEGIN{exit !(s >= 100 && s <= 100000)}' || fail "probe-slice: $s us"
echo "schedsim: hand-worked answers hold; time slice here $s us"
