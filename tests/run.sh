#!/usr/bin/env bash
# Runs the unit-test binaries given as arguments, then the command-line tests,
# and prints one closing line "N passed, N failed".
set -u
passed=0
failed=0
failed_names=()
for t in "$@"; do
    if "$t"; then passed=$((passed + 1)); else failed=$((failed + 1)); failed_names+=("$(basename "$t")"); fi
done
for t in tests/cli/*.sh; do
    [ -e "$t" ] || continue
    echo "[ RUN      ] $(basename "$t")"
    if BIN="${BIN:-bin}" bash "$t"; then
        echo "[       OK ] $(basename "$t")"; passed=$((passed + 1))
    else
        echo "[  FAILED  ] $(basename "$t")"; failed=$((failed + 1)); failed_names+=("$(basename "$t")")
    fi
done
[ "$failed" -eq 0 ] || echo "failed suites: ${failed_names[*]}"
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
