#!/usr/bin/env bash
# Runs the cmocka test binaries given as arguments, then the command-line
# tests (tests/cli/*.sh), and closes with one line "N passed, N failed"
# counting individual tests.  Each program's line ends with its seconds:
# CI must stay well under 15 minutes, and this shows where they go.
set -u
passed=0
failed=0
failed_names=()
# the unit tests keep their files in /tmp/lanray-test-*, which they remove
# (helpers.h): one left behind is a failure, naming the folder
tmpdirs() { ls -d /tmp/lanray-test-* 2>/dev/null | sort; }
before=$(tmpdirs)
# The unit test programs two at a time (TEST_JOBS): each is deterministic
# and times nothing, and one alone leaves the second core idle much of the
# time (under the sanitizers they took over a minute one after another).
# Each one's output is kept apart and shown whole, in order, when all are
# done; its seconds are its own, beside another.
units=$(mktemp -d)
trap 'rm -rf "$units"' EXIT # (and the command-line tests' logs, below)
i=0
for t in "$@"; do
    while [ "$(jobs -rp | wc -l)" -ge "${TEST_JOBS:-2}" ]; do wait -n; done
    (t0=$SECONDS; "$t" >"$units/$i.log" 2>&1; echo $? >"$units/$i.rc"; echo $((SECONDS - t0)) >"$units/$i.s") &
    i=$((i + 1))
done
wait
i=0
for t in "$@"; do
    log=$units/$i.log
    cat "$log"
    rc=$(cat "$units/$i.rc" 2>/dev/null || echo 1)
    echo "[ TIME     ] $(basename "$t") $(cat "$units/$i.s" 2>/dev/null) s"
    i=$((i + 1))
    p=$(sed -n 's/^\[  PASSED  \] \([0-9]*\) test(s)\./\1/p' "$log" | tail -1)
    f=$(sed -n 's/^\[  FAILED  \] \([0-9]*\) test(s), listed below:/\1/p' "$log" | tail -1)
    passed=$((passed + ${p:-0}))
    failed=$((failed + ${f:-0}))
    if [ "$rc" -ne 0 ]; then
        failed_names+=("$(basename "$t")")
        [ -n "$f" ] || failed=$((failed + 1)) # crashed before reporting
    fi
done
left=$(comm -13 <(echo "$before") <(tmpdirs))
if [ -n "$left" ]; then
    echo "[  FAILED  ] unit tests left temporary folders: $left"
    failed=$((failed + 1)); failed_names+=("temporary folders")
else
    passed=$((passed + 1))
fi
# Each command-line test has CLI_TEST_TIMEOUT seconds (the slowest takes
# under a minute under AddressSanitizer): one that hangs fails by name, its
# processes ended (timeout signals the test's whole process group, and the
# test's EXIT trap still removes its folder), and the rest still run.
limit=${CLI_TEST_TIMEOUT:-300}
# The command-line tests two at a time (CLI_TEST_JOBS), as the unit tests:
# most spend their time in one-thread renders, python and process starts,
# and 19 of them took 91 s one after another, 53 s two at a time.  Those
# that time what they watch (frames or status lines a second, a stalled
# client's deadline, a window's frames, Avahi's answers, a time slice) or
# run make in the tree run after them, alone.  Each test's output is kept
# and shown whole when it ends.
alone=" animation chaos cli deb distributed edit faults install mdns panel schedsim window "
cli_run() { # TEST LOG: runs TEST, its output into LOG, its status into LOG.rc, its seconds into LOG.s
    local t0=$SECONDS
    BIN="${BIN:-bin}" timeout --kill-after=10 "$limit" bash "$1" >"$2" 2>&1
    echo $? >"$2.rc"
    echo $((SECONDS - t0)) >"$2.s"
}
cli_report() { # TEST LOG
    local name rc s why=
    name=$(basename "$1")
    rc=$(cat "$2.rc" 2>/dev/null || echo 1) s=$(cat "$2.s" 2>/dev/null)
    echo "[ RUN      ] $name"
    cat "$2"
    if [ "$rc" -eq 0 ]; then
        echo "[       OK ] $name ($s s)"; passed=$((passed + 1))
    else
        [ "$rc" -eq 124 ] || [ "$rc" -eq 137 ] && why=", timed out after $limit s"
        echo "[  FAILED  ] $name ($s s$why)"; failed=$((failed + 1)); failed_names+=("$name")
    fi
}
clis=$(mktemp -d)
trap 'rm -rf "$units" "$clis"' EXIT
declare -A running=() # pid -> test
reap() { # waits for one running test to end and reports it
    local pid
    wait -n -p pid "${!running[@]}"
    cli_report "${running[$pid]}" "$clis/$(basename "${running[$pid]}").log"
    unset "running[$pid]"
}
for t in tests/cli/*.sh; do
    [ -e "$t" ] || continue
    n=$(basename "$t" .sh)
    [[ $alone == *" $n "* ]] && continue
    while [ ${#running[@]} -ge "${CLI_TEST_JOBS:-2}" ]; do reap; done
    cli_run "$t" "$clis/$n.sh.log" &
    running[$!]=$t
done
while [ ${#running[@]} -gt 0 ]; do reap; done
for t in tests/cli/*.sh; do
    n=$(basename "$t" .sh)
    [[ $alone == *" $n "* ]] || continue
    cli_run "$t" "$clis/$n.sh.log"
    cli_report "$t" "$clis/$n.sh.log"
done
[ ${#failed_names[@]} -eq 0 ] || echo "failing: ${failed_names[*]}"
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ] && [ ${#failed_names[@]} -eq 0 ]
