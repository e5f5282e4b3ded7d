#!/usr/bin/env bash
# Runs the cmocka test binaries given as arguments, then the command-line
# tests (tests/cli/*.sh), and closes with one line "N passed, N failed"
# counting individual tests.  Each program's line ends with its seconds:
# CI must stay well under 15 minutes, and this shows where they go.
set -u
passed=0
failed=0
failed_names=()
# The command-line tests start python3 hundreds of times (the window tests
# poll the screen with it).  Where python3 is a version manager's shim
# (pyenv's: a bash script that works out the version each time, 0.34 s
# a start on the CI machines against 0.07 s for the interpreter itself),
# the interpreter's own folder goes first on PATH.
if py=$(python3 -c 'import sys; print(sys.executable)' 2>/dev/null) && [ -n "$py" ]; then
    PATH="$(dirname "$py"):$PATH"; export PATH
fi
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
trap 'rm -rf "$units"' EXIT
# run_in DIR I COMMAND...: the command's output in DIR/I.log, its exit
# status in DIR/I.rc and its seconds in DIR/I.s
run_in() {
    local out=$1 i=$2 t0=$SECONDS
    shift 2
    "$@" >"$out/$i.log" 2>&1
    local rc=$?
    echo $((SECONDS - t0)) >"$out/$i.s"
    echo "$rc" >"$out/$i.rc"
}
# in_lanes JOBS DIR COMMAND-PREFIX... -- ITEM...: run_in DIR I PREFIX ITEM
# for each ITEM (I counting from 0), JOBS at a time; AFTER (a command) runs
# each time one is done
in_lanes() {
    local lanes=$1 out=$2 i=0 prefix=()
    shift 2
    while [ "$1" != -- ]; do prefix+=("$1"); shift; done
    shift
    for t in "$@"; do
        while [ "$(jobs -rp | wc -l)" -ge "$lanes" ]; do wait -n; ${AFTER:-:}; done
        run_in "$out" "$i" "${prefix[@]}" "$t" &
        i=$((i + 1))
    done
    wait
}
in_lanes "${TEST_JOBS:-2}" "$units" -- "$@"
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
# They run CLI_JOBS at a time (2): most of a test's time is its processes
# waiting on each other (a server for its clients, a window test for the
# screen), one at a time they kept 1.2 cores of 2 busy, and CI
# went past its 15 minutes.  Each keeps its own folder, ports (port 0)
# and X display (-displayfd); its output is shown whole, in order, as
# soon as it and those before it are done (the slowest started first).
limit=${CLI_TEST_TIMEOUT:-300}
# (CLI_TESTS: the names of those to run, without .sh; all unless given)
clis=()
if [ -n "${CLI_TESTS+set}" ]; then
    for n in $CLI_TESTS; do clis+=("tests/cli/$n.sh"); done
else
    # the slowest first (seconds in CI, 2026-12-02), so that no long test
    # starts last and runs alone while the other lane idles
    for n in cli randscene path chaos double panel window pathtrace faults formats denoise drop desktop; do
        [ -e "tests/cli/$n.sh" ] && clis+=("tests/cli/$n.sh")
    done
    for t in tests/cli/*.sh; do
        [ -e "$t" ] && [[ " ${clis[*]} " != *" $t "* ]] && clis+=("$t")
    done
fi
cli_out=$units/cli
mkdir -p "$cli_out"
shown=0
show_done() { # prints the tests done, in order, up to the first still running
    while [ "$shown" -lt ${#clis[@]} ] && [ -e "$cli_out/$shown.rc" ]; do
        local name rc s
        name=$(basename "${clis[$shown]}")
        rc=$(cat "$cli_out/$shown.rc")
        s=$(cat "$cli_out/$shown.s")
        echo "[ RUN      ] $name"
        cat "$cli_out/$shown.log"
        if [ "$rc" -eq 0 ]; then
            echo "[       OK ] $name ($s s)"; passed=$((passed + 1))
        else
            why=; [ "$rc" -eq 124 ] || [ "$rc" -eq 137 ] && why=", timed out after $limit s"
            echo "[  FAILED  ] $name ($s s$why)"; failed=$((failed + 1)); failed_names+=("$name")
        fi
        shown=$((shown + 1))
    done
}
AFTER=show_done in_lanes "${CLI_JOBS:-2}" "$cli_out" env BIN="${BIN:-bin}" timeout --kill-after=10 "$limit" bash -- "${clis[@]}"
show_done
[ ${#failed_names[@]} -eq 0 ] || echo "failing: ${failed_names[*]}"
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ] && [ ${#failed_names[@]} -eq 0 ]
