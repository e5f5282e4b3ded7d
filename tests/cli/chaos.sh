#!/usr/bin/env bash
# Clients killed at random moments over many frames: tools/bench/loadtest, short.
# Six single-thread clients; every quarter second one leaves (SIGKILL at a
# random moment, or SIGTERM) and the one before joins again, for 20 s (12 s
# under the sanitizers, whose run is for memory errors: some 50 departures).  The
# server checks every frame against lanray-render's (--verify); the test
# fails on a wrong pixel, a dead server or server memory that grows.
set -u
BIN=${BIN:-bin}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
# Under AddressSanitizer freed memory sits in its quarantine (up to 256 MB),
# so the server's RSS grows by design there; LeakSanitizer checks for leaks
# at exit instead, and the memory check is the normal build's.
rss_check=1 duration=20
case "$BIN" in *asan*) rss_check=0 duration=12 ;; esac
out=$(CLIENTS=6 DURATION=$duration CHURN=0.25 W=160 H=120 BIN="$BIN" RSS_CHECK=$rss_check tools/bench/loadtest "$dir" 2>&1)
rc=$?
echo "$out"
[ "$rc" = 0 ] || { echo "FAIL: chaos"; exit 1; }
grep -q "wrong_pixels=0 " <<<"$out" || { echo "FAIL: wrong pixels"; exit 1; }
