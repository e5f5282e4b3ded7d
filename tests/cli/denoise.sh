#!/usr/bin/env bash
# Denoising (settings denoise, --denoise: render/denoise.h): the Cornell box
# path-traced at one sample a pixel (96 x 96) comes at least three times as
# close to its converged picture denoised as not, at 4x4 samples 1.5 times
# (at 400 x 400 the filter has more pixels a wall: 4.5 and 3.3 times,
# docs/renderer.md); the denoised
# frame is the same bytes on every SIMD path, in segments of any size,
# with adaptive anti-aliasing, through a lens and a fisheye, in .hdr; a
# Whitted frame passes as it is; through a server and two clients (moving
# frames added up by their history, and the still ones that refine), the
# frames are lanray-render's --server-frame pictures bit for bit, with the
# server's --denoise or the scene's own setting, and without the history
# its one-frame --denoise pictures; a frame too large for memory whole is refused,
# naming denoising, and leaves no file.  Under ThreadSanitizer (make
# check-tsan: the server filters on a thread of its own) and ASan the
# accuracy measurements are left out (the plain pass takes them).
set -u
source tests/tools/server-lib.sh
S=models/cornell.scene W=96 H=96
render() { "$BIN/lanray-render" "$@" --quiet >/dev/null 2>"$dir/render.err" || fail "lanray-render $*: $(cat "$dir/render.err")"; }
rmse() { "$BIN/lanray-imgdiff" --csv "$1" "$2" | cut -d, -f3; }
# the converged reference: 24 x 24 samples a pixel
[ $sanitized = 1 ] || render $S --integrator path --aa 24 --width $W --height $H -o "$dir/ref.png"
for a in "1 3" "4 1.5"; do
    set -- $a
    a=$1 k=$2
    render $S --integrator path --aa $a --width $W --height $H -o "$dir/raw-$a.png"
    render $S --integrator path --aa $a --width $W --height $H --denoise on -o "$dir/dn-$a.png"
    [ $sanitized = 1 ] && continue
    raw=$(rmse "$dir/raw-$a.png" "$dir/ref.png") dn=$(rmse "$dir/dn-$a.png" "$dir/ref.png")
    echo "cornell ${a}x$a: RMSE $raw raw, $dn denoised"
    python3 -c "import sys; sys.exit(0 if $dn * $k < $raw else 1)" ||
        fail "at ${a}x$a samples denoising took RMSE $raw only to $dn"
done
# one picture on every path, in segments, whatever the threads
render $S --integrator path --aa 1 --width $W --height $H --denoise on --segment 7 --threads 1 -o "$dir/seg.png"
cmp -s "$dir/seg.png" "$dir/dn-1.png" || fail "in segments of 7 lines the denoised frame differs"
sed 's/^settings \(.*\)/settings \1 integrator path denoise on/' $S >"$dir/on.scene"
sed 's/^settings \(.*\)/settings \1 integrator path/' $S >"$dir/path.scene"
grep -q "denoise on" "$dir/on.scene" || fail "no settings line to add denoise to in $S"
render "$dir/on.scene" --aa 1 --width $W --height $H -o "$dir/scene-on.png"
cmp -s "$dir/scene-on.png" "$dir/dn-1.png" || fail "the scene's settings denoise on is not --denoise on"
same_on_simd_paths "$dir/on.scene" "$dir/dn-1.png" $W $H "the denoised Cornell box"
# adaptive anti-aliasing, a lens, a fisheye, .hdr: denoised, changed, finite
render $S --integrator path --aa adaptive:2 --width $W --height $H --denoise on -o "$dir/adapt.png"
render $S --integrator path --aa adaptive:2 --width $W --height $H -o "$dir/adapt-raw.png"
cmp -s "$dir/adapt.png" "$dir/adapt-raw.png" && fail "denoising changed no pixel of an adaptive frame"
for cam in "fov 40 aperture 20 focus 800" "fisheye 170"; do
    sed "s/^camera \(.*\) fov 40/camera \1 $cam/" "$dir/on.scene" >"$dir/cam.scene"
    render "$dir/cam.scene" --aa 1 --width $W --height $H -o "$dir/cam.png"
    render "$dir/cam.scene" --aa 1 --width $W --height $H --denoise off -o "$dir/cam-raw.png"
    cmp -s "$dir/cam.png" "$dir/cam-raw.png" && fail "denoising changed nothing with camera $cam"
done
render $S --integrator path --aa 1 --width $W --height $H --denoise on -o "$dir/dn.hdr"
render $S --integrator path --aa 1 --width $W --height $H -o "$dir/raw.hdr"
[ $sanitized = 1 ] || render $S --integrator path --aa 24 --width $W --height $H -o "$dir/ref.hdr"
[ $sanitized = 1 ] || {
e_dn=$("$BIN/lanray-imgdiff" --csv --relative --block 4 "$dir/dn.hdr" "$dir/ref.hdr" | cut -d, -f1)
e_raw=$("$BIN/lanray-imgdiff" --csv --relative --block 4 "$dir/raw.hdr" "$dir/ref.hdr" | cut -d, -f1)
echo "cornell .hdr 1x1: relative error in 4x4 blocks $e_raw raw, $e_dn denoised"
python3 -c "import sys; sys.exit(0 if $e_dn < $e_raw else 1)" || fail "a denoised .hdr is no closer: $e_dn against $e_raw"
}
# Whitted frames have no noise to take out: the same bytes
render --aa 1 --width $W --height $H -o "$dir/w.png"
render --aa 1 --width $W --height $H --denoise on -o "$dir/w-on.png"
cmp -s "$dir/w.png" "$dir/w-on.png" || fail "a Whitted frame changed under --denoise on"
# through a server: a flight of 3 moving frames (1 sample, each another of
# the pixel's, added up by the history: --temporal 4, the default), then
# still frames of 1, 2, 4, 8 and 16 samples of 4x4 (--still-aa 4: batches,
# their sums and their guides' added up by the server, the first ones
# weighed with the history), each lanray-render's --server-frame K picture bit for
# bit; with --temporal 0 the moving frames are lanray-render's --denoise
# pictures of one sample at their time, and the still frames its
# --still-frame K pictures
cat >"$dir/room.path" <<'PATH'
key 0 position 278 273 -800 lookat 278 273 0 fov 40
key 1 position 200 300 -700 lookat 278 273 0 fov 40
PATH
fly=(--integrator path --path "$dir/room.path" --path-step 0.5 --aa 1 --still-aa 4 --width 48 --height 48 --denoise on)
for k in 1 2 3 4 5 6 7 8; do
    render $S "${fly[@]}" --server-frame $k -o "$dir/t-$k.png"
done
for t in 0 0.5 1; do
    render $S --integrator path --path "$dir/room.path" --at $t --aa 1 --width 48 --height 48 --denoise on -o "$dir/m-$t.png"
done
for k in 1 2 3 4 5; do
    render $S --integrator path --path "$dir/room.path" --at 1 --aa 4 --still-frame $k --width 48 --height 48 --denoise on \
        -o "$dir/s-$k.png"
done
cmp -s "$dir/m-0.png" "$dir/m-1.png" && fail "the path does not move the camera: the test cannot fail"
cmp -s "$dir/t-3.png" "$dir/m-1.png" && fail "the history changed nothing in the third moving frame"
cmp -s "$dir/t-8.png" "$dir/s-5.png" || fail "the flight's converged frame is not lanray-render's --still-frame 5"
# a moving frame's one sample a pixel is sample 0 of the pixel's 32 x 32 in
# their progressive order (settings jitter): a 32x32 still's first frame
render $S --integrator path --aa 1 --server-frame 1 --width 48 --height 48 --denoise on -o "$dir/j-1.png"
render $S --integrator path --aa 32 --still-frame 1 --width 48 --height 48 --denoise on -o "$dir/j-s1.png"
cmp -s "$dir/j-1.png" "$dir/j-s1.png" || fail "a moving frame's sample is not the 32x32 still's first"
render $S --integrator path --aa 1 --width 48 --height 48 --denoise on -o "$dir/c-1.png"
cmp -s "$dir/j-1.png" "$dir/c-1.png" && fail "the moving frame's sample is the pixel's centre: the test cannot tell"
for how in flag scene notemporal; do
    case $how in
    flag) args=(--denoise "$dir/path.scene") want=(t-1 t-2 t-3 t-4 t-5 t-6 t-7 t-8) ;;
    scene) args=("$dir/on.scene") want=(t-1 t-2 t-3 t-4 t-5 t-6 t-7 t-8) ;;
    notemporal) args=(--temporal 0 "$dir/on.scene") want=(m-0 m-0.5 m-1 s-1 s-2 s-3 s-4 s-5) ;;
    esac
    start_server room-$how --port 0 --width 48 --height 48 --path "$dir/room.path" --path-step 0.5 --wait-clients 2 \
        --still-aa 4 "${args[@]}" --out "$dir/$how"
    serve_flight $how 8 # 3 moving frames and 5 still ones
    served_are $how "${want[@]}"
done
# too large to hold whole: refused, nothing left
out=$("$BIN/lanray-render" $S --integrator path --denoise on --aa 1 --width 64 --height 64 --band 16 -o "$dir/big.png" 2>&1)
[ $? = 1 ] && grep -q "denoising needs the whole frame" <<<"$out" || fail "a banded frame with --denoise: $out"
[ -e "$dir/big.png" ] && fail "a refused render left its file"
# a whole frame whose denoiser's planes (84 bytes a pixel) do not fit is
# refused before rendering, naming them (under a limit on the address
# space; not under the sanitizers, whose shadow memory takes it all)
if [ $sanitized = 0 ]; then
    out=$( (ulimit -v 700000; "$BIN/lanray-render" $S --integrator path --denoise on --aa 1 --width 4000 --height 4000 \
        -o "$dir/big.png") 2>&1)
    [ $? = 1 ] && grep -q "the frame with its denoiser needs" <<<"$out" || fail "a denoiser too large: $out"
    [ -e "$dir/big.png" ] && fail "a render refused for its denoiser left its file"
fi
echo "denoise: ok"
