#!/usr/bin/env bash
# Replays every fuzz corpus input and every crash input found so far through
# its harness (gcc build; under make check-asan with sanitizers).
set -u
BUILD=${BUILD:-build/float}
export LSAN_OPTIONS="suppressions=$PWD/tests/fuzz/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
fail=0
for h in tests/fuzz/fuzz_*.c; do
    name=$(basename "$h" .c); name=${name#fuzz_}
    files=(tests/fuzz/corpus/"$name"/* tests/fuzz/crashes/"$name"-*)
    existing=()
    for f in "${files[@]}"; do [ -f "$f" ] && existing+=("$f"); done
    [ ${#existing[@]} -gt 0 ] || { echo "FAIL: no corpus for $name"; fail=1; continue; }
    out=$("$BUILD/fuzz/replay_$name" "${existing[@]}" 2>&1) || { echo "FAIL: $name: $out" | tail -20; fail=1; continue; }
    echo "$name: $out"
done
exit $fail
