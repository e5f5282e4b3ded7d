#!/usr/bin/env bash
# View transforms (settings tonemap, lanray-render --tonemap: none, aces,
# neutral; render/tonemap.h): `none` is the picture without the option
# byte for byte; the built-in scene one stop over (--exposure 1) has
# pixels cut to 255 in a channel, and through either curve far fewer; a
# scene's `settings tonemap` is the option's picture (lanray-server's
# --tonemap too); a server's frames are lanray-render's, a Whitted frame
# and a path-traced still whose batches the server adds up and codes
# itself (the curve there too); a word the format does not know is
# refused naming the scene's line; a .hdr keeps the light itself:
# lanray-render refuses the option with one, lanray-server --hdr writes
# the same frames with it (the curve is its window's).
set -u
source tests/tools/server-lib.sh
render() { "$BIN/lanray-render" "$@" --quiet >/dev/null 2>"$dir/render.err" || fail "lanray-render $*: $(cat "$dir/render.err")"; }
small=(--width 64 --height 48 --aa 1 --exposure 1)
render "${small[@]}" -o "$dir/plain.png"
render "${small[@]}" --tonemap none -o "$dir/none.png"
cmp -s "$dir/plain.png" "$dir/none.png" || fail "--tonemap none changed the picture"
# pixels with a channel at 255, in each picture
cut() { python3 -c "
import sys; sys.path.insert(0, 'tests/tools')
from pngpixel import read
rows, ch = read(sys.argv[1])
print(sum(1 for r in rows for i in range(0, len(r), ch) if max(r[i:i + 3]) == 255))" "$1"; }
n_none=$(cut "$dir/none.png")
for t in aces neutral; do
    render "${small[@]}" --tonemap $t -o "$dir/$t.png"
    n=$(cut "$dir/$t.png")
    [ "$n_none" -gt 50 ] && [ "$n" -lt $((n_none / 4)) ] ||
        fail "--tonemap $t: $n pixels cut at 255 against $n_none without (a stop over)"
    eval "n_$t=$n"
done
cmp -s "$dir/aces.png" "$dir/neutral.png" && fail "the two curves gave one picture"
# the scene's setting, and through a server (Whitted)
printf 'settings exposure 1 tonemap neutral\nmaterial floor diffuse 0.9 0.9 0.9\nplane point 0 0 0 normal 0 1 0 material floor\nmaterial red diffuse 1 0.2 0.1\nsphere centre 0 0.5 0 radius 0.5 material red\nlight point position 1 3 2 intensity 2\ncamera position 0 1 3 lookat 0 0.4 0 fov 50\n' \
    >"$dir/lit.scene"
render "$dir/lit.scene" --width 64 --height 64 --aa 1 -o "$dir/lit.png"
render "$dir/lit.scene" --width 64 --height 64 --aa 1 --tonemap none -o "$dir/lit-none.png"
cmp -s "$dir/lit.png" "$dir/lit-none.png" && fail "the scene's tonemap changed nothing: the test cannot tell"
verify_distributed lit "$dir/lit.scene" "$dir/lit.png" "with settings tonemap"
# the server's --tonemap over the scene's setting
sed 's/ tonemap neutral//' "$dir/lit.scene" >"$dir/bare.scene"
verify_distributed option "$dir/bare.scene" "$dir/lit.png" "with lanray-server --tonemap" --tonemap neutral
# lanray-server --hdr's frames keep the light: with --tonemap the same
# bytes (the curve is its window's: tests/cli/window.sh)
for t in none aces; do
    start_server "hdr-$t" "$dir/bare.scene" --port 0 --width 32 --height 24 --frames 1 --wait-clients 1 --hdr \
        --tonemap "$t" --out "$dir/hdr-$t"
    "$BIN/lanray-client" "127.0.0.1:$port" --threads 2 --once --quiet 2>"$dir/c-hdr-$t.err" &
    pids+=("$!")
    server_done 120 "hdr-$t"
    [ -s "$dir/hdr-$t/frame-00001.hdr" ] || fail "lanray-server --hdr --tonemap $t wrote no frame"
done
cmp -s "$dir/hdr-none/frame-00001.hdr" "$dir/hdr-aces/frame-00001.hdr" ||
    fail "lanray-server --hdr --tonemap aces changed the frames' light"
# a path-traced still of 2 x 2 samples in batches, coded by the server
sed 's/^settings exposure 1 tonemap neutral/settings exposure 1 tonemap aces integrator path/' "$dir/lit.scene" >"$dir/pt.scene"
render "$dir/pt.scene" --width 32 --height 24 --aa 2 -o "$dir/pt.png"
render "$dir/pt.scene" --width 32 --height 24 --aa 2 --tonemap none -o "$dir/pt-none.png"
cmp -s "$dir/pt.png" "$dir/pt-none.png" && fail "a path-traced still of 2 x 2 samples went through no curve"
start_server pt "$dir/pt.scene" --port 0 --width 32 --height 24 --wait-clients 2 --still-aa 2 --frames 4 --out "$dir/pt"
serve_flight pt 4
cmp -s "$dir/pt/frame-00004.png" "$dir/pt.png" || fail "a path-traced still through a server (batches coded there) is not lanray-render's"
# a word the scene format does not know: refused, naming the file and line
refused_setting "settings tonemap filmic" "'tonemap' of settings must be none, aces or neutral"
# a .hdr keeps the light
out=$("$BIN/lanray-render" --width 8 --height 8 --tonemap aces -o "$dir/x.hdr" 2>&1)
[ $? = 2 ] && grep -q "tonemap" <<<"$out" || fail "--tonemap with a .hdr: $out"
echo "tonemap: none is the plain picture; a stop over, $n_none pixels cut at 255 plain, $n_aces through aces, $n_neutral through neutral; the scene's setting is the option's; through a server (Whitted, and a path-traced still coded by the server) as lanray-render; a .hdr refuses it, a server's --hdr frames keep the light"
