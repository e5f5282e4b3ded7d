#!/usr/bin/env bash
# No build or fuzzer artefact is tracked: a fuzzer's leak-*, crash-*,
# timeout-*, oom-* or slow-unit-* file, or a *.tmp (a write that was never
# renamed), anywhere but tests/fuzz/crashes/, where make check replays the
# fuzzers' findings on purpose.  The check reads `git ls-files` (in a
# checkout without git, the files under the tree less build/ and bin/), and
# is shown to fail on a planted list.
set -u
fail() { echo "FAIL: $*"; exit 1; }
# artefacts NAMES...: the names (from stdin) that are artefacts
artefacts() {
    grep -E '(^|/)(leak|crash|timeout|oom|slow-unit)-[^/]*$|\.tmp$' | grep -v '^tests/fuzz/crashes/'
}
if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
    files=$(git ls-files)
else
    files=$(find . -path ./build -prune -o -path ./bin -prune -o -type f -print | sed 's|^\./||')
fi
found=$(artefacts <<<"$files")
[ -z "$found" ] || fail "tracked artefacts (remove them, and let .gitignore keep them out):
$found"
planted=$(printf '%s\n' "$files" leak-8d1175d7 docs/tradeoff.csv.tmp tests/fuzz/crashes/obj-crash-1 common/model/crash-2 | artefacts)
[ "$planted" = "leak-8d1175d7
docs/tradeoff.csv.tmp
common/model/crash-2" ] || fail "planted artefacts not all found, or a replayed crash counted: $planted"
echo "no build or fuzzer artefacts tracked ($(wc -l <<<"$files") files); planted ones are found"
