#!/usr/bin/env bash
# Live scene edits: a server follows its scene file and the files it names
# while it runs.  A model added to the file, a texture file replaced, then a
# syntax error, then a fix: the frames show each good version as
# lanray-render draws it (byte for byte), the error is logged with its file
# and line while the last good scene stays on, and the one client never
# reconnects; a frame size or denoise edited in is said (a headless
# server's frames keep theirs; a window takes the size: resize.sh).
set -u
source tests/tools/server-lib.sh
W=64 H=48
mkdir -p "$dir/s"
cp models/cube.obj models/cube.mtl "$dir/s/"
printf 'P3\n2 2\n255\n255 0 0  0 255 0\n0 0 255  255 255 255\n' >"$dir/s/tex.ppm"
base='camera position 0 1.5 4 lookat 0 0.3 0 fov 50
texture t tex.ppm closest
material tiles texture t
plane point 0 -0.5 0 normal 0 1 0 material tiles
sphere centre -1 0.2 0 radius 0.5
light point position 2 4 3
'
v1=$base
v2="${base}model cube cube.obj
instance cube translate 0.8 0 0 rotate 0 30 0
"
v4=${v2/sphere centre -1 0.2 0/sphere centre -1.2 0.5 -0.5}
render_ref() { # NAME TEXT: lanray-render's picture of that scene (with the texture there now)
    printf '%s' "$2" >"$dir/s/ref.scene"
    "$BIN/lanray-render" "$dir/s/ref.scene" --aa 1 --width $W --height $H -o "$dir/$1.png" --quiet >/dev/null ||
        fail "lanray-render $1"
}
render_ref ref1 "$v1"
render_ref ref2 "$v2"
cp "$dir/s/tex.ppm" "$dir/tex-before.ppm"
printf 'P3\n2 2\n255\n0 0 0  255 255 0\n255 0 255  0 255 255\n' >"$dir/s/tex.ppm"
render_ref ref3 "$v2"
render_ref ref4 "$v4"
cp "$dir/tex-before.ppm" "$dir/s/tex.ppm"
cmp -s "$dir/ref2.png" "$dir/ref3.png" && fail "the new texture does not show: the test cannot fail"
rm -f "$dir/s/ref.scene"
printf '%s' "$v1" >"$dir/s/e.scene"
start_server edit "$dir/s/e.scene" --port 0 --width $W --height $H --aa 1 --max-fps 25 --out "$dir/f"
"$BIN/lanray-client" "127.0.0.1:$port" --threads 1 --once 2>"$dir/client.err" >/dev/null &
pids+=("$!")
# the last frame in folder $1 written whole (one being written is a .tmp beside it)
last_frame() { ls "$1" 2>/dev/null | grep '\.png$' | tail -1; }
# shows REF WHAT: waits (10 s at most) for a frame written from now on that is REF
shows() {
    local from=$(last_frame "$dir/f")
    for _ in $(seq 200); do
        local last=$(last_frame "$dir/f")
        if [ -n "$last" ] && [ "$last" != "$from" ] && cmp -s "$dir/f/$last" "$dir/$1.png"; then
            return 0
        fi
        sleep 0.05
    done
    fail "$2: the frames did not become lanray-render's picture (last: $(last_frame "$dir/f"))"
}
shows ref1 "the first scene"
printf '%s' "$v2" >"$dir/s/e.scene.tmp" && mv "$dir/s/e.scene.tmp" "$dir/s/e.scene" # as editors save
shows ref2 "a model added"
printf 'P3\n2 2\n255\n0 0 0  255 255 0\n255 0 255  0 255 255\n' >"$dir/s/tex.ppm"
shows ref3 "the texture replaced"
printf '%ssphere centre 0 0\n' "$v2" >"$dir/s/e.scene"
for _ in $(seq 200); do grep -q "the last good scene stays" "$dir/edit.err" && break; sleep 0.05; done
grep -q "e.scene:9: .*(the last good scene stays)" "$dir/edit.err" ||
    fail "the error is not reported with its file and line: $(tail -2 "$dir/edit.err")"
shows ref3 "a syntax error (the last good scene stays on)"
printf '%s' "$v4" >"$dir/s/e.scene"
shows ref4 "the error fixed, a sphere moved"
kill -TERM "$server_pid"
wait "$server_pid" 2>/dev/null
sleep 0.2
n=$(grep -c "connected to" "$dir/client.err")
[ "$n" = 1 ] || fail "the client connected $n times: $(cat "$dir/client.err")"
grep -q "reconnecting" "$dir/client.err" && fail "the client reconnected: $(cat "$dir/client.err")"
grep -q "scenes decoded" "$dir/client.err" || fail "the client did not end its session cleanly: $(cat "$dir/client.err")"
# a frame size and denoise edited into a scene served headless without
# --width, --height, --denoise: the frames stay as they are (the frames
# written are one size; denoise the server cannot take while it runs) and
# the log says so, rather than nothing
mkdir "$dir/z" "$dir/fz"
printf 'settings width 64 height 48\n%s' "$v1" >"$dir/z/z.scene"
cp "$dir/s/tex.ppm" "$dir/z/"
start_server size "$dir/z/z.scene" --port 0 --aa 1 --max-fps 25 --out "$dir/fz"
"$BIN/lanray-client" "127.0.0.1:$port" --threads 1 --quiet --once 2>/dev/null &
client=$!
pids+=("$client")
for _ in $(seq 100); do [ -n "$(ls "$dir/fz")" ] && break; sleep 0.05; done
printf 'settings width 80 height 48 denoise on\n%s' "$v1" >"$dir/z/z.scene"
for _ in $(seq 200); do grep -q "asks for denoise" "$dir/size.err" && break; sleep 0.05; done
grep -q "z.scene asks for 80x48 frames; they stay 64x48 until the server is started again" "$dir/size.err" ||
    fail "a frame size edited in: not said ($(cat "$dir/size.err"))"
grep -q "z.scene asks for denoise on; the frames stay raw until the server is started again" "$dir/size.err" ||
    fail "denoise edited in: not said ($(cat "$dir/size.err"))"
sleep 0.3
last=$(last_frame "$dir/fz")
size=$(python3 -c 'import struct,sys; print("%dx%d" % struct.unpack(">II", open(sys.argv[1], "rb").read()[16:24]))' "$dir/fz/$last")
[ "$size" = 64x48 ] || fail "a frame size edited in: the frames are $size"
kill -TERM "$server_pid"
wait "$server_pid" "$client" 2>/dev/null
echo "edit: a frame size and denoise edited in are said, the frames stay 64x48"

# a scene is read on a thread of its own: while a large model is read and
# its tree built, the scene shown goes on being served (read in the loop,
# no frame was finished meanwhile); tiny frames, as many as the farm makes
mkdir "$dir/big"
cp "$dir/s/tex.ppm" "$dir/big/"
printf '%s' "$v1" >"$dir/big/b.scene"
python3 - "$dir/big/grid.obj" <<'GRID'
import math, sys
n = 224  # 2 n^2 = 100352 triangles: a tenth of a second to read and build, where a frame of 16x12 takes a millisecond
rows = ["v %.5f %.5f %.5f" % (i / n - 0.5, 0.05 * math.sin(20 * i / n) * math.cos(20 * j / n), j / n - 0.5)
        for j in range(n + 1) for i in range(n + 1)]
w = n + 1
rows += ["f %d %d %d\nf %d %d %d" % (a, a + w, a + 1, a + 1, a + w, a + w + 1)
         for a in (j * w + i + 1 for j in range(n) for i in range(n))]
open(sys.argv[1], "w").write("\n".join(rows) + "\n")
GRID
start_server big "$dir/big/b.scene" --port 0 --width 16 --height 12 --aa 1 --discard
"$BIN/lanray-client" "127.0.0.1:$port" --threads 1 --quiet --once 2>/dev/null &
client=$!
pids+=("$client")
for _ in $(seq 200); do grep -q "^lanray-server: [1-9][0-9]* frames" "$dir/big.err" && break; sleep 0.05; done
printf '%smodel grid grid.obj\ninstance grid translate 0 0 0\n' "$v1" >"$dir/big/b.scene"
for _ in $(seq 400); do grep -q "b.scene read again in" "$dir/big.err" && break; sleep 0.05; done
line=$(grep "b.scene read again in" "$dir/big.err") || fail "the scene with a large model was not read again"
meanwhile=$(sed -n 's/.*(\([0-9]*\) frames shown meanwhile).*/\1/p' <<<"$line")
[ "${meanwhile:-0}" -ge 3 ] || fail "frames went on while the scene was read: $line"
# and its model is sent ahead of its frames (server/ahead.c): the scene
# shown goes on while the client takes the model in on its own thread
for _ in $(seq 400); do grep -q "taken in by every client" "$dir/big.err" && break; sleep 0.05; done
ahead=$(grep "taken in by every client" "$dir/big.err") || fail "the new model was not sent ahead: $(cat "$dir/big.err")"
meanwhile=$(sed -n 's/.*(\([0-9]*\) frames meanwhile).*/\1/p' <<<"$ahead")
[ "${meanwhile:-0}" -ge 3 ] || fail "frames went on while the client took the model in: $ahead"
kill -TERM "$server_pid"
wait "$server_pid" "$client" 2>/dev/null
echo "edit: ${line#lanray-server: }"
echo "edit: ${ahead#lanray-server: }"
echo "edit: a model added, a texture replaced, an error (logged with its line, the last good scene kept) and its fix, each followed by the frames as lanray-render draws it, with one connection"
