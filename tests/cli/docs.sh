#!/usr/bin/env bash
# docs/tools.md says what the tools' --help says (it is generated from them:
# after changing an option, `make tools-doc`), and the README links every
# document in docs/ that a user reads.
set -u
BIN=${BIN:-bin}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
bash tools/tools-doc "$BIN" "$dir/tools.md" >/dev/null || fail "tools-doc failed"
diff -u docs/tools.md "$dir/tools.md" >"$dir/diff" || { head -40 "$dir/diff"; fail "docs/tools.md differs from the tools' --help (run make tools-doc)"; }
for d in getting-started tools scene protocol tmd; do
    grep -q "docs/$d.md" README.md || fail "README.md does not link docs/$d.md"
done
exit 0
