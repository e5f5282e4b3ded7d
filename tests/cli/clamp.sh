#!/usr/bin/env bash
# The path integrator's Clamp Indirect (settings clamp_indirect,
# lanray-render --clamp-indirect): each light a sample gathers after its
# first bounce is held to a sum of red, green and blue.  A hold no light
# reaches (1e6) leaves the picture byte for byte; a hold near nothing
# leaves the direct light alone (the Cornell box's mean comes within 2% of
# its direct light, --depth 0, where the unclamped box is 30% brighter);
# a scene's `settings clamp_indirect` is the option's picture; through a
# server and a client the picture is lanray-render's (the setting travels
# with the view), the server's --clamp-indirect too; a negative hold is
# refused, in a scene (naming its line) and on the command line.
set -u
source tests/tools/server-lib.sh
render() { "$BIN/lanray-render" "$@" --quiet >/dev/null 2>"$dir/render.err" || fail "lanray-render $*: $(cat "$dir/render.err")"; }
grep -v "^light rect" models/cornell.scene | sed 's/^settings .*/settings integrator path depth 8/' >"$dir/box.scene"
box=("$dir/box.scene" --width 48 --height 36 --aa 4)
render "${box[@]}" -o "$dir/free.png"
render "${box[@]}" --clamp-indirect 1e6 -o "$dir/huge.png"
cmp -s "$dir/free.png" "$dir/huge.png" || fail "a hold no light reaches changed the picture"
render "${box[@]}" --clamp-indirect 1e-6 -o "$dir/tiny.png"
render "${box[@]}" --depth 0 -o "$dir/direct.png"
# the mean of a picture's codes (green: the boxes and floor are white)
mean() { python3 -c "
import sys; sys.path.insert(0, 'tests/tools')
from pngpixel import read
rows, ch = read(sys.argv[1])
print('%.2f' % (sum(sum(r[1::ch]) for r in rows) / sum(len(r) // ch for r in rows)))" "$1"; }
m_free=$(mean "$dir/free.png") m_tiny=$(mean "$dir/tiny.png") m_direct=$(mean "$dir/direct.png")
python3 -c "import sys; f, t, d = map(float, sys.argv[1:]); sys.exit(0 if abs(t - d) < 0.02 * d and f > 1.3 * d else 1)" \
    "$m_free" "$m_tiny" "$m_direct" ||
    fail "a hold near nothing: mean $m_tiny, the direct light's $m_direct, unclamped $m_free"
# the scene's setting, and through a server
sed 's/^settings integrator path depth 8/settings integrator path depth 8 clamp_indirect 0.5/' "$dir/box.scene" \
    >"$dir/held.scene"
render "$dir/held.scene" --width 48 --height 36 --aa 4 -o "$dir/held.png"
render "${box[@]}" --clamp-indirect 0.5 -o "$dir/opt.png"
cmp -s "$dir/held.png" "$dir/opt.png" || fail "settings clamp_indirect 0.5 is not --clamp-indirect 0.5's picture"
cmp -s "$dir/held.png" "$dir/free.png" && fail "a hold of 0.5 changed nothing: the test cannot tell"
setting_travels held "$dir/held.scene" "$dir/box.scene" clamp_indirect --clamp-indirect 0.5
refused_setting "settings integrator path clamp_indirect -2" "'clamp_indirect' of settings must be from 0"
out=$("$BIN/lanray-render" "${box[@]}" --clamp-indirect -1 -o "$dir/no.png" 2>&1)
[ $? = 2 ] && grep -q "clamp-indirect" <<<"$out" || fail "a negative hold: $out"
echo "clamp: a hold no light reaches changes no byte; one near nothing leaves the direct light (mean $m_tiny against $m_direct, unclamped $m_free); the scene's setting is the option's; through a server as lanray-render"
