#!/usr/bin/env bash
# samepixels.sh BEFORE_BIN [AFTER_BIN] - a refactoring changed no pixel.
#
# Renders the default scene, models/example.scene and SEEDS (60) random
# scenes of tests/tools/randscene.py with lanray-render from two builds'
# bin folders (an earlier commit's, this one's: AFTER_BIN, default bin),
# on every SIMD path this CPU has, and compares the pixels byte for byte
# (as binary PPM: a PNG's bytes follow its encoder's settings too, which
# changed on 2026-11-28).
# (That a served frame equals lanray-render's is tests/cli/randscene.sh.)
# Exits 1 naming each scene and path that differs.
set -u
export LANRAY_RANDSCENE_WHITTED=1 # scenes an older build reads
before=${1:?usage: samepixels.sh BEFORE_BIN [AFTER_BIN]}
after=${2:-bin}
SEEDS=${SEEDS:-60}
W=${W:-160} H=${H:-120}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
# each side's scenes with its own model file (a .tmd in its own version)
for side in before after; do
    mkdir -p "$dir/$side"
    python3 tests/tools/randscene.py 0 "$dir/$side" >/dev/null || exit 1
    b=${!side}
    "$b/obj2tmd" "$dir/$side/mesh.obj" "$dir/$side/mesh.tmd" >/dev/null || exit 1
done
paths=(auto)
declare -A before_path=([auto]=auto) # a path an older build lacks: its best one there
for p in scalar sse avx2 avx512; do
    "$after/lanray-render" --simd "$p" --width 1 --height 1 -o "$dir/probe.png" --quiet >/dev/null 2>&1 || continue
    paths+=("$p") before_path[$p]=auto
    "$before/lanray-render" --simd "$p" --width 1 --height 1 -o "$dir/probe.png" --quiet >/dev/null 2>&1 &&
        before_path[$p]=$p
done
scenes=("" models/example.scene)
for seed in $(seq 1 "$SEEDS"); do
    python3 tests/tools/randscene.py "$seed" "$dir/before" >/dev/null || exit 1
    scenes+=("$(python3 tests/tools/randscene.py "$seed" "$dir/after")")
done
bad=0 n=0
for scene in "${scenes[@]}"; do
    for p in "${paths[@]}"; do
        for side in before after; do
            b=${!side} q=$p
            [ $side = before ] && q=${before_path[$p]}
            scene_of_side=${scene/$dir\/after/$dir\/$side}
            "$b/lanray-render" $scene_of_side --simd "$q" --width "$W" --height "$H" --threads 2 -o "$dir/$side.ppm" \
                --quiet >/dev/null 2>&1 || { echo "samepixels: ${scene:-default} ($p): $b/lanray-render failed"; bad=$((bad + 1)); }
        done
        n=$((n + 1))
        cmp -s "$dir/before.ppm" "$dir/after.ppm" ||
            { echo "samepixels: ${scene:-default scene} ($p): the pictures differ"; bad=$((bad + 1)); }
    done
done
[ $bad -eq 0 ] || { echo "samepixels: $bad problems in $n renders"; exit 1; }
echo "samepixels: $n renders ($((${#scenes[@]})) scenes x ${#paths[@]} SIMD paths) byte-identical"
