#!/usr/bin/env bash
# Every SIMD traversal path gives the same bytes: the scalar binary-tree
# traversal, SSE (4-wide nodes), AVX2 and AVX-512 (8-wide), each forced in turn with
# --simd, on the built-in scene, a 20k-triangle smooth mesh with each
# builder, a grid whose rays cross shared edges (ties: wide.h), and random
# scenes (tests/tools/randscene.py).  Paths this CPU or build lacks are
# reported and skipped.
set -u
BIN=${BIN:-bin}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
# under a sanitizer (check-asan, check-tsan) smaller frames: the same code
# on every path, a third of the pixels
W=200 H=150
case "$BIN" in *asan* | *tsan*) W=120 H=90 ;; esac
paths=()
for p in scalar sse avx2 avx512; do
    if "$BIN/lanray-render" --simd "$p" --width 1 --height 1 -o "$dir/probe.png" --quiet >/dev/null 2>&1; then
        paths+=("$p")
    else
        echo "simd: no $p path here"
    fi
done
[ ${#paths[@]} -ge 1 ] || fail "no SIMD path runs"
python3 tests/tools/meshes.py "$dir" || fail "meshes.py"
mkdir -p "$dir/s"
python3 tests/tools/randscene.py 0 "$dir/s" >/dev/null || fail "randscene.py"
"$BIN/obj2tmd" "$dir/s/mesh.obj" "$dir/s/mesh.tmd" >/dev/null || fail "obj2tmd mesh.obj"
jobs=("default|" "bumpy-sbt|$dir/bumpy.obj --bvh sbt" "bumpy-mst|$dir/bumpy.obj --bvh mst"
      "bumpy-sah|$dir/bumpy.obj --bvh sah" "grid|$dir/grid.obj")
for seed in $(seq 1 ${SEEDS:-12}); do
    jobs+=("seed-$seed|$(python3 tests/tools/randscene.py "$seed" "$dir/s")")
done
n=0
for job in "${jobs[@]}"; do
    name=${job%%|*}
    read -r -a args <<<"${job#*|}"
    for p in "${paths[@]}"; do
        "$BIN/lanray-render" "${args[@]}" --simd "$p" --width $W --height $H --aa 1 --threads 2 --quiet \
            -o "$dir/$name-$p.png" >"$dir/log" 2>&1 || { cat "$dir/log"; fail "$name: lanray-render --simd $p failed"; }
        grep -q "simd $p " "$dir/log" || fail "$name: --simd $p did not take: $(cat "$dir/log")"
        [ "$p" = "${paths[0]}" ] && continue
        cmp -s "$dir/$name-${paths[0]}.png" "$dir/$name-$p.png" ||
            fail "$name: --simd $p differs from --simd ${paths[0]}: $("$BIN/lanray-imgdiff" "$dir/$name-${paths[0]}.png" "$dir/$name-$p.png")"
    done
    n=$((n + 1))
done
# A farm mixes CPUs, and the C library picks its own variants of sinf,
# cosf, powf, expf ... by the CPU (FMA, AVX2): with those taken away
# (GLIBC_TUNABLES, as on a CPU without them) the pixels stay the same, the
# Whitted and path-traced default scene and a panorama's sky (its
# directions by atan2 and sin/cos) alike.  (A C library that ignores the
# tunable checks nothing new.)
narrow="glibc.cpu.hwcaps=-AVX2,-FMA,-AVX512F"
cp tests/data/cycles/environment.scene tests/data/cycles/sky.hdr "$dir/"
for job in "whitted|--aa 2" "path|--integrator path --aa 2" "sky|$dir/environment.scene --aa 2"; do
    name=${job%%|*}
    # shellcheck disable=SC2086 # the job's options are words
    "$BIN/lanray-render" ${job#*|} --width 96 --height 72 -o "$dir/libm-$name.ppm" --quiet >/dev/null ||
        fail "libm $name did not render"
    # shellcheck disable=SC2086
    GLIBC_TUNABLES=$narrow "$BIN/lanray-render" ${job#*|} --width 96 --height 72 -o "$dir/libm-$name-narrow.ppm" \
        --quiet >/dev/null || fail "libm $name did not render without FMA and AVX2"
    cmp -s "$dir/libm-$name.ppm" "$dir/libm-$name-narrow.ppm" ||
        fail "$name: the C library's variants without FMA and AVX2 change the pixels: $("$BIN/lanray-imgdiff" \
            "$dir/libm-$name.ppm" "$dir/libm-$name-narrow.ppm")"
done
# ... and the renderer and the client call none of the C library's
# functions that glibc picks by the CPU and that were found to differ
# (tests/tools/libm-imports.sh says which)
nlib=$(bash tests/tools/libm-imports.sh "$BIN/lanray-render" "$BIN/lanray-client") || fail "$nlib"
echo "simd: $n scenes byte-identical across ${paths[*]}; the C library's variants without FMA and AVX2 give the same pixels; of libm the renderer and the client call only exact or CPU-independent functions ($nlib)"
