#!/usr/bin/env bash
# The layering (docs/architecture.md): every #include across folders goes
# down, from common/'s higher layers to its lower ones, from server/ and
# client/ to common/, from tools/ to the rest; and the check itself fails
# on a back-edge planted in a copy of the tree (base/vec.h including the
# scene), naming the file, the line and the layers; and the scheduler, pure
# logic, includes nothing but base/ and its segment type (a planted
# net/msg.h fails).
set -u
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
out=$(python3 tests/tools/layers.py) || fail "layering: $out"
python3 tests/tools/layers.py --dot | cmp -s - docs/architecture.dot ||
    fail "docs/architecture.dot is not the code's graph any more: make architecture"
mkdir -p "$dir/tree"
cp -r common server client tools "$dir/tree/"
sed -i 's|#include "base/real.h"|#include "base/real.h"\n#include "scene/scene.h"|' "$dir/tree/common/base/vec.h"
grep -q '"scene/scene.h"' "$dir/tree/common/base/vec.h" || fail "could not plant the back-edge"
planted=$(python3 tests/tools/layers.py --root "$dir/tree") && fail "a planted back-edge passed: $planted"
grep -q "common/base/vec.h:[0-9]*: base (layer base) includes scene/scene.h, of layer scene above or beside it" <<<"$planted" ||
    fail "the back-edge is not named: $planted"
# server and client are beside each other: neither may include the other
sed -i 's|#include "server.h"|#include "server.h"\n#include "client.h"|' "$dir/tree/server/server.c"
planted=$(python3 tests/tools/layers.py --root "$dir/tree") && fail "server including client passed"
grep -q "server/server.c:[0-9]*: server (layer server) includes client.h" <<<"$planted" || fail "server -> client not named: $planted"
# the scheduler is pure logic: the wire's packets are not for it
sed -i 's|#include "render/segment.h"|#include "render/segment.h"\n#include "net/msg.h"|' "$dir/tree/server/scheduler.h"
grep -q '"net/msg.h"' "$dir/tree/server/scheduler.h" || fail "could not plant the scheduler's include"
planted=$(python3 tests/tools/layers.py --root "$dir/tree") && fail "the scheduler including net/msg.h passed"
grep -q "server/scheduler.h:[0-9]*: the scheduler (pure logic) includes net/msg.h" <<<"$planted" ||
    fail "the scheduler's include of net/ is not named: $planted"
echo "$out; a planted back-edge and a planted include of net/ in the scheduler fail"
