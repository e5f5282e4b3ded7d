#!/usr/bin/env bash
# Property: a frame rendered by a server and two clients is bit-identical to
# lanray-render's, for scenes drawn at random from the whole scene grammar
# (tests/tools/randscene.py).  Each seed is rendered standalone, then served
# with `--verify` to two clients (segment size, tail rule and each client's
# SIMD path drawn from the seed too); any differing pixel fails, naming the
# seed and its scene file.  Every fourth seed is refined instead: the server
# renders frame 1 with one sample a pixel and the still frame 2 with
# --still-aa adaptive:4, which must be lanray-render's --aa adaptive:4 (a
# path-traced scene refines in two still frames: 2x2, then frame 3); every
# eighth also with --still-light-samples K (K 2, 3 or 5: the area lights'
# points doubled a side each still frame up to K), whose last frame must be
# lanray-render's --aa adaptive:4 --light-samples K.  A path-traced scene
# of a seed 2 past a multiple of 4 refines at --still-aa 2: three still
# frames of batches of its samples added up, the last lanray-render's --aa 2.
# SEEDS=N sets how many (default 60; 12 under the sanitizers, which are slow).
set -u
source tests/tools/server-lib.sh
case "$BIN" in *asan* | *tsan*) default_seeds=12 ;; *) default_seeds=60 ;; esac
SEEDS=${SEEDS:-$default_seeds}
FIRST_SEED=${FIRST_SEED:-1}
mkdir -p "$dir/s"
python3 tests/tools/randscene.py 0 "$dir/s" >/dev/null || fail "randscene.py"
"$BIN/obj2tmd" "$dir/s/mesh.obj" "$dir/s/mesh.tmd" >/dev/null || fail "obj2tmd mesh.obj"
W=${W:-160} H=${H:-120}
simd=(auto) # the paths this build and CPU have
for p in scalar sse avx2 avx512; do
    "$BIN/lanray-render" --simd "$p" --width 1 --height 1 -o "$dir/probe.png" --quiet >/dev/null 2>&1 && simd+=("$p")
done
bad=0
for seed in $(seq "$FIRST_SEED" $((FIRST_SEED + SEEDS - 1))); do
    scene=$(python3 tests/tools/randscene.py "$seed" "$dir/s") || fail "randscene.py $seed"
    ref="$dir/ref-$seed.png"
    segs=(1 2 3 5 7 auto)
    tails=(static smart adaptive)
    seg=${segs[$((seed % ${#segs[@]}))]}
    tail=${tails[$((seed / 6 % 3))]}
    linear=()
    [ $((seed % 5)) -eq 0 ] && linear=(--linear) # the output encoding travels to the clients too
    # (unrefined, the server's frame 1: lanray-render's --server-frame 1, a
    # path-traced denoised view's moving frame taking its first sample)
    refine=() check=(--frames 1 --verify "$ref") aa=(--server-frame 1) last=2
    grep -q "integrator path" "$scene" && last=3 # a path-traced view refines at 2x2 first, then adaptive:4
    if [ $((seed % 4)) -eq 0 ]; then
        aa=(--aa adaptive:4)
        refine=(--aa 1 --still-aa adaptive:4)
        if [ $((seed % 8)) -eq 0 ]; then
            k=$((2 + seed / 8 % 3)); k=${k/4/5} # 2, 3 or 5
            aa+=(--light-samples "$k")
            refine+=(--still-light-samples "$k")
            last=7 # from a light's own points (at least 1) to K: at most 1, 2, 4, 5; then the same frame
        fi
        check=(--frames $last)
    elif [ $((seed % 4)) -eq 2 ] && grep -q "integrator path" "$scene"; then
        # a path-traced view at 2x2 still: its 4 samples come in 3 batches
        # (1, 1, 2), added up by the server (render/progressive.h)
        aa=(--aa 2)
        refine=(--aa 1 --still-aa 2)
        last=4
        check=(--frames $last)
    fi
    "$BIN/lanray-render" "$scene" -o "$ref" --width $W --height $H --threads 2 "${linear[@]}" "${aa[@]}" --quiet >"$dir/render.log" 2>&1 ||
        { cat "$dir/render.log"; fail "seed $seed: lanray-render failed"; }
    rm -rf "$dir/f"
    start_server "seed-$seed" "$scene" "${linear[@]}" --port 0 --width $W --height $H "${check[@]}" "${refine[@]}" --wait-clients 2 --segment "$seg" --tail "$tail" \
        --out "$dir/f"
    # the two clients as two CPUs: each takes another traversal path (simd.h)
    s1=${simd[$((seed % ${#simd[@]}))]} s2=${simd[$(((seed + 1) % ${#simd[@]}))]}
    "$BIN/lanray-client" "127.0.0.1:$port" --threads 2 --once --quiet --simd "$s1" 2>/dev/null &
    c1=$!
    "$BIN/lanray-client" "127.0.0.1:$port" --threads 1 --once --quiet --simd "$s2" 2>/dev/null &
    c2=$!
    pids+=("$c1" "$c2")
    for _ in $(seq 600); do kill -0 "$server_pid" 2>/dev/null || break; sleep 0.05; done
    kill -0 "$server_pid" 2>/dev/null && fail "seed $seed: the frame did not finish in 30 s"
    wait "$server_pid"
    rc=$?
    wait "$c1" "$c2" 2>/dev/null
    if [ $rc -eq 0 ] && [ ${#refine[@]} -gt 0 ] && ! cmp -s "$dir/f/frame-0000$last.png" "$ref"; then
        rc=3
        echo "seed $seed: the refined frame $last differs from lanray-render ${aa[*]}" >>"$dir/seed-$seed.err"
    fi
    if [ $rc -eq 3 ]; then
        bad=$((bad + 1))
        echo "seed $seed ($seg-line segments, $tail tail): $(grep -o '[0-9]* pixels differ\|the refined frame [0-9] differs.*' "$dir/seed-$seed.err")"
        mkdir -p build/randscene-failures && cp "$scene" build/randscene-failures/
    elif [ $rc -ne 0 ]; then
        fail "seed $seed: server exited $rc"
    fi
done
[ $bad -eq 0 ] || fail "$bad of $SEEDS random scenes differ between lanray-render and a server with two clients (scenes in build/randscene-failures/)"
echo "random scenes: $SEEDS of $SEEDS bit-identical to lanray-render's through a server and two clients (every fourth refined: its still frame lanray-render's adaptive:4, every eighth with --still-light-samples; path-traced ones 2 past a fourth in batches to 2x2)"
