#!/usr/bin/env bash
# Short functions, thin mains (docs/architecture.md): no function in
# common/, server/, client/ or tools/ over 120 lines, no main over 60
# (tests/tools/funclen.py), and the check fails on a planted long one.
set -u
fail() { echo "FAIL: $*"; exit 1; }
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
out=$(python3 tests/tools/funclen.py --top 3 --max-lines 120 --max-main 60 common server client tools 2>&1) ||
    fail "functions too long: $out"
mkdir -p "$dir/common"
{
    echo "int planted(int x);"
    echo "int planted(int x)"
    echo "{"
    for i in $(seq 130); do echo "    x += $i;"; done
    echo "    return x;"
    echo "}"
} >"$dir/common/long.c"
planted=$(python3 tests/tools/funclen.py --max-lines 120 --max-main 60 "$dir/common" 2>&1) && fail "a 134-line function passed"
grep -q "long.c:2: planted is 134 lines, more than 120" <<<"$planted" || fail "the planted function is not named: $planted"
echo "function lengths: at most 120 lines, mains at most 60; the longest:"
echo "$out"
