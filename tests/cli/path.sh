#!/usr/bin/env bash
# A camera path (--path): frame k of a served flight with --path-step S is
# lanray-render's image of the path's camera at (k-1) x S, byte for byte,
# through two clients, with frames pipelined (started before the one before
# is finished: the summary counts them) and without; a camera that moves costs a client no scene and no
# top-level tree (it decodes one description and builds one tree for the
# whole flight), while an animation that turns the model does (one each a
# frame: the counters can tell); a headless flight without --frames stops
# at the path's end and prints the frame rate it held (with --still-aa, after
# one more, still frame: the converged one, lanray-render's picture bit for
# bit; a path-traced scene refines over still frames of 2x2, 4x4 ... samples
# up to the converged one); with --target-fps a moving frame is rendered at a render scale and
# shown in blocks, lanray-render's smaller picture; bad path files are
# refused naming the file and line.  The flights of the default scene run
# without the Whitted history (--whitted-temporal 0: each moving frame is
# then the picture of its view; tests/cli/history.sh checks the history).
set -u
source tests/tools/server-lib.sh
cat >"$dir/fly.path" <<'PATH'
# round the default scene
key 0   position 0 1.2 5   lookat 0 0.6 0 fov 60
key 1   position 2.5 1.5 4 lookat 0 0.6 0 fov 55
key 2.5 position 4 2 0.5   lookat 0 0.5 0 fov 50
PATH
W=96 H=72
for k in 1 2 3 4 5 6; do
    t=$(python3 -c "print(($k - 1) * 0.5)")
    "$BIN/lanray-render" --path "$dir/fly.path" --at "$t" --aa 1 --width $W --height $H -o "$dir/ref-$k.png" --quiet \
        >/dev/null || fail "lanray-render --at $t"
done
cmp -s "$dir/ref-1.png" "$dir/ref-2.png" && fail "the path does not move the camera: the test cannot fail"
# clients: run_clients N LOG-STEM; waits for the server
run_clients() {
    for c in $(seq "$1"); do
        "$BIN/lanray-client" "127.0.0.1:$port" --threads 1 --once 2>"$dir/$2-$c.err" >/dev/null &
        pids+=("$!")
    done
    for _ in $(seq 400); do kill -0 "$server_pid" 2>/dev/null || break; sleep 0.05; done
    wait "$server_pid" || fail "the server exited $?"
    sleep 0.2
}
start_server fly --port 0 --width $W --height $H --path "$dir/fly.path" --path-step 0.5 --whitted-temporal 0 --wait-clients 2 --out "$dir/f"
run_clients 2 fly
n=$(ls "$dir/f" | wc -l)
[ "$n" = 6 ] || fail "the flight of 2.5 s at 0.5 s a frame wrote $n frames, not 6 (it stops at the path's end)"
for k in 1 2 3 4 5 6; do
    cmp -s "$dir/f/frame-0000$k.png" "$dir/ref-$k.png" || fail "frame $k is not the path's camera at $(((k - 1) * 5))/10 s"
done
grep -q "^path: frames 1 to 6 in .* fps while moving" "$dir/fly.log" || fail "no frame rate line: $(tail -2 "$dir/fly.log")"
# pipelined frames (the default): the path's next view is known, so a frame
# starts while the one before still has segments out; the frames are the
# same, in order, as without (--pipeline off)
grep -q "^pipelined: [1-9][0-9]* frames started before" "$dir/fly.log" ||
    fail "no frame of the flight started ahead: $(grep -E '^pipelined|^summary' "$dir/fly.log")"
start_server serial --port 0 --width $W --height $H --path "$dir/fly.path" --path-step 0.5 --whitted-temporal 0 --wait-clients 2 \
    --pipeline off --out "$dir/serial"
run_clients 2 serial
grep -q "^pipelined:" "$dir/serial.log" && fail "--pipeline off started frames ahead"
for k in 1 2 3 4 5 6; do
    cmp -s "$dir/serial/frame-0000$k.png" "$dir/ref-$k.png" || fail "frame $k without pipelining differs"
done
for c in 1 2; do
    grep -q "1 scenes decoded, 1 top-level trees built" "$dir/fly-$c.err" ||
        fail "client $c decoded or built more than once for camera moves: $(tail -1 "$dir/fly-$c.err")"
done
# refined: the still frame after the flight is lanray-render's full picture
# (its default, adaptive:4) of the path's end, through 1 and through 2
# clients, and the moving frames its picture with adaptive light sampling
# where the server is asked for it
"$BIN/lanray-render" --path "$dir/fly.path" --at 2.5 --width $W --height $H -o "$dir/still.png" --quiet >/dev/null ||
    fail "lanray-render the still"
cmp -s "$dir/still.png" "$dir/ref-6.png" && fail "the still quality looks like the moving one: the test cannot fail"
# the moving frames with adaptive light sampling (--moving-lights adaptive)
"$BIN/lanray-render" --path "$dir/fly.path" --at 2.5 --aa 1 --light-sampling adaptive --width $W --height $H \
    -o "$dir/ref-6a.png" --quiet >/dev/null || fail "lanray-render adaptive lights"
cmp -s "$dir/ref-6a.png" "$dir/ref-6.png" && fail "adaptive light sampling changed no pixel: the test cannot tell"
for n in 1 2; do
    start_server refine-$n --port 0 --width $W --height $H --path "$dir/fly.path" --path-step 0.5 --whitted-temporal 0 --wait-clients $n \
        --still-aa adaptive:4 --moving-lights adaptive --out "$dir/r$n"
    run_clients $n refine-$n
    [ "$(ls "$dir/r$n" | wc -l)" = 7 ] || fail "refining, the flight should write 6 moving frames and the still one"
    cmp -s "$dir/r$n/frame-00006.png" "$dir/ref-6a.png" ||
        fail "refining, a moving frame is not lanray-render's with adaptive light sampling ($n clients)"
    cmp -s "$dir/r$n/frame-00007.png" "$dir/still.png" || fail "the converged frame is not lanray-render's ($n clients)"
    grep -q "^path: converged frame 7, .* s after the last move" "$dir/refine-$n.log" || fail "no converged line"
done
# a path-traced scene refines over several still frames.  At --still-aa
# 4 each renders the next batch of each pixel's 4 x 4 samples, doubling
# them (1, then 1, 2, 4, 8 more), and the server adds them up: still frame
# K is lanray-render's --still-frame K, the last its 4x4 bit for bit,
# through 2 clients; at 8 (with the denoiser: the guides' sums add up too)
# 7 batches, the last lanray-render's 8x8; RGBE (--hdr) at 2x2 in 3 batches,
# lanray-render's .hdr; at 3, not a power of two, each
# frame is rendered whole: 2x2, then 3x3
cat >"$dir/room.scene" <<'S'
camera position 0 1 5 lookat 0 0.5 0 fov 50
background 0.2 0.25 0.3
settings integrator path depth 4
material red diffuse 0.7 0.1 0.1 checker 0.9 0.9 0.9 checker_size 0.25
material bulb diffuse 0 0 0 emit 8 7 6
plane point 0 0 0 normal 0 1 0
sphere centre -1 0.5 0 radius 0.5 material red
sphere centre 0 2.5 1 radius 0.3 material bulb
S
cat >"$dir/room.path" <<'PATH'
key 0 position 0 1 5 lookat 0 0.5 0 fov 50
key 1 position 1 1.2 4.5 lookat 0 0.5 0 fov 50
PATH
room_ref() { # NAME AA [options]: lanray-render's picture of the room at the path's end
    local name=$1 a=$2
    shift 2
    "$BIN/lanray-render" "$dir/room.scene" --path "$dir/room.path" --at 1 --aa "$a" --width 48 --height 36 "$@" \
        -o "$dir/$name.png" --quiet >/dev/null || fail "lanray-render the room: $name"
}
room_ref room-2 2
room_ref room-3 3
room_ref room-4 4
room_ref room-4-1 4 --still-frame 1
room_ref room-4-3 4 --still-frame 3
room_ref room-8 8 --denoise on
room_ref room-8-5 8 --denoise on --still-frame 5
# lanray-render --progressive: the batches one after another, the picture
# written after each (1, 2, 4 ... samples), the last the one-pass picture
# byte for byte (denoised too, and RGBE); refused where there are no batches
"$BIN/lanray-render" "$dir/room.scene" --path "$dir/room.path" --at 1 --aa 8 --denoise on --width 48 --height 36 \
    --progressive -o "$dir/room-8-prog.png" >"$dir/prog.log" 2>&1 || fail "lanray-render --progressive: $(cat "$dir/prog.log")"
cmp -s "$dir/room-8-prog.png" "$dir/room-8.png" || fail "--progressive's last picture is not the one-pass one"
[ "$(grep -c "^wrote .*room-8-prog.png: [0-9]* samples\? a pixel" "$dir/prog.log")" = 6 ] ||
    fail "--progressive at 8x8 should write 6 pictures on the way (1 ... 32 samples): $(cat "$dir/prog.log")"
"$BIN/lanray-render" "$dir/room.scene" --path "$dir/room.path" --at 1 --aa 2 --width 48 --height 36 --progressive \
    -o "$dir/room-2-prog.hdr" --quiet >/dev/null || fail "lanray-render --progressive .hdr"
out=$("$BIN/lanray-render" "$dir/room.scene" --aa 3 --progressive -o "$dir/no.png" 2>&1)
[ $? = 2 ] && grep -q "goes in batches; this one does not" <<<"$out" || fail "--progressive at 3x3: $out"
[ -e "$dir/no.png" ] && fail "a refused --progressive left its file"
cmp -s "$dir/room-4-3.png" "$dir/room-4.png" && fail "4 samples of 16 look like 16: the test cannot fail"
cmp -s "$dir/room-4-3.png" "$dir/room-2.png" && fail "the first 4 of 4x4 are the 2x2 picture: the samples are not 4x4's"
# the light itself (RGBE): a batch's sums encoded so too
"$BIN/lanray-render" "$dir/room.scene" --path "$dir/room.path" --at 1 --aa 2 --width 48 --height 36 -o "$dir/room-2.hdr" \
    --quiet >/dev/null || fail "lanray-render the room's .hdr"
for q in 4 8 3 2; do
    extra=()
    [ $q = 8 ] && extra=(--denoise)
    [ $q = 2 ] && extra=(--hdr)
    start_server "room$q" --port 0 --width 48 --height 36 --path "$dir/room.path" --path-step 0.5 --wait-clients 2 \
        "$dir/room.scene" --still-aa $q "${extra[@]}" --out "$dir/room$q"
    run_clients 2 "room$q"
done
[ "$(ls "$dir/room4" | wc -l)" = 8 ] || fail "a path-traced flight of 3 frames should refine in 5 still ones: $(ls "$dir/room4")"
cmp -s "$dir/room4/frame-00004.png" "$dir/room-4-1.png" || fail "the first still path-traced frame is not lanray-render's --still-frame 1"
cmp -s "$dir/room4/frame-00006.png" "$dir/room-4-3.png" || fail "the third still path-traced frame is not lanray-render's --still-frame 3"
cmp -s "$dir/room4/frame-00008.png" "$dir/room-4.png" || fail "the converged path-traced frame is not lanray-render's at 4x4"
[ "$(ls "$dir/room8" | wc -l)" = 10 ] || fail "at --still-aa 8, 7 still frames: $(ls "$dir/room8")"
cmp -s "$dir/room8/frame-00008.png" "$dir/room-8-5.png" || fail "the fifth of 7 batches, denoised, is not lanray-render's --still-frame 5"
cmp -s "$dir/room8/frame-00010.png" "$dir/room-8.png" || fail "the converged denoised frame of 7 batches is not lanray-render's at 8x8"
cmp -s "$dir/room2/frame-00006.hdr" "$dir/room-2.hdr" || fail "an RGBE still at 2x2 in 3 batches is not lanray-render's .hdr"
cmp -s "$dir/room-2-prog.hdr" "$dir/room-2.hdr" || fail "lanray-render --progressive's .hdr is not the one-pass one"
cmp -s "$dir/room3/frame-00004.png" "$dir/room-2.png" || fail "at --still-aa 3 the first still frame is not lanray-render's 2x2"
cmp -s "$dir/room3/frame-00005.png" "$dir/room-3.png" || fail "at --still-aa 3 the converged frame is not lanray-render's 3x3"
grep -q "^path: converged frame 8, " "$dir/room4.log" || fail "no converged line for frame 8: $(grep '^path' "$dir/room4.log")"
grep -q "^path: converged frame 5, " "$dir/room3.log" || fail "no converged line for frame 5: $(grep '^path' "$dir/room3.log")"
# soft shadows converge (--still-light-samples 6): after the still frame at
# adaptive 4x4 with the round lamp's own 3 x 3 points, one more with 6 x 6,
# lanray-render's --light-samples 6 bit for bit, the converged one; at the
# lamp's own points the penumbrae differ from it
"$BIN/lanray-render" --path "$dir/fly.path" --at 2.5 --aa adaptive:4 --light-samples 6 --width $W --height $H \
    -o "$dir/soft.png" --quiet >/dev/null || fail "lanray-render --light-samples 6"
cmp -s "$dir/soft.png" "$dir/still.png" && fail "6 x 6 points of the lamp changed no pixel: the test cannot tell"
start_server soft --port 0 --width $W --height $H --path "$dir/fly.path" --path-step 0.5 --whitted-temporal 0 --wait-clients 2 \
    --still-aa adaptive:4 --still-light-samples 6 --frames 8 --out "$dir/soft"
run_clients 2 soft
[ "$(ls "$dir/soft" | wc -l)" = 8 ] || fail "refining the lamp's points, 6 moving frames and 2 still ones: $(ls "$dir/soft")"
cmp -s "$dir/soft/frame-00007.png" "$dir/still.png" || fail "the first still frame is not lanray-render's adaptive:4"
cmp -s "$dir/soft/frame-00008.png" "$dir/soft.png" || fail "the converged frame is not lanray-render's --light-samples 6"
grep -q "^path: converged frame 8, " "$dir/soft.log" || fail "no converged line for frame 8: $(grep '^path' "$dir/soft.log")"
out=$("$BIN/lanray-server" --headless --port 0 --still-light-samples 6 2>&1)
[ $? -eq 2 ] && grep -q "give both" <<<"$out" || fail "--still-light-samples without --still-aa: $out"
# a render scale (--target-fps out of reach: the coarsest, 8, to start
# with; the pace may probe a finer one where a coarse frame takes under
# 0.75 ms, as a fast machine's 12 x 9 pixels do): a moving frame at scale 8
# is lanray-render's picture of W/8 x H/8 pixels brought to the full size,
# smooth (the default: the integer bilinear rule of server/upscale.c,
# computed again here) or, with --upscale blocks, each pixel an 8 x 8
# block, and at least one of the six is; the first still frame after the
# flight is whole at one sample a pixel (the view's own: sharp at once),
# the next the refined one.  At a fixed scale in quarter steps (--render-scale 2.5:
# frames of ceil(W / 2.5) x ceil(H / 2.5) pixels, 39 x 29 for 96 x 72,
# each pixel where its ray went: 39 span the width, the 29 lines centred)
# every moving frame is (so too at 2.75: 35 x 27).
# small EXT S: lanray-render's six small frames at scale S (quarter steps) as $dir/small-S-F.EXT
small() {
    local sw sh
    sw=$(( (4 * W + $2 - 1) / $2 )) sh=$(( (4 * H + $2 - 1) / $2 ))
    for f in 1 2 3 4 5 6; do
        t=$(python3 -c "print(($f - 1) * 0.5)")
        "$BIN/lanray-render" --path "$dir/fly.path" --at "$t" --aa 1 --width $sw --height $sh \
            -o "$dir/small-$2-$f.$1" --quiet >/dev/null || fail "lanray-render small $sw x $sh --at $t"
    done
}
# scaled_ok DIR S UP any|all: whether any (or all) of frames 1 to 6 in DIR
# are the small frames at scale S (quarter steps) brought up UP (smooth,
# blocks, or hdr: RGBE smooth, the light decoded, mixed with the same
# weights in double and coded again: upscale_smooth_rgbe)
scaled_ok() {
    local f pairs=() ext=png
    [ "$3" = hdr ] && ext=hdr
    for f in 1 2 3 4 5 6; do
        pairs+=("$1/frame-$(printf %05d $f).$ext" "$dir/small-$2-$f.$ext")
    done
    python3 tests/tools/scaledup.py "$2" "$3" "$4" "${pairs[@]}" 2>&1
}
small png 32
small png 10
small png 11
for up in smooth blocks; do
    start_server "scale-$up" --port 0 --width $W --height $H --path "$dir/fly.path" --path-step 0.5 --whitted-temporal 0 --wait-clients 2 \
        --target-fps 1000 --still-aa adaptive:4 --upscale "$up" --out "$dir/sc-$up"
    run_clients 2 "scale-$up"
    out=$(scaled_ok "$dir/sc-$up" 32 "$up" any) ||
        fail "no moving frame at render scale 8 is lanray-render's small frame scaled up ($up): $out"
    grep -q "^pace: target 1000.0 fps, mean render scale " "$dir/scale-$up.log" || fail "no pace line: $(tail -3 "$dir/scale-$up.log")"
    cmp -s "$dir/sc-$up/frame-00007.png" "$dir/ref-6.png" ||
        fail "the first still frame after a scaled flight is not whole at one sample a pixel (sharp at once)"
    cmp -s "$dir/sc-$up/frame-00008.png" "$dir/still.png" || fail "the still frame after a scaled flight is not whole and refined"
    grep -q "^path: converged frame 8, " "$dir/scale-$up.log" || fail "no converged line for frame 8: $(grep '^path' "$dir/scale-$up.log")"
    start_server "half-$up" --port 0 --width $W --height $H --path "$dir/fly.path" --path-step 0.5 --whitted-temporal 0 --wait-clients 2 \
        --render-scale 2.5 --upscale "$up" --out "$dir/half-$up"
    run_clients 2 "half-$up"
    out=$(scaled_ok "$dir/half-$up" 10 "$up" all) ||
        fail "a moving frame at render scale 2.5 is not lanray-render's small frame scaled up ($up): $out"
done
# and at a quarter step, 2.75 (35 x 27 pixels for 96 x 72)
start_server quarter --port 0 --width $W --height $H --path "$dir/fly.path" --path-step 0.5 --whitted-temporal 0 --wait-clients 2 \
    --render-scale 2.75 --out "$dir/quarter"
run_clients 2 quarter
out=$(scaled_ok "$dir/quarter" 11 smooth all) ||
    fail "a moving frame at render scale 2.75 is not lanray-render's small frame scaled up: $out"

# ... and lands where the full frame's pixels are: against lanray-render's
# full-size frames of the same moments, the frames at 2.5 come closer than
# the same small frames spread as 2.5 x 2.5 blocks from the corner would
# (the rule before 2026-11-30, which moved the picture by up to a pixel;
# the full-size frames: ref-F.png, the flight's references above)
out=$(python3 - "$dir" 2>&1 <<'PY'
import sys
sys.path.insert(0, "tests/tools")
from pngpixel import read
d, k = sys.argv[1], 2.5
def px(rows, x, y, c):
    return rows[y][3 * x + c]
def corner(small, W, H):  # bilinear, small pixel i's centre at (i + 1/2) k full pixels
    sh, sw = len(small), len(small[0]) // 3
    out = []
    for y in range(H):
        v = min(max((y + 0.5) / k - 0.5, 0), sh - 1)
        j0 = int(v); j1 = min(j0 + 1, sh - 1); fy = v - j0
        for x in range(W):
            u = min(max((x + 0.5) / k - 0.5, 0), sw - 1)
            i0 = int(u); i1 = min(i0 + 1, sw - 1); fx = u - i0
            for c in range(3):
                top = px(small, i0, j0, c) * (1 - fx) + px(small, i1, j0, c) * fx
                bot = px(small, i0, j1, c) * (1 - fx) + px(small, i1, j1, c) * fx
                out.append(top * (1 - fy) + bot * fy)
    return out
served = blocks = 0.0
for f in range(1, 7):
    full, _ = read("%s/ref-%d.png" % (d, f))
    got, _ = read("%s/half-smooth/frame-%05d.png" % (d, f))
    small, _ = read("%s/small-10-%d.png" % (d, f))
    H, W = len(full), len(full[0]) // 3
    ref = [full[y][i] for y in range(H) for i in range(3 * W)]
    served += sum((got[y][i] - ref[y * 3 * W + i]) ** 2 for y in range(H) for i in range(3 * W))
    blocks += sum((a - b) ** 2 for a, b in zip(corner(small, W, H), ref))
print("%.1f %.1f" % (served, blocks))
sys.exit(0 if served < 0.9 * blocks else 1)
PY
) || fail "frames at render scale 2.5 are not where their rays went: squared error $out (served, blocks from the corner)"
# RGBE frames (--hdr) smooth, at render scales 8 and 2.5
small hdr 32
small hdr 10
start_server scale-hdr --port 0 --width $W --height $H --path "$dir/fly.path" --path-step 0.5 --whitted-temporal 0 --wait-clients 2 \
    --target-fps 1000 --hdr --out "$dir/sc-hdr"
run_clients 2 scale-hdr
out=$(scaled_ok "$dir/sc-hdr" 32 hdr any) || fail "no RGBE frame at render scale 8 is lanray-render's small .hdr brought up smooth: $out"
start_server half-hdr --port 0 --width $W --height $H --path "$dir/fly.path" --path-step 0.5 --whitted-temporal 0 --wait-clients 2 \
    --render-scale 2.5 --hdr --out "$dir/half-hdr"
run_clients 2 half-hdr
out=$(scaled_ok "$dir/half-hdr" 10 hdr all) || fail "an RGBE frame at render scale 2.5 is not lanray-render's small .hdr brought up smooth: $out"
for bad in 0.7 2.1 "2.5 --target-fps 10"; do
    # shellcheck disable=SC2086
    out=$("$BIN/lanray-server" --headless --port 0 --render-scale $bad 2>&1)
    [ $? -eq 2 ] && grep -q "\-\-render-scale" <<<"$out" || fail "--render-scale $bad: $out"
done
# the same flight with the model turning: a new description every frame
start_server turn --port 0 --width $W --height $H --path "$dir/fly.path" --path-step 0.5 --whitted-temporal 0 --wait-clients 1 --rotate 10 \
    --out "$dir/t"
run_clients 1 turn
grep -q "6 scenes decoded, 6 top-level trees built" "$dir/turn-1.err" ||
    fail "a turning model should cost a scene and a tree a frame: $(tail -1 "$dir/turn-1.err")"
# bad paths: each refused with the file, the line and the reason
bad() {
    printf '%b' "$1" >"$dir/bad.path"
    out=$("$BIN/lanray-render" --path "$dir/bad.path" -o "$dir/bad.png" --width 8 --height 8 2>&1) && fail "accepted: $1"
    grep -q "$2" <<<"$out" || fail "for '$1' expected '$2', got: $out"
    [ -e "$dir/bad.png" ] && fail "an image was left behind for a bad path"
    return 0
}
bad 'key 0 position 0 1 5\nkey 0 position 1 1 5\n' 'bad.path:2: key at 0 s is not after the key before it'
bad 'key 0 position 0 1 5\nwaypoint 1 position 1 1 5\n' "bad.path:2: unknown directive 'waypoint'"
bad 'key 0 position 0 1 5\nkey 1 position 1 1 5 ortho 4\n' 'bad.path:2: a key of another projection'
bad 'key x position 0 1 5\n' "bad.path:1: 'key' expects a time"
bad 'key 0 position 0 1 5 fov 200\n' 'bad.path:1:'
bad '# nothing\n' 'no camera keys'
"$BIN/lanray-server" --headless --path "$dir/missing.path" --port 0 2>"$dir/miss.err" && fail "the server took a missing path"
grep -q "missing.path" "$dir/miss.err" || fail "the server's error does not name the path: $(cat "$dir/miss.err")"
# the server's --integrator over a scene's: the Cornell box (Whitted in its
# file) served path-traced is lanray-render --integrator path's picture
"$BIN/lanray-render" models/cornell.scene --integrator path --aa 1 --width 64 --height 64 -o "$dir/cornell-path.png" \
    --quiet >/dev/null || fail "lanray-render the Cornell box path-traced"
verify_distributed cornell-path models/cornell.scene "$dir/cornell-path.png" "served --integrator path" --integrator path
echo "path: 6 frames of a flight through 2 clients equal lanray-render's cameras on the path, and the converged one its full picture; a frame at render scale 8 or 2.5 is its small picture brought up smooth (or in blocks), an RGBE one too; a camera move decodes no scene and builds no tree (6 each with a turning model); bad paths named by line; a Whitted scene served --integrator path"
