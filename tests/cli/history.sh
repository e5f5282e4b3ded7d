#!/usr/bin/env bash
# A Whitted view's moving frames added up (lanray-server --whitted-temporal,
# render/temporal.h): frame 11 of make demo's flight (models/demo.path at
# 1/15 s a frame, one sample a pixel, 160 x 120) comes closer to the
# full-quality picture of its view with the history of 2 frames than
# without (RMSE 6.98 against 10.18: at least 15% closer).  Through a server
# and two clients the moving frames of a flight at the full size are
# lanray-render's --server-frame pictures bit for bit (the history changed
# the third), the still frame after them its plain picture; so too in RGBE
# (--hdr), with adaptive light sampling while moving, and from clients on
# the scalar path, and with the lamp's 2 x 2 points while moving
# (--moving-light-samples 2: lanray-render --light-samples 2, the still
# frame the lamp's own); with --whitted-temporal 0 every moving frame is
# lanray-render's picture of its view.  At render scale 1.5 the history
# changes the third moving frame (each moving frame lanray-render's
# --server-frame picture at the small size, brought up), at 2 the moving
# frames carry no guides (the same bytes as without it); after moving
# frames at a render scale the first still frame is the plain picture,
# whole (sharp at once), the next the still quality.  A turning model
# (--rotate) keeps the history (Whitted's and a denoised path-traced
# view's), through a server as lanray-render --server-frame --rotate.  Under the
# sanitizers the accuracy measurement is left out (the plain pass takes it).
set -u
source tests/tools/server-lib.sh
render() { "$BIN/lanray-render" "$@" --quiet >/dev/null 2>"$dir/render.err" || fail "lanray-render $*: $(cat "$dir/render.err")"; }
if [ $sanitized = 0 ]; then
    step=$(python3 -c "print(1 / 15)")
    render --path models/demo.path --at "$(python3 -c "print(10 / 15)")" --aa adaptive:4 --light-samples 12 --width 160 \
        --height 120 -o "$dir/ref.png"
    for f in 0 2; do
        render --path models/demo.path --path-step "$step" --server-frame 11 --aa 1 --whitted-temporal $f --width 160 \
            --height 120 -o "$dir/h-$f.png"
    done
    e0=$("$BIN/lanray-imgdiff" --csv "$dir/h-0.png" "$dir/ref.png" | cut -d, -f3)
    e2=$("$BIN/lanray-imgdiff" --csv "$dir/h-2.png" "$dir/ref.png" | cut -d, -f3)
    echo "demo flight frame 11, 160x120: RMSE $e0 alone, $e2 with the history of 2"
    python3 -c "import sys; sys.exit(0 if $e2 < 0.85 * $e0 else 1)" || fail "the history took RMSE $e0 only to $e2"
fi
# a served flight: 3 moving frames (t = 0, 0.5, 1), then the still one
cat >"$dir/fly.path" <<'PATH'
key 0 position 0 1.2 5   lookat 0 0.6 0 fov 60
key 1 position 1.5 1.4 4.5 lookat 0 0.6 0 fov 55
PATH
W=64 H=48
fly=(--path "$dir/fly.path" --path-step 0.5 --aa 1 --width $W --height $H)
for k in 1 2 3; do
    render "${fly[@]}" --server-frame $k -o "$dir/t-$k.png"
done
for t in 0 0.5 1; do
    render --path "$dir/fly.path" --at $t --aa 1 --width $W --height $H -o "$dir/m-$t.png"
done
render --path "$dir/fly.path" --at 1 --aa adaptive:2 --width $W --height $H -o "$dir/still.png"
cmp -s "$dir/m-0.png" "$dir/m-1.png" && fail "the path does not move the camera: the test cannot fail"
cmp -s "$dir/t-3.png" "$dir/m-1.png" && fail "the history changed nothing in the third moving frame"
cmp -s "$dir/t-1.png" "$dir/m-0.png" || fail "the first moving frame (no history yet) is not the plain picture"
for how in history none scale2 scale2none scale15 scale15none; do
    case $how in
    history) args=() want=(t-1 t-2 t-3 still) ;;
    none) args=(--whitted-temporal 0) want=(m-0 m-0.5 m-1 still) ;;
    scale2) args=(--render-scale 2) ;;
    scale2none) args=(--render-scale 2 --whitted-temporal 0) ;;
    scale15) args=(--render-scale 1.5) ;;
    scale15none) args=(--render-scale 1.5 --whitted-temporal 0) ;;
    esac
    start_server $how --port 0 --width $W --height $H --path "$dir/fly.path" --path-step 0.5 --wait-clients 2 \
        --still-aa adaptive:2 "${args[@]}" --out "$dir/$how"
    case $how in
    scale*) # 3 moving frames at a render scale, one still one whole of
        # one sample a pixel (sharp at once), then the still quality
        serve_flight $how 5
        cmp -s "$dir/$how/frame-00004.png" "$dir/m-1.png" ||
            fail "the first still frame after frames at a render scale ($how) is not the whole plain picture"
        cmp -s "$dir/$how/frame-00005.png" "$dir/still.png" || fail "the converged frame ($how) is not lanray-render's"
        continue
        ;;
    esac
    serve_flight $how 4 # 3 moving frames and a still one
    served_are $how "${want[@]}"
done
for k in 1 2 3 4; do
    cmp -s "$dir/scale2/frame-0000$k.png" "$dir/scale2none/frame-0000$k.png" ||
        fail "at render scale 2 frame $k differs with the history: moving frames there are not added up"
done
cmp -s "$dir/scale2/frame-00002.png" "$dir/none/frame-00002.png" && fail "render scale 2 changed nothing: the test cannot tell"
cmp -s "$dir/scale15/frame-00003.png" "$dir/scale15none/frame-00003.png" &&
    fail "at render scale 1.5 the history changed nothing in the third moving frame"
# ... where each moving frame is lanray-render's frame of the flight at the
# small size (43 x 32), its history the same, brought up smooth
pairs=()
for k in 1 2 3; do
    render --path "$dir/fly.path" --path-step 0.5 --aa 1 --width 43 --height 32 --server-frame $k -o "$dir/small-$k.png"
    pairs+=("$dir/scale15/frame-0000$k.png" "$dir/small-$k.png")
done
out=$(python3 tests/tools/scaledup.py 6 smooth all "${pairs[@]}" 2>&1) ||
    fail "a moving frame at render scale 1.5 is not lanray-render's history at the small size brought up: $out"
# the light itself (--hdr: RGBE colours added up), moving frames with
# adaptive light sampling (--moving-lights adaptive: the probes' frames
# guided too), and clients on the scalar path against lanray-render's own
for k in 1 2 3; do
    render "${fly[@]}" --server-frame $k -o "$dir/t-$k.hdr"
    render "${fly[@]}" --light-sampling adaptive --server-frame $k -o "$dir/a-$k.png"
    render "${fly[@]}" --light-samples 2 --server-frame $k -o "$dir/p-$k.png"
done
cmp -s "$dir/a-3.png" "$dir/t-3.png" && fail "adaptive light sampling changed nothing: the test cannot tell"
cmp -s "$dir/p-3.png" "$dir/t-3.png" && fail "the lamp's 2 x 2 points changed nothing: the test cannot tell"
start_server hdr --port 0 --width $W --height $H --path "$dir/fly.path" --path-step 0.5 --wait-clients 2 --hdr \
    --out "$dir/hdr"
serve_flight hdr 3
# no frame starts past the flight: the last one goes to the history's stage
# before it is shown, and a fourth started then was, now and then, done and
# written before the server stopped (4 frames where 3 were asked)
grep -q "^frames started 3;" "$dir/hdr.log" || fail "a frame past the flight started: $(grep "^frames started" "$dir/hdr.log")"
for k in 1 2 3; do
    cmp -s "$dir/hdr/frame-0000$k.hdr" "$dir/t-$k.hdr" || fail "served RGBE frame $k is not lanray-render's"
done
start_server lights --port 0 --width $W --height $H --path "$dir/fly.path" --path-step 0.5 --wait-clients 2 \
    --moving-lights adaptive --out "$dir/lights"
LANRAY_SIMD=scalar serve_flight lights 3
served_are lights a-1 a-2 a-3
# the lamp's 2 x 2 points while moving (--moving-light-samples 2), its
# own 3 x 3 in the still frame
start_server points --port 0 --width $W --height $H --path "$dir/fly.path" --path-step 0.5 --wait-clients 2 \
    --still-aa adaptive:2 --moving-light-samples 2 --out "$dir/points"
serve_flight points 4
served_are points p-1 p-2 p-3 still
# a turning model (--rotate) changes the scene every frame but keeps the
# history, Whitted's and a denoised path-traced view's (settings and
# scenes that change otherwise still drop it): each served frame is
# lanray-render's --server-frame K --rotate picture (a server that
# dropped the history at each turn showed frame 2 alone); five frames, the
# camera still after the third, every one a moving frame
for how in turn pathturn; do
    case $how in # (lanray-render's --denoise takes on or off, the server's none)
    turn) args=() sargs=() ;;
    pathturn) args=(--integrator path --denoise on) sargs=(--integrator path --denoise) ;;
    esac
    want=()
    for k in 1 2 3 4 5; do
        render "${fly[@]}" "${args[@]}" --rotate 5 --server-frame $k -o "$dir/$how-$k.png"
        want+=("$how-$k")
    done
    render "${fly[@]}" "${args[@]}" --rotate 5 --server-frame 2 --whitted-temporal 0 --temporal 0 -o "$dir/$how-alone.png"
    cmp -s "$dir/$how-2.png" "$dir/$how-alone.png" && fail "the history changed nothing in a turning frame ($how)"
    start_server $how --port 0 --width $W --height $H --path "$dir/fly.path" --path-step 0.5 --wait-clients 2 \
        --still-aa adaptive:2 --rotate 5 --frames 5 "${sargs[@]}" --out "$dir/$how"
    serve_flight $how 5
    served_are $how "${want[@]}"
done
echo "history: ok"
