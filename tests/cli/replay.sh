#!/usr/bin/env bash
# tools/bench-scaling REPLAY=LOG: a logged run's measurements come back as
# they were logged (each configuration its fastest pass), the simulator
# predicts every one of them with the log's calibration, and a file that is
# not such a log is refused, naming it, with nothing written.  The log is a
# real reduced run (CLIENTS="1 2" SEGMENTS="16 256" TAILS="static smart"
# FRAMES=2 PLAN=0); the profile is flat, so that no models are needed.
set -u
BIN=${BIN:-bin}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
log=tests/data/scaling-small.log
for i in $(seq 0 767); do echo "$i,200"; done >"$dir/flat.csv"
replay() { REPLAY=$1 PROFILE="$dir/flat.csv" PLAN=0 BIN=$BIN LANRAY_MODELS="$dir/none" tools/bench-scaling "$2" >"$dir/out.txt" 2>&1; }

replay "$log" "$dir/out" || { cat "$dir/out.txt"; fail "replay of $log exited non-zero"; }
csv="$dir/out/scaling-small.csv" # named as the log: scaling-small.log -> scaling-small.*
[ -s "$csv" ] || fail "no $csv"
# every configuration of the log, once, with its fastest pass's figures
awk '/^pass [0-9]+: [0-9]+ clients, / {
        k = $3 "," $5 "," $6; sub(/:$/, "", k)
        f = $0; sub(/.* fps=/, "", f); sub(/ .*/, "", f)
        w = $0; sub(/.* wall_s=/, "", w); sub(/ .*/, "", w)
        if (!(k in best) || f + 0 > best[k] + 0) { best[k] = f; wall[k] = w } }
    END { for (k in best) print k "," wall[k] "," best[k] }' "$log" | sort >"$dir/expected"
awk -F, 'NR > 1 { print $1 "," $3 "," $4 "," $6 "," $7 }' "$csv" | sort >"$dir/got"
[ "$(wc -l <"$dir/expected")" -eq 10 ] || fail "expected 10 configurations in $log, found $(wc -l <"$dir/expected")"
diff "$dir/expected" "$dir/got" || fail "measured columns differ from the log's fastest passes"
# a prediction for every row, and the flat profile's worked answer: 256-line
# segments are 3 per frame, so 2 clients take 2 segment times where 16-line
# ones take 1.5: about 0.75 of the FPS
awk -F, 'NR > 1 && !($14 > 0) { exit 1 }' "$csv" || fail "a row without a prediction"
r=$(awk -F, '$1 == 2 && $3 == "static" { p[$4] = $14 } END { printf "%.3f", p[256] / p[16] }' "$csv")
awk -v r="$r" 'BEGIN { exit !(r > 0.65 && r < 0.85) }' || fail "2 clients, 256 against 16 lines predicted at $r, expected about 0.75"
# the automatic size's comparison as logged
grep -E '^[0-9]+,(static|smart|adaptive),[0-9]+,[0-9.]+,[0-9.]+,[0-9]+,[0-9.]+$' "$log" >"$dir/auto.expected"
tail -n +2 "$dir/out/scaling-small-auto.csv" | diff "$dir/auto.expected" - || fail "automatic size rows differ from the log"
grep -q "of 10 configurations within 15%" "$dir/out/scaling-small-results.md" || fail "results table does not count 10 configurations"

# not a log, and a log cut after its first line: refused, naming the file
echo "hello" >"$dir/scaling-bad.log"
head -1 "$log" >"$dir/scaling-cut.log"
for bad in "$dir/scaling-bad.log" "$dir/scaling-cut.log"; do
    replay "$bad" "$dir/bad" && fail "replay of $(basename "$bad") succeeded"
    grep -q "$bad" "$dir/out.txt" || fail "the error does not name $bad: $(cat "$dir/out.txt")"
    [ ! -e "$dir/bad" ] || fail "replay of $(basename "$bad") wrote $(ls "$dir/bad")"
done
exit 0
