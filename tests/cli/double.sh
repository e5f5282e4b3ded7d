#!/usr/bin/env bash
# The double-precision build (make PRECISION=double: bench-pov's converged
# references, the stability comparisons) compiles with the warnings as
# errors, built from scratch in a folder of its own, and renders the
# default scene and models/example.scene as the float build does: the same
# light, the two differing only where rounding picks another surface or
# sample (nothing else builds it: a change once broke it unnoticed).
set -u
BIN=${BIN:-bin}
# once, with the plain build: under the sanitizers this built a second
# library from scratch (make passes SAN on) for a check of the same code
case "$BIN" in *asan* | *tsan*) echo "double: checked with the plain build only"; exit 0 ;; esac
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

make --no-print-directory -j2 PRECISION=double BUILD="$dir/build" BIN="$dir/bin" "$dir/bin/lanray-render" \
    >"$dir/log" 2>&1 || { tail -20 "$dir/log"; fail "the double build"; }
for scene in "" models/example.scene; do
    "$dir/bin/lanray-render" $scene --width 96 --height 72 --aa 2 -o "$dir/d.png" --quiet >/dev/null 2>&1 ||
        fail "double render of ${scene:-the default scene}"
    "$BIN/lanray-render" $scene --width 96 --height 72 --aa 2 -o "$dir/f.png" --quiet >/dev/null 2>&1 ||
        fail "float render of ${scene:-the default scene}"
    rmse=$("$BIN/lanray-imgdiff" --csv "$dir/d.png" "$dir/f.png" | cut -d, -f3)
    awk -v r="$rmse" 'BEGIN { exit !(r + 0 < 3) }' ||
        fail "${scene:-the default scene}: double and float pictures differ by RMSE $rmse"
done
# its maths the same on every CPU, as the float build's (simd.sh)
nlib=$(bash tests/tools/libm-imports.sh "$dir/bin/lanray-render") || fail "$nlib"
echo "double: the double build compiles and renders the default scene and the example as the float build (RMSE under 3); of libm it calls only exact or CPU-independent functions ($nlib)"
